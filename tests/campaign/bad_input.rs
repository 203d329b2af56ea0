//! The bad-input corpus: every subcommand and every input format, each case
//! run through the real binary in a fresh directory. Each case asserts the
//! exit code (1 for a refused input, 2 for a usage error; never 101, a Rust
//! panic, nor 134, an abort), that standard error names what is wrong, and
//! that nothing is left behind: after the run the directory holds exactly
//! the files the case put there.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::files_under;

/// One bad input and what the binary must say about it.
struct Case {
    /// What is wrong, for the failure report.
    name: &'static str,
    /// Files written into the fresh directory before the run.
    files: Vec<(&'static str, Vec<u8>)>,
    /// The command line after `metabezier`.
    args: Vec<&'static str>,
    /// The exit code: 1 for refused input, 2 for a usage error.
    code: i32,
    /// Text that standard error must contain.
    message: &'static str,
}

/// A case without input files.
fn case(name: &'static str, args: &str, code: i32, message: &'static str) -> Case {
    Case {
        name,
        files: Vec::new(),
        args: args.split_whitespace().map(leak).collect(),
        code,
        message,
    }
}

fn leak(s: &str) -> &'static str {
    Box::leak(s.to_owned().into_boxed_str())
}

impl Case {
    /// Adds an input file.
    fn with(mut self, name: &'static str, bytes: impl Into<Vec<u8>>) -> Case {
        self.files.push((name, bytes.into()));
        self
    }
}

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn real(p: &str) -> Vec<u8> {
    std::fs::read(repo(p)).unwrap()
}

/// A tiny valid benchmark campaign.
const SPEC: &str = "[experiment]\nname = \"t\"\nseed = 1\nruns = 2\nbudget = 100\n\n[[problem]]\nfunction = \"sphere\"\ndim = 2\n\n[[algorithm]]\nname = \"hs\"\n";

/// [`SPEC`] with `from` replaced by `to`.
fn spec_with(from: &str, to: &str) -> String {
    assert!(SPEC.contains(from), "{from}");
    SPEC.replace(from, to)
}

/// [`SPEC`] with `extra` appended (inside the `[[algorithm]]` table).
fn spec_plus(extra: &str) -> String {
    format!("{SPEC}{extra}\n")
}

/// A fitting campaign on `input` with `extra` lines in its `[[fit]]` table.
fn fit_spec(input: &str, extra: &str) -> String {
    format!("[experiment]\nname = \"f\"\nseed = 1\nruns = 1\nbudget = 50\nthreshold = 0\n\n[[fit]]\ninput = \"{input}\"\nfunction = \"cubic\"\ncontinuity = \"g1\"\nsegments = 4\n{extra}\n[[algorithm]]\nname = \"hs\"\n")
}

/// A circle of `n` points as CSV text.
fn circle(n: usize) -> String {
    let mut s = String::from("x,y\n");
    for i in 0..n {
        let t = i as f64 / n as f64 * std::f64::consts::TAU;
        s.push_str(&format!("{},{}\n", 10.0 * t.cos(), 10.0 * t.sin()));
    }
    s
}

/// The real CT extract with one bit flipped in its compressed body.
fn flipped_ct() -> Vec<u8> {
    let mut b = real("data/ct0051/ct0051_z040-100.inv3");
    let at = b.len() / 2;
    b[at] ^= 0x10;
    b
}

/// The real DICOM slice with its PixelData two bytes short (the element's
/// length field and its value both shortened; the elements after it kept).
fn short_dicom() -> Vec<u8> {
    let mut b = real("data/dicom/CT_small.dcm");
    let tag = [0xE0, 0x7F, 0x10, 0x00];
    let at = b.windows(4).rposition(|w| w == tag).expect("PixelData tag");
    // Explicit VR little endian: tag, "OW", two reserved bytes, u32 length.
    assert_eq!(&b[at + 4..at + 6], b"OW");
    let len_at = at + 8;
    let len = u32::from_le_bytes(b[len_at..len_at + 4].try_into().unwrap());
    b[len_at..len_at + 4].copy_from_slice(&(len - 2).to_le_bytes());
    let end = len_at + 4 + len as usize;
    b.drain(end - 2..end);
    b
}

