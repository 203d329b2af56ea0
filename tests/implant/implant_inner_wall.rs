//! The inner wall (issue 27, the 3D validation level): where a slice cuts
//! the vault obliquely (ProMED CT 0051 near the vertex, z = 90–96) the
//! bone is up to ~23 mm thick in plane and thickest mid-gap, so an inner
//! wall at the ends' thickness, capped at 15 mm and held to 0.5 mm per
//! slice, leaves much of the removed bone uncovered. The shipped spec's
//! inner wall (a wide cap, a 1 mm step, the ends filled up to the bone's
//! cut face) covers it; the other side's thickness profile is an option.

use std::path::Path;

use metabezier::ct::{read_inv3, Volume, CT0051_FIRST_Z, CT0051_PATH};
use metabezier::fit::LmSolver;
use metabezier::implant::*;

fn volume() -> Volume {
    read_inv3(Path::new(CT0051_PATH)).unwrap()
}

/// The defaults of a wall with the shipped spec's validation setup: the
/// midline estimated on z = 86–92, no defect slices.
fn config(wall: WallOptions, smoothing: Smoothing) -> DefectConfig {
    DefectConfig {
        first_z: CT0051_FIRST_Z,
        slices: Vec::new(),
        midline: MidlineSpec::Auto((86..=92).collect()),
        max_tilt_deg: 20.0,
        threshold: 300,
        wall,
        smoothing,
        templates: None,
        plane: None,
        ring_points: 120,
        thickness_mm: None,
    }
}

/// The shipped spec's inner wall (experiments/ch6_cranial.toml).
fn shipped() -> (WallOptions, Smoothing) {
    let wall = WallOptions {
        max_thickness_mm: 25.0,
        fill_ends: true,
        ..WallOptions::default()
    };
    let smoothing = Smoothing {
        max_thickness_step_mm: 1.0,
        ..Smoothing::default()
    };
    (wall, smoothing)
}

#[test]
fn the_inner_wall_covers_the_oblique_vault_and_never_enters_bone() {
    let v = volume();
    let case = Case3d {
        range: (90, 96),
        position_deg: 150.0,
        width_mm: 30.0,
    };
    let base = config(WallOptions::default(), Smoothing::default());
    let (midline, _) = resolve_midline(&v, &base).unwrap();
    let (wall, smoothing) = shipped();
    let run = |cfg: &DefectConfig, kind: WallKind| {
        let p = prepare_case_3d(&v, cfg, case, midline).unwrap();
        let m = evaluate_3d(&p, kind, 10.0, &mut LmSolver::default()).unwrap();
        let imp = reconstruct_from(
            &p.cut,
            &p.config,
            (p.midline, None),
            &p.contexts,
            kind,
            &mut LmSolver::default(),
        )
        .unwrap();
        (m, imp, p)
    };
    for kind in [WallKind::CurveFit, WallKind::Straight] {
        let (old, _, _) = run(&base, kind);
        let (new, imp, p) = run(&config(wall, smoothing), kind);
        // Measured (LM): curve Dice 0.817 -> 0.867, HD95 5.01 -> 3.03 mm;
        // straight 0.825 -> 0.861, 3.69 -> 2.02 mm.
        assert!(new.dice >= old.dice + 0.03, "{kind:?}: {old:?} -> {new:?}");
        assert!(new.hd95 < old.hd95 - 1.0, "{kind:?}: {old:?} -> {new:?}");
        assert!(new.dice > 0.86 && new.hd95 <= 3.5, "{kind:?}: {new:?}");
        // Filling the ends does not put the implant into intact bone: the
        // clipped sections hold no bone pixel, and the rings lofted from
        // them (resampled to `ring_points`) rasterise onto at most 1 % of
        // bone, as on the real defect.
        for s in &imp.slices {
            let k = s.z - CT0051_FIRST_Z;
            let slice = p.cut.slice(k);
            let on_bone = imp
                .mask
                .slice(k)
                .pixels()
                .iter()
                .filter(|&&(r, c)| slice.get(r, c) >= 300)
                .count();
            let all = imp.mask.slice(k).count();
            assert!(100 * on_bone <= all, "z {}: {on_bone} of {all}", s.z);
        }
    }
    // The mirrored profile, where asked for and the template is the
    // mirror, keeps the seats' thickness at A' and B', and on this patch,
    // thickest mid-gap, covers more of it (measured: Dice 0.882 against
    // the linear profile's 0.867).
    let mirrored = WallOptions {
        thickness_profile: ThicknessProfile::Mirror,
        ..wall
    };
    let (linear, _, _) = run(&config(wall, smoothing), WallKind::CurveFit);
    let (m, imp, _) = run(&config(mirrored, smoothing), WallKind::CurveFit);
    assert!(m.dice > linear.dice + 0.005, "{linear:?} -> {m:?}");
    for s in &imp.slices {
        let m = s
            .wall
            .design
            .mirror_thickness
            .as_ref()
            .expect("mirror template");
        let (ta, tb) = (m.excess(m.th_a), m.excess(m.th_a + m.span));
        assert!(ta.abs() < 1e-9 && tb.abs() < 1e-9, "z {}", s.z);
        assert!(m.values.iter().all(|&t| t > 0.0 && t <= 25.0));
    }
    let (_, imp, _) = run(&config(wall, smoothing), WallKind::CurveFit);
    assert!(imp
        .slices
        .iter()
        .all(|s| s.wall.design.mirror_thickness.is_none()));
}

#[test]
fn the_linear_profile_and_no_fill_are_the_defaults_and_spec_errors_name_the_choices() {
    let w = WallOptions::default();
    assert_eq!(w.thickness_profile, ThicknessProfile::Linear);
    assert!(!w.fill_ends);
    let p = Path::new("x.toml");
    let spec = |extra: &str| {
        format!("[implant]\nvolume = \"v.inv3\"\n{extra}\n[defect]\nslices = [1, 3]\n")
    };
    let ok =
        ImplantSpec::parse(p, &spec("thickness_profile = \"mirror\"\nfill_ends = true")).unwrap();
    assert_eq!(
        ok.defect_config.wall.thickness_profile,
        ThicknessProfile::Mirror
    );
    assert!(ok.defect_config.wall.fill_ends);
    let e = ImplantSpec::parse(p, &spec("thickness_profile = \"thick\"")).unwrap_err();
    let m = e.to_string();
    assert!(
        e.field == "implant.thickness_profile" && m.contains("x.toml:3:21"),
        "{m}"
    );
    assert!(m.contains("\"linear\", \"mirror\""), "{m}");
    let e = ImplantSpec::parse(p, &spec("fill_ends = \"yes\"")).unwrap_err();
    assert!(
        e.field == "implant.fill_ends" && e.to_string().contains("expected true or false"),
        "{e}"
    );
    // The shipped spec asks for the inner wall of this file's test.
    let shipped_spec = ImplantSpec::load(Path::new("experiments/ch6_cranial.toml")).unwrap();
    let (wall, smoothing) = shipped();
    let w = &shipped_spec.defect_config.wall;
    assert_eq!(
        (w.max_thickness_mm, w.thickness_profile, w.fill_ends),
        (
            wall.max_thickness_mm,
            wall.thickness_profile,
            wall.fill_ends
        )
    );
    assert_eq!(
        shipped_spec.defect_config.smoothing.max_thickness_step_mm,
        smoothing.max_thickness_step_mm
    );
}
