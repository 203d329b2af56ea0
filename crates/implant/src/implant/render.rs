//! The chapter-6 pictures: per-slice overlays a clinician can read (the
//! whole slice and a zoom on the defect, anterior at the top, a colour key
//! and 10 mm scale bars) and the labelled 3D preview of the implant on the
//! skull (see [`super::run`] for the driver that writes them, and
//! [`super::tables`] for the CSV tables and the report).

use super::pipeline::{DefectConfig, Implant, ImplantError, SliceResult};
use super::wall::envelope_radius;
use crate::ct::{
    bone_loops, bone_mask_slice, loft, mesh_view, slice_view_rgb, Anatomy, Canvas, Frame, Mesh,
    MeshView, MidLine, Overlay, PatientDirection, Polyline, SliceView, View, Volume, Window,
};
use crate::geometry::Point;

/// Colours of the overlays (RGB), with their legend labels.
const OUTER_TABLE: [u8; 3] = [40, 200, 40];
const INNER_TABLE: [u8; 3] = [60, 140, 255];
const TEMPLATE: [u8; 3] = [255, 0, 255];
const OUTER_WALL: [u8; 3] = [255, 40, 40];
const INNER_WALL: [u8; 3] = [255, 170, 0];
const SECTION: [u8; 3] = [255, 255, 80];
const MIDLINE: [u8; 3] = [230, 230, 230];
const OVERLAP: [u8; 3] = [255, 120, 200];
const ENDS: [u8; 3] = [255, 255, 0];
const MIRRORED: [u8; 3] = [0, 255, 255];

/// How the overlays and the preview are oriented, derived in one place
/// from the volume's [`Anatomy`] ([`Frame::anatomy`]: ImageOrientationPatient
/// for DICOM, the declared convention for `.inv3`): the slice is drawn with
/// `+y` up or down so that anterior (or, on a coronal slice, superior) is
/// at the top, `+x` to the right; every edge label names the patient
/// direction that edge faces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Orientation {
    /// Where the voxel axes point.
    pub anatomy: Anatomy,
    /// Whether `+y` is drawn upwards.
    pub y_up: bool,
}

impl Orientation {
    /// The orientation of a frame (errors when its axes are ambiguous).
    pub fn of(frame: &Frame) -> Result<Orientation, ImplantError> {
        let anatomy = frame.anatomy()?;
        let y_up = matches!(
            anatomy.y,
            PatientDirection::Anterior | PatientDirection::Superior
        );
        Ok(Orientation { anatomy, y_up })
    }

    /// The patient directions at the top, bottom, left and right edges of
    /// a slice picture.
    pub fn edges(&self) -> [PatientDirection; 4] {
        let y = self.anatomy.y;
        let (top, bottom) = if self.y_up {
            (y, y.opposite())
        } else {
            (y.opposite(), y)
        };
        let x = self.anatomy.x;
        [top, bottom, x.opposite(), x]
    }

    /// The view of the millimetre box `[lo, hi]` in `size × size` pixels,
    /// flipped and labelled by this orientation.
    pub fn slice_view(&self, lo: Point, hi: Point, size: u32) -> SliceView {
        let [top, bottom, left, right] = self.edges().map(|d| d.label().to_string());
        SliceView {
            min: lo,
            max: hi,
            width: size,
            height: size,
            y_up: self.y_up,
            top_label: top,
            bottom_label: bottom,
            left_label: left,
            right_label: right,
        }
    }

    /// The sign of `+y` along the anterior direction (1: `+y` anterior,
    /// −1: posterior; 0 when `+y` is not antero-posterior).
    pub fn anterior_sign(&self) -> f64 {
        match self.anatomy.y {
            PatientDirection::Anterior => 1.0,
            PatientDirection::Posterior => -1.0,
            _ => 0.0,
        }
    }

    /// The sign of `+z` along the superior direction (1 or −1; 1 when `+z`
    /// is not supero-inferior).
    pub fn superior_sign(&self) -> f64 {
        if self.anatomy.z == PatientDirection::Inferior {
            -1.0
        } else {
            1.0
        }
    }
}

