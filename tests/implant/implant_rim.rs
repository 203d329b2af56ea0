//! The 3D templates of issue 56 on a synthetic skull: a vertex defect,
//! where an axial slice is oblique to the vault, built by the rim fill
//! (`template_source = "rim"`) through the whole pipeline, its templates
//! on the true outer surface and its implant scored against the removed
//! bone; the same defect by the 3D mirror.

use metabezier::ct::{MidLine, Spacing, Volume};
use metabezier::fit::LmSolver;
use metabezier::implant::surface_template::{self, SurfaceTemplates, Template3dError};
use metabezier::implant::*;

/// The sphere's centre (voxel mm) and outer and inner radii.
const C: [f64; 3] = [90.0, 90.0, 10.0];
const R_OUT: f64 = 75.0;
const R_IN: f64 = 68.0;

/// A spherical skull 7 mm thick (1000 HU) around brain (40 HU) in air,
/// 1 × 1 × 2 mm voxels, its vertex at z = 85 mm (slice 42.5).
fn skull() -> Volume {
    let (nx, ny, nz) = (180, 180, 45);
    let sp = Spacing {
        x: 1.0,
        y: 1.0,
        z: 2.0,
    };
    let mut data = vec![-1000i16; nx * ny * nz];
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let d = ((x as f64 - C[0]).powi(2)
                    + (y as f64 - C[1]).powi(2)
                    + (z as f64 * 2.0 - C[2]).powi(2))
                .sqrt();
                data[(z * ny + y) * nx + x] = if d <= R_IN {
                    40
                } else if d <= R_OUT {
                    1000
                } else {
                    -1000
                };
            }
        }
    }
    Volume::new(nx, ny, nz, sp, [0.0; 3], data).unwrap()
}

/// The 3D templates of a prepared case on `volume` with `cfg`.
fn surface_templates(
    volume: &Volume,
    cfg: &DefectConfig,
    contexts: &[SliceContext],
    midline: &MidLine,
) -> Result<Option<SurfaceTemplates>, Template3dError> {
    let slices: Vec<_> = contexts.iter().map(SliceContext::defect_slice).collect();
    surface_template::surface_templates(
        volume,
        (&cfg.wall, cfg.threshold, cfg.plane),
        &slices,
        midline,
    )
}

fn config(template: TemplateChoice) -> DefectConfig {
    DefectConfig {
        first_z: 0,
        slices: Vec::new(),
        midline: MidlineSpec::Given(MidLine::vertical(C[0])),
        max_tilt_deg: 20.0,
        threshold: 300,
        wall: WallOptions {
            template,
            max_thickness_mm: 25.0,
            ..WallOptions::default()
        },
        smoothing: Smoothing::default(),
        templates: None,
        plane: None,
        ring_points: 160,
        thickness_mm: None,
    }
}

/// A 30 mm patch on slices 30–38 (z = 60–76 mm, 10–25° below the
/// vertex's tangent plane), 40° from the +x axis.
fn vertex_case(v: &Volume, template: TemplateChoice) -> Prepared3d {
    let case = Case3d {
        range: (30, 38),
        position_deg: 40.0,
        width_mm: 30.0,
    };
    prepare_case_3d(v, &config(template), case, MidLine::vertical(C[0])).unwrap()
}