/// An implant spec on the CT at `volume` with `extra` lines appended.
fn implant_spec(volume: &str, extra: &str) -> String {
    format!("[implant]\nvolume = \"{volume}\"\nfirst_z = 40\nthreshold = 300\nmidline = \"auto\"\nmidline_slices = [86, 92]\nfunction = \"rational-cubic\"\ncontinuity = \"g1\"\nmethod = \"lm\"\nbudget = 100\nseed = 1\n\n[defect]\nslices = [64, 66]\nends = \"auto\"\n{extra}")
}

fn spec_cases() -> Vec<Case> {
    let spec = |name, text: String, message| {
        case(name, "run spec.toml", 1, message).with("spec.toml", text)
    };
    vec![
        case("spec file missing", "run none.toml", 1, "none.toml: cannot read"),
        case("spec is a directory", "run .", 1, "cannot read"),
        spec("empty spec", String::new(), "spec.toml"),
        spec("not TOML", "[experiment\nname=".into(), "spec.toml:1:"),
        spec("binary garbage", "\u{0}\u{1}\u{2}\u{3}".into(), "spec.toml"),
        spec("no experiment table", "[[problem]]\nfunction = \"sphere\"\ndim = 2\n".into(), "experiment"),
        spec("unknown top-level table", spec_plus("[bogus]\nx = 1"), "bogus"),
        spec("unknown experiment key", spec_with("seed = 1", "seed = 1\nsede = 2"), "sede"),
        spec("negative seed", spec_with("seed = 1", "seed = -1"), "experiment.seed"),
        spec("seed as text", spec_with("seed = 1", "seed = \"one\""), "experiment.seed"),
        spec("zero runs", spec_with("runs = 2", "runs = 0"), "experiment.runs"),
        spec("runs over the limit", spec_with("runs = 2", "runs = 4294967295"), "--allow-large"),
        spec("zero budget", spec_with("budget = 100", "budget = 0"), "experiment.budget: expected an integer ≥ 1, found 0"),
        spec("negative threshold", spec_with("seed = 1", "seed = 1\nthreshold = -1"), "experiment.threshold"),
        spec("NaN threshold", spec_with("seed = 1", "seed = 1\nthreshold = nan"), "experiment.threshold"),
        spec("unknown function", spec_with("\"sphere\"", "\"spere\""), "sphere"),
        spec("zero dimension", spec_with("dim = 2", "dim = 0"), "problem[1].dim"),
        spec("huge dimension", spec_with("dim = 2", "dim = 100000000"), "problem[1].dim"),
        spec("six-hump camel at D = 3", spec_with("\"sphere\"\ndim = 2", "\"six_hump_camel\"\ndim = 3"), "six_hump_camel"),
        spec("unknown transform", spec_with("dim = 2", "dim = 2\ntransform = \"twist\""), "problem[1].transform"),
        spec("zero instances", spec_with("dim = 2", "dim = 2\ntransform = \"shift\"\ninstances = 0"), "problem[1].instances"),
        spec("empty instance list", spec_with("dim = 2", "dim = 2\ntransform = \"shift\"\ninstances = []"), "problem[1].instances: expected a value or a non-empty list"),
        spec("instance listed twice", spec_with("dim = 2", "dim = 2\ntransform = \"shift\"\ninstances = [6, 7, 6]"), "problem[1].instances: instance 6 is listed twice"),
        spec("instance 0 in a list", spec_with("dim = 2", "dim = 2\ntransform = \"shift\"\ninstances = [6, 0]"), "problem[1].instances: expected an integer in 1..=10000, found 0"),
        spec("instance as text", spec_with("dim = 2", "dim = 2\ntransform = \"shift\"\ninstances = [\"six\"]"), "problem[1].instances: expected an integer"),
        spec("instance over the limit", spec_with("dim = 2", "dim = 2\ntransform = \"shift\"\ninstances = [10001]"), "problem[1].instances: expected an integer in 1..=10000, found 10001"),
        spec("unknown algorithm", spec_with("name = \"hs\"", "name = \"hss\""), "algorithm[1].name"),
        spec("hmcr above one", spec_plus("hmcr = 1.5"), "algorithm[1].hmcr: expected a real number in [0, 1], found 1.5"),
        spec("par negative", spec_plus("par = -0.1"), "algorithm[1].par"),
        spec("hms zero", spec_plus("hms = 0"), "algorithm[1].hms"),
        spec("cmaes lambda one", spec_with("name = \"hs\"", "name = \"cmaes\"\nlambda = 1"), "algorithm[1].lambda: λ must be at least 2 (or 0 for 4 + ⌊3 ln D⌋), found 1"),
        spec("cmaes sigma0 zero", spec_with("name = \"hs\"", "name = \"cmaes\"\nsigma0 = 0"), "algorithm[1].sigma0: expected a real number in (0, 1], found 0"),
        spec("cmaes unknown restarts", spec_with("name = \"hs\"", "name = \"cmaes\"\nrestarts = \"foo\""), "algorithm[1].restarts: expected one of \"ipop\", \"bipop\" or \"none\", found \"foo\""),
        spec("parameter of another algorithm", spec_plus("inertia = 0.5"), "algorithm[1]"),
        spec("lshade p_best zero", spec_with("name = \"hs\"", "name = \"lshade\"\np_best = 0"), "algorithm[1].p_best: expected a real number in (0, 1], found 0"),
        spec("lshade memory zero", spec_with("name = \"hs\"", "name = \"lshade\"\nmemory = 0"), "algorithm[1].memory: expected an integer in 1..=1000, found 0"),
        spec("lshade negative archive rate", spec_with("name = \"hs\"", "name = \"lshade\"\narc_rate = -1"), "algorithm[1].arc_rate"),
        spec("lshade zero r_n_init", spec_with("name = \"hs\"", "name = \"lshade\"\nr_n_init = 0.0"), "algorithm[1].r_n_init: expected a real number in (0, 1000], found 0"),
        spec("random search given a parameter", spec_with("name = \"hs\"", "name = \"random\"\nhms = 5"), "algorithm[1].hms: unknown parameter for random (it has none)"),
        spec("empty grid list", spec_plus("hmcr = []"), "algorithm[1].hmcr"),
        spec("duplicated grid values", spec_plus("hmcr = [0.9, 0.9]"), "algorithm cell hs [hms=5;hmcr=0.9;par=0.3;bw=0.01;bw_decay=none;bw_min=0.000001;bounds=clip] appears twice"),
        spec("duplicated algorithm", format!("{SPEC}\n[[algorithm]]\nname = \"hs\"\n"), "algorithm"),
        spec("no algorithm", spec_with("[[algorithm]]\nname = \"hs\"\n", ""), "algorithm"),
        spec("no problem", spec_with("[[problem]]\nfunction = \"sphere\"\ndim = 2\n", ""), "problem"),
        spec("unknown paired factor", spec_with("seed = 1", "seed = 1\npaired = [\"colour\"]"), "experiment.paired"),
        spec("budget list with zero", spec_with("budget = 100", "budget = [100, 0]"), "experiment.budget"),
        spec("bbob function 25", spec_with("function = \"sphere\"\ndim = 2", "suite = \"bbob\"\nfunction = 25\ndim = 2"), "problem[1].function"),
        spec("bbob dimension 4", spec_with("function = \"sphere\"\ndim = 2", "suite = \"bbob\"\nfunction = 1\ndim = 4"), "problem[1].dim"),
        spec("bbob instance 0", spec_with("function = \"sphere\"\ndim = 2", "suite = \"bbob\"\nfunction = 1\ndim = 2\ninstances = [0]"), "problem[1].instances"),
        spec("unknown suite", spec_with("function = \"sphere\"", "suite = \"cec\"\nfunction = \"sphere\""), "problem[1].suite"),
        spec("fit input missing", fit_spec("nothing.png", ""), "nothing.png"),
        spec("fit unknown function", fit_spec("c.csv", "").replace("\"cubic\"", "\"quartic\""), "fit[1].function").with("c.csv", circle(40)),
        spec("fit unknown continuity", fit_spec("c.csv", "").replace("\"g1\"", "\"g3\""), "fit[1].continuity").with("c.csv", circle(40)),
        spec("fit zero segments", fit_spec("c.csv", "").replace("segments = 4", "segments = 0"), "fit[1].segments").with("c.csv", circle(40)),
        spec("fit negative alpha_size", fit_spec("c.csv", "alpha_size = -1"), "fit[1].alpha_size").with("c.csv", circle(40)),
        spec("fit unknown closing", fit_spec("c.csv", "closing = \"tight\""), "fit[1].closing").with("c.csv", circle(40)),
        spec("fit unknown search space", fit_spec("c.csv", "search_space = \"box\""), "fit[1].search_space").with("c.csv", circle(40)),
        spec("fit contour out of range", fit_spec("c.csv", "contour = 3"), "contour 3").with("c.csv", circle(40)),
        spec("fit CSV with NaN", fit_spec("c.csv", ""), "c.csv:3: column 1 (x)").with("c.csv", "x,y\n1,2\nnan,3\n4,5\n"),
        case("check of a bad spec", "check spec.toml", 1, "experiment.runs").with("spec.toml", spec_with("runs = 2", "runs = 0")),
        case("slurm of a bad spec", "slurm spec.toml --tasks 2", 1, "experiment.runs").with("spec.toml", spec_with("runs = 2", "runs = 0")),
    ]
}

