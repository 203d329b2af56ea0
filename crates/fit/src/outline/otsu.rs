//! Otsu's threshold (Otsu 1979, "A threshold selection method from gray-level
//! histograms", IEEE Trans. SMC 9(1):62–66).

/// The grey-level histogram of 8-bit luminance values: `h[i]` pixels have level `i`.
pub fn histogram(levels: &[u8]) -> [u64; 256] {
    let mut h = [0u64; 256];
    for &v in levels {
        h[v as usize] += 1;
    }
    h
}

/// Otsu's threshold `k*` maximising the between-class variance
/// `σ_B²(k) = (μ_T ω(k) − μ(k))² / (ω(k)(1 − ω(k)))` (Otsu 1979, eq. 18), where
/// class 0 is the levels `≤ k`; `None` when fewer than two levels occur.
///
/// When `σ_B²` is maximal on a run of levels (an empty gap between two modes)
/// the middle of the first such run is returned, rounded down.
pub fn otsu_threshold(hist: &[u64; 256]) -> Option<u8> {
    let n: u64 = hist.iter().sum();
    if hist.iter().filter(|&&c| c > 0).count() < 2 {
        return None;
    }
    let m_total: u64 = hist.iter().enumerate().map(|(i, &c)| i as u64 * c).sum();
    // s = N²σ_B² = (m_T w − m N)² / (w (N − w)) from the exact integer sums
    // w = Nω and m = Nμ, so that a gap (equal w, m) gives bit-identical values.
    let (nf, mtf) = (n as f64, m_total as f64);
    let mut w = 0u64;
    let mut m = 0u64;
    let mut best = f64::NEG_INFINITY;
    let (mut first, mut last) = (0usize, 0usize);
    let mut in_run = false;
    for (k, &c) in hist.iter().enumerate().take(255) {
        w += c;
        m += k as u64 * c;
        if w == 0 || w == n {
            in_run = false;
            continue;
        }
        let wf = w as f64;
        let d = mtf * wf - m as f64 * nf;
        let s = d * d / (wf * (nf - wf));
        if s > best {
            best = s;
            first = k;
            last = k;
            in_run = true;
        } else if s == best && in_run && last + 1 == k {
            last = k;
        } else {
            in_run = false;
        }
    }
    Some(((first + last) / 2) as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The within-class variance `σ_W²(k) = Σ_classes Σ (i − μ_c)² h_i / N`, computed
    /// directly; Otsu (1979) shows minimising it equals maximising `σ_B²`.
    fn within_class_variance(hist: &[u64; 256], k: usize) -> f64 {
        let mut total = 0.0;
        for range in [0..=k, k + 1..=255] {
            let (mut c, mut s) = (0.0, 0.0);
            for i in range.clone() {
                c += hist[i] as f64;
                s += i as f64 * hist[i] as f64;
            }
            if c == 0.0 {
                continue;
            }
            let mu = s / c;
            for i in range {
                total += (i as f64 - mu).powi(2) * hist[i] as f64;
            }
        }
        total
    }

    fn gaussian_mixture(means: &[(f64, f64, f64)]) -> [u64; 256] {
        let mut h = [0u64; 256];
        for (i, bin) in h.iter_mut().enumerate() {
            let x = i as f64;
            let v: f64 = means
                .iter()
                .map(|&(mu, sd, weight)| weight * (-0.5 * ((x - mu) / sd).powi(2)).exp())
                .sum();
            *bin = v.round() as u64;
        }
        h
    }

    #[test]
    fn symmetric_bimodal_histogram_splits_in_the_middle() {
        // Symmetric under i ↦ 251 − i, so the best split is between 125 and 126.
        let h = gaussian_mixture(&[(80.0, 12.0, 1000.0), (171.0, 12.0, 1000.0)]);
        for i in 0..=251 {
            assert_eq!(h[i], h[251 - i]);
        }
        assert_eq!(otsu_threshold(&h), Some(125));
    }

    #[test]
    fn two_spikes_give_the_middle_of_the_gap() {
        let mut h = [0u64; 256];
        h[50] = 300;
        h[200] = 100;
        assert_eq!(otsu_threshold(&h), Some(124));
    }

    #[test]
    fn agrees_with_minimum_within_class_variance() {
        let h = gaussian_mixture(&[
            (60.0, 20.0, 500.0),
            (150.0, 35.0, 200.0),
            (220.0, 8.0, 90.0),
        ]);
        let k = otsu_threshold(&h).unwrap() as usize;
        let best = (0..255)
            .map(|j| within_class_variance(&h, j))
            .fold(f64::INFINITY, f64::min);
        let at_k = within_class_variance(&h, k);
        assert!((at_k - best).abs() <= 1e-9 * best, "{at_k} vs {best}");
    }

    #[test]
    fn a_single_level_has_no_threshold() {
        assert_eq!(otsu_threshold(&histogram(&[7, 7, 7])), None);
        assert_eq!(otsu_threshold(&[0; 256]), None);
        assert_eq!(otsu_threshold(&histogram(&[0, 255])), Some(127));
    }
}
