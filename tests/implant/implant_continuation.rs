//! The continuation template (crates/implant/src/implant/continuation.rs, beyond the
//! thesis) on the vendored ProMED CT 0051 extract: a defect across the
//! posterior midline gets a wall where the mirror refuses it, near-midline
//! defects are routed to it, the spec key and its errors, and the CLI's
//! `template_source` column. Cheap: LM fits on one slice, one small CLI run.

use std::path::{Path, PathBuf};
use std::process::Command;

use metabezier::ct::{read_inv3, CtError, MidLine, CT0051_FIRST_Z, CT0051_PATH};
use metabezier::fit::LmSolver;
use metabezier::geometry::Point;
use metabezier::implant::continuation::{crosses_midline, source_for};
use metabezier::implant::*;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "metabezier-continuation-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn crate_path(p: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(p)
        .display()
        .to_string()
}

#[test]
fn a_defect_across_the_posterior_midline_gets_a_continued_wall() {
    let v = read_inv3(Path::new(CT0051_PATH)).unwrap();
    // The midline of CT 0051 as `midline = "auto"` estimates it from the
    // intact slices 86–92 (docs/reproduction/ch6.md: x = 124.03 mm at y = 105.26 mm,
    // tilt −3.15°), given here to keep the test cheap.
    let mx = MidLine {
        point: Point::new(124.03, 105.26),
        tilt: (-3.15f64).to_radians(),
    };
    let p = prepare_case(
        &v,
        Case {
            index: 90 - CT0051_FIRST_Z,
            position_deg: 270.0,
            width_mm: 40.0,
        },
        mx,
        300,
    )
    .unwrap();
    // z = 90, 40 mm at the posterior midline. The thesis's mirror refuses
    // it, naming both ways out.
    let mirror = WallOptions::default();
    let e =
        reconstruct_case(&p, WallKind::CurveFit, &mirror, &mut LmSolver::default()).unwrap_err();
    assert!(
        matches!(e, SliceError::Ct(CtError::DefectCrossesMidline { .. })),
        "{e}"
    );
    assert!(e.to_string().contains("template_source"), "{e}");
    // Auto continues the bone from both sides, for every wall kind.
    let auto = WallOptions {
        template: TemplateChoice::Auto,
        ..WallOptions::default()
    };
    assert_eq!(
        validation::case_template_source(&p, &auto),
        TemplateSource::Continuation
    );
    let mut dice = Vec::new();
    for kind in WallKind::ALL {
        let w = reconstruct_case(&p, kind, &auto, &mut LmSolver::default()).unwrap();
        assert_eq!(w.design.template_source, TemplateSource::Continuation);
        // No mirror image: C and D are the ends themselves.
        assert_eq!((w.design.c, w.design.d), (w.design.a, w.design.b));
        let m = case_metrics(&p, &w, 10.0).unwrap();
        dice.push((kind, m.dice, m.dev_mean));
    }
    let (curve, straight) = (dice[0], dice[2]);
    // The continued wall follows the removed outer table where the chord
    // cannot (a 40 mm gap: Dice 0.92 against 0.75 on this case with LM).
    assert!(curve.1 > 0.85, "{dice:?}");
    assert!(curve.1 > straight.1 + 0.05, "{dice:?}");
    assert!(curve.2 < 2.0 && curve.2 < straight.2, "{dice:?}");
    let (ja, jb) = reconstruct_case(&p, WallKind::CurveFit, &auto, &mut LmSolver::default())
        .unwrap()
        .join_angles_deg();
    assert!(ja < 1e-6 && jb < 1e-6, "{ja} {jb}");
}

#[test]
fn the_source_is_told_by_the_file_the_choice_and_the_midline() {
    let line = MidLine::vertical(100.0);
    let opts = |template| WallOptions {
        template,
        ..WallOptions::default()
    };
    let (a, b) = (Point::new(40.0, 0.0), Point::new(93.0, 0.0));
    let across = Point::new(110.0, 0.0);
    assert!(!crosses_midline(a, b, &line));
    assert!(crosses_midline(a, across, &line));
    let src = |a, b, file, o: &WallOptions| source_for(a, b, &line, file, o);
    let auto = opts(TemplateChoice::Auto);
    assert_eq!(src(a, b, false, &auto), TemplateSource::Mirror);
    assert_eq!(src(a, across, false, &auto), TemplateSource::Continuation);
    assert_eq!(src(a, across, true, &auto), TemplateSource::File);
    let forced = opts(TemplateChoice::Continuation);
    assert_eq!(src(a, b, false, &forced), TemplateSource::Continuation);
    let mirror = opts(TemplateChoice::Mirror);
    assert_eq!(src(a, across, false, &mirror), TemplateSource::Mirror);
}

fn spec(dir: &Path, extra: &str) -> PathBuf {
    let text = format!(
        "[implant]\nvolume = \"{}\"\nfirst_z = 40\nmidline_slices = [86, 92]\nmethod = \"lm\"\n{extra}\n\n[validation]\nslices = [88]\npositions = [200, 270]\nwidths = [30]\nmethods = [\"lm\"]\nruns = 1\n",
        crate_path("data/ct0051/ct0051_z040-100.inv3")
    );
    let p = dir.join("spec.toml");
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn the_spec_chooses_the_template_source_and_names_bad_choices() {
    let dir = tmp("spec");
    for (line, want) in [
        ("", TemplateChoice::Mirror),
        ("template_source = \"auto\"", TemplateChoice::Auto),
        ("template_source = \"mirror\"", TemplateChoice::Mirror),
        (
            "template_source = \"continuation\"",
            TemplateChoice::Continuation,
        ),
    ] {
        let s = ImplantSpec::load(&spec(&dir, line)).unwrap();
        assert_eq!(s.defect_config.wall.template, want, "{line}");
    }
    let bad = spec(&dir, "template_source = \"symmetry\"");
    let e = ImplantSpec::load(&bad).unwrap_err().to_string();
    for part in [
        "spec.toml:6:",
        "implant.template_source",
        "\"symmetry\"",
        "\"auto\", \"mirror\", \"continuation\"",
    ] {
        assert!(e.contains(part), "{part} missing in: {e}");
    }
}

#[test]
fn validation_csv_records_the_template_source_and_the_crossing_case_is_a_row() {
    let dir = tmp("cli");
    let out = dir.join("out");
    let s = Command::new(env!("CARGO_BIN_EXE_metabezier"))
        .arg("implant")
        .arg(spec(&dir, "template_source = \"auto\""))
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(s.status.success(), "{}", String::from_utf8_lossy(&s.stderr));
    let csv = std::fs::read_to_string(out.join("validation.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (pos, status, source) = (col("position_deg"), col("status"), col("template_source"));
    let mut seen = Vec::new();
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        assert_eq!(f[status], "ok", "{l}");
        seen.push((f[pos].to_owned(), f[source].to_owned()));
    }
    // 2 positions × (template, straight, curve:lm).
    assert_eq!(seen.len(), 6);
    for (p, s) in seen {
        let want = if p == "270" { "continuation" } else { "mirror" };
        assert_eq!(s, want, "position {p}");
    }
}
