//! The units of the chapter-6 verdicts: independent regions of the skull.
//!
//! The validation cases are not independent observations: the widths of
//! one position are nested cuts of the same bone, and adjacent slices (or
//! overlapping slice ranges) cut the same region of the vault. Treating
//! them as independent is pseudo-replication (Hurlbert 1984, "Pseudo-
//! replication and the design of ecological field experiments", Ecol.
//! Monogr. 54(2):187–211). A unit is one defect position on one slice
//! cluster ([`UnitKey`]); per case the curve fit's median over its runs
//! minus the baseline's value is the case's difference
//! ([`case_differences`]), a unit's summary is the median of its cases'
//! differences ([`unit_summaries`]), and the test across units
//! ([`crate::stats::across_units`]) sees one summary per unit
//! ([`verdict_row`]). Holm's correction runs over each family, the rows of
//! one table at one scope ([`decide_families`]).

use std::cmp::Ordering;
use std::collections::BTreeMap;
use std::fmt;

use crate::files::fmt_real;
use crate::stats::{
    across_units, decide_family, median, smallest_signed_rank_p, AcrossUnits, Equivalence,
    ShiftInterval, Verdict, VerdictRow, VerdictTest,
};

/// A slice cluster: the slices `first..=last` (original numbering), a
/// maximal run of validation slices or slice ranges that overlap or touch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SliceCluster {
    /// The cluster's first slice.
    pub first: usize,
    /// The cluster's last slice.
    pub last: usize,
}

impl SliceCluster {
    /// Whether the slice range `z0..=z1` lies in the cluster.
    pub fn contains(&self, (z0, z1): (usize, usize)) -> bool {
        self.first <= z0.min(z1) && z0.max(z1) <= self.last
    }
}

impl fmt::Display for SliceCluster {
    /// `z = 64` for one slice, `z = 88–90` for several.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.first == self.last {
            write!(f, "z = {}", self.first)
        } else {
            write!(f, "z = {}–{}", self.first, self.last)
        }
    }
}

/// The clusters of slice ranges `z0..=z1`: maximal sets of ranges that
/// overlap or touch (the next range starts at most one slice after the
/// previous one ends), sorted by their first slice. `[87, 93]`, `[90, 96]`
/// and `[88, 98]` form the one cluster 87–98.
pub fn range_clusters(ranges: &[(usize, usize)]) -> Vec<SliceCluster> {
    let mut sorted: Vec<(usize, usize)> =
        ranges.iter().map(|&(a, b)| (a.min(b), a.max(b))).collect();
    sorted.sort_unstable();
    let mut out: Vec<SliceCluster> = Vec::new();
    for (first, last) in sorted {
        match out.last_mut() {
            Some(c) if first <= c.last.saturating_add(1) => c.last = c.last.max(last),
            _ => out.push(SliceCluster { first, last }),
        }
    }
    out
}

/// The clusters of single slices: maximal runs of consecutive slice
/// numbers ([`range_clusters`] of one-slice ranges). Slices 64, 72, 88, 89
/// and 90 give the clusters 64, 72 and 88–90.
pub fn slice_clusters(slices: &[usize]) -> Vec<SliceCluster> {
    let ranges: Vec<(usize, usize)> = slices.iter().map(|&z| (z, z)).collect();
    range_clusters(&ranges)
}

/// The clusters of single slices that lie at most `max_gap` slices apart
/// (`max_gap = 1`: [`slice_clusters`]). A one-slice validation cut of
/// width `w` on slices less than `w` apart cuts bone a 3D patch of that
/// width would share, so they are one cluster (issue 48): with widths up
/// to 40 mm and 1.5 mm slices, CT 0051's slices 64, 72, 88–90 are one.
pub fn slice_clusters_within(slices: &[usize], max_gap: usize) -> Vec<SliceCluster> {
    let mut sorted = slices.to_vec();
    sorted.sort_unstable();
    let mut out: Vec<SliceCluster> = Vec::new();
    for z in sorted {
        match out.last_mut() {
            Some(c) if z <= c.last.saturating_add(max_gap.max(1)) => c.last = c.last.max(z),
            _ => out.push(SliceCluster { first: z, last: z }),
        }
    }
    out
}

