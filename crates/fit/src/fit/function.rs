//! The curve family a segment is fitted with.

use crate::geometry::Continuity;

/// The Bézier function fitted to each segment (the thesis compares the
/// four): polynomial or rational, quadratic or cubic, rational ones in
/// standard form `w₀ = w_m = 1` (Farin 2002, §12.3 and §13.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FunctionType {
    /// `P(t) = (1−t)²C₀ + 2(1−t)t C₁ + t²C₂`.
    Quadratic,
    /// `P(t) = Σ C_i B_i^3(t)`.
    Cubic,
    /// `Q(t) = ((1−t)²C₀ + 2h₁(1−t)t C₁ + t²C₂)/((1−t)² + 2h₁(1−t)t + t²)`.
    RationalQuadratic,
    /// `Q(t) = Σ w_i C_i B_i^3(t) / Σ w_i B_i^3(t)`, `w₀ = w₃ = 1`.
    RationalCubic,
}

impl FunctionType {
    /// The names accepted in experiment specs, in the order of the enum.
    pub const NAMES: [&'static str; 4] =
        ["quadratic", "cubic", "rational-quadratic", "rational-cubic"];

    /// All four, in the order of [`FunctionType::NAMES`].
    pub const ALL: [FunctionType; 4] = [
        FunctionType::Quadratic,
        FunctionType::Cubic,
        FunctionType::RationalQuadratic,
        FunctionType::RationalCubic,
    ];

    /// Parses a spec name (see [`FunctionType::NAMES`]; `_` may replace `-`).
    pub fn from_name(name: &str) -> Option<FunctionType> {
        match name.replace('_', "-").as_str() {
            "quadratic" => Some(FunctionType::Quadratic),
            "cubic" => Some(FunctionType::Cubic),
            "rational-quadratic" => Some(FunctionType::RationalQuadratic),
            "rational-cubic" => Some(FunctionType::RationalCubic),
            _ => None,
        }
    }

    /// The spec name.
    pub fn name(self) -> &'static str {
        match self {
            FunctionType::Quadratic => "quadratic",
            FunctionType::Cubic => "cubic",
            FunctionType::RationalQuadratic => "rational-quadratic",
            FunctionType::RationalCubic => "rational-cubic",
        }
    }

    /// The degree `m`: 2 or 3.
    pub fn degree(self) -> usize {
        match self {
            FunctionType::Quadratic | FunctionType::RationalQuadratic => 2,
            FunctionType::Cubic | FunctionType::RationalCubic => 3,
        }
    }

    /// Whether the function has free inner weights.
    pub fn is_rational(self) -> bool {
        matches!(
            self,
            FunctionType::RationalQuadratic | FunctionType::RationalCubic
        )
    }

    /// The number of free scalars of an unjoined segment with fixed ends:
    /// `2(m − 1)` inner control point coordinates plus `m − 1` weights if
    /// rational (2, 4, 3, 6).
    pub fn free_dim(self) -> usize {
        let inner = self.degree() - 1;
        2 * inner + if self.is_rational() { inner } else { 0 }
    }

    /// The free scalars one segment adds to a closed chain of segments
    /// joined with `continuity` whose join points are fixed: the
    /// [`FunctionType::free_dim`] of an unjoined segment, less the one
    /// scalar a G1 join takes (the start leg's direction is the shared
    /// tangent's) or the two a C1 join takes (the first inner control point
    /// follows from the shared derivative), so 2/4/3/6 for C0, 1/3/2/5 for
    /// G1 and 0/2/1/4 for C1 (quadratic, cubic, rational quadratic, rational
    /// cubic). It is the dimension of a segment whose start is joined, and
    /// `segments × chain_dim` the number of unknowns of a cyclic chain
    /// solved jointly; a corner or an open end adds a few more.
    pub fn chain_dim(self, continuity: Continuity) -> usize {
        let taken = match continuity {
            Continuity::C0 => 0,
            Continuity::G1 => 1,
            Continuity::C1 => 2,
        };
        self.free_dim() - taken
    }

    /// The fewest data points a segment needs: the two fixed ends plus
    /// enough interior points, two equations each, to determine the
    /// [`FunctionType::free_dim`] free scalars of an unjoined segment
    /// (`2 + ⌈free_dim/2⌉`: 3, 4, 4 and 5).
    pub fn min_points(self) -> usize {
        2 + self.free_dim().div_ceil(2)
    }
}

impl std::fmt::Display for FunctionType {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for (f, n) in FunctionType::ALL.iter().zip(FunctionType::NAMES) {
            assert_eq!(FunctionType::from_name(n), Some(*f));
            assert_eq!(f.name(), n);
        }
        assert_eq!(
            FunctionType::from_name("rational_cubic"),
            Some(FunctionType::RationalCubic)
        );
        assert_eq!(FunctionType::from_name("quartic"), None);
        let dims: Vec<usize> = FunctionType::ALL.iter().map(|f| f.free_dim()).collect();
        assert_eq!(dims, [2, 4, 3, 6]);
        let mins: Vec<usize> = FunctionType::ALL.iter().map(|f| f.min_points()).collect();
        assert_eq!(mins, [3, 4, 4, 5]);
    }
}