fn run_cases() -> Vec<Case> {
    let ok = |c: Case| c.with("spec.toml", SPEC);
    vec![
        ok(case(
            "zero threads",
            "run spec.toml --threads 0",
            2,
            "--threads",
        )),
        ok(case(
            "too many threads",
            "run spec.toml --threads 65535",
            1,
            "--threads 65535: at most",
        )),
        ok(case(
            "threads as text",
            "run spec.toml --threads many",
            2,
            "--threads",
        )),
        ok(case(
            "shard 0 of 3",
            "run spec.toml --shard 0/3",
            2,
            "--shard",
        )),
        ok(case(
            "shard 4 of 3",
            "run spec.toml --shard 4/3",
            2,
            "--shard",
        )),
        ok(case(
            "shard without slash",
            "run spec.toml --shard 2",
            2,
            "--shard",
        )),
        ok(case(
            "shard as text",
            "run spec.toml --shard a/b",
            2,
            "--shard",
        )),
        ok(case(
            "zero max runs",
            "run spec.toml --max-runs 0",
            2,
            "--max-runs",
        )),
        ok(case("unknown option", "run spec.toml --fast", 2, "--fast")),
        ok(case(
            "out is a file",
            "run spec.toml --out spec.toml",
            1,
            "spec.toml",
        )),
        ok(case(
            "coco log without bbob problems",
            "run spec.toml --coco-log logs",
            1,
            "bbob",
        )),
        case(
            "coco log into a file",
            "run b.toml --coco-log afile",
            1,
            "afile: cannot create the directory",
        )
        .with(
            "b.toml",
            spec_with(
                "function = \"sphere\"\ndim = 2",
                "suite = \"bbob\"\nfunction = 1\ndim = 2",
            ),
        )
        .with("afile", "x"),
        case("no spec argument", "run", 2, "<SPEC>"),
        case("unknown subcommand", "fly", 2, "fly"),
        case("no subcommand", "", 2, "Usage"),
        case("list with an argument", "list extra", 2, "extra"),
    ]
}

