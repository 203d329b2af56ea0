//! Parameterisations `t₀ = 0 < … < t_N = 1` of an ordered point list
//! (Farin 2002, §9.6; Lee 1989).

use super::error::GeometryError;
use super::Point;

/// How the parameter value `tᵢ` of each data point is chosen, from the gaps
/// `Δᵢ = |Rᵢ − R_{i−1}|^α` by `t₀ = 0`, `tᵢ = t_{i−1} + Δᵢ / ΣΔ` (Farin 2002, §9.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Parameterisation {
    /// Equally spaced, `α = 0`: `tᵢ = i/N`.
    Uniform,
    /// Chord length, `α = 1`: gaps proportional to `|Rᵢ − R_{i−1}|`.
    #[default]
    ChordLength,
    /// Centripetal, `α = ½` (Lee 1989, "Choosing nodes in parametric curve
    /// interpolation", *Computer-Aided Design* 21(6)).
    Centripetal,
}

impl Parameterisation {
    /// The names accepted in experiment specs, in the order of the enum.
    pub const NAMES: [&'static str; 3] = ["uniform", "chord", "centripetal"];

    /// Parses a spec name (`"uniform"`, `"chord"` or `"centripetal"`).
    pub fn from_name(name: &str) -> Option<Parameterisation> {
        match name {
            "uniform" => Some(Parameterisation::Uniform),
            "chord" | "chord-length" | "chord_length" => Some(Parameterisation::ChordLength),
            "centripetal" => Some(Parameterisation::Centripetal),
            _ => None,
        }
    }

    /// The spec name of this parameterisation.
    pub fn name(self) -> &'static str {
        match self {
            Parameterisation::Uniform => "uniform",
            Parameterisation::ChordLength => "chord",
            Parameterisation::Centripetal => "centripetal",
        }
    }

    /// The exponent `α` in `Δᵢ = |Rᵢ − R_{i−1}|^α`: 0, 1 or ½.
    pub fn exponent(self) -> f64 {
        match self {
            Parameterisation::Uniform => 0.0,
            Parameterisation::ChordLength => 1.0,
            Parameterisation::Centripetal => 0.5,
        }
    }

    /// The parameters `t₀..t_N` of `points` (see [`Parameterisation::params_into`]).
    pub fn params(self, points: &[Point]) -> Vec<f64> {
        let mut out = vec![0.0; points.len()];
        self.params_into(points, &mut out);
        out
    }

    /// Writes `tᵢ` for the pairs of `points` and `out` (the shorter decides):
    /// `t₀ = 0`, `t_N = 1` exactly, non-decreasing. A duplicate point gets the
    /// same `t` as its predecessor (zero gap, no NaN); if every gap is zero
    /// (all points equal) the uniform parameterisation is used.
    pub fn params_into(self, points: &[Point], out: &mut [f64]) {
        let n = points.len().min(out.len());
        if n == 0 {
            return;
        }
        let (points, out) = (&points[..n], &mut out[..n]);
        let alpha = self.exponent();
        out[0] = 0.0;
        let mut acc = 0.0;
        for (o, w) in out[1..].iter_mut().zip(points.windows(2)) {
            let chord = w[1].distance(w[0]);
            acc += if alpha == 0.0 {
                1.0
            } else if alpha == 1.0 {
                chord
            } else {
                chord.powf(alpha)
            };
            *o = acc;
        }
        if n == 1 {
            return;
        }
        if acc > 0.0 && acc.is_finite() {
            for o in out.iter_mut() {
                *o /= acc;
            }
        } else {
            let last = (n - 1) as f64;
            for (i, o) in out.iter_mut().enumerate() {
                *o = i as f64 / last;
            }
        }
        out[n - 1] = 1.0;
    }
}

/// The local parameters `sᵢ = (tᵢ − t_a)/(t_b − t_a)` for `i ∈ a..=b` of the
/// segment fitted to the sub-range `a..=b` (so `s_a = 0`, `s_b = 1`).
///
/// Fails unless `a ≤ b < t.len()`. When `t_b = t_a` (a single point or a run
/// of duplicates) the local parameters are spaced uniformly by index instead.
pub fn reparameterise(t: &[f64], a: usize, b: usize) -> Result<Vec<f64>, GeometryError> {
    if a > b || b >= t.len() {
        return Err(GeometryError::InvalidRange { a, b, len: t.len() });
    }
    let mut out = vec![0.0; b - a + 1];
    reparameterise_into(t, a, b, &mut out)?;
    Ok(out)
}

