//! The 3D templates (BEYOND THE THESIS), sliced to one outer-wall template
//! per defect slice so that the chapter-5 fit, the seats and the inner wall
//! follow unchanged: a radius per ray about the slice's polar centre `O`
//! ([`RayTemplate`]), read by the wall design where the slice-wise mirror
//! reads the mirrored envelope `R(θ)`.
//!
//! - `mirror3d`: the outer table mirrored across the mid-sagittal **plane**
//!   ([`crate::ct::symmetry3d`]): on the ray `q(t) = (O + t(cos θ, sin θ), z)`
//!   the template point is the outermost `t` at which the reflected point
//!   `R(q(t))` is bone (the HU, trilinear, crosses the threshold), found
//!   walking inwards from `1.3 r` to `0.7 r` in 0.2 mm steps and refined
//!   linearly (`r` the ends' mean distance from `O`). The reflection may
//!   land on another slice: a head that is rolled is mirrored correctly,
//!   which a line per slice cannot do.
//! - `rim`: the rim fill ([`super::rim_fill`]) through the outer table
//!   around the defect on the defect slices and `rim_mm` above and below,
//!   cut by the same rays.
//!
//! `auto3d` chooses per slice (the stated rule): the 3D mirror where the
//! defect lies on one side of the plane's trace on the slice, every ray of
//! the gap meets the mirrored bone, and the mirrored template meets the
//! bone next to both tips within `mirror_tolerance_mm`; else the rim fill.
//! The reason is kept with each slice ([`RayTemplate::reason`]).

use std::collections::BTreeMap;

use super::continuation::TemplateSource;
use super::polar::{angle, wrap};
pub use super::ray_template::RayTemplate;
use super::rim_fill::{RimError, RimSurface};
use super::wall_input::TemplateChoice;
use super::wall_input::WallOptions;
use crate::ct::{mid_sagittal_plane, MidLine, Plane3, Volume};
use crate::geometry::Point;

/// The arc (mm) beyond each tip over which a ray template is sampled: the
/// seats lie at most `seat_max_mm` behind the tips; 8 mm more covers the
/// tangent windows.
const EXTRA_MM: f64 = 8.0;

/// One slice's gap and the rays a template is sampled on.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Rays {
    centre: Point,
    z_mm: f64,
    th_a: f64,
    span: f64,
    r: f64,
    theta0: f64,
    step: f64,
    n: usize,
}

impl Rays {
    /// The rays of a slice context: from `EXTRA_MM + seat_max_mm` of arc
    /// before A to as far after B, 0.5 mm of arc apart.
    pub(crate) fn of(volume: &Volume, ctx: &DefectSlice, seat_max_mm: f64) -> Rays {
        let o = ctx.centre;
        let (a, b) = ctx.ends;
        let th_a = angle(a, o);
        let span = wrap(angle(b, o) - th_a);
        let r = 0.5 * (a.distance(o) + b.distance(o));
        let sign = if span < 0.0 { -1.0 } else { 1.0 };
        let margin = (seat_max_mm + EXTRA_MM) / r;
        let step = sign * 0.5 / r;
        let n = ((span.abs() + 2.0 * margin) / step.abs()).ceil() as usize + 1;
        Rays {
            centre: o,
            z_mm: ctx.k as f64 * volume.spacing.z,
            th_a,
            span,
            r,
            theta0: th_a - sign * margin,
            step,
            n,
        }
    }

    fn theta(&self, i: usize) -> f64 {
        self.theta0 + self.step * i as f64
    }

    fn point(&self, theta: f64, t: f64) -> [f64; 3] {
        [
            self.centre.x + t * theta.cos(),
            self.centre.y + t * theta.sin(),
            self.z_mm,
        ]
    }

    fn template(&self, kind: TemplateSource, radii: Vec<Option<f64>>) -> RayTemplate {
        RayTemplate {
            kind,
            reason: String::new(),
            centre: self.centre,
            theta0: self.theta0,
            step: self.step,
            radii,
        }
    }
}

/// The HU at `p` (voxel mm) by trilinear interpolation; `None` outside the
/// volume's voxel centres.
fn trilinear(volume: &Volume, p: [f64; 3]) -> Option<f64> {
    let sp = volume.spacing;
    let g = [p[0] / sp.x, p[1] / sp.y, p[2] / sp.z];
    let dims = [volume.nx, volume.ny, volume.nz];
    if (0..3).any(|i| !(g[i] >= 0.0 && g[i] <= (dims[i] - 1) as f64)) {
        return None;
    }
    let i0 = [0, 1, 2].map(|i| (g[i].floor() as usize).min(dims[i].saturating_sub(2)));
    let f = [0, 1, 2].map(|i| g[i] - i0[i] as f64);
    let mut v = 0.0;
    for c in 0..8 {
        let o = [c & 1, (c >> 1) & 1, (c >> 2) & 1];
        let idx = [0, 1, 2].map(|i| (i0[i] + o[i]).min(dims[i] - 1));
        let w: f64 = (0..3)
            .map(|i| if o[i] == 1 { f[i] } else { 1.0 - f[i] })
            .product();
        v += w * f64::from(volume.get(idx[2], idx[1], idx[0]));
    }
    Some(v)
}