/// The colour key of the overlays.
fn legend() -> Vec<(String, [u8; 3])> {
    [
        ("outer table", OUTER_TABLE),
        ("inner table", INNER_TABLE),
        ("template", TEMPLATE),
        ("outer wall (fit)", OUTER_WALL),
        ("inner wall (offset)", INNER_WALL),
        ("implant section", SECTION),
        ("midline", MIDLINE),
        ("implant on bone", OVERLAP),
        ("A′, B′", ENDS),
        ("C, D (mirrored)", MIRRORED),
    ]
    .iter()
    .map(|(l, c)| (l.to_string(), *c))
    .collect()
}

/// The midline as a segment across the box `[lo, hi]` (mm).
fn midline_segment(line: &MidLine, lo: Point, hi: Point) -> (Point, Point) {
    (line.at_y(lo.y), line.at_y(hi.y))
}

/// The overlay of one slice: tables, template, walls, section, ends,
/// midline and the implant's pixels on bone.
fn slice_overlay(s: &SliceResult, on_bone: Vec<(usize, usize)>, lo: Point, hi: Point) -> Overlay {
    let w = &s.wall;
    let d = &w.design;
    let (m0, m1) = midline_segment(&s.midline, lo, hi);
    Overlay {
        polylines: vec![
            (s.outer.clone(), OUTER_TABLE),
            (s.inner.clone(), INNER_TABLE),
            (d.template.clone(), TEMPLATE),
            (w.inner.clone(), INNER_WALL),
            (w.section.clone(), SECTION),
            (d.outer.clone(), OUTER_WALL),
        ],
        points: vec![
            ("A′".into(), d.a, ENDS),
            ("B′".into(), d.b, ENDS),
            ("C".into(), d.c, MIRRORED),
            ("D".into(), d.d, MIRRORED),
        ],
        lines: vec![(m0, m1, MIDLINE)],
        pixels: on_bone.into_iter().map(|p| (p, OVERLAP)).collect(),
        ..Overlay::default()
    }
}

/// The zoom box around a slice's section: square, centred on it, at least
/// 30 mm wide and 12 mm wider than the section.
fn zoom_box(s: &SliceResult) -> (Point, Point) {
    let (lo, hi) = s
        .wall
        .raw_section
        .bbox()
        .unwrap_or((s.wall.design.a, s.wall.design.b));
    let c = (lo + hi) * 0.5;
    let half = 0.5 * ((hi.x - lo.x).max(hi.y - lo.y) + 12.0).max(30.0);
    (c - Point::new(half, half), c + Point::new(half, half))
}

/// The picture of one reconstructed slice: a title with its figures, the
/// whole slice (left, the zoom box marked) and a zoom on the defect
/// (right), anterior at the top, each with a 10 mm scale bar, and the
/// colour key below.
pub fn overlay_png(
    volume: &Volume,
    cfg: &DefectConfig,
    implant: &Implant,
    s: &SliceResult,
) -> Result<Vec<u8>, ImplantError> {
    let k = s.z - cfg.first_z;
    let slice = volume.slice(k);
    let on_bone: Vec<(usize, usize)> = implant
        .mask
        .slice(k)
        .pixels()
        .into_iter()
        .filter(|&(r, c)| slice.get(r, c) >= cfg.threshold)
        .collect();
    let orientation = Orientation::of(&implant.frame)?;
    let full_lo = Point::new(-0.5 * slice.sx, -0.5 * slice.sy);
    let full_hi = Point::new(
        (slice.nx as f64 - 0.5) * slice.sx,
        (slice.ny as f64 - 0.5) * slice.sy,
    );
    let (zlo, zhi) = zoom_box(s);
    let panel = 512u32;
    let view = |lo: Point, hi: Point| orientation.slice_view(lo, hi, panel);
    let (full, zoom) = (view(full_lo, full_hi), view(zlo, zhi));
    let left = slice_view_rgb(
        &slice,
        Window::BONE,
        &full,
        &slice_overlay(s, on_bone.clone(), full_lo, full_hi),
    )?;
    let right = slice_view_rgb(
        &slice,
        Window::BONE,
        &zoom,
        &slice_overlay(s, on_bone.clone(), zlo, zhi),
    )?;
    let (x0, y0, gap) = (12u32, 40u32, 12u32);
    let mut canvas = Canvas::new(2 * panel + 2 * x0 + gap, y0 + panel + 110, [255, 255, 255]);
    canvas.blit(&left, panel, panel, x0, y0);
    canvas.blit(&right, panel, panel, x0 + panel + gap, y0);
    let (a, b) = (full.to_px(zlo), full.to_px(zhi));
    let (ax, ay, bx, by) = (
        a.0 as i32 + x0 as i32,
        a.1 as i32 + y0 as i32,
        b.0 as i32 + x0 as i32,
        b.1 as i32 + y0 as i32,
    );
    canvas.rect(
        (ax.min(bx), ay.min(by)),
        (ax.max(bx), ay.max(by)),
        [255, 255, 0],
        false,
    )?;
    canvas.text(
        &overlay_title(s, on_bone.len()),
        x0 as i32,
        10,
        17,
        [0, 0, 0],
    )?;
    canvas.legend(&legend(), (x0 as i32, (y0 + panel + 14) as i32), 5, 210)?;
    canvas.text(
        "left: whole slice (yellow box = zoom); right: zoom on the defect; bone window W 2000 / L 500",
        x0 as i32,
        (y0 + panel + 64) as i32,
        14,
        [60, 60, 60],
    )?;
    Ok(canvas.png()?)
}

