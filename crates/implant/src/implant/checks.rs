//! The checks of a spec against its volume that run before anything is
//! computed or written (issue 14's fail-fast rule): every slice the spec
//! names lies in the volume, pixel ends lie in the image and differ, and a
//! given midline crosses the image. An error here leaves the output
//! directory untouched.

use super::pipeline::{check_distinct_ends, slice_index, Ends, ImplantError, MidlineSpec};
use super::spec::ImplantSpec;
use crate::ct::{MidLine, Volume};

/// Checks `spec` against `volume`: the defect, midline, validation and 3D
/// validation slices lie in the volume; each `[[defect.end]]` pixel lies in
/// the image and A ≠ B; a given midline crosses the image.
pub fn check_inputs(spec: &ImplantSpec, volume: &Volume) -> Result<(), ImplantError> {
    let cfg = &spec.defect_config;
    for s in &cfg.slices {
        slice_index(cfg, volume, s.z, "defect slice")?;
        if let Ends::Pixels { a, b } = s.ends {
            check_pixel_ends(volume, s.z, a, b)?;
        }
    }
    match &cfg.midline {
        MidlineSpec::Auto(zs) => {
            for &z in zs {
                slice_index(cfg, volume, z, "midline slice")?;
            }
        }
        MidlineSpec::Given(line) => check_midline(volume, line)?,
    }
    if let Some(val) = &spec.validation {
        for &z in &val.slices {
            slice_index(cfg, volume, z, "validation slice")?;
        }
    }
    if let Some(val) = &spec.validation_3d {
        for &(z0, z1) in &val.ranges {
            slice_index(cfg, volume, z0, "validation_3d slice")?;
            slice_index(cfg, volume, z1, "validation_3d slice")?;
        }
    }
    Ok(())
}

/// A and B given as `(row, col)` pixels on slice `z`: inside the image
/// ([`ImplantError::EndOutside`]) and apart
/// ([`ImplantError::EndsCoincide`]).
fn check_pixel_ends(
    volume: &Volume,
    z: usize,
    a: (f64, f64),
    b: (f64, f64),
) -> Result<(), ImplantError> {
    let (rows, cols) = (volume.ny, volume.nx);
    for (what, (row, col)) in [("A", a), ("B", b)] {
        if row > (rows - 1) as f64 || col > (cols - 1) as f64 {
            return Err(ImplantError::EndOutside {
                z,
                what,
                row,
                col,
                rows,
                cols,
            });
        }
    }
    let (sx, sy) = (volume.spacing.x, volume.spacing.y);
    let mm = |(r, c): (f64, f64)| crate::geometry::Point::new(c * sx, r * sy);
    check_distinct_ends(z, (mm(a), mm(b)), (sx, sy))
}

/// A given midline must cross the image: its x at some row within
/// `0..=(nx − 1)·s_x` ([`ImplantError::MidlineOutside`] otherwise, the
/// usual slip being a column number where millimetres are expected).
fn check_midline(volume: &Volume, line: &MidLine) -> Result<(), ImplantError> {
    let width = (volume.nx - 1) as f64 * volume.spacing.x;
    let height = (volume.ny - 1) as f64 * volume.spacing.y;
    let (x0, x1) = (line.x_at(0.0), line.x_at(height));
    let (lo, hi) = (x0.min(x1), x0.max(x1));
    if hi < 0.0 || lo > width || !(lo.is_finite() && hi.is_finite()) {
        return Err(ImplantError::MidlineOutside {
            x_mm: line.x_at(0.5 * height),
            tilt_deg: line.tilt_deg(),
            width_mm: width,
            cols: volume.nx,
            sx: volume.spacing.x,
        });
    }
    Ok(())
}
