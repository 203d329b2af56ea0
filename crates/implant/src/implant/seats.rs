//! The seats A′ and B′ of a stack of slices, chosen jointly so that the
//! implant's edge follows the bone without jumping between slices
//! (RECONSTRUCTION: the surviving thesis text names A and B but does not
//! say how they are placed from slice to slice).

use super::polar::SEAT_STEP_MM;

/// What one side of one slice offers as seats: per candidate
/// `s_k = k·0.25` mm behind the bone tip ([`super::wall::seat_profiles`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SeatProfile {
    /// The bend of the outer table there (degrees): the angle between the
    /// 3 mm secant after the seat and the next 3 mm secant.
    pub bend_deg: Vec<f64>,
    /// The kink a wall joined there would make against the bone (degrees):
    /// the largest angle between the bone's iso-contour secant over 1.5 mm
    /// (3 mm) from the seat and either the join tangent at the seat or the
    /// secant over the last 1.5 mm (3 mm) of the template blended onto the
    /// bone there (`Gap::blended_near_seat`), the wall's expected end turn.
    pub kink_deg: Vec<f64>,
    /// How far the template lies from the bone at the seat (mm, signed as
    /// [`super::polar::Blend::offset_mm`]).
    pub offset_mm: Vec<f64>,
}

/// How seats are chosen ([`choose_seats`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeatRule {
    /// The table bend accepted at a seat (degrees; `seat_bend_deg`).
    pub bend_deg: f64,
    /// The kink accepted at a seat (degrees); each degree above costs 10.
    pub kink_deg: f64,
    /// The template–bone offset accepted at a seat (mm).
    pub offset_tol_mm: f64,
    /// The cost of each mm of offset above `offset_tol_mm` (degrees per mm).
    pub offset_deg_per_mm: f64,
    /// The cost of each mm a seat lies behind the bone tip (degrees per
    /// mm): the implant should not cover more intact bone than it must.
    pub setback_deg_per_mm: f64,
    /// The cost of moving a seat between adjacent slices (degrees per mm).
    pub change_deg_per_mm: f64,
}

impl SeatProfile {
    /// The number of candidates.
    pub fn len(&self) -> usize {
        self.bend_deg.len()
    }

    /// Whether there is no candidate.
    pub fn is_empty(&self) -> bool {
        self.bend_deg.is_empty()
    }

    /// The cost of candidate `k` under `rule` (degrees):
    /// `max(0, bend − bend_deg) + 10·max(0, kink − kink_deg)
    /// + μ·max(0, |offset| − tol) + ν·s_k` (`ν` the setback cost).
    pub fn cost(&self, k: usize, rule: &SeatRule) -> f64 {
        let at = |v: &[f64]| v.get(k).copied().unwrap_or(0.0);
        (at(&self.bend_deg) - rule.bend_deg).max(0.0)
            + 10.0 * (at(&self.kink_deg) - rule.kink_deg).max(0.0)
            + rule.offset_deg_per_mm * (at(&self.offset_mm).abs() - rule.offset_tol_mm).max(0.0)
            + rule.setback_deg_per_mm * k as f64 * SEAT_STEP_MM
    }
}

/// The seats of a stack of slices (`zs`), per side, by dynamic programming
/// (Viterbi) over the candidate seats `s_k = k·0.25` mm: they minimise
/// `Σ_z cost_z(s_z) + λ·Σ |s_z − s_{z+1}|` (adjacent slices only), the
/// cost of [`SeatProfile::cost`] (the table's excess bend, the excess
/// kink a wall joined there would make against the bone, the template's
/// excess offset from the bone, the setback behind the tip) and `λ = rule.change_deg_per_mm` degrees per mm of seat change
/// between slices, so the implant's edge follows the bone without
/// jumping. One slice (or `λ = 0`) gets its cheapest seat.
pub fn choose_seats(
    profiles: &[(SeatProfile, SeatProfile)],
    zs: &[usize],
    rule: &SeatRule,
) -> Vec<(f64, f64)> {
    let a = viterbi(&profiles.iter().map(|b| &b.0).collect::<Vec<_>>(), zs, rule);
    let b = viterbi(&profiles.iter().map(|b| &b.1).collect::<Vec<_>>(), zs, rule);
    a.into_iter().zip(b).collect()
}

/// One side of [`choose_seats`].
fn viterbi(profiles: &[&SeatProfile], zs: &[usize], rule: &SeatRule) -> Vec<f64> {
    let step = SEAT_STEP_MM;
    let lambda = rule.change_deg_per_mm;
    let n = profiles.len();
    let mut acc: Vec<Vec<f64>> = Vec::with_capacity(n);
    let mut from: Vec<Vec<usize>> = Vec::with_capacity(n);
    for i in 0..n {
        let row: Vec<(f64, usize)> = (0..profiles[i].len())
            .map(|k| {
                let here = profiles[i].cost(k, rule);
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
    let Some(last) = acc.last() else {
        return Vec::new();
    };
    let mut k = (0..last.len())
        .min_by(|&x, &y| last[x].total_cmp(&last[y]))
        .unwrap_or(0);
    let mut out = vec![0.0; n];
    for i in (0..n).rev() {
        out[i] = k as f64 * step;
        k = from[i].get(k).copied().unwrap_or(0);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn profile(bend: &[f64], kink: &[f64], offset: &[f64]) -> SeatProfile {
        SeatProfile {
            bend_deg: bend.to_vec(),
            kink_deg: kink.to_vec(),
            offset_mm: offset.to_vec(),
        }
    }

    const RULE: SeatRule = SeatRule {
        bend_deg: 3.0,
        kink_deg: 8.0,
        offset_tol_mm: 1.0,
        offset_deg_per_mm: 2.0,
        setback_deg_per_mm: 0.01,
        change_deg_per_mm: 0.0,
    };

    #[test]
    fn a_seat_moves_off_a_corner_and_towards_agreement() {
        // A 40° corner at the tip, then straight table: the seat leaves it.
        let p = profile(&[0.0; 5], &[40.0, 30.0, 9.0, 2.0, 2.0], &[0.0; 5]);
        assert_eq!(
            choose_seats(&[(p.clone(), p)], &[0], &RULE)[0],
            (0.75, 0.75)
        );
        // Straight table, the template 4 mm off at the tip and agreeing
        // 0.5 mm back: the seat goes where they agree.
        let p = profile(&[0.0; 4], &[0.0; 4], &[4.0, 2.0, 0.5, 0.5]);
        assert_eq!(choose_seats(&[(p.clone(), p)], &[0], &RULE)[0], (0.5, 0.5));
    }

    #[test]
    fn seats_change_smoothly_between_adjacent_slices() {
        // Slice 1 prefers the tip weakly; a large change cost keeps it with
        // its neighbour's seat.
        let far = profile(&[9.0, 9.0, 9.0, 0.0], &[0.0; 4], &[0.0; 4]);
        let near = profile(&[0.0, 0.0, 0.0, 0.5], &[0.0; 4], &[0.0; 4]);
        let rule = SeatRule {
            change_deg_per_mm: 20.0,
            ..RULE
        };
        let s = choose_seats(&[(far.clone(), far), (near.clone(), near)], &[5, 6], &rule);
        assert_eq!(s, vec![(0.75, 0.75), (0.75, 0.75)]);
    }
}