/// The title of a slice picture: slice, width, thickness, kinks (at each
/// end the worse of design and delivery, as the report judges them),
/// overlap.
fn overlay_title(s: &SliceResult, on_bone: usize) -> String {
    let d = &s.wall.design;
    let (ka, kb) = s.judged_kinks_deg();
    format!(
        "z = {}   |A′B′| = {:.1} mm   thickness {:.1} / {:.1} mm   kinks {:.1}° / {:.1}°   implant on bone {} of {} px ({:.1} %)   midline tilt {:.2}°",
        s.z,
        d.width(),
        s.wall.thickness.0,
        s.wall.thickness.1,
        ka,
        kb,
        on_bone,
        s.implant_pixels,
        100.0 * s.bone_overlap_fraction,
        s.midline.tilt_deg()
    )
}

/// Whether the ray at angle `t` on slice `k` lies in one of the `recess`
/// wedges (volume index, first and last angle in radians; the wedge is the
/// shorter way round between them).
fn in_recess(recess: &[(usize, f64, f64)], k: usize, t: f64) -> bool {
    let tau = std::f64::consts::TAU;
    recess.iter().any(|&(kk, t1, t2)| {
        let w = (t2 - t1).rem_euclid(tau);
        let (lo, w) = if w > std::f64::consts::PI {
            (t2, tau - w)
        } else {
            (t1, w)
        };
        kk == k && (t - lo).rem_euclid(tau) <= w
    })
}

/// The outer envelope of `outer` over 180 rays about `o` on slice `k`
/// (rays that miss keep the previous radius; rays in a `recess` wedge are
/// pulled in to 80 %).
fn envelope_ring(outer: &Polyline, o: Point, k: usize, recess: &[(usize, f64, f64)]) -> Vec<Point> {
    let mut last = None;
    let mut ring = Vec::new();
    for j in 0..180 {
        let t = j as f64 * std::f64::consts::TAU / 180.0;
        let rr = envelope_radius(&[outer], o, t).or(last);
        if let Some(mut rr) = rr {
            last = Some(rr);
            if in_recess(recess, k, t) {
                rr *= 0.8;
            }
            ring.push(o + Point::new(t.cos(), t.sin()) * rr);
        }
    }
    ring
}

/// A closed proxy of the skull surface: on every slice from `z0` to `z1`
/// (volume indices), the outer envelope over 180 rays about the midline
/// point at the contour's mean height (rays that miss keep the previous
/// radius), lofted. On the slices listed in `recess` (volume index, first
/// and last angle in radians), the rays between the two angles are pulled
/// in to 80 % so that an implant there shows in the preview.
pub fn skull_proxy(
    volume: &Volume,
    threshold: i16,
    midline: &MidLine,
    z0: usize,
    z1: usize,
    recess: &[(usize, f64, f64)],
) -> Result<Mesh, ImplantError> {
    let mut sections = Vec::new();
    let mut zs = Vec::new();
    for k in z0..=z1.min(volume.nz - 1) {
        let slice = volume.slice(k);
        let Ok(mask) = bone_mask_slice(&slice, threshold) else {
            continue;
        };
        let loops = bone_loops(&slice, &mask, threshold);
        let Some(outer) = loops.iter().find(|l| l.signed_area() > 0.0) else {
            continue;
        };
        let o = midline.at_y(outer.vertex_mean().y);
        let ring = envelope_ring(outer, o, k, recess);
        if ring.len() >= 3 {
            sections.push(Polyline::closed(ring));
            zs.push(k as f64 * volume.spacing.z);
        }
    }
    if sections.len() == 1 {
        // A one-slice study: the proxy is a slab one slice thick.
        let (z, h) = (zs[0], 0.5 * volume.spacing.z);
        sections.push(sections[0].clone());
        zs = vec![z - h, z + h];
    }
    Ok(loft(&sections, &zs, 180)?)
}

