//! Exact Euclidean distance transform with anisotropic spacing, by the
//! separable lower-envelope-of-parabolas algorithm of Felzenszwalb &
//! Huttenlocher, "Distance transforms of sampled functions", Theory of
//! Computing 8 (2012): one 1D pass per axis, linear time.

use super::mask::Mask3;

/// 1D squared distance transform of `f` sampled at positions `q·s`:
/// `d(q) = min_p (s²(q − p)² + f(p))`; infinite samples are not sites.
fn dt1d(f: &[f64], s: f64, d: &mut [f64], v: &mut [usize], zb: &mut [f64]) {
    let n = f.len();
    let pos = |q: usize| q as f64 * s;
    let mut k: isize = -1;
    for q in 0..n {
        if !f[q].is_finite() {
            continue;
        }
        loop {
            if k < 0 {
                k = 0;
                v[0] = q;
                zb[0] = f64::NEG_INFINITY;
                zb[1] = f64::INFINITY;
                break;
            }
            let p = v[k as usize];
            let x =
                ((f[q] + pos(q) * pos(q)) - (f[p] + pos(p) * pos(p))) / (2.0 * (pos(q) - pos(p)));
            if x <= zb[k as usize] {
                k -= 1;
                continue;
            }
            k += 1;
            v[k as usize] = q;
            zb[k as usize] = x;
            zb[k as usize + 1] = f64::INFINITY;
            break;
        }
    }
    if k < 0 {
        d.iter_mut().for_each(|x| *x = f64::INFINITY);
        return;
    }
    let mut j = 0usize;
    for (q, out) in d.iter_mut().enumerate() {
        while zb[j + 1] < pos(q) {
            j += 1;
        }
        let p = v[j];
        let dx = pos(q) - pos(p);
        *out = dx * dx + f[p];
    }
}

/// Squared Euclidean distances in mm² from every voxel to the nearest true
/// voxel of `sites` (0 on sites, ∞ everywhere when there is none), with the
/// mask's anisotropic spacing.
pub fn edt_squared(sites: &Mask3) -> Vec<f64> {
    let (nx, ny, nz) = (sites.nx, sites.ny, sites.nz);
    let mut g: Vec<f64> = sites
        .data
        .iter()
        .map(|&b| if b { 0.0 } else { f64::INFINITY })
        .collect();
    let nmax = nx.max(ny).max(nz);
    let (mut f, mut d) = (vec![0.0; nmax], vec![0.0; nmax]);
    let (mut v, mut zb) = (vec![0usize; nmax], vec![0.0; nmax + 1]);
    let sp = sites.spacing;
    // Along x.
    for z in 0..nz {
        for y in 0..ny {
            let o = (z * ny + y) * nx;
            f[..nx].copy_from_slice(&g[o..o + nx]);
            dt1d(&f[..nx], sp.x, &mut d[..nx], &mut v, &mut zb);
            g[o..o + nx].copy_from_slice(&d[..nx]);
        }
    }
    // Along y.
    for z in 0..nz {
        for x in 0..nx {
            for y in 0..ny {
                f[y] = g[(z * ny + y) * nx + x];
            }
            dt1d(&f[..ny], sp.y, &mut d[..ny], &mut v, &mut zb);
            for y in 0..ny {
                g[(z * ny + y) * nx + x] = d[y];
            }
        }
    }
    // Along z.
    for y in 0..ny {
        for x in 0..nx {
            for z in 0..nz {
                f[z] = g[(z * ny + y) * nx + x];
            }
            dt1d(&f[..nz], sp.z, &mut d[..nz], &mut v, &mut zb);
            for z in 0..nz {
                g[(z * ny + y) * nx + x] = d[z];
            }
        }
    }
    g
}
