//! Which slices of a design are refused, and the mesh of the rest (issue
//! 48): a slice whose design fails a [`super::plausibility`] check is left
//! out of the smoothing across slices; a finished slice that fails one is
//! left out of the mesh. The accepted slices are lofted run by run (a run:
//! accepted slices adjacent in the design's slice list), so no piece of
//! implant bridges a refused slice; the runs' closed meshes together are
//! the implant.

use super::plausibility::{
    design_values, head_hull, measure_wall, width_jumps, CheckValues, Finding, DESIGN_CHECKS,
};
use super::wall::{finish_wall, OuterDesign, Wall, WallKind, WallOptions};
use crate::ct::{ConvexHull, MidLine, Polyline, Volume};

/// The design checks of a stack of outer designs at slices `zs`: each
/// slice's values (widths against neighbours, template, fit) and what fails.
pub fn design_checks(
    designs: &[OuterDesign],
    zs: &[usize],
    (options, kind): (&WallOptions, WallKind),
) -> Vec<(CheckValues, Vec<Finding>)> {
    let widths: Vec<f64> = designs.iter().map(OuterDesign::width).collect();
    let jumps = width_jumps(&widths, zs);
    designs
        .iter()
        .zip(jumps)
        .map(|(d, (jump, neighbours))| {
            let mut v = design_values(d, kind);
            v.width_jump_mm = jump;
            v.neighbour_width_mm = neighbours;
            let f = v.findings_of(&DESIGN_CHECKS, &options.checks);
            (v, f)
        })
        .collect()
}

/// A refused design finished as well as it goes, for its row of
/// `metrics.csv`: at its own bone thickness and not clipped (it goes into
/// no mesh, and a wild wall's clipping grid is what a design must not pay
/// for), or with an empty section where even that fails.
pub fn finish_refused(design: OuterDesign, options: &WallOptions) -> Wall {
    let t = design.bone_thickness;
    match finish_wall(design.clone(), t, None, options) {
        Ok(w) => w,
        Err(_) => Wall {
            design,
            inner: Polyline::open(Vec::new()),
            raw_section: Polyline::closed(Vec::new()),
            section: Polyline::closed(Vec::new()),
            thickness: t,
            clipped_fraction: f64::NAN,
        },
    }
}

/// Every check of a finished wall: its own values on the head's hull, the
/// width jump carried over from the design checks.
pub fn wall_checks(
    (wall, kind): (&Wall, WallKind),
    hull: &ConvexHull,
    design: &CheckValues,
    options: &WallOptions,
) -> (CheckValues, Vec<Finding>) {
    let mut v = measure_wall(wall, hull, kind);
    v.width_jump_mm = design.width_jump_mm;
    v.neighbour_width_mm = design.neighbour_width_mm;
    let f = v.findings(&options.checks);
    (v, f)
}

/// The head hull of a slice of `volume` with bone mask `mask`.
pub fn slice_hull(volume: &Volume, mask: &crate::ct::Mask2, midline: &MidLine) -> ConvexHull {
    head_hull(mask, (volume.spacing.x, volume.spacing.y), midline)
}

/// The runs of accepted slices: maximal sequences of positions in the
/// slice list whose slices are all accepted.
pub fn accepted_runs(accepted: &[bool]) -> Vec<Vec<usize>> {
    let mut runs: Vec<Vec<usize>> = Vec::new();
    let mut current = Vec::new();
    for (i, &ok) in accepted.iter().enumerate() {
        if ok {
            current.push(i);
        } else if !current.is_empty() {
            runs.push(std::mem::take(&mut current));
        }
    }
    if !current.is_empty() {
        runs.push(current);
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refused_slices_split_the_runs() {
        assert_eq!(
            accepted_runs(&[true, true, false, true, false, false, true]),
            vec![vec![0, 1], vec![3], vec![6]]
        );
        assert!(accepted_runs(&[false, false]).is_empty());
    }
}
