//! Binary STL (3D Systems, "StereoLithography Interface Specification",
//! 1988): an 80-byte header, a little-endian u32 triangle count, then per
//! triangle the normal and three vertices as 12 little-endian f32 and a u16
//! attribute count (0). Units are millimetres.

use std::collections::HashMap;
use std::path::Path;

use super::error::CtError;
use super::mesh::Mesh;
use crate::files::write_atomic;

/// The binary STL bytes of `mesh`; `header` (at most 80 bytes used) is
/// padded with spaces and must not start with "solid" (ASCII STL's magic).
pub fn stl_bytes(mesh: &Mesh, header: &str) -> Vec<u8> {
    let mut out = Vec::with_capacity(84 + 50 * mesh.triangles.len());
    let mut h = [b' '; 80];
    let text = header.strip_prefix("solid").unwrap_or(header).as_bytes();
    let k = text.len().min(80);
    h[..k].copy_from_slice(&text[..k]);
    out.extend_from_slice(&h);
    out.extend_from_slice(&(mesh.triangles.len() as u32).to_le_bytes());
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for c in mesh.normal(t) {
            out.extend_from_slice(&(c as f32).to_le_bytes());
        }
        for &i in tri {
            for c in mesh.vertices[i] {
                out.extend_from_slice(&(c as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&0u16.to_le_bytes());
    }
    out
}

/// Writes `mesh` as binary STL to `path`, atomically (no partial file).
pub fn write_stl(path: &Path, mesh: &Mesh, header: &str) -> Result<(), CtError> {
    write_atomic(path, &stl_bytes(mesh, header))?;
    Ok(())
}

/// Parses binary STL bytes; vertices with identical f32 coordinates are
/// merged, so a watertight mesh stays watertight. Errors on a short or
/// inconsistent file (`path` is only used in messages).
pub fn parse_stl(bytes: &[u8], path: &Path) -> Result<Mesh, CtError> {
    if bytes.len() < 84 {
        return Err(CtError::StlTooShort {
            path: path.to_owned(),
            len: bytes.len(),
        });
    }
    let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
    if bytes.len() != 84 + 50 * n {
        return Err(CtError::StlLength {
            path: path.to_owned(),
            triangles: n,
            expected: 84 + 50 * n,
            found: bytes.len(),
        });
    }
    let f = |o: usize| f32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
    let mut mesh = Mesh::default();
    let mut index: HashMap<[u32; 3], usize> = HashMap::new();
    for t in 0..n {
        let base = 84 + 50 * t + 12;
        let mut tri = [0usize; 3];
        for (k, slot) in tri.iter_mut().enumerate() {
            let o = base + 12 * k;
            let p = [f(o), f(o + 4), f(o + 8)];
            let key = p.map(f32::to_bits);
            *slot = *index.entry(key).or_insert_with(|| {
                mesh.vertices.push(p.map(|c| c as f64));
                mesh.vertices.len() - 1
            });
        }
        mesh.triangles.push(tri);
    }
    Ok(mesh)
}