/// Per implant slice, its volume index and the polar angles of A′ and B′
/// about the slice's polar centre: where the skull proxy is recessed.
fn implant_recess(cfg: &DefectConfig, implant: &Implant) -> Vec<(usize, f64, f64)> {
    implant
        .slices
        .iter()
        .map(|s| {
            let k = s.z - cfg.first_z;
            let o = s.wall.design.centre;
            let ang = |p: Point| (p.y - o.y).atan2(p.x - o.x);
            (k, ang(s.wall.design.a), ang(s.wall.design.b))
        })
        .collect()
}

/// Three shaded orthographic views of the implant (red) on the
/// skull-surface proxy (grey), each labelled: from the defect's side, from
/// the front and from above (anterior up), in voxel millimetres.
pub fn preview_png(
    volume: &Volume,
    cfg: &DefectConfig,
    implant: &Implant,
) -> Result<Vec<u8>, ImplantError> {
    let k0 = implant.slices.first().map_or(0, |s| s.z - cfg.first_z);
    let k1 = implant.slices.last().map_or(0, |s| s.z - cfg.first_z);
    let skull = skull_proxy(
        volume,
        cfg.threshold,
        &implant.midline,
        k0.saturating_sub(8),
        k1 + 8,
        &implant_recess(cfg, implant),
    )?;
    // The defect's side of the midline, and where the face is.
    let side = implant
        .slices
        .first()
        .map_or(-1.0, |s| s.midline.side(s.wall.design.a).signum());
    let orientation = Orientation::of(&implant.frame)?;
    let front = if orientation.anterior_sign() < 0.0 {
        -1.0
    } else {
        1.0
    };
    let sup = orientation.superior_sign();
    let sides = if side < 0.0 { "−x" } else { "+x" };
    let views = [
        (
            format!("from the defect's side ({sides}), turned 30° to the face"),
            [-side, -0.6 * front, 0.0],
            [0.0, 0.0, sup],
        ),
        (
            "from the front (face)".to_string(),
            [0.0, -front, 0.0],
            [0.0, 0.0, sup],
        ),
        (
            "from above (anterior up)".to_string(),
            [0.0, 0.0, -sup],
            [0.0, front, 0.0],
        ),
    ];
    let size = 360u32;
    let mut canvas = Canvas::new(3 * size, size + 34, [255, 255, 255]);
    for (i, (label, direction, up)) in views.iter().enumerate() {
        let view = mesh_view(
            &[(&skull, [200, 200, 200]), (&implant.mesh, [230, 40, 40])],
            View {
                direction: *direction,
                up: *up,
                mirror: !orientation.anatomy.right_handed(),
            },
            size,
        );
        let x0 = i as i32 * size as i32;
        canvas.blit(&view.rgb, size, size, x0 as u32, 34);
        canvas.text(label, x0 + 8, 8, 15, [0, 0, 0])?;
        // A scale bar at the bottom left.
        if let Some(mm) = scale_bar_mm(view.mm_per_px, size) {
            let px = (f64::from(mm) / view.mm_per_px).round() as i32;
            let y = 34 + size as i32 - 14;
            canvas.line((x0 + 12, y), (x0 + 12 + px, y), [0, 0, 0], 3)?;
            canvas.text(&format!("{mm} mm"), x0 + 12, y - 20, 13, [0, 0, 0])?;
        }
        // The patient axes at the bottom right.
        let origin = (x0 + size as i32 - 46, 34 + size as i32 - 46);
        for (name, tip, colour) in triad(&view, &orientation.anatomy, 30.0) {
            let end = (
                origin.0 + tip[0].round() as i32,
                origin.1 + tip[1].round() as i32,
            );
            canvas.line(origin, end, colour, 2)?;
            canvas.text(name, end.0 - 4, end.1 - 8, 12, colour)?;
        }
    }
    Ok(canvas.png()?)
}

