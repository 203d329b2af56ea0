//! The convergence trace of a whole fit: the segments' best-so-far errors
//! summed at equal evaluations per segment.

use super::FittedSegment;
use crate::optim::TracePoint;

/// The best-so-far `E` of a set of segments, each solved with its own
/// budget, as one trace: at every evaluation count `e` that some segment's
/// trace records, `E(e) = Σ_k best_k(e)` (the best value segment `k` had
/// after `min(e, n_k)` of its `n_k` evaluations) against the evaluations
/// `Σ_k min(e, n_k)` spent so far when every segment has had `e`.
///
/// Segments are solved one after another, so this is not the order in which
/// the evaluations happened: it is the fit the outline would have if every
/// segment stopped after `e` evaluations, the natural anytime view of a
/// per-segment budget. The last point is the fit's own `E` (at the solvers'
/// values) and total evaluations. Empty if a segment has no trace.
pub fn outline_trace<'a>(segments: impl IntoIterator<Item = &'a FittedSegment>) -> Vec<TracePoint> {
    let traces: Vec<(&[TracePoint], u64)> = segments
        .into_iter()
        .map(|s| (s.trace.as_slice(), s.metrics.evaluations))
        .collect();
    if traces.is_empty() || traces.iter().any(|(t, _)| t.is_empty()) {
        return Vec::new();
    }
    let mut grid: Vec<u64> = traces
        .iter()
        .flat_map(|(t, _)| t.iter().map(|p| p.evaluations))
        .collect();
    grid.sort_unstable();
    grid.dedup();
    let mut next = vec![0usize; traces.len()];
    let mut out: Vec<TracePoint> = Vec::with_capacity(grid.len());
    for e in grid {
        let mut best = 0.0;
        let mut spent = 0u64;
        for ((trace, n), at) in traces.iter().zip(next.iter_mut()) {
            while *at < trace.len() && trace[*at].evaluations <= e {
                *at += 1;
            }
            best += if *at == 0 {
                f64::INFINITY
            } else {
                trace[*at - 1].best
            };
            spent += e.min(*n);
        }
        match out.last_mut() {
            Some(last) if last.evaluations == spent => last.best = best,
            _ => out.push(TracePoint {
                evaluations: spent,
                best,
            }),
        }
    }
    out
}
