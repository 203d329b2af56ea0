//! Average ranks (midranks) with the tie-group sizes needed by tie corrections.

use super::error::{check_no_nan, StatsError};

/// Ranks of a sample where tied values share the mean of the ranks they span
/// ("midranks", Kendall 1945, "The treatment of ties in ranking problems",
/// Biometrika 33(3):239–251), plus the sizes of the tie groups.
#[derive(Clone, Debug, PartialEq)]
pub struct Ranks {
    /// Rank of each value, in input order; the smallest value has rank 1.
    pub ranks: Vec<f64>,
    /// Sizes t of the groups of two or more equal values, in increasing order of value.
    pub tie_sizes: Vec<usize>,
}

impl Ranks {
    /// The tie-correction term Σ (t³ − t) over the tie groups (Kendall 1945).
    pub fn tie_term(&self) -> f64 {
        tie_term(&self.tie_sizes)
    }

    /// Whether any two values were equal.
    pub fn has_ties(&self) -> bool {
        !self.tie_sizes.is_empty()
    }
}

/// Average ranks of `values` (rank 1 = smallest, ties get the mean of their
/// ranks; Kendall 1945, Biometrika 33(3):239–251); −0.0 and +0.0 are equal.
///
/// An empty slice gives empty ranks; a NaN gives [`StatsError::NotANumber`].
pub fn average_ranks(values: &[f64]) -> Result<Ranks, StatsError> {
    check_no_nan(values, "values")?;
    let mut order = Vec::with_capacity(values.len());
    let mut ranks = Vec::with_capacity(values.len());
    let mut tie_sizes = Vec::new();
    midranks_into(values, &mut order, &mut ranks, |t| {
        if t > 1 {
            tie_sizes.push(t);
        }
    });
    Ok(Ranks { ranks, tie_sizes })
}

/// The tie-correction term Σ (t³ − t) over tie-group sizes t (Kendall 1945,
/// Biometrika 33(3):239–251); groups of size 1 contribute nothing.
pub fn tie_term(tie_sizes: &[usize]) -> f64 {
    tie_sizes
        .iter()
        .map(|&t| {
            let t = t as f64;
            t * t * t - t
        })
        .sum()
}

/// Midranks of `values` written to `ranks` (resized to `values.len()`), using
/// `order` as scratch space; `on_group` is called with the size of every group
/// of equal values (including groups of size 1), in increasing order of value.
///
/// Callers must have rejected NaN; the sort never panics either way.
pub(crate) fn midranks_into(
    values: &[f64],
    order: &mut Vec<usize>,
    ranks: &mut Vec<f64>,
    mut on_group: impl FnMut(usize),
) {
    order.clear();
    order.extend(0..values.len());
    // Adding +0.0 maps −0.0 to +0.0 so that total_cmp agrees with `==`.
    order.sort_by(|&a, &b| (values[a] + 0.0).total_cmp(&(values[b] + 0.0)));
    ranks.clear();
    ranks.resize(values.len(), 0.0);
    let mut i = 0;
    while i < order.len() {
        let v = values[order[i]];
        let mut j = i + 1;
        while j < order.len() && values[order[j]] == v {
            j += 1;
        }
        // Mean of the ordinal ranks i+1 ..= j.
        let r = (i + 1 + j) as f64 / 2.0;
        for &idx in &order[i..j] {
            ranks[idx] = r;
        }
        on_group(j - i);
        i = j;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn midranks_and_ties() {
        // scipy 1.17.1: scipy.stats.rankdata([3, 1, 4, 1, 5, 9, 2, 6, 5, 3, 5])
        //   -> [4.5, 1.5, 6, 1.5, 8, 11, 3, 10, 8, 4.5, 8]
        let r = average_ranks(&[3., 1., 4., 1., 5., 9., 2., 6., 5., 3., 5.]).unwrap();
        assert_eq!(
            r.ranks,
            vec![4.5, 1.5, 6., 1.5, 8., 11., 3., 10., 8., 4.5, 8.]
        );
        assert_eq!(r.tie_sizes, vec![2, 2, 3]);
        assert_eq!(r.tie_term(), 6. + 6. + 24.);
        assert!(r.has_ties());
    }

    #[test]
    fn signed_zero_ties_and_edge_cases() {
        let r = average_ranks(&[0.0, -0.0, 1.0]).unwrap();
        assert_eq!(r.ranks, vec![1.5, 1.5, 3.0]);
        assert_eq!(r.tie_sizes, vec![2]);
        let r = average_ranks(&[]).unwrap();
        assert!(r.ranks.is_empty() && !r.has_ties());
        let r = average_ranks(&[7.0]).unwrap();
        assert_eq!(r.ranks, vec![1.0]);
        let r = average_ranks(&[2.0; 4]).unwrap();
        assert_eq!(r.ranks, vec![2.5; 4]);
        assert_eq!(r.tie_term(), 60.0);
        let r = average_ranks(&[f64::NEG_INFINITY, f64::INFINITY, 0.0]).unwrap();
        assert_eq!(r.ranks, vec![1.0, 3.0, 2.0]);
        assert_eq!(
            average_ranks(&[1.0, f64::NAN]),
            Err(StatsError::NotANumber {
                what: "values",
                index: 1
            })
        );
    }
}