/// As [`reparameterise`], writing `s_a..s_b` into `out`, which must hold
/// exactly `b − a + 1` values (else an error), without allocation.
pub fn reparameterise_into(
    t: &[f64],
    a: usize,
    b: usize,
    out: &mut [f64],
) -> Result<(), GeometryError> {
    if a > b || b >= t.len() || out.len() != b - a + 1 {
        return Err(GeometryError::InvalidRange { a, b, len: t.len() });
    }
    let (ta, tb) = (t[a], t[b]);
    let span = tb - ta;
    if span > 0.0 && span.is_finite() {
        for (o, &ti) in out.iter_mut().zip(&t[a..=b]) {
            *o = (ti - ta) / span;
        }
        out[b - a] = 1.0;
    } else if a == b {
        out[0] = 0.0;
    } else {
        let last = (b - a) as f64;
        for (i, o) in out.iter_mut().enumerate() {
            *o = i as f64 / last;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &[f64], b: &[f64]) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-15)
    }

    #[test]
    fn hand_computed_values() {
        // Gaps: |(3,4)| = 5, duplicate 0, |(0,9)| = 9.
        let pts = [
            Point::ZERO,
            Point::new(3.0, 4.0),
            Point::new(3.0, 4.0),
            Point::new(3.0, 13.0),
        ];
        assert!(close(
            &Parameterisation::Uniform.params(&pts),
            &[0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0]
        ));
        let chord = Parameterisation::ChordLength.params(&pts);
        assert!(
            close(&chord, &[0.0, 5.0 / 14.0, 5.0 / 14.0, 1.0]),
            "{chord:?}"
        );
        let s5 = 5f64.sqrt();
        let cen = Parameterisation::Centripetal.params(&pts);
        assert!(
            close(&cen, &[0.0, s5 / (s5 + 3.0), s5 / (s5 + 3.0), 1.0]),
            "{cen:?}"
        );
        // Gaps 1 and 4: chord (0, 0.2, 1), centripetal √1, √4 → (0, 1/3, 1).
        let pts = [Point::ZERO, Point::new(1.0, 0.0), Point::new(1.0, 4.0)];
        assert!(close(
            &Parameterisation::ChordLength.params(&pts),
            &[0.0, 0.2, 1.0]
        ));
        assert!(close(
            &Parameterisation::Centripetal.params(&pts),
            &[0.0, 1.0 / 3.0, 1.0]
        ));
    }

    #[test]
    fn degenerate_inputs() {
        assert!(Parameterisation::ChordLength.params(&[]).is_empty());
        assert_eq!(
            Parameterisation::ChordLength.params(&[Point::ZERO]),
            vec![0.0]
        );
        let same = [Point::new(1.0, 1.0); 4];
        for p in [
            Parameterisation::Uniform,
            Parameterisation::ChordLength,
            Parameterisation::Centripetal,
        ] {
            let t = p.params(&same);
            assert!(close(&t, &[0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0]), "{p:?} {t:?}");
            assert!(t.iter().all(|x| x.is_finite()));
        }
        let mut out = [9.0; 2];
        Parameterisation::ChordLength.params_into(
            &[Point::ZERO, Point::new(2.0, 0.0), Point::new(5.0, 0.0)],
            &mut out,
        );
        assert_eq!(out, [0.0, 1.0]);
    }

    #[test]
    fn names_round_trip() {
        for n in Parameterisation::NAMES {
            assert_eq!(Parameterisation::from_name(n).unwrap().name(), n);
        }
        assert_eq!(Parameterisation::from_name("nope"), None);
        assert_eq!(Parameterisation::default(), Parameterisation::ChordLength);
    }

    #[test]
    fn sub_range_reparameterisation() {
        let t = [0.0, 0.2, 0.5, 0.9, 1.0];
        let s = reparameterise(&t, 1, 3).unwrap();
        assert!(close(&s, &[0.0, 3.0 / 7.0, 1.0]), "{s:?}");
        assert_eq!(reparameterise(&t, 0, 4).unwrap(), t.to_vec());
        assert_eq!(reparameterise(&t, 2, 2).unwrap(), vec![0.0]);
        assert!(reparameterise(&t, 3, 2).is_err());
        assert!(reparameterise(&t, 0, 5).is_err());
        // A run of equal parameters falls back to uniform spacing.
        let flat = [0.0, 0.5, 0.5, 0.5, 1.0];
        assert!(close(
            &reparameterise(&flat, 1, 3).unwrap(),
            &[0.0, 0.5, 1.0]
        ));
        let mut out = [0.0; 2];
        assert!(reparameterise_into(&t, 1, 3, &mut out).is_err());
    }
}