/// The largest slice gap of [`slice_clusters_within`] for cuts up to
/// `widest_mm` wide on slices `slice_mm` apart: slices closer than the
/// widest cut share a unit.
pub fn within_gap(widest_mm: f64, slice_mm: f64) -> usize {
    if !(widest_mm > 0.0 && slice_mm > 0.0) {
        return 1;
    }
    ((widest_mm / slice_mm).ceil() as usize)
        .saturating_sub(1)
        .max(1)
}

/// The cluster of `clusters` holding the slice range `z0..=z1`, if any.
pub fn cluster_of(clusters: &[SliceCluster], range: (usize, usize)) -> Option<SliceCluster> {
    clusters.iter().copied().find(|c| c.contains(range))
}

/// The circular distance (degrees) between two polar angles.
fn angular_distance(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

/// The unit position of each defect position, given each position's
/// widest patch as `(position_deg, half_width_deg)`: positions whose
/// patches overlap on the circle (centres closer than the sum of their
/// half-widths) cut the same bone and form one unit, named by the group's
/// smallest position; the others are their own unit. Returns
/// `(position, unit position)` in the order of `extents`. A position with
/// a non-finite half-width (no patch built) is its own unit.
pub fn position_units(extents: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let n = extents.len();
    let mut group: Vec<usize> = (0..n).collect();
    fn root(g: &mut [usize], mut i: usize) -> usize {
        while g[i] != i {
            g[i] = g[g[i]];
            i = g[i];
        }
        i
    }
    for i in 0..n {
        for j in i + 1..n {
            let ((p, h), (q, k)) = (extents[i], extents[j]);
            if (h + k).is_finite() && angular_distance(p, q) < h + k {
                let (ri, rj) = (root(&mut group, i), root(&mut group, j));
                group[ri.max(rj)] = ri.min(rj);
            }
        }
    }
    let mut name = vec![f64::INFINITY; n];
    for (i, &(position, _)) in extents.iter().enumerate() {
        let r = root(&mut group, i);
        name[r] = name[r].min(position);
    }
    (0..n)
        .map(|i| (extents[i].0, name[root(&mut group, i)]))
        .collect()
}

/// Each of `positions` with the half-width (degrees) of its widest patch
/// among `cells` (`(position_deg, half_width_deg)` of every built case),
/// NaN when none of it was built: the extents [`position_units`] reads.
pub fn position_extents(
    positions: &[f64],
    cells: impl Iterator<Item = (f64, f64)> + Clone,
) -> Vec<(f64, f64)> {
    positions
        .iter()
        .map(|&p| {
            let h = cells
                .clone()
                .filter(|(q, h)| q.to_bits() == p.to_bits() && h.is_finite())
                .map(|c| c.1)
                .fold(f64::NAN, f64::max);
            (p, h)
        })
        .collect()
}

/// The unit position of `position` under `units` ([`position_units`]),
/// `None` where it is not listed.
pub fn unit_position(units: &[(f64, f64)], position: f64) -> Option<f64> {
    units
        .iter()
        .find(|(p, _)| p.to_bits() == position.to_bits())
        .map(|u| u.1)
}

/// The smallest gap (degrees) between the widest patches of two distinct
/// positions (`(position_deg, half_width_deg)`): the circular distance of
/// their centres minus both half-widths; negative when two overlap, `None`
/// with fewer than two finite extents.
pub fn smallest_patch_gap(extents: &[(f64, f64)]) -> Option<f64> {
    let e: Vec<(f64, f64)> = extents
        .iter()
        .copied()
        .filter(|e| e.1.is_finite())
        .collect();
    let mut best: Option<f64> = None;
    for i in 0..e.len() {
        for j in i + 1..e.len() {
            let g = angular_distance(e[i].0, e[j].0) - e[i].1 - e[j].1;
            best = Some(best.map_or(g, |b: f64| b.min(g)));
        }
    }
    best
}

/// An independent unit of the validation: a defect position (polar angle,
/// degrees) on a slice cluster. With several CTs the patient would be a
/// third field of the key (one CT so far).
#[derive(Clone, Copy, Debug)]
pub struct UnitKey {
    /// The slice cluster.
    pub cluster: SliceCluster,
    /// The position's polar angle (degrees).
    pub position_deg: f64,
}

impl Ord for UnitKey {
    /// By cluster, then by position ([`f64::total_cmp`]).
    fn cmp(&self, other: &Self) -> Ordering {
        self.cluster
            .cmp(&other.cluster)
            .then(self.position_deg.total_cmp(&other.position_deg))
    }
}

impl PartialOrd for UnitKey {
    /// [`UnitKey::cmp`].
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for UnitKey {
    /// The same cluster and the same position bits.
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for UnitKey {}

impl fmt::Display for UnitKey {
    /// `z = 88–90, 200°`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}, {}°", self.cluster, fmt_real(self.position_deg))
    }
}

/// A validation case: its slice range (`(z, z)` for one slice), position
/// and width, ordered by [`f64::total_cmp`] on the reals.
#[derive(Clone, Copy, Debug)]
pub struct CaseId {
    /// First and last slice.
    pub slices: (usize, usize),
    /// The position's polar angle (degrees).
    pub position_deg: f64,
    /// The width (mm).
    pub width_mm: f64,
}

impl Ord for CaseId {
    /// By slices, position, then width.
    fn cmp(&self, other: &Self) -> Ordering {
        self.slices
            .cmp(&other.slices)
            .then(self.position_deg.total_cmp(&other.position_deg))
            .then(self.width_mm.total_cmp(&other.width_mm))
    }
}

impl PartialOrd for CaseId {
    /// [`CaseId::cmp`].
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for CaseId {
    /// The same slices and the same position and width bits.
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for CaseId {}

/// One reconstruction's value of one metric: the case, its unit, the
/// method (`template`, `straight`, `curve:<name>`) and the value.
#[derive(Clone, Copy, Debug)]
pub struct Observation<'r> {
    /// The case.
    pub case: CaseId,
    /// The case's unit.
    pub unit: UnitKey,
    /// The method.
    pub method: &'r str,
    /// The metric's value (non-finite values are left out).
    pub value: f64,
}

impl<'r> Observation<'r> {
    /// The observation of a case through `slices` (first, last) at a
    /// position and width: its unit is the cluster of `clusters` that holds
    /// the slices (the slices themselves when none does) at that position.
    pub fn at(
        clusters: &[SliceCluster],
        slices: (usize, usize),
        (position_deg, width_mm): (f64, f64),
        method: &'r str,
        value: f64,
    ) -> Self {
        let cluster = cluster_of(clusters, slices).unwrap_or(SliceCluster {
            first: slices.0.min(slices.1),
            last: slices.0.max(slices.1),
        });
        Observation {
            case: CaseId {
                slices,
                position_deg,
                width_mm,
            },
            unit: UnitKey {
                cluster,
                position_deg,
            },
            method,
            value,
        }
    }
}

/// One case's difference d = median over the compared method's runs −
/// median over the reference's runs (one run for the deterministic
/// baselines).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CaseDifference {
    /// The case.
    pub case: CaseId,
    /// The case's unit.
    pub unit: UnitKey,
    /// The difference.
    pub difference: f64,
}

/// Differences within this relative tolerance of the values compared are
/// ties: the same distance reached by two sums in a different order (an
/// HD95 of √(1.5² + 0.957²) mm, say) differs in its last bits, and would
/// otherwise count as a unit better or worse by 10⁻¹⁶.
pub const TIE_TOLERANCE: f64 = 1e-12;

/// Per case of `obs`, the median of `algorithm`'s finite values minus the
/// median of `reference`'s, for the cases where both have one, sorted by
/// case; a difference within [`TIE_TOLERANCE`] of the medians is 0.
pub fn case_differences(
    obs: &[Observation<'_>],
    algorithm: &str,
    reference: &str,
) -> Vec<CaseDifference> {
    let mut by_case: BTreeMap<CaseId, (UnitKey, Vec<f64>, Vec<f64>)> = BTreeMap::new();
    for o in obs.iter().filter(|o| o.value.is_finite()) {
        let side = if o.method == algorithm {
            0
        } else if o.method == reference {
            1
        } else {
            continue;
        };
        let e = by_case
            .entry(o.case)
            .or_insert_with(|| (o.unit, Vec::new(), Vec::new()));
        if side == 0 {
            e.1.push(o.value);
        } else {
            e.2.push(o.value);
        }
    }
    by_case
        .into_iter()
        .filter(|(_, (_, a, r))| !a.is_empty() && !r.is_empty())
        .map(|(case, (unit, a, r))| {
            let (ma, mr) = (median(&a), median(&r));
            let d = ma - mr;
            let tie = d.abs() <= TIE_TOLERANCE * ma.abs().max(mr.abs());
            CaseDifference {
                case,
                unit,
                difference: if tie { 0.0 } else { d },
            }
        })
        .collect()
}

/// One unit's summary: the median of its cases' differences.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnitSummary {
    /// The unit.
    pub unit: UnitKey,
    /// The cases pooled into it.
    pub cases: usize,
    /// The median of their differences.
    pub summary: f64,
}

/// The unit summaries of `diffs`, sorted by unit: per unit, the median of
/// its cases' differences (the nested widths and the slices of its
/// cluster).
pub fn unit_summaries(diffs: &[CaseDifference]) -> Vec<UnitSummary> {
    let mut by_unit: BTreeMap<UnitKey, Vec<f64>> = BTreeMap::new();
    for d in diffs {
        by_unit.entry(d.unit).or_default().push(d.difference);
    }
    by_unit
        .into_iter()
        .map(|(unit, d)| UnitSummary {
            unit,
            cases: d.len(),
            summary: median(&d),
        })
        .collect()
}

/// What a verdict row compares: its table, measure, the compared
/// algorithm and the reference, and which sign of the difference favours
/// the algorithm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comparison<'a> {
    /// `validation-2d` or `validation-3d`.
    pub table: &'a str,
    /// The measure's name in `verdicts.csv` (`dice`, `hd95-mm`, …).
    pub measure: &'a str,
    /// The compared algorithm (`curve:mhs`).
    pub algorithm: &'a str,
    /// The reference (`template`, `straight`).
    pub reference: &'a str,
    /// Whether a lower value of the measure is better.
    pub lower_is_better: bool,
    /// The half-width of the measure's region of practical equivalence
    /// ([`ImplantRopes::of`]).
    pub rope: f64,
}

/// The regions of practical equivalence of the validation's measures, for
/// the Bayesian signed-rank test beside every verdict (Benavoli, Corani,
/// Demšar & Zaffalon 2017, JMLR 18(77):1–36): the spec's `rope_overlap`
/// and `rope_mm` of `[validation]` and `[validation_3d]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImplantRopes {
    /// Dice and boundary Dice (default 0.01: one hundredth of the overlap,
    /// below the spread between expert segmentations of bone, e.g. Dice
    /// 0.95–0.98 in the AutoImplant challenge's inter-rater comparison).
    pub overlap: f64,
    /// HD95 and the mean and maximum deviations in mm (default 0.5 mm:
    /// half the in-plane pixel of a head CT and below a printed implant's
    /// manufacturing tolerance).
    pub distance_mm: f64,
}