/// `fit`'s inputs: missing, malformed, degenerate or of the wrong kind.
fn fit_input_cases() -> Vec<Case> {
    let refused = |n, args: &str, m| case(n, leak(&format!("{args} --out out")), 1, m);
    vec![
        refused("input missing", "fit none.csv", "none.csv"),
        refused("unknown extension", "fit shape.bmp", "shape.bmp").with("shape.bmp", "BM"),
        refused("empty CSV", "fit e.csv", "e.csv").with("e.csv", ""),
        refused("CSV of one point", "fit e.csv", "e.csv: 1 point(s) found").with("e.csv", "1,2\n"),
        refused(
            "CSV with text",
            "fit e.csv",
            "e.csv:3: column 2 (y): expected a finite number, found \"abc\"",
        )
        .with("e.csv", "x,y\n1,2\n3,abc\n5,6\n"),
        refused("CSV with infinity", "fit e.csv", "e.csv:2: column 1 (x)")
            .with("e.csv", "x,y\ninf,2\n3,4\n5,6\n"),
        refused("CSV with three columns", "fit e.csv", "e.csv:2:")
            .with("e.csv", "x,y\n1,2,3\n3,4\n5,6\n"),
        refused(
            "CSV with a huge coordinate",
            "fit e.csv",
            "e.csv:3: column 1 (x): 1e300 is beyond ±1e15",
        )
        .with("e.csv", "x,y\n1,2\n1e300,4\n5,6\n"),
        refused(
            "CSV too small to resolve",
            "fit e.csv",
            "e.csv: the points span",
        )
        .with("e.csv", "1e-300,0\n0,1e-300\n-1e-300,0\n"),
        refused(
            "CSV of one repeated point",
            "fit e.csv",
            "e.csv: the points span 0e0 units",
        )
        .with("e.csv", "1,1\n1,1\n1,1\n"),
        refused("CSV not UTF-8", "fit e.csv", "e.csv")
            .with("e.csv", b"x,y\n1,2\n\xff\xfe,3\n".to_vec()),
        refused("PNG truncated", "fit h.png", "h.png")
            .with("h.png", real("data/outlines/horse.png")[..100].to_vec()),
        refused("PNG garbage", "fit h.png", "h.png").with("h.png", "not a png"),
        refused("blank PNG", "fit b.png", "b.png").with("b.png", blank_png()),
        refused("font missing", "fit font:none.ttf:S", "none.ttf"),
        refused(
            "font garbage",
            "fit font:f.ttf:S",
            "f.ttf: cannot read the font",
        )
        .with("f.ttf", "not a font"),
        refused(
            "glyph missing from the font",
            "fit font:f.ttf:\u{4e2d}",
            "the font has no glyph",
        )
        .with("f.ttf", real("data/outlines/DejaVuSans.ttf")),
        refused("glyph without outline", "fit font:f.ttf:\u{200b}", "f.ttf")
            .with("f.ttf", real("data/outlines/DejaVuSans.ttf")),
        refused("font input without glyph", "fit font:f.ttf", "font:")
            .with("f.ttf", real("data/outlines/DejaVuSans.ttf")),
        refused(
            "contour beyond the input's",
            "fit c.csv --contour 4",
            "contour 4 was asked for",
        )
        .with("c.csv", circle(40)),
        refused(
            "true breaks on a CSV",
            "fit c.csv --true-breaks",
            "--true-breaks: c.csv is not a glyph",
        )
        .with("c.csv", circle(40)),
    ]
}