/// The outermost `t` in `[(1 − band) r, (1 + band) r]` at which
/// `hu(t) ≥ threshold`, walking inwards in 0.2 mm steps and interpolating
/// linearly between the last two samples; `None` when no sample is bone or
/// one is outside the volume before bone is met.
fn outer_hit(r: f64, band: f64, threshold: f64, hu: impl Fn(f64) -> Option<f64>) -> Option<f64> {
    let (lo, hi) = ((1.0 - band) * r, (1.0 + band) * r);
    let steps = ((hi - lo) / 0.2).ceil() as usize;
    let mut prev = (hi, hu(hi)?);
    for k in 1..=steps {
        let t = hi - (hi - lo) * k as f64 / steps as f64;
        let v = hu(t)?;
        if v >= threshold {
            let f = (prev.1 - threshold) / (prev.1 - v);
            return Some(prev.0 + (t - prev.0) * f.clamp(0.0, 1.0));
        }
        prev = (t, v);
    }
    None
}

/// The `mirror3d` template of one slice: on each ray the outer table of
/// the volume mirrored across `plane` (module documentation).
pub(crate) fn mirror3d_template(
    volume: &Volume,
    rays: &Rays,
    plane: &Plane3,
    threshold: i16,
) -> RayTemplate {
    let radii = (0..rays.n)
        .map(|i| {
            let th = rays.theta(i);
            outer_hit(rays.r, 0.3, f64::from(threshold), |t| {
                trilinear(volume, plane.reflect(rays.point(th, t)))
            })
        })
        .collect();
    rays.template(TemplateSource::Mirror3d, radii)
}

/// The rim points of a defect: the outer table (within 0.85–1.15× the
/// ends' radius) on the rays of each defect slice outside its gap (1.5 mm of arc clear of the tips, at most
/// `rim_mm` beyond them), and on the slices up to `rim_mm` above and below
/// the defect on the rays of the nearest defect slice, its gap included;
/// thinned to one mean point per 2.5 mm cell.
pub(crate) fn rim_points(
    volume: &Volume,
    rays: &[(usize, Rays)],
    rim_mm: f64,
    threshold: i16,
) -> Vec<[f64; 3]> {
    let mut raw = Vec::new();
    let sz = volume.spacing.z;
    let reach = (rim_mm / sz).round() as i64;
    let (k_lo, k_hi) = (rays[0].0 as i64, rays[rays.len() - 1].0 as i64);
    for k in (k_lo - reach).max(0)..=(k_hi + reach).min(volume.nz as i64 - 1) {
        let inside = (k_lo..=k_hi).contains(&k);
        let nearest = rays
            .iter()
            .min_by_key(|(kk, _)| (*kk as i64 - k).abs())
            .map(|(_, r)| r)
            .copied()
            .expect("at least one defect slice");
        let slice = volume.slice(k as usize);
        let own = rays.iter().find(|(kk, _)| *kk as i64 == k).map(|(_, r)| r);
        if inside && own.is_none() {
            continue;
        }
        let r = own.copied().unwrap_or(nearest);
        for i in 0..r.n {
            let th = r.theta(i);
            // Arc (mm) from the gap: negative inside it.
            let u = (th - r.th_a) / r.span.signum();
            let arc = if u < 0.0 { -u } else { u - r.span.abs() } * r.r;
            if arc > rim_mm || (inside && arc < 1.5) {
                continue;
            }
            let hit = outer_hit(r.r, 0.15, f64::from(threshold), |t| {
                let p = r.centre + Point::new(th.cos(), th.sin()) * t;
                Some(slice.bilinear(p.y / slice.sy, p.x / slice.sx, -1000.0))
            });
            if let Some(t) = hit {
                raw.push([
                    r.centre.x + t * th.cos(),
                    r.centre.y + t * th.sin(),
                    k as f64 * sz,
                ]);
            }
        }
    }
    thin(&raw, 2.5)
}