impl Default for ImplantRopes {
    fn default() -> Self {
        ImplantRopes {
            overlap: 0.01,
            distance_mm: 0.5,
        }
    }
}

impl ImplantRopes {
    /// The rope of the measure named `measure` in `verdicts.csv`: an
    /// overlap (`dice`, `boundary-dice`) or a distance (the others, in mm).
    pub fn of(&self, measure: &str) -> f64 {
        if measure.ends_with("dice") {
            self.overlap
        } else {
            self.distance_mm
        }
    }
}

/// The verdict row of `cmp` at `scope` over the case differences `diffs`
/// (already restricted to the scope): the Wilcoxon signed-rank test of the
/// unit summaries against zero ([`across_units`]), verdict undecided until
/// [`decide_families`]. Without a unit the p-value is NaN and the row stays
/// out of its family's correction.
pub fn verdict_row(cmp: &Comparison<'_>, scope: &str, diffs: &[CaseDifference]) -> VerdictRow {
    let s: Vec<f64> = unit_summaries(diffs).iter().map(|u| u.summary).collect();
    let across = across_units(&s, cmp.lower_is_better).unwrap_or(AcrossUnits {
        units: s.len(),
        better: 0,
        equal: 0,
        worse: 0,
        p_value: f64::NAN,
        p_min: smallest_signed_rank_p(0),
        effect_size: f64::NAN,
        improvement: f64::NAN,
    });
    let mut row = VerdictRow {
        table: cmp.table.to_owned(),
        measure: cmp.measure.to_owned(),
        algorithm: cmp.algorithm.to_owned(),
        reference: cmp.reference.to_owned(),
        scope: scope.to_owned(),
        problems: diffs.len(),
        test: VerdictTest::WilcoxonSignedRank,
        across,
        p_adjusted: f64::NAN,
        family: 0,
        shift: ShiftInterval::unknown(),
        equivalence: Equivalence::unknown(cmp.rope),
        verdict: Verdict::Undecided,
    };
    row.weigh(&s, cmp.lower_is_better, cmp.rope);
    row
}