/// `fit`'s options out of range, unknown or in conflict.
fn fit_option_cases() -> Vec<Case> {
    let c = |n, extra: &str, m| {
        case(n, leak(&format!("fit c.csv --out out {extra}")), 2, m).with("c.csv", circle(40))
    };
    let refused = |n, args: &str, m| case(n, leak(&format!("{args} --out out")), 1, m);
    vec![
        c(
            "zero segments",
            "--segments 0",
            "invalid value '0' for '--segments <SEGMENTS>'",
        ),
        refused(
            "unknown algorithm",
            "fit c.csv --algorithm sa",
            "--algorithm: unknown algorithm \"sa\"",
        )
        .with("c.csv", circle(40)),
        refused(
            "zero tolerance",
            "fit c.csv --tolerance 0",
            "--tolerance: expected a finite distance > 0",
        )
        .with("c.csv", circle(40)),
        refused(
            "out is a file",
            "fit c.csv",
            "out: cannot use as the output directory: out is a file",
        )
        .with("c.csv", circle(40))
        .with("out", "x"),
        c(
            "NaN corner angle",
            "--corner-angle NaN",
            "expected an angle in degrees in [0, 180)",
        ),
        c("negative corner angle", "--corner-angle -30", "found -30"),
        c("corner angle 180", "--corner-angle 180", "found 180"),
        c(
            "corner angle as text",
            "--corner-angle steep",
            "expected an angle in degrees, found \"steep\"",
        ),
        c("corner k zero", "--corner-k 0", "--corner-k"),
        c(
            "reparameterise 1000 rounds",
            "--reparameterise 1000",
            "--reparameterise",
        ),
        c("zero budget", "--budget 0", "--budget"),
        refused(
            "negative tolerance",
            "fit c.csv --tolerance -1",
            "--tolerance: expected a finite distance > 0 (data units), found -1",
        )
        .with("c.csv", circle(40)),
        c("unknown function", "--function quartic", "quartic"),
        c("unknown continuity", "--continuity g2", "g2"),
        c("unknown closing", "--closing tight", "tight"),
        c("unknown parameterisation", "--parameterisation arc", "arc"),
        c(
            "segments and tolerance",
            "--segments 4 --tolerance 1",
            "--tolerance",
        ),
        c("negative seed", "--seed -1", "unexpected argument '-1'"),
    ]
}

