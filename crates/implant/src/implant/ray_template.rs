//! A template as a radius per ray about a slice's polar centre `O`: the
//! form in which the 3D templates ([`super::surface_template`]) reach the
//! wall design, which reads it where the slice-wise mirror reads the
//! mirrored envelope `R(θ)`. Its own file, below the wall input.

use super::template_source::TemplateSource;
use crate::geometry::Point;

/// `d` wrapped into `(−π, π]` (the polar reading of a gap,
/// [`super::polar`], uses it too).
pub(crate) fn wrap(d: f64) -> f64 {
    let t = std::f64::consts::TAU;
    let r = d.rem_euclid(t);
    if r > std::f64::consts::PI {
        r - t
    } else {
        r
    }
}

/// A template as a radius per ray about a slice's polar centre.
#[derive(Clone, Debug, PartialEq)]
pub struct RayTemplate {
    /// Where it came from ([`TemplateSource::Mirror3d`] or
    /// [`TemplateSource::Rim`]).
    pub kind: TemplateSource,
    /// Why this template serves the slice (the `auto3d` rule, or the
    /// spec's choice).
    pub reason: String,
    /// The polar centre `O` (mm).
    pub centre: Point,
    /// The first ray's angle (radians).
    pub theta0: f64,
    /// The signed angular step between rays (radians).
    pub step: f64,
    /// The radius on each ray (mm); `None` where the ray misses.
    pub radii: Vec<Option<f64>>,
}

impl RayTemplate {
    /// The template point on the ray at `theta`, linear in θ between the
    /// two nearest rays; `None` outside the sampled rays or where either
    /// misses.
    pub fn at(&self, theta: f64) -> Option<Point> {
        let u = wrap(theta - self.theta0) / self.step;
        let n = self.radii.len();
        if !(u >= -1e-9 && u <= (n - 1) as f64 + 1e-9) {
            return None;
        }
        let i = (u.floor() as usize).min(n.saturating_sub(2));
        let f = (u - i as f64).clamp(0.0, 1.0);
        let r = self.radii[i]? * (1.0 - f) + self.radii[(i + 1).min(n - 1)]? * f;
        Some(self.centre + Point::new(theta.cos(), theta.sin()) * r)
    }

    /// Whether every ray from `th_a` over `span` (radians) meets the
    /// template (checked every step).
    pub fn covers(&self, th_a: f64, span: f64) -> bool {
        let n = (span.abs() / self.step.abs()).ceil() as usize + 1;
        (0..=n).all(|k| self.at(th_a + span * k as f64 / n as f64).is_some())
    }
}
