//! The implant refuses what it cannot build (issue 48): patches cut out of
//! CT 0051 in code at the skull base, the posterior midline and the vertex,
//! designed with automatic defect ends, are either built well against the
//! removed bone or refused with a message naming the slice and the check;
//! a template that wraps the wrong way round the head is `implausible`;
//! the delivered STL rings of the shipped design keep the kink target;
//! `--allow-partial` writes `implant.partial.stl`.

use std::path::{Path, PathBuf};
use std::process::Command;

use metabezier::ct::{read_inv3, write_inv3, Polyline, Volume, CT0051_PATH};
use metabezier::fit::LmSolver;
use metabezier::geometry::Point;
use metabezier::implant::plausibility::{measure_wall, Check};
use metabezier::implant::tables2d::{self, validation_csv};
use metabezier::implant::*;

fn shipped() -> ImplantSpec {
    ImplantSpec::load(Path::new("experiments/ch6_cranial.toml")).unwrap()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "metabezier-plausibility-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A patch cut out of CT 0051 with the shipped spec's options.
fn cut(v: &Volume, range: (usize, usize), position_deg: f64, width_mm: f64) -> Prepared3d {
    let cfg = shipped().defect_config;
    let (midline, _) = resolve_midline(v, &cfg).unwrap();
    let case = Case3d {
        range,
        position_deg,
        width_mm,
    };
    prepare_case_3d(v, &cfg, case, midline).unwrap()
}

/// The prepared case's design with every slice's ends detected.
fn auto_config(p: &Prepared3d) -> DefectConfig {
    let mut cfg = p.config.clone();
    for s in &mut cfg.slices {
        s.ends = Ends::Auto;
    }
    cfg
}

/// Writes the cut volume and a design spec with automatic ends for it.
fn cut_spec(dir: &Path, p: &Prepared3d, extra: &str) -> PathBuf {
    write_inv3(&dir.join("cut.inv3"), &p.cut, "cut").unwrap();
    let spec = format!(
        "[implant]\nvolume = \"cut.inv3\"\nfirst_z = 40\nthreshold = 300\nmidline = \"auto\"\nmidline_slices = [86, 92]\nmethod = \"lm\"\ntemplate_source = \"auto\"\nmax_thickness_mm = 25\nmax_thickness_step_mm = 1\nfill_ends = true\n\n[defect]\nslices = [{}, {}]\nends = \"auto\"\n{extra}",
        p.case.range.0, p.case.range.1
    );
    let path = dir.join("cut.toml");
    std::fs::write(&path, spec).unwrap();
    path
}

#[test]
fn cut_patches_with_automatic_ends_are_built_well_or_refused() {
    let v = read_inv3(Path::new(CT0051_PATH)).unwrap();
    // The skull base (the face's natural opening is detected as the
    // defect), the posterior midline (one slice's ends jump 108 mm), the
    // vertex (the top slice's ring is closed to the detection).
    for (range, pos, w) in [
        ((44, 52), 180.0, 40.0),
        ((86, 96), 270.0, 35.0),
        ((90, 100), 95.0, 45.0),
    ] {
        let p = cut(&v, range, pos, w);
        let dir = tmp(&format!("cut{pos}"));
        let spec = ImplantSpec::load(&cut_spec(&dir, &p, "")).unwrap();
        let out = dir.join("out");
        match run_implant(&spec, &out) {
            Ok(_) => {
                let imp =
                    reconstruct_defect(&p.cut, &auto_config(&p), &mut LmSolver::default()).unwrap();
                let m = score_3d(&p, &imp, 10.0).unwrap();
                assert!(
                    m.dice >= 0.85 && m.hd95 <= 3.0,
                    "{range:?} {pos}: built {m:?}"
                );
                assert!(out.join("implant.stl").exists());
            }
            Err(e) => {
                let msg = e.to_string();
                assert!(msg.contains("slice z = "), "{range:?} {pos}: {msg}");
                let named = Check::ALL.iter().any(|c| msg.contains(c.name()))
                    || msg.contains("no defect found");
                assert!(named, "{range:?} {pos}: {msg}");
                assert!(!out.exists(), "{range:?} {pos}: a refusal writes nothing");
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

#[test]
fn the_same_patches_with_their_ends_given_are_built_and_plausible() {
    let v = read_inv3(Path::new(CT0051_PATH)).unwrap();
    // The skull-base patch at 180° once got a template the long way round
    // the head on one slice (a seat moved across the ray at ±180°).
    for (range, pos, w) in [((44, 52), 180.0, 40.0), ((86, 96), 270.0, 35.0)] {
        let p = cut(&v, range, pos, w);
        let imp = reconstruct_from(
            &p.cut,
            &p.config,
            (p.midline, None),
            &p.contexts,
            WallKind::CurveFit,
            &mut LmSolver::default(),
        )
        .unwrap();
        for s in &imp.slices {
            assert!(s.accepted(), "{range:?} z = {}: {:?}", s.z, s.findings);
            assert!(s.checks.template_ratio < 1.3, "{:?}", s.checks);
        }
        let m = score_3d(&p, &imp, 10.0).unwrap();
        assert!(m.dice >= 0.85 && m.hd95 <= 3.0, "{range:?}: {m:?}");
    }
}

/// The outer loop's long way from the point nearest `a` to the one nearest
/// `b`: a template round the wrong side of the head.
fn long_way(outer: &Polyline, a: Point, b: Point) -> Polyline {
    let n = outer.points.len();
    let near = |q: Point| {
        (0..n)
            .min_by(|&i, &j| {
                outer.points[i]
                    .distance(q)
                    .total_cmp(&outer.points[j].distance(q))
            })
            .unwrap()
    };
    let (ia, ib) = (near(a), near(b));
    let forward: Vec<Point> = (0..n).map(|k| outer.points[(ia + k) % n]).collect();
    let k_b = (ib + n - ia) % n;
    let (fwd, back): (Vec<Point>, Vec<Point>) = (
        forward[..=k_b].to_vec(),
        std::iter::once(forward[0])
            .chain(forward[k_b..].iter().rev().copied())
            .collect(),
    );
    let len = |p: &[Point]| p.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
    Polyline::open(if len(&fwd) > len(&back) { fwd } else { back })
}

#[test]
fn a_template_that_wraps_the_wrong_way_makes_an_implausible_row() {
    let spec = shipped();
    let v = read_inv3(Path::new(CT0051_PATH)).unwrap();
    let (midline, _) = resolve_midline(&v, &spec.defect_config).unwrap();
    let case = Case {
        index: 88 - 40,
        position_deg: 210.0,
        width_mm: 40.0,
    };
    let p = prepare_case(&v, case, midline, 300).unwrap();
    let wrapped = long_way(&p.outer, p.a, p.b);
    assert!(wrapped.length() > 5.0 * p.a.distance(p.b));
    let options = WallOptions {
        mirror_tolerance_mm: 50.0,
        ..spec.defect_config.wall
    };
    let mut rows = Vec::new();
    for (kind, method) in [
        (WallKind::Template, "template"),
        (WallKind::CurveFit, "curve:lm"),
        (WallKind::Straight, "straight"),
    ] {
        let wall =
            reconstruct_case_with(&p, Some(&wrapped), kind, &options, &mut LmSolver::default())
                .unwrap();
        let checks = measure_wall(&wall, &p.head, kind);
        let findings = checks.findings(&options.checks);
        let names: Vec<Check> = findings.iter().map(|f| f.check).collect();
        // The straight bridge does not follow the template: it is plausible.
        assert_eq!(
            names.contains(&Check::TemplateWrap),
            kind != WallKind::Straight,
            "{kind:?}: {checks:?}"
        );
        rows.push(ValidationRow {
            case,
            z: 88,
            method: method.into(),
            run: 0,
            seed: 0,
            metrics: Ok(case_metrics(&p, &wall, 10.0).unwrap()),
            fit_error: wall.design.fit_error,
            join_deg: wall.join_angles_deg(),
            template_source: Some(wall.design.template_source),
            checks,
            findings,
            half_width_deg: p.half_width_deg,
            region: metabezier::implant::regions::Region::Back,
        });
    }
    let status: Vec<&str> = rows.iter().map(ValidationRow::status).collect();
    assert_eq!(status, ["implausible", "implausible", "ok"]);
    // The verdicts read them as failures of their method (Dice 0), and
    // again without them.
    let val = ValidationSpec {
        slices: vec![88],
        positions: vec![210.0],
        widths: vec![40.0],
        methods: vec![metabezier::reconstruction::Method::from_name("lm").unwrap()],
        runs: 1,
        margin_mm: 10.0,
        alpha: 0.05,
        ropes: metabezier::implant::units::ImplantRopes::default(),
    };
    let mut report = String::new();
    let verdicts = tables2d::validation_report(&mut report, &val, &rows, 1.5);
    assert!(
        report.contains("2 of the 3 rows are `implausible`"),
        "{report}"
    );
    let dice = |table: &str| {
        verdicts
            .iter()
            .find(|v| v.table == table && v.reference == "straight" && v.measure == "dice")
            .map(|v| (v.across.units, v.across.effect_size))
            .unwrap()
    };
    let (units, effect) = dice("validation-2d");
    assert!(
        units == 1 && effect < -0.5,
        "read as a failure: {units} {effect}"
    );
    assert_eq!(
        dice("validation-2d-plausible").0,
        0,
        "no plausible pair is left"
    );
    let rows: Vec<ValidationRow> = rows
        .into_iter()
        .filter(|r| r.method != "straight")
        .collect();
    let csv = String::from_utf8(validation_csv(&rows)).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let status = header.iter().position(|h| *h == "status").unwrap();
    let failed = header.iter().position(|h| *h == "checks_failed").unwrap();
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f[status], "implausible");
        assert!(f[failed].contains("template_wrap"), "{line}");
    }
}

#[test]
fn the_delivered_rings_of_the_shipped_design_keep_the_kink_target() {
    let spec = shipped();
    let v = read_inv3(Path::new(CT0051_PATH)).unwrap();
    let mut solver = spec.method.solver(spec.seed);
    let imp = reconstruct_defect(&v, &spec.defect_config, &mut *solver).unwrap();
    assert_eq!(imp.refused().count(), 0);
    for s in &imp.slices {
        let d = s.delivered.expect("an accepted slice is measured");
        let (a, b) = d.kinks_deg[1];
        assert!(
            a <= 10.0 && b <= 10.0,
            "z = {}: delivered 3 mm kinks {a:.2}°, {b:.2}°",
            s.z
        );
        assert!(s.bone_overlap_fraction <= 0.02, "z = {}", s.z);
        assert!(
            d.thickness.0.is_finite() || d.thickness.1.is_finite(),
            "z = {}",
            s.z
        );
    }
    let csv = String::from_utf8(tables::defect_csv(&imp)).unwrap();
    let header = csv.lines().next().unwrap();
    for col in [
        "kink_delivered_a_3mm_deg",
        "kink_delivered_b_1p5mm_deg",
        "thickness_delivered_a_mm",
        "template_dev_bare_mean_mm",
        "template_dev_bare_max_mm",
        "status",
        "check_width_jump_mm",
        "check_outside_head_mm",
        "check_template_ratio",
        "check_volume_ratio",
        "check_fit_rms_mm",
        "check_template_join_deg",
        "checks_failed",
    ] {
        assert!(
            header.split(',').any(|h| h == col),
            "{col} missing: {header}"
        );
    }
}

/// Runs the binary.
fn metabezier(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_metabezier"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn allow_partial_writes_the_accepted_slices_and_names_the_rest() {
    let v = read_inv3(Path::new(CT0051_PATH)).unwrap();
    let p = cut(&v, (86, 96), 270.0, 35.0);
    let dir = tmp("partial");
    let spec = cut_spec(&dir, &p, "");
    let (spec_s, out) = (spec.to_str().unwrap(), dir.join("out"));
    let out_s = out.to_str().unwrap();
    let refused = metabezier(&["implant", spec_s, "--out", out_s]);
    let err = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success());
    assert!(err.contains("slice z = 86 refused: width_jump"), "{err}");
    assert!(err.contains("--allow-partial"), "{err}");
    assert!(!out.exists());
    let partial = metabezier(&["implant", spec_s, "--out", out_s, "--allow-partial"]);
    assert!(
        partial.status.success(),
        "{}",
        String::from_utf8_lossy(&partial.stderr)
    );
    assert!(out.join(PARTIAL_STL).exists() && !out.join("implant.stl").exists());
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    let first = report.lines().next().unwrap();
    assert!(
        first.contains("lacks slices z = 86") && first.contains("width_jump"),
        "{first}"
    );
    let metrics = std::fs::read_to_string(out.join("metrics.csv")).unwrap();
    let header: Vec<&str> = metrics.lines().next().unwrap().split(',').collect();
    let (status, failed) = (
        header.iter().position(|h| *h == "status").unwrap(),
        header.iter().position(|h| *h == "checks_failed").unwrap(),
    );
    let rows: Vec<Vec<&str>> = metrics
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 11);
    for r in &rows {
        let (want, checks) = if r[0] == "86" {
            ("refused", "width_jump")
        } else {
            ("ok", "")
        };
        assert_eq!((r[status], r[failed]), (want, checks), "{r:?}");
    }
    // At the skull base most slices are refused: the detection failed as a
    // whole, and --allow-partial does not write the rest either.
    let base = cut(&v, (44, 52), 180.0, 40.0);
    let spec = cut_spec(&dir, &base, "");
    let out = dir.join("base");
    let refused = metabezier(&[
        "implant",
        spec.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--allow-partial",
    ]);
    let err = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success() && !out.exists(), "{err}");
    assert!(err.contains("max_refused_fraction"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_checks_section_sets_the_limits_and_names_bad_keys() {
    let v = read_inv3(Path::new(CT0051_PATH)).unwrap();
    let p = cut(&v, (86, 96), 270.0, 35.0);
    let dir = tmp("checks");
    // Loosened, the jump passes and the whole design is built.
    let spec = cut_spec(
        &dir,
        &p,
        "\n[checks]\nmax_width_jump_mm = 200\nmax_outside_head_mm = 10\n",
    );
    let s = ImplantSpec::load(&spec).unwrap();
    assert_eq!(s.defect_config.wall.checks.max_width_jump_mm, 200.0);
    run_implant(&s, &dir.join("out")).unwrap();
    assert!(dir.join("out/implant.stl").exists());
    for (extra, want) in [
        ("\n[checks]\nmax_jump = 3\n", "max_width_jump_mm"),
        ("\n[checks]\nmax_fit_rms_mm = -1\n", "checks.max_fit_rms_mm"),
        ("\n[checks]\nmax_refused_fraction = 2\n", "(0, 1]"),
    ] {
        let e = ImplantSpec::load(&cut_spec(&dir, &p, extra))
            .unwrap_err()
            .to_string();
        assert!(e.contains(want) && e.contains("cut.toml"), "{extra}: {e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