/// A 16×16 PNG with no shape on it (all white).
fn blank_png() -> Vec<u8> {
    let img = image::GrayImage::from_pixel(16, 16, image::Luma([255]));
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .unwrap();
    bytes
}

fn score_cases() -> Vec<Case> {
    let svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 20 20\"><path d=\"M 0 0 L 10 10 Z\"/></svg>";
    let s = |n, args: &str, m| case(n, leak(args), 1, m).with("c.csv", circle(40));
    vec![
        s("curves file missing", "score c.csv none.svg", "none.svg"),
        s("curves not SVG", "score c.csv p.svg", "p.svg").with("p.svg", "not xml <"),
        s("SVG without paths", "score c.csv p.svg", "p.svg")
            .with("p.svg", "<svg xmlns=\"http://www.w3.org/2000/svg\"></svg>"),
        s("SVG path with a bad command", "score c.csv p.svg", "p.svg")
            .with("p.svg", svg.replace("L 10 10", "X 10 10")),
        s("SVG path with a NaN", "score c.csv p.svg", "p.svg")
            .with("p.svg", svg.replace("L 10 10", "L NaN 10")),
        s("outline missing", "score none.csv p.svg", "none.csv").with("p.svg", svg),
        case("bad offset", "score c.csv p.svg --offset 1", 2, "--offset")
            .with("c.csv", circle(40))
            .with("p.svg", svg),
        s("out is a file", "score c.csv p.svg --out out", "out")
            .with("p.svg", svg)
            .with("out", "x"),
    ]
}

/// Run 0 of [`SPEC`] as runs.csv holds it.
const ROW: &str = "hs,hs,hms=5;hmcr=0.9;par=0.3;bw=0.01;bw_decay=none;bw_min=0.000001;bounds=clip,sphere,2,100,0,28524055920582096,395.05688038927065,395.05688038927065,100,,false\n";

fn report_cases() -> Vec<Case> {
    let runs = "algorithm,kind,params,problem,dim,budget,run,seed,best,error,evaluations,evaluations_to_target,success\n";
    vec![
        case("report of a missing directory", "report none", 1, "none"),
        case("report of a directory without runs", "report d", 1, "d/").with("d/notes.txt", "x"),
        case("report with a garbage runs.csv", "report d", 1, "d/").with("d/runs.csv", "garbage\n\u{0}"),
        case("report with a header-only runs.csv", "report d", 1, "d/").with("d/runs.csv", runs),
        case("report with alpha above one", "report d --alpha 2", 1, "--alpha: the significance level must lie strictly between 0 and 1, found 2").with("d/runs.csv", runs),
        case("report with alpha NaN", "report d --alpha NaN", 1, "found NaN").with("d/runs.csv", runs),
        case("report with a missing external file", "report d --external none.csv", 1, "none.csv").with("d/runs.csv", format!("{runs}{ROW}")),
        case("report with a duplicated row", "report d", 1, "d/runs.csv: run 0 of hs:hs[hms=5;hmcr=0.9;par=0.3;bw=0.01;bw_decay=none;bw_min=0.000001;bounds=clip] on sphere-2 appears twice").with("d/runs.csv", format!("{runs}{ROW}{ROW}")).with("d/spec.toml", SPEC),
        case("report with a missing row", "report d", 1, "d/runs.csv: 1 of 2 runs are missing (the first is run 1 of").with("d/runs.csv", format!("{runs}{ROW}")).with("d/spec.toml", SPEC),
        case("report with a foreign row", "report d", 1, "on rastrigin-2 is not a run of spec.toml").with("d/runs.csv", format!("{runs}{}", ROW.replace("sphere", "rastrigin"))).with("d/spec.toml", SPEC),
        case("report with a spec but no runs", "report d", 1, "d/").with("d/spec.toml", SPEC),
        case("report of an unfinished campaign", "report d", 1, "d: campaign unfinished (a journal.csv and no runs.csv): run `metabezier run SPEC --resume` to finish it").with("d/spec.toml", SPEC).with("d/journal.csv", "hs,hs,hms=5;hmcr=0.9;par=0.3;bw=0.01;bw_decay=none;bw_min=0.000001;bounds=clip,sphere,2,100,0,28524055920582096,395.05688038927065,395.05688038927065,100,,false,100:395.05688038927065,,2.3195e-5,none,1,,ok\n"),
        case("merge of nothing", "merge none", 1, "none"),
        case("merge of a directory without shards", "merge d", 1, "d").with("d/notes.txt", "x"),
        case("merge with a spec but no shards", "merge d --spec none.toml", 1, "d holds no shard directories").with("d/notes.txt", "x"),
        case("merge without arguments", "merge", 2, "<DIRS>"),
        case("slurm without tasks", "slurm spec.toml", 2, "--tasks").with("spec.toml", SPEC),
        case("slurm with zero tasks", "slurm spec.toml --tasks 0", 2, "--tasks").with("spec.toml", SPEC),
        case("slurm with more tasks than runs", "slurm spec.toml --tasks 1000", 1, "runs").with("spec.toml", SPEC),
        case("slurm with a bad time", "slurm spec.toml --tasks 2 --time 1h", 1, "--time \"1h\": expected a time limit per task as HH:MM:SS").with("spec.toml", SPEC),
        case("slurm with zero cpus", "slurm spec.toml --tasks 2 --cpus 0", 2, "--cpus").with("spec.toml", SPEC),
    ]
}

