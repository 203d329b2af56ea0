//! The figure that answers chapter 6's question: `metabezier implant`
//! draws Dice and HD95 per method and defect width
//! (`validation_dice_hd95.png`, with its SVG), a panel pair per validation
//! that ran (slice by slice, in 3D), links it from the summary of
//! `report.md` and shows it in a section of its own; the picture fits a
//! screen and the methods keep their colours.

use crate::common;

use std::path::{Path, PathBuf};

use metabezier::ct::CT0051_PATH;

/// A fresh directory under the system's temporary directory.
fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "metabezier-implant-figures-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs `metabezier implant` on `text` in `dir` ([`common::implant`]) and
/// returns its output directory, `dir/out`.
fn run(dir: &Path, text: &str) -> PathBuf {
    let (ok, err) = common::implant(dir, text);
    assert!(ok, "{err}");
    dir.join("out")
}

/// A validation-only spec on the vendored CT 0051 extract with the given
/// validation sections.
fn spec(validations: &str) -> String {
    let volume = Path::new(env!("CARGO_MANIFEST_DIR")).join(CT0051_PATH);
    format!(
        "[implant]\nvolume = \"{}\"\nfirst_z = 40\nmidline_slices = [86, 92]\nmethod = \"mhs\"\n\
         budget = 2000\nseed = 7\n\n{validations}",
        volume.display()
    )
}

const TWO_D: &str = "[validation]\nslices = [88]\npositions = [200, 225]\nwidths = [20, 30]\n\
                     methods = [\"mhs\", \"lm\"]\nruns = 2\n\n";
const THREE_D: &str = "[validation_3d]\nranges = [[88, 92]]\npositions = [30]\nwidths = [20, 40]\n\
                       methods = [\"mhs\", \"lm\"]\nruns = 1\n";

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn an_implant_run_draws_dice_and_hd95_per_method_and_width() {
    let dir = tmp("both");
    let out = run(&dir, &spec(&format!("{TWO_D}{THREE_D}")));
    let faults = common::unreadable(&out);
    assert!(faults.is_empty(), "{faults:?}");
    let (w, h) = common::png_size(&out.join("validation_dice_hd95.png"));
    assert!(w <= 3000 && h <= 3000, "{w} × {h}");
    // Two panels side by side, two rows (2D and 3D).
    assert!(w > h / 2 && h > 600, "{w} × {h}");
    let md = read(&out.join("report.md"));
    let summary = &md[md.find("## Summary").unwrap()..];
    let summary = &summary[..summary[3..].find("\n## ").unwrap()];
    assert!(
        summary.contains(
            "The figure that answers the question: [Dice and HD95 per method and width](validation_dice_hd95.png)"
        ),
        "{summary}"
    );
    assert!(md.contains("## Dice and HD95 per method and width\n\n![Dice and HD95 per method and width](validation_dice_hd95.png)"));
    assert!(md.contains("HD95, the 95th percentile of the surface distances in mm"));
    let svg = read(&out.join("validation_dice_hd95.svg"));
    for text in [
        "Dice, slice by slice (validation.csv)",
        "HD95, slice by slice (validation.csv)",
        "Dice, in 3D (validation_3d.csv)",
        "HD95, in 3D (validation_3d.csv)",
        "defect width (mm)",
        "HD95 mm (smaller is better)",
        "template",
        "straight",
        "curve:mhs",
        "curve:lm",
    ] {
        assert!(svg.contains(text), "no {text:?} in the figure");
    }
    // A tick label at every width.
    for width in ["20", "30", "40"] {
        assert!(svg.lines().any(|l| l.trim() == width), "no tick {width}");
    }
    // MHS's vermillion and LM's indigo, as in every report.
    for colour in ["#D55E00", "#332288"] {
        assert!(svg.contains(colour), "no {colour}");
    }
    // A point per method and width: 4 methods × 2 widths × 2 metrics in
    // each of the two validations.
    assert_eq!(svg.matches("<circle").count(), 32);
    // report.html inlines the figure.
    let html = read(&out.join("report.html"));
    assert!(html.contains("Dice, in 3D (validation_3d.csv)"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn without_a_3d_validation_the_figure_has_no_3d_panels() {
    let dir = tmp("2d");
    let out = run(&dir, &spec(TWO_D));
    let svg = read(&out.join("validation_dice_hd95.svg"));
    assert!(svg.contains("Dice, slice by slice (validation.csv)"));
    assert!(!svg.contains("in 3D"), "a 3D panel without a 3D validation");
    assert_eq!(svg.matches("<circle").count(), 16);
    let _ = std::fs::remove_dir_all(&dir);
}