/// The scope of one width: `width_mm=20`.
pub fn width_scope(width_mm: f64) -> String {
    format!("width_mm={}", fmt_real(width_mm))
}

/// The verdict rows of `cmp`: scope `all` over every case difference, then
/// one scope per width of `widths` ([`width_scope`]) over that width's
/// cases; paired with the cases favouring the algorithm (descriptive: the
/// cases are not independent).
pub fn scoped_rows(
    cmp: &Comparison<'_>,
    diffs: &[CaseDifference],
    widths: &[f64],
) -> Vec<(VerdictRow, usize)> {
    let favours = |d: &[CaseDifference]| {
        d.iter()
            .filter(|c| {
                if cmp.lower_is_better {
                    c.difference < 0.0
                } else {
                    c.difference > 0.0
                }
            })
            .count()
    };
    let mut out = vec![(verdict_row(cmp, "all", diffs), favours(diffs))];
    for &w in widths {
        let d: Vec<CaseDifference> = diffs
            .iter()
            .copied()
            .filter(|c| c.case.width_mm.to_bits() == w.to_bits())
            .collect();
        out.push((verdict_row(cmp, &width_scope(w), &d), favours(&d)));
    }
    out
}

/// Decides every family of `rows` at level `alpha`: the rows of one table
/// at one scope, Holm-corrected together ([`decide_family`]). Rows without
/// a p-value (no unit) keep p_adjusted NaN and no verdict, and do not count
/// in their family's correction.
pub fn decide_families(rows: &mut [VerdictRow], alpha: f64) {
    let mut families: Vec<(String, String)> = Vec::new();
    for r in rows.iter() {
        let k = (r.table.clone(), r.scope.clone());
        if !families.contains(&k) {
            families.push(k);
        }
    }
    for (table, scope) in families {
        let idx: Vec<usize> = (0..rows.len())
            .filter(|&i| rows[i].table == table && rows[i].scope == scope)
            .collect();
        let (tested, untested): (Vec<usize>, Vec<usize>) = idx
            .into_iter()
            .partition(|&i| !rows[i].across.p_value.is_nan());
        let mut family: Vec<VerdictRow> = tested.iter().map(|&i| rows[i].clone()).collect();
        decide_family(&mut family, alpha);
        for (i, r) in tested.into_iter().zip(family) {
            rows[i] = r;
        }
        for i in untested {
            rows[i].p_adjusted = f64::NAN;
            rows[i].verdict = Verdict::Undecided;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(first: usize, last: usize) -> SliceCluster {
        SliceCluster { first, last }
    }

    #[test]
    fn overlapping_patches_are_one_unit_across_zero_degrees() {
        // 350° and 10° (half-widths 12°) overlap across 0°; 90° and 120°
        // (half-widths 14° and 17°) overlap over 103°–104°; 200° stands
        // alone, as would 120° with a half-width of 15° (a 1° gap).
        let e = [
            (350.0, 12.0),
            (90.0, 14.0),
            (10.0, 12.0),
            (120.0, 17.0),
            (200.0, 14.0),
        ];
        let u = position_units(&e);
        assert_eq!(
            u,
            vec![
                (350.0, 10.0),
                (90.0, 90.0),
                (10.0, 10.0),
                (120.0, 90.0),
                (200.0, 200.0)
            ]
        );
        assert!((smallest_patch_gap(&e).unwrap() - (-4.0)).abs() < 1e-12);
        let touching = [(90.0, 14.0), (120.0, 15.0)];
        assert!(position_units(&touching).iter().all(|(p, u)| p == u));
        // Apart: every position its own unit.
        let apart = [(0.0, 10.0), (30.0, 10.0), (330.0, 10.0)];
        assert!(position_units(&apart).iter().all(|(p, u)| p == u));
        assert!((smallest_patch_gap(&apart).unwrap() - 10.0).abs() < 1e-12);
    }

    #[test]
    fn slices_cluster_by_adjacency() {
        assert_eq!(
            slice_clusters(&[64, 72, 88, 89, 90]),
            vec![c(64, 64), c(72, 72), c(88, 90)]
        );
        assert_eq!(slice_clusters(&[88]), vec![c(88, 88)]);
        // Non-adjacent slices, unsorted and repeated: each its own cluster.
        assert_eq!(
            slice_clusters(&[90, 70, 88, 70]),
            vec![c(70, 70), c(88, 88), c(90, 90)]
        );
        assert!(slice_clusters(&[]).is_empty());
        let cl = slice_clusters(&[64, 72, 88, 89, 90]);
        assert_eq!(cluster_of(&cl, (89, 89)), Some(c(88, 90)));
        assert_eq!(cluster_of(&cl, (65, 65)), None);
        assert_eq!(c(88, 90).to_string(), "z = 88–90");
        assert_eq!(c(64, 64).to_string(), "z = 64");
    }

    #[test]
    fn ranges_cluster_when_they_overlap_or_touch() {
        assert_eq!(
            range_clusters(&[(87, 93), (90, 96), (88, 98)]),
            vec![c(87, 98)]
        );
        // Touching (94 follows 93) joins; a gap of one slice does not.
        assert_eq!(range_clusters(&[(87, 93), (94, 96)]), vec![c(87, 96)]);
        assert_eq!(
            range_clusters(&[(95, 99), (87, 93)]),
            vec![c(87, 93), c(95, 99)]
        );
        assert_eq!(range_clusters(&[(60, 62)]), vec![c(60, 62)]);
        // A range nested in a longer one.
        assert_eq!(range_clusters(&[(80, 99), (85, 90)]), vec![c(80, 99)]);
        let cl = range_clusters(&[(87, 93), (90, 96), (88, 98)]);
        assert_eq!(cluster_of(&cl, (90, 96)), Some(c(87, 98)));
    }

    /// A hand-made set: two clusters × two positions, the curve method
    /// with two runs, the baseline with one.
    #[test]
    fn unit_summaries_by_hand() {
        let cl = slice_clusters(&[10, 11, 20]);
        let mut obs = Vec::new();
        let mut add = |z: usize, pos: f64, w: f64, method: &'static str, v: f64| {
            obs.push(Observation {
                case: CaseId {
                    slices: (z, z),
                    position_deg: pos,
                    width_mm: w,
                },
                unit: UnitKey {
                    cluster: cluster_of(&cl, (z, z)).unwrap(),
                    position_deg: pos,
                },
                method,
                value: v,
            });
        };
        // Unit (10–11, 0°): cases (10, w20), (10, w30), (11, w20).
        add(10, 0.0, 20.0, "curve:x", 0.9);
        add(10, 0.0, 20.0, "curve:x", 0.7); // median 0.8
        add(10, 0.0, 20.0, "base", 0.5); // d = 0.3
        add(10, 0.0, 30.0, "curve:x", 0.6);
        add(10, 0.0, 30.0, "curve:x", 0.6);
        add(10, 0.0, 30.0, "base", 0.7); // d = -0.1
        add(11, 0.0, 20.0, "curve:x", 0.9);
        add(11, 0.0, 20.0, "curve:x", 1.1);
        add(11, 0.0, 20.0, "base", 0.8); // d = 0.2
                                         // → median(0.3, -0.1, 0.2) = 0.2.
                                         // Unit (10–11, 90°): one case; the baseline's value non-finite in
                                         // another (left out), a third method ignored.
        add(10, 90.0, 20.0, "curve:x", 0.5);
        add(10, 90.0, 20.0, "base", 0.25); // d = 0.25
        add(11, 90.0, 20.0, "curve:x", 0.5);
        add(11, 90.0, 20.0, "base", f64::NAN);
        add(11, 90.0, 20.0, "other", 0.0);
        // Unit (20, 0°): two widths, d = -0.5 and 0.3 → median -0.1.
        add(20, 0.0, 20.0, "curve:x", 0.5);
        add(20, 0.0, 20.0, "base", 1.0);
        add(20, 0.0, 30.0, "curve:x", 0.8);
        add(20, 0.0, 30.0, "base", 0.5);
        let d = case_differences(&obs, "curve:x", "base");
        assert_eq!(d.len(), 6);
        let u = unit_summaries(&d);
        let got: Vec<(usize, f64, usize)> = u
            .iter()
            .map(|s| (s.unit.cluster.first, s.unit.position_deg, s.cases))
            .collect();
        assert_eq!(got, vec![(10, 0.0, 3), (10, 90.0, 1), (20, 0.0, 2)]);
        let want = [0.2, 0.25, -0.1];
        for (s, w) in u.iter().zip(want) {
            assert!((s.summary - w).abs() < 1e-12, "{} {}", s.unit, s.summary);
        }
        // Higher is better: two units better, one worse; effect = median
        // of (0.2, 0.25, -0.1) = 0.2. Ranks of |s|: 0.1 → 1, 0.2 → 2,
        // 0.25 → 3, so R⁻ = 1 of n = 3 and the exact two-sided p is
        // 2·P(R⁻ ≤ 1) = 2·2/8 = 0.5 (subsets {} and {1} of {1, 2, 3}).
        let cmp = Comparison {
            table: "t",
            measure: "dice",
            algorithm: "curve:x",
            reference: "base",
            lower_is_better: false,
            rope: 0.01,
        };
        let rows = scoped_rows(&cmp, &d, &[20.0, 30.0]);
        let scopes: Vec<&str> = rows.iter().map(|r| r.0.scope.as_str()).collect();
        assert_eq!(scopes, ["all", "width_mm=20", "width_mm=30"]);
        let all = &rows[0].0;
        assert_eq!(
            (
                all.across.units,
                all.across.better,
                all.across.worse,
                all.problems
            ),
            (3, 2, 1, 6)
        );
        assert!((all.across.effect_size - 0.2).abs() < 1e-12);
        assert!(
            (all.across.p_value - 0.5).abs() < 1e-12,
            "{}",
            all.across.p_value
        );
        assert_eq!(all.across.p_min, 0.25);
        assert_eq!(rows[0].1, 4); // cases with d > 0
                                  // Width 30: units (10–11, 0°) with d = -0.1 and (20, 0°) with 0.3.
        let w30 = &rows[2].0;
        assert_eq!((w30.across.units, w30.problems), (2, 2));
        assert_eq!((w30.across.better, w30.across.worse), (1, 1));
    }

    #[test]
    fn the_same_distance_summed_in_another_order_is_a_tie() {
        let clusters = slice_clusters(&[10]);
        let hd = (1.5f64 * 1.5 + 0.957 * 0.957).sqrt();
        let noisy = (0.957f64 * 0.957 + 1.5 * 1.5).sqrt() + 2.0 * f64::EPSILON;
        assert_ne!(hd, noisy);
        let obs = [
            Observation::at(&clusters, (10, 10), (0.0, 20.0), "curve:x", noisy),
            Observation::at(&clusters, (10, 10), (0.0, 20.0), "base", hd),
            Observation::at(&clusters, (10, 10), (0.0, 30.0), "curve:x", 1.0),
            Observation::at(&clusters, (10, 10), (0.0, 30.0), "base", 1.5),
        ];
        let d = case_differences(&obs, "curve:x", "base");
        assert_eq!(d[0].difference, 0.0);
        assert_eq!(d[1].difference, -0.5);
    }

    #[test]
    fn families_are_one_table_at_one_scope() {
        let unit = |p: f64| UnitKey {
            cluster: c(1, 1),
            position_deg: p,
        };
        let diffs: Vec<CaseDifference> = (0..8)
            .map(|i| CaseDifference {
                case: CaseId {
                    slices: (1, 1),
                    position_deg: i as f64,
                    width_mm: 20.0,
                },
                unit: unit(i as f64),
                difference: -1.0 - i as f64,
            })
            .collect();
        let cmp = |measure| Comparison {
            table: "t",
            measure,
            algorithm: "a",
            reference: "r",
            lower_is_better: true,
            rope: 0.5,
        };
        let mut rows: Vec<VerdictRow> = Vec::new();
        // Eight units, all better: p = 2/256 each; two measures in one
        // family give Holm p = 2 · 2/256 = 0.015625 < 0.05.
        for m in ["hd95-mm", "max-deviation-mm"] {
            rows.extend(scoped_rows(&cmp(m), &diffs, &[]).into_iter().map(|r| r.0));
        }
        // Another table's row with no unit: NaN, not counted.
        rows.push(verdict_row(
            &Comparison {
                table: "u",
                ..cmp("dice")
            },
            "all",
            &[],
        ));
        decide_families(&mut rows, 0.05);
        for r in &rows[..2] {
            assert!((r.p_adjusted - 0.015625).abs() < 1e-12, "{}", r.p_adjusted);
            assert_eq!(r.verdict, Verdict::Better);
        }
        assert!(rows[2].p_adjusted.is_nan() && rows[2].across.units == 0);
        assert_eq!(rows[2].verdict, Verdict::Undecided);
        // At α = 0.01 the same family does not reject.
        decide_families(&mut rows, 0.01);
        assert_eq!(rows[0].verdict, Verdict::Undecided);
    }
}