/// `implant`'s spec and volume: missing, malformed or with unknown values.
fn implant_spec_cases() -> Vec<Case> {
    let ct = "ct.inv3";
    let spec =
        |n, text: String, m| case(n, "implant spec.toml --out out", 1, m).with("spec.toml", text);
    vec![
        case("implant spec missing", "implant none.toml", 1, "none.toml"),
        spec("implant spec not TOML", "[implant\n".into(), "spec.toml:1:"),
        spec(
            "implant volume missing",
            implant_spec("none.inv3", ""),
            "none.inv3",
        ),
        spec("implant volume of garbage", implant_spec(ct, ""), "ct.inv3").with(ct, "garbage"),
        spec(
            "implant volume with a flipped bit",
            implant_spec(ct, ""),
            "ct.inv3: ",
        )
        .with(ct, flipped_ct()),
        spec("implant volume truncated", implant_spec(ct, ""), "ct.inv3").with(
            ct,
            real("data/ct0051/ct0051_z040-100.inv3")[..100_000].to_vec(),
        ),
        spec(
            "implant unknown key",
            implant_spec(ct, "colour = 1\n"),
            "defect.colour",
        )
        .with(ct, "x"),
        spec(
            "implant negative threshold NaN",
            implant_spec(ct, "").replace("threshold = 300", "threshold = nan"),
            "implant.threshold",
        )
        .with(ct, "x"),
        spec(
            "implant unknown function",
            implant_spec(ct, "").replace("\"rational-cubic\"", "\"spline\""),
            "implant.function",
        )
        .with(ct, "x"),
        spec(
            "implant unknown method",
            implant_spec(ct, "").replace("method = \"lm\"", "method = \"sa\""),
            "implant.method",
        )
        .with(ct, "x"),
    ]
}

