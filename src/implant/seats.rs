//! The seats A′ and B′ of a stack of slices, chosen jointly so that the
//! implant's edge follows the bone without jumping between slices
//! (RECONSTRUCTION: the surviving thesis text names A and B but does not
//! say how they are placed from slice to slice).

use super::polar::SEAT_STEP_MM;

/// The seats of a stack of slices (`zs`), per side, by dynamic programming
/// (Viterbi) over the candidate seats `s_k = k·0.25` mm: they minimise
/// `Σ_z [max(0, bend_z(s_z) − bend_deg) + 0.01·s_z] + λ·Σ |s_z − s_{z+1}|`
/// (adjacent slices only), the table's excess bend at the seat (degrees;
/// `Gap::bends` in [`super::polar`]), a slight preference for seats near the
/// tips, and `λ` degrees per mm of seat change between slices, so the
/// implant's edge follows the bone without jumping. One slice (or
/// `λ = 0`) gets the first seat whose bend is at most `bend_deg`, else the
/// least bent one.
pub fn choose_seats(
    bends: &[(Vec<f64>, Vec<f64>)],
    zs: &[usize],
    bend_deg: f64,
    lambda: f64,
) -> Vec<(f64, f64)> {
    let a = viterbi(
        &bends.iter().map(|b| b.0.as_slice()).collect::<Vec<_>>(),
        zs,
        bend_deg,
        lambda,
    );
    let b = viterbi(
        &bends.iter().map(|b| b.1.as_slice()).collect::<Vec<_>>(),
        zs,
        bend_deg,
        lambda,
    );
    a.into_iter().zip(b).collect()
}

/// One side of [`choose_seats`].
fn viterbi(bends: &[&[f64]], zs: &[usize], bend_deg: f64, lambda: f64) -> Vec<f64> {
    let step = SEAT_STEP_MM;
    let cost = |b: &[f64], k: usize| (b[k] - bend_deg).max(0.0) + 0.01 * k as f64 * step;
    let n = bends.len();
    let mut acc: Vec<Vec<f64>> = Vec::with_capacity(n);
    let mut from: Vec<Vec<usize>> = Vec::with_capacity(n);
    for i in 0..n {
        let row: Vec<(f64, usize)> = (0..bends[i].len())
            .map(|k| {
                let here = cost(bends[i], k);
                if i == 0 {
                    return (here, 0);
                }
                let linked = zs[i].abs_diff(zs[i - 1]) == 1;
                let (best, j) = acc[i - 1]
                    .iter()
                    .enumerate()
                    .map(|(j, &c)| {
                        let jump = if linked {
                            lambda * (k.abs_diff(j) as f64 * step)
                        } else {
                            0.0
                        };
                        (c + jump, j)
                    })
                    .min_by(|x, y| x.0.total_cmp(&y.0))
                    .unwrap_or((0.0, 0));
                (here + best, j)
            })
            .collect();
        acc.push(row.iter().map(|r| r.0).collect());
        from.push(row.iter().map(|r| r.1).collect());
    }
    let mut k = (0..acc[n - 1].len())
        .min_by(|&x, &y| acc[n - 1][x].total_cmp(&acc[n - 1][y]))
        .unwrap_or(0);
    let mut out = vec![0.0; n];
    for i in (0..n).rev() {
        out[i] = k as f64 * step;
        k = from[i][k];
    }
    out
}
