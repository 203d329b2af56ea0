//! Helpers shared by the integration tests that include this module.

/// A right-handed oblique frame: the voxel axes turned 15° about z, then
/// 10° about x.
pub fn oblique_axes() -> [[f64; 3]; 3] {
    let (a, b) = (15f64.to_radians(), 10f64.to_radians());
    let rz = |v: [f64; 3]| {
        [
            a.cos() * v[0] - a.sin() * v[1],
            a.sin() * v[0] + a.cos() * v[1],
            v[2],
        ]
    };
    let rx = |v: [f64; 3]| {
        [
            v[0],
            b.cos() * v[1] - b.sin() * v[2],
            b.sin() * v[1] + b.cos() * v[2],
        ]
    };
    metabezier::ct::IDENTITY_AXES.map(|v| rx(rz(v)))
}