/// One mean point per occupied `cell`-mm cube, the cell grown by half
/// until at most 600 remain.
fn thin(points: &[[f64; 3]], cell: f64) -> Vec<[f64; 3]> {
    let mut cells: BTreeMap<[i64; 3], ([f64; 3], f64)> = BTreeMap::new();
    for p in points {
        let key = p.map(|v| (v / cell).floor() as i64);
        let e = cells.entry(key).or_insert(([0.0; 3], 0.0));
        for (sum, v) in e.0.iter_mut().zip(p) {
            *sum += v;
        }
        e.1 += 1.0;
    }
    if cells.len() > 600 {
        return thin(points, cell * 1.5);
    }
    cells.values().map(|(s, n)| s.map(|v| v / n)).collect()
}

/// The `rim` template of one slice cut from a fitted rim surface.
pub(crate) fn rim_template(surface: &RimSurface, rays: &Rays) -> RayTemplate {
    let radii = (0..rays.n)
        .map(|i| {
            let th = rays.theta(i);
            let origin = rays.point(th, 0.0);
            let dir = [th.cos(), th.sin(), 0.0];
            surface.ray_hit(origin, dir, (0.5 * rays.r, 1.5 * rays.r))
        })
        .collect();
    rays.template(TemplateSource::Rim, radii)
}

/// Fits the rim surface of a defect from the rays of its slices.
pub(crate) fn rim_surface(
    volume: &Volume,
    rays: &[(usize, Rays)],
    rim_mm: f64,
    threshold: i16,
) -> Result<RimSurface, RimError> {
    RimSurface::fit(&rim_points(volume, rays, rim_mm, threshold), 1.0)
}

/// The `auto3d` rule on one slice: `Ok(reason)` when the 3D mirror serves
/// it, `Err(reason)` when the rim fill must (module documentation).
pub(crate) fn mirror3d_serves(
    mirrored: &RayTemplate,
    rays: &Rays,
    plane: &Plane3,
    ends: (Point, Point),
    tolerance_mm: f64,
) -> Result<String, String> {
    let side = |p: Point| plane.side([p.x, p.y, rays.z_mm]);
    if side(ends.0) * side(ends.1) <= 0.0 {
        return Err("the defect crosses the mid-sagittal plane".into());
    }
    if !mirrored.covers(rays.th_a, rays.span) {
        return Err("a ray of the gap misses the mirrored bone".into());
    }
    for (name, p, th) in [
        ("A", ends.0, rays.th_a),
        ("B", ends.1, rays.th_a + rays.span),
    ] {
        let d = mirrored.at(th).map_or(f64::INFINITY, |q| q.distance(p));
        if d > tolerance_mm {
            return Err(format!(
                "the mirrored bone lies {d:.1} mm from the tip {name} (tolerance {tolerance_mm} mm)"
            ));
        }
    }
    Ok("the defect lies on one side of the plane and its mirror image is intact bone".into())
}

/// The 3D templates of a defect, one per defect slice, with what they were
/// built from.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceTemplates {
    /// Each defect slice's template (original numbering).
    pub slices: BTreeMap<usize, RayTemplate>,
    /// The mid-sagittal plane used (`mirror3d`, `auto3d`).
    pub plane: Option<Plane3>,
    /// The rim surface's RMS distance from its rim points (mm; `rim`,
    /// `auto3d`).
    pub rim_rms_mm: Option<f64>,
}

/// The arc (mm) of outer table around a defect that the rim fill is
/// fitted to, within the slices and across them.
pub const RIM_MM: f64 = 15.0;

/// The spec name of a 3D choice.
fn choice_name(choice: TemplateChoice) -> &'static str {
    match choice {
        TemplateChoice::Mirror3d => "mirror3d",
        TemplateChoice::Rim => "rim",
        _ => "auto3d",
    }
}

/// What the 3D templates need of one defect slice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DefectSlice {
    /// The slice (original numbering).
    pub z: usize,
    /// Its volume index.
    pub k: usize,
    /// The polar centre `O` (mm).
    pub centre: Point,
    /// A and B (mm).
    pub ends: (Point, Point),
}

/// A 3D template that could not be built: the spec's choice and what went
/// wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("template_source = \"{choice}\": {message}")]
pub struct Template3dError {
    /// The spec's choice.
    pub choice: &'static str,
    /// What went wrong, and what to do.
    pub message: String,
}

/// What a 3D template choice builds its slices' templates from: the
/// mirror across the mid-sagittal plane (`mirror3d`), the rim's filled
/// surface (`rim`), or both, the mirror where it serves (`auto3d`).
enum Sources {
    Mirror(Plane3),
    Rim(RimSurface),
    Both(Plane3, RimSurface),
}