#[test]
fn a_vertex_defect_is_built_by_the_rim_fill() {
    let v = skull();
    let p = vertex_case(&v, TemplateChoice::Rim);
    // The templates lie on the true outer surface.
    let t = surface_templates(&p.cut, &p.config, &p.contexts, &p.midline)
        .unwrap()
        .unwrap();
    assert!(t.rim_rms_mm.unwrap() < 0.5, "rim rms {:?}", t.rim_rms_mm);
    let mut worst = 0.0f64;
    for (ctx, (z, tpl)) in p.contexts.iter().zip(&t.slices) {
        assert_eq!(ctx.z, *z);
        assert_eq!(tpl.kind, TemplateSource::Rim);
        let (a, b) = ctx.ends;
        let (ta, tb) = (
            (a.y - ctx.centre.y).atan2(a.x - ctx.centre.x),
            (b.y - ctx.centre.y).atan2(b.x - ctx.centre.x),
        );
        for k in 0..=20 {
            let th = ta + (tb - ta) * k as f64 / 20.0;
            let q = tpl.at(th).unwrap();
            let zmm = ctx.k as f64 * 2.0;
            let r = ((q.x - C[0]).powi(2) + (q.y - C[1]).powi(2) + (zmm - C[2]).powi(2)).sqrt();
            worst = worst.max((r - R_OUT).abs());
        }
    }
    assert!(worst < 0.5, "worst template error {worst} mm");
    // The whole pipeline builds it from the rim fill, close to the removed
    // bone.
    let m = evaluate_3d(&p, WallKind::CurveFit, 10.0, &mut LmSolver::default()).unwrap();
    eprintln!(
        "rim: template worst {worst:.3} mm, rim rms {:.3} mm, Dice {:.3}, HD95 {:.2} mm",
        t.rim_rms_mm.unwrap(),
        m.dice,
        m.hd95
    );
    assert_eq!(m.template_source_name(), "rim");
    assert!(m.refused.is_empty(), "{:?}", m.refused);
    assert!(m.dice > 0.85, "Dice {}", m.dice);
    assert!(m.hd95 < 2.0, "HD95 {}", m.hd95);
}

#[test]
fn the_3d_mirror_builds_the_same_defect_and_the_plane_is_the_sphere_s() {
    let v = skull();
    let p = vertex_case(&v, TemplateChoice::Mirror3d);
    let t = surface_templates(&p.cut, &p.config, &p.contexts, &p.midline)
        .unwrap()
        .unwrap();
    let plane = t.plane.unwrap();
    // A sphere is symmetric about every plane through its centre; the
    // search starts from x = 90 and must stay there.
    assert!(plane.side(C).abs() < 0.5, "offset {}", plane.side(C));
    let m = evaluate_3d(&p, WallKind::CurveFit, 10.0, &mut LmSolver::default()).unwrap();
    eprintln!(
        "mirror3d: offset {:.3} mm, Dice {:.3}, HD95 {:.2} mm",
        plane.side(C),
        m.dice,
        m.hd95
    );
    assert_eq!(m.template_source_name(), "mirror3d");
    assert!(m.dice > 0.85, "Dice {}", m.dice);
}

#[test]
fn a_3d_template_on_one_slice_is_refused_with_the_choices() {
    let v = skull();
    let p = vertex_case(&v, TemplateChoice::Rim);
    let one = p.cut.sub_z(30, 31);
    let err = surface_templates(&one, &p.config, &p.contexts, &p.midline).unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("\"rim\"") && text.contains("\"mirror\""),
        "{text}"
    );
    // `auto3d` on one slice chooses as `auto` does: no 3D template.
    let mut cfg = p.config.clone();
    cfg.wall.template = TemplateChoice::Auto3d;
    assert!(surface_templates(&one, &cfg, &p.contexts, &p.midline)
        .unwrap()
        .is_none());
}

#[test]
fn the_spec_reads_the_3d_choices_and_names_them_in_its_error() {
    let spec = |choice: &str| {
        format!(
            "[implant]\nvolume = \"../data/ct0051/ct0051_z040-100.inv3\"\nfirst_z = 40\nmidline = 124.0\ntemplate_source = \"{choice}\"\n\n[defect]\nslices = [64, 64]\nends = \"auto\"\n"
        )
    };
    let path = std::path::Path::new("experiments/probe.toml");
    for (name, choice) in [
        ("mirror3d", TemplateChoice::Mirror3d),
        ("rim", TemplateChoice::Rim),
        ("auto3d", TemplateChoice::Auto3d),
    ] {
        let s = ImplantSpec::parse(path, &spec(name)).unwrap();
        assert_eq!(s.defect_config.wall.template, choice);
    }
    let err = ImplantSpec::parse(path, &spec("rimm"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("implant.template_source"), "{err}");
    assert!(err.contains("probe.toml:5:"), "{err}");
    for name in ["\"mirror3d\"", "\"rim\"", "\"auto3d\"", "\"auto\""] {
        assert!(err.contains(name), "{err}");
    }
}