/// The file stem of the figure of Dice and HD95 per method and width
/// (`validation_dice_hd95.png` and `.svg`).
pub const VALIDATION_FIGURE: &str = "validation_dice_hd95";

/// One successful reconstruction of a validation case: (method, width in
/// mm, Dice, HD95 in mm).
pub type Scored<'a> = (&'a str, f64, f64, f64);

/// The figure that answers chapter 6's question, as files and as the
/// section of `report.md` that shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct ValidationFigure {
    /// `validation_dice_hd95.png`.
    pub png: Vec<u8>,
    /// `validation_dice_hd95.svg` (inlined by `report.html`).
    pub svg: Vec<u8>,
    /// The section of `report.md` that shows the figure with its caption.
    pub section: String,
}

/// The style of a reconstruction method in the figures: a curve fit
/// (`curve:mhs`, `curve:mhs+lm`) in its optimiser's fixed colour, dashed
/// for a hybrid, as in every report ([`metabezier_plot::style`]); the
/// baselines (`template`, `straight`) in Tol's muted colours, in order.
fn method_styles(methods: &[String]) -> Vec<metabezier_plot::style::SeriesStyle> {
    use metabezier_plot::style::{base_colour, label_colours, SeriesStyle};
    let baselines: Vec<&str> = methods
        .iter()
        .filter(|m| !m.starts_with("curve:"))
        .map(String::as_str)
        .collect();
    let mut others = label_colours(&baselines).into_iter();
    methods
        .iter()
        .map(|m| match m.strip_prefix("curve:") {
            Some(opt) => SeriesStyle {
                colour: base_colour(opt.split('+').next().unwrap_or(opt)),
                dashed: opt.contains('+'),
            },
            None => SeriesStyle::solid(others.next().unwrap_or(BLACK_RGB)),
        })
        .collect()
}

/// Black, for a style that has no colour of its own.
const BLACK_RGB: plotters::style::RGBColor = plotters::style::RGBColor(0, 0, 0);

/// The caption of the validation figure: what its points and bars are,
/// and how many reconstructions (`no_hd95`) have no finite HD95.
fn validation_caption(no_hd95: usize) -> String {
    let mut caption = String::from(
        "Dice of the implant and the removed bone (larger is better) and HD95, the 95th \
         percentile of the surface distances in mm (smaller is better), of every method at \
         each defect width (mm): the point is the median over the validation cases (slices \
         or slice ranges, and positions) and the runs of a stochastic method, the bar the \
         interquartile range (25 % to 75 %, type-7 quantiles); the methods are set side by \
         side at each width. template: the mirrored template; straight: the straight \
         bridge; curve:<method>: the curve-fitted wall, in the method's colour of every \
         report. The verdicts across independent units are in the sections above and in \
         verdicts.csv.",
    );
    if no_hd95 > 0 {
        caption.push_str(&format!(
            " {no_hd95} reconstruction(s) without a finite HD95 (an empty implant) are left \
             out of the HD95 panels."
        ));
    }
    caption
}