impl Sources {
    /// The template of the slice with `rays` whose defect ends are `ends`,
    /// at bone `threshold`, with the reason it was chosen; `auto3d` keeps
    /// the mirror where it lies within `tolerance_mm` of the ends
    /// ([`mirror3d_serves`]), else fills the rim.
    fn template(
        &self,
        volume: &Volume,
        r: &Rays,
        ends: (Point, Point),
        (threshold, tolerance_mm): (i16, f64),
    ) -> RayTemplate {
        match self {
            Sources::Mirror(p) => {
                let mut m = mirror3d_template(volume, r, p, threshold);
                m.reason = "template_source = \"mirror3d\"".into();
                m
            }
            Sources::Rim(s) => {
                let mut t = rim_template(s, r);
                t.reason = "template_source = \"rim\"".into();
                t
            }
            Sources::Both(p, s) => {
                let mut m = mirror3d_template(volume, r, p, threshold);
                match mirror3d_serves(&m, r, p, ends, tolerance_mm) {
                    Ok(why) => {
                        m.reason = why;
                        m
                    }
                    Err(why) => {
                        let mut t = rim_template(s, r);
                        t.reason = format!("rim fill: {why}");
                        t
                    }
                }
            }
        }
    }
}

/// The 3D templates the wall options ask for (`mirror3d`, `rim`, `auto3d`;
/// `None` for the slice-wise choices, and for `auto3d` on a one-slice
/// volume, which then chooses as `auto`), of the defect slices `contexts`
/// at bone `threshold`. The plane is `plane` or, when
/// `None`, estimated from the volume starting from `midline`.
///
/// Errors ([`Template3dError`]): `mirror3d` or `rim` on a volume
/// of fewer than 3 slices, a plane that cannot be estimated, a rim that
/// does not determine a surface, and a slice whose 3D template misses a
/// ray of its gap (a wrong template is never passed on as a plausible one).
pub fn surface_templates(
    volume: &Volume,
    (wall, threshold, plane): (&WallOptions, i16, Option<Plane3>),
    contexts: &[DefectSlice],
    midline: &MidLine,
) -> Result<Option<SurfaceTemplates>, Template3dError> {
    let choice = wall.template;
    if !matches!(
        choice,
        TemplateChoice::Mirror3d | TemplateChoice::Rim | TemplateChoice::Auto3d
    ) || contexts.is_empty()
    {
        return Ok(None);
    }
    let name = choice_name(choice);
    let fail = |message: String| Template3dError {
        choice: name,
        message,
    };
    if volume.nz < 3 {
        if choice == TemplateChoice::Auto3d {
            return Ok(None);
        }
        return Err(fail(format!("the volume has {} slice(s); a 3D template needs at least 3 (use \"mirror\", \"auto\" or \"continuation\" on one-slice data)", volume.nz)));
    }
    let rays: Vec<(usize, Rays)> = contexts
        .iter()
        .map(|c| (c.k, Rays::of(volume, c, wall.seat_max_mm)))
        .collect();
    let plane = || -> Result<Plane3, Template3dError> {
        Ok(match plane {
            Some(p) => p,
            None => mid_sagittal_plane(volume, threshold, midline)
                .ok_or_else(|| fail("the mid-sagittal plane could not be estimated (fewer than 20 mirror pairs of bone-surface points within 8 mm of the midline's plane)".into()))?
                .plane,
        })
    };
    let rim = || rim_surface(volume, &rays, RIM_MM, threshold).map_err(|e| fail(e.to_string()));
    let sources = match choice {
        TemplateChoice::Mirror3d => Sources::Mirror(plane()?),
        TemplateChoice::Rim => Sources::Rim(rim()?),
        _ => {
            let p = plane()?;
            Sources::Both(p, rim()?)
        }
    };
    let mut slices = BTreeMap::new();
    for (ctx, (_, r)) in contexts.iter().zip(&rays) {
        let t = sources.template(volume, r, ctx.ends, (threshold, wall.mirror_tolerance_mm));
        if !t.covers(r.th_a, r.span) {
            return Err(fail(format!(
                "slice z = {}: the {} template misses a ray of the defect (no mirrored outer table within 0.7–1.3×, or filled surface within 0.5–1.5×, the ends' radius {:.1} mm from the polar centre)",
                ctx.z,
                t.kind.name(),
                r.r
            )));
        }
        slices.insert(ctx.z, t);
    }
    let (plane, rim_rms_mm) = match sources {
        Sources::Mirror(p) => (Some(p), None),
        Sources::Rim(s) => (None, Some(s.rim_rms_mm)),
        Sources::Both(p, s) => (Some(p), Some(s.rim_rms_mm)),
    };
    Ok(Some(SurfaceTemplates {
        slices,
        plane,
        rim_rms_mm,
    }))
}