/// `implant`'s slices, geometry, template and validation out of place.
fn implant_geometry_cases() -> Vec<Case> {
    let ct = "ct.inv3";
    let spec =
        |n, text: String, m| case(n, "implant spec.toml --out out", 1, m).with("spec.toml", text);
    vec![
        spec(
            "implant slices reversed",
            implant_spec(ct, "").replace("slices = [64, 66]", "slices = [70, 60]"),
            "defect.slices",
        )
        .with(ct, "x"),
        spec(
            "implant slices outside the volume",
            implant_spec(ct, "").replace("slices = [64, 66]", "slices = [150, 160]"),
            "150",
        )
        .with(ct, real("data/ct0051/ct0051_z040-100.inv3")),
        case(
            "implant of a DICOM file with short pixel data",
            "implant spec.toml --out out",
            1,
            "PixelData holds 32766 bytes, 128x128 at 16 bits allocated needs 32768",
        )
        .with(
            "spec.toml",
            implant_spec("d", "").replace("first_z = 40\n", ""),
        )
        .with("d/slice.dcm", short_dicom()),
        spec(
            "implant negative pixel",
            implant_spec(
                ct,
                "[[defect.end]]\nz = 65\na = [184, -86]\nb = [184, 86]\n",
            ),
            "defect.end[0].a: expected a pixel column ≥ 0",
        )
        .with(ct, real("data/ct0051/ct0051_z040-100.inv3")),
        spec(
            "implant A equal to B",
            implant_spec(ct, "[[defect.end]]\nz = 65\na = [184, 86]\nb = [184, 86]\n")
                .replace("ends = \"auto\"\n", ""),
            "slice z = 65: A and B are the same point",
        )
        .with(ct, real("data/ct0051/ct0051_z040-100.inv3")),
        spec(
            "implant midline outside the image",
            implant_spec(ct, "").replace("midline = \"auto\"", "midline = 400.0"),
            "does not cross the image",
        )
        .with(ct, real("data/ct0051/ct0051_z040-100.inv3")),
        spec(
            "implant one slice without a midline",
            implant_spec(ct, "")
                .replace("midline_slices = [86, 92]\n", "")
                .replace("slices = [64, 66]", "slices = [64, 64]"),
            "one-slice study needs `midline_slices`",
        )
        .with(ct, "x"),
        spec(
            "implant template of other slices",
            implant_spec(ct, "template = \"tpl.csv\"\n"),
            "tpl.csv:2:1",
        )
        .with(ct, real("data/ct0051/ct0051_z040-100.inv3"))
        .with("tpl.csv", "z,x_mm,y_mm\n69,80,180\n69,90,190\n"),
        spec(
            "implant validation slice outside the volume",
            implant_spec(
                ct,
                "[validation]\nslices = [88, 120]\npositions = [200]\nwidths = [20]\n",
            ),
            "validation slice z = 120 is outside the volume",
        )
        .with(ct, real("data/ct0051/ct0051_z040-100.inv3")),
        case(
            "implant out is a file",
            "implant spec.toml --out out",
            1,
            "out is a file",
        )
        .with("spec.toml", implant_spec(ct, ""))
        .with(ct, "x")
        .with("out", "x"),
    ]
}

/// Runs one case; `Err` says how it failed.
fn check(c: &Case) -> Result<(), String> {
    let tmp = tempfile::tempdir().unwrap();
    for (name, bytes) in &c.files {
        let path = tmp.path().join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, bytes).unwrap();
    }
    let before = files_under(tmp.path());
    let out = Command::new(env!("CARGO_BIN_EXE_metabezier"))
        .current_dir(tmp.path())
        .args(&c.args)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    let after = files_under(tmp.path());
    let mut problems = Vec::new();
    if out.status.code() != Some(c.code) {
        problems.push(format!(
            "exit code {:?}, expected {}",
            out.status.code(),
            c.code
        ));
    }
    if !stderr.contains(c.message) {
        problems.push(format!("standard error lacks {:?}", c.message));
    }
    if stderr.contains("panicked") {
        problems.push("a panic".into());
    }
    if after != before {
        let left: Vec<_> = after.difference(&before).collect();
        problems.push(format!("left behind {left:?}"));
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{} (`metabezier {}`): {}\n  stderr: {}",
            c.name,
            c.args.join(" "),
            problems.join("; "),
            stderr.trim_end().replace('\n', "\n          ")
        ))
    }
}

#[test]
fn every_bad_input_is_refused_with_its_message_and_leaves_nothing() {
    let cases: Vec<Case> = [
        spec_cases(),
        run_cases(),
        fit_input_cases(),
        fit_option_cases(),
        score_cases(),
        report_cases(),
        implant_spec_cases(),
        implant_geometry_cases(),
    ]
    .into_iter()
    .flatten()
    .collect();
    assert!(cases.len() >= 100, "{} cases", cases.len());
    println!("{} bad-input cases", cases.len());
    let failures: Vec<String> = cases.iter().filter_map(|c| check(c).err()).collect();
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}