/// The figure of Dice and HD95 (mm) per method and defect width: for each
/// validation that ran (`two_d`, slice by slice, from `validation.csv`;
/// `three_d`, in 3D, from `validation_3d.csv`), a Dice panel and an HD95
/// panel; at each width (mm) the median over the cases and runs of every
/// method in `methods` (in their order) with a bar over its interquartile
/// range (type-7 quantiles), the methods side by side. A reconstruction
/// without a finite HD95 (an empty implant) is left out of the HD95 panel
/// and counted in the caption. `None` when no validation row succeeded.
pub fn validation_figure(
    methods: &[String],
    two_d: &[Scored<'_>],
    three_d: &[Scored<'_>],
) -> Result<Option<ValidationFigure>, ImplantError> {
    use metabezier_plot::factor_lines::{FactorLines, FactorPanel, FactorSeries, Spread};
    let styles = method_styles(methods);
    let mut panels = Vec::new();
    let mut legend_used = vec![false; methods.len()];
    let mut no_hd95 = 0usize;
    for (scope, rows) in [
        ("slice by slice (validation.csv)", two_d),
        ("in 3D (validation_3d.csv)", three_d),
    ] {
        if rows.is_empty() {
            continue;
        }
        let mut widths: Vec<f64> = rows.iter().map(|r| r.1).filter(|w| w.is_finite()).collect();
        widths.sort_by(f64::total_cmp);
        widths.dedup();
        for (metric, label, pick) in [
            ("Dice", "Dice (larger is better)", 2usize),
            ("HD95", "HD95 mm (smaller is better)", 3),
        ] {
            let mut series = Vec::new();
            for (i, m) in methods.iter().enumerate() {
                let points: Vec<(f64, f64, f64, f64)> = widths
                    .iter()
                    .filter_map(|&w| {
                        let v: Vec<f64> = rows
                            .iter()
                            .filter(|r| r.0 == m && r.1 == w)
                            .map(|r| if pick == 2 { r.2 } else { r.3 })
                            .collect();
                        let finite: Vec<f64> =
                            v.iter().copied().filter(|x| x.is_finite()).collect();
                        if pick == 3 {
                            no_hd95 += v.len() - finite.len();
                        }
                        let s = crate::stats::summarize(&finite).ok()?;
                        Some((w, s.q1, s.median, s.q3))
                    })
                    .collect();
                if !points.is_empty() {
                    legend_used[i] = true;
                    series.push(FactorSeries {
                        style: styles[i],
                        points,
                    });
                }
            }
            if !series.is_empty() {
                panels.push(FactorPanel {
                    title: format!("{metric}, {scope}"),
                    y_label: label.into(),
                    y_log: false,
                    series,
                    reference: None,
                });
            }
        }
    }
    if panels.is_empty() {
        return Ok(None);
    }
    let legend = methods
        .iter()
        .zip(&styles)
        .zip(&legend_used)
        .filter(|(_, used)| **used)
        .map(|((m, s), _)| (m.clone(), *s))
        .collect();
    let figure = FactorLines {
        title: "Dice and HD95 per method and defect width (bar: interquartile range)".into(),
        legend,
        x_label: "defect width (mm)".into(),
        x_log: false,
        spread: Spread::Bars,
        columns: 2,
        panels,
    };
    let (svg, png) = metabezier_plot::render::draw_in_memory(&figure).map_err(|e| {
        ImplantError::Ct(crate::ct::CtError::Draw {
            message: format!("{VALIDATION_FIGURE}: {}", e.0),
        })
    })?;
    let caption = validation_caption(no_hd95);
    let section = format!(
        "## Dice and HD95 per method and width\n\n![Dice and HD95 per method and width]({VALIDATION_FIGURE}.png)\n\n{caption}\n\n"
    );
    Ok(Some(ValidationFigure {
        png,
        svg: svg.into_bytes(),
        section,
    }))
}

/// [`validation_figure`] of the rows of a run of `spec`: the baselines and
/// then every curve method of its validations, in the spec's order; the
/// successful rows of `validation.csv` (`two_d`) and `validation_3d.csv`
/// (`three_d`).
pub fn validation_figure_of(
    spec: &super::spec::ImplantSpec,
    two_d: &[super::validation::ValidationRow],
    three_d: &[super::validation3d::Row3d],
) -> Result<Option<ValidationFigure>, ImplantError> {
    let mut methods = vec!["template".to_string(), "straight".to_string()];
    let curves = spec.validation.iter().flat_map(|v| &v.methods);
    for m in curves.chain(spec.validation_3d.iter().flat_map(|v| &v.methods)) {
        let name = format!("curve:{}", m.name());
        if !methods.contains(&name) {
            methods.push(name);
        }
    }
    let rows_2d: Vec<Scored<'_>> = two_d
        .iter()
        .filter_map(|r| {
            let m = r.metrics.as_ref().ok()?;
            Some((r.method.as_str(), r.case.width_mm, m.dice, m.hd95))
        })
        .collect();
    let rows_3d: Vec<Scored<'_>> = three_d
        .iter()
        .filter_map(|r| {
            let m = r.metrics.as_ref().ok()?;
            Some((r.method.as_str(), r.case.width_mm, m.dice, m.hd95))
        })
        .collect();
    validation_figure(&methods, &rows_2d, &rows_3d)
}

/// The length of a scale bar for a view of `mm_per_px` millimetres per
/// pixel and `size` pixels: the largest of 1, 2, 5 × 10ᵏ mm that spans at
/// most a quarter of the view; `None` for a view without a scale.
pub fn scale_bar_mm(mm_per_px: f64, size: u32) -> Option<u32> {
    let max = mm_per_px * f64::from(size) / 4.0;
    if !max.is_finite() || max < 1.0 {
        return None;
    }
    [1u32, 2, 5, 10, 20, 50, 100, 200, 500, 1000]
        .into_iter()
        .rev()
        .find(|&l| f64::from(l) <= max)
}

/// The axis triad of a view: for the volume's `+x`, `+y` and `+z`, the
/// short name of the patient direction it points to (L/R, A/P, S/I), where
/// its arrow of `length` pixels ends on screen (relative to the triad's
/// origin, `y` down) and its colour; an axis along the line of sight is
/// left out.
pub fn triad(
    view: &MeshView,
    anatomy: &Anatomy,
    length: f64,
) -> Vec<(&'static str, [f64; 2], [u8; 3])> {
    let axes = [
        ([1.0, 0.0, 0.0], anatomy.x, [200, 30, 30]),
        ([0.0, 1.0, 0.0], anatomy.y, [20, 140, 20]),
        ([0.0, 0.0, 1.0], anatomy.z, [30, 60, 220]),
    ];
    axes.into_iter()
        .filter_map(|(v, d, colour)| {
            let s = view.screen(v);
            (s[0].hypot(s[1]) > 0.2).then(|| (short(d), [s[0] * length, s[1] * length], colour))
        })
        .collect()
}

/// The one-letter name of a patient direction.
fn short(d: PatientDirection) -> &'static str {
    match d {
        PatientDirection::Left => "L",
        PatientDirection::Right => "R",
        PatientDirection::Anterior => "A",
        PatientDirection::Posterior => "P",
        PatientDirection::Superior => "S",
        PatientDirection::Inferior => "I",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scale_bar_is_a_round_length_of_at_most_a_quarter_view() {
        // 360 px at 0.5 mm per px: 180 mm wide, a bar of at most 45 mm.
        assert_eq!(scale_bar_mm(0.5, 360), Some(20));
        assert_eq!(scale_bar_mm(0.56, 360), Some(50));
        assert_eq!(scale_bar_mm(0.01, 360), None);
        assert_eq!(scale_bar_mm(f64::NAN, 360), None);
    }

    #[test]
    fn the_triad_names_the_patient_axes_where_they_point_on_screen() {
        // Looking at the face along +y (LPS: towards posterior), +z up.
        let view = MeshView {
            rgb: Vec::new(),
            mm_per_px: 0.5,
            right: [1.0, 0.0, 0.0],
            up: [0.0, 0.0, 1.0],
        };
        let lps = Anatomy {
            x: PatientDirection::Left,
            y: PatientDirection::Posterior,
            z: PatientDirection::Superior,
        };
        let t = triad(&view, &lps, 30.0);
        // +y is the line of sight: left out.
        let names: Vec<&str> = t.iter().map(|a| a.0).collect();
        assert_eq!(names, ["L", "S"]);
        assert_eq!(t[0].1, [30.0, 0.0]);
        // Superior is up: negative screen y.
        assert_eq!(t[1].1, [0.0, -30.0]);
        // A volume whose +z points to the feet labels the same arrow I.
        let feet = Anatomy {
            z: PatientDirection::Inferior,
            ..lps
        };
        assert_eq!(triad(&view, &feet, 30.0)[1].0, "I");
    }

    #[test]
    fn handedness_follows_the_patient_axes() {
        use PatientDirection::*;
        let a = |x, y, z| Anatomy { x, y, z };
        assert!(a(Left, Posterior, Superior).right_handed());
        assert!(a(Right, Anterior, Superior).right_handed());
        assert!(a(Anterior, Left, Superior).right_handed());
        // The .inv3 convention flips the rows of LPS: left-handed, so its
        // preview is mirrored back.
        assert!(!crate::ct::INV3_ANATOMY.right_handed());
        assert!(!a(Left, Posterior, Inferior).right_handed());
    }
}
