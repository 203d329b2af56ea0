//! Meshes, STL, voxels and the metrics: lofts, ear clipping, watertight round
//! trips, Dice, HD95, the distance transform and contour deviation.

use super::*;

#[test]
fn loft_of_circles_is_a_closed_oriented_cylinder() {
    let r = 10.0;
    let sections: Vec<Polyline> = (0..5)
        .map(|k| {
            // Alternate orientation and start point: loft must normalise both.
            let c = circle(Point::new(50.0, 40.0), r, 90 + 7 * k);
            if k % 2 == 1 {
                c.reversed()
            } else {
                c
            }
        })
        .collect();
    let zs: Vec<f64> = (0..5).map(|k| k as f64 * 1.5).collect();
    let mesh = loft(&sections, &zs, 64).unwrap();
    assert!(mesh.is_watertight());
    assert!(mesh.is_consistently_oriented());
    assert_eq!(mesh.triangles.len(), 4 * 64 * 2 + 2 * (64 - 2));
    // Volume of the inscribed 64-gon prism: ½ n r² sin(2π/n) · h.
    let n = 64.0;
    let poly_area = 0.5 * n * r * r * (std::f64::consts::TAU / n).sin();
    let expect = poly_area * 6.0;
    assert!(
        (mesh.signed_volume() - expect).abs() / expect < 0.01,
        "{}",
        mesh.signed_volume()
    );
    // Flipping one triangle breaks the orientation but not watertightness.
    let mut bad = mesh.clone();
    bad.triangles[3].swap(0, 1);
    assert!(bad.is_watertight() && !bad.is_consistently_oriented());
    // Removing one breaks watertightness.
    let mut open = mesh.clone();
    open.triangles.pop();
    assert!(!open.is_watertight());
    assert!(loft(&sections[..1], &zs[..1], 64).is_err());
}

#[test]
fn ear_clipping_a_nonconvex_polygon() {
    // An L-shape (area 3) plus a collinear vertex.
    let p = [
        Point::new(0.0, 0.0),
        Point::new(1.0, 0.0),
        Point::new(2.0, 0.0),
        Point::new(2.0, 1.0),
        Point::new(1.0, 1.0),
        Point::new(1.0, 2.0),
        Point::new(0.0, 2.0),
    ];
    let tris = ear_clip(&p);
    assert_eq!(tris.len(), p.len() - 2);
    let area: f64 = tris
        .iter()
        .map(|t| (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]) / 2.0)
        .sum();
    assert!((area - 3.0).abs() < 1e-12, "{area}");
    assert!(tris
        .iter()
        .all(|t| (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]) >= 0.0));
}

#[test]
fn stl_round_trip_keeps_a_watertight_mesh() {
    let sections = vec![
        circle(Point::new(0.0, 0.0), 5.0, 40),
        circle(Point::new(1.0, 0.5), 6.0, 40),
    ];
    let mesh = loft(&sections, &[0.0, 2.0], 32).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("implant.stl");
    write_stl(&p, &mesh, "metabezier test").unwrap();
    let bytes = std::fs::read(&p).unwrap();
    assert_eq!(bytes.len(), 84 + 50 * mesh.triangles.len());
    assert!(!bytes.starts_with(b"solid"));
    let back = parse_stl(&bytes, &p).unwrap();
    assert_eq!(back.triangles.len(), mesh.triangles.len());
    assert_eq!(back.vertices.len(), mesh.vertices.len());
    assert!(back.is_watertight() && back.is_consistently_oriented());
    assert!((back.signed_volume() - mesh.signed_volume()).abs() < 1e-3);
    assert!(parse_stl(&bytes[..bytes.len() - 1], &p).is_err());
    // No temporary file is left behind.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn voxelised_disc_has_the_disc_area() {
    let sp = Spacing {
        x: 0.5,
        y: 0.75,
        z: 1.5,
    };
    let r = 12.0;
    let c = Point::new(25.0, 30.0);
    let m = voxelise(&[(1, circle(c, r, 400))], 100, 80, 3, sp);
    assert_eq!(m.slice(0).count(), 0);
    // Voxel centres inside the exact circle (the 400-gon differs by < 0.01%).
    let lattice = (0..80)
        .flat_map(|row| (0..100).map(move |col| (row, col)))
        .filter(|&(row, col)| Point::new(col as f64 * sp.x, row as f64 * sp.y).distance(c) < r)
        .count();
    assert!(
        m.slice(1).count().abs_diff(lattice) <= 2,
        "{} vs {lattice}",
        m.slice(1).count()
    );
    let area = m.slice(1).count() as f64 * sp.x * sp.y;
    let expect = std::f64::consts::PI * r * r;
    assert!((area - expect).abs() / expect < 0.02, "{area} vs {expect}");
    // Each voxel agrees with the point-in-polygon test of its centre.
    let poly = circle(c, r, 400);
    for row in 0..80 {
        for col in 0..100 {
            let p = Point::new(col as f64 * sp.x, row as f64 * sp.y);
            assert_eq!(m.get(1, row, col), poly.contains(p), "({row}, {col})");
        }
    }
}

// ---------------------------------------------------------------- metrics

fn cube(n: usize, lo: [usize; 3], size: usize, sp: Spacing) -> Mask3 {
    Mask3::from_fn(n, n, n, sp, |z, y, x| {
        (lo[0]..lo[0] + size).contains(&z)
            && (lo[1]..lo[1] + size).contains(&y)
            && (lo[2]..lo[2] + size).contains(&x)
    })
}

#[test]
fn dice_of_offset_cubes_is_analytic() {
    let sp = Spacing {
        x: 1.0,
        y: 1.0,
        z: 1.0,
    };
    let a = cube(30, [5, 5, 5], 10, sp);
    for d in 0..=10 {
        let b = cube(30, [5, 5, 5 + d], 10, sp);
        let expect = 1.0 - d as f64 / 10.0;
        assert!((dice(&a, &b).unwrap() - expect).abs() < 1e-12, "shift {d}");
    }
    let empty = Mask3::new(30, 30, 30, sp);
    assert_eq!(dice(&empty, &empty).unwrap(), 1.0);
    assert!(dice(&a, &Mask3::new(29, 30, 30, sp)).is_err());
}

#[test]
fn hd95_of_a_shifted_cube_is_the_shift_in_mm() {
    // Anisotropic spacing: shifts along x, y and z give shift × spacing.
    let sp = Spacing {
        x: 0.5,
        y: 0.75,
        z: 1.5,
    };
    let a = cube(32, [8, 8, 8], 12, sp);
    for (axis, s) in [(2usize, sp.x), (1, sp.y), (0, sp.z)] {
        for d in [1usize, 2, 3] {
            let mut lo = [8, 8, 8];
            lo[axis] += d;
            let b = cube(32, lo, 12, sp);
            let h = hd95(&a, &b).unwrap();
            assert!(
                (h - d as f64 * s).abs() < 1e-9,
                "axis {axis} shift {d}: {h}"
            );
        }
    }
    assert_eq!(hd95(&a, &a).unwrap(), 0.0);
    assert!(hd95(&a, &Mask3::new(32, 32, 32, sp)).is_err());
}

#[test]
fn hd95_of_a_shifted_square_slice_is_the_shift() {
    // One-slice masks (the 2D case): a 20×20 square shifted by 4 columns.
    let sp = Spacing {
        x: 0.8,
        y: 0.8,
        z: 1.5,
    };
    let sq = |c0: usize| {
        Mask3::from_fn(40, 40, 1, sp, |_, y, x| {
            (10..30).contains(&y) && (c0..c0 + 20).contains(&x)
        })
    };
    let h = hd95(&sq(8), &sq(12)).unwrap();
    assert!((h - 4.0 * 0.8).abs() < 1e-9, "{h}");
}

#[test]
fn edt_matches_brute_force() {
    let sp = Spacing {
        x: 0.7,
        y: 1.1,
        z: 2.0,
    };
    // A scattered set of sites.
    let sites = Mask3::from_fn(13, 11, 7, sp, |z, y, x| (x * 7 + y * 13 + z * 29) % 37 == 0);
    let d2 = edt_squared(&sites);
    let pts: Vec<(usize, usize, usize)> = (0..7)
        .flat_map(|z| (0..11).flat_map(move |y| (0..13).map(move |x| (z, y, x))))
        .filter(|&(z, y, x)| sites.get(z, y, x))
        .collect();
    assert!(!pts.is_empty());
    for z in 0..7 {
        for y in 0..11 {
            for x in 0..13 {
                let bf = pts
                    .iter()
                    .map(|&(zz, yy, xx)| {
                        let (dx, dy, dz) = (
                            (x as f64 - xx as f64) * sp.x,
                            (y as f64 - yy as f64) * sp.y,
                            (z as f64 - zz as f64) * sp.z,
                        );
                        dx * dx + dy * dy + dz * dz
                    })
                    .fold(f64::INFINITY, f64::min);
                assert!((d2[sites.index(z, y, x)] - bf).abs() < 1e-9);
            }
        }
    }
    assert!(edt_squared(&Mask3::new(3, 3, 3, sp))
        .iter()
        .all(|d| d.is_infinite()));
}

#[test]
fn boundary_dice_only_counts_voxels_near_the_skull() {
    let sp = Spacing {
        x: 1.0,
        y: 1.0,
        z: 1.0,
    };
    // Skull: the slab x < 5. Implant truth: 5 ≤ x < 25; prediction: 5 ≤ x < 15.
    let n = 30;
    let slab =
        |lo: usize, hi: usize| Mask3::from_fn(n, n, n, sp, move |_, _, x| (lo..hi).contains(&x));
    let skull = slab(0, 5);
    let truth = slab(5, 25);
    let pred = slab(5, 15);
    // Within 10 mm of the skull (x ≤ 14) both agree exactly.
    assert_eq!(boundary_dice(&pred, &truth, &skull, 10.0).unwrap(), 1.0);
    // Within 15 mm (x ≤ 19): |A∩B| = 10·n², |A| = 10·n², |B| = 15·n².
    let bd = boundary_dice(&pred, &truth, &skull, 15.0).unwrap();
    assert!((bd - 2.0 * 10.0 / 25.0).abs() < 1e-12, "{bd}");
    // The plain Dice sees the whole difference.
    assert!((dice(&pred, &truth).unwrap() - 2.0 * 10.0 / 30.0).abs() < 1e-12);
}

#[test]
fn contour_deviation_of_known_curves() {
    let a = circle(Point::new(0.0, 0.0), 10.0, 720);
    let b = circle(Point::new(0.0, 0.0), 12.0, 720);
    let d = contour_deviation(&a, &b, 0.1).unwrap();
    assert!(
        (d.mean - 2.0).abs() < 0.01 && (d.max - 2.0).abs() < 0.01,
        "{d:?}"
    );
    // Parallel segments 3 mm apart: exactly 3 everywhere.
    let s1 = Polyline::open(vec![Point::new(0.0, 0.0), Point::new(10.0, 0.0)]);
    let s2 = Polyline::open(vec![Point::new(0.0, 3.0), Point::new(10.0, 3.0)]);
    let d = contour_deviation(&s1, &s2, 0.5).unwrap();
    assert!(
        (d.mean - 3.0).abs() < 1e-12 && (d.max - 3.0).abs() < 1e-12,
        "{d:?}"
    );
    // A bump of height 1 over a 2 mm base on a 10 mm line: max 1.
    let bump = Polyline::open(vec![
        Point::new(0.0, 0.0),
        Point::new(4.0, 0.0),
        Point::new(5.0, 1.0),
        Point::new(6.0, 0.0),
        Point::new(10.0, 0.0),
    ]);
    let d = contour_deviation(&s1, &bump, 0.05).unwrap();
    assert!((d.max - 1.0).abs() < 1e-9 && d.mean < 0.2, "{d:?}");
}

#[test]
fn loft_of_real_outer_tables_is_watertight_and_voxelises_back() {
    let v = ct0051();
    let zs: Vec<usize> = (88..=92).collect();
    let mut sections = Vec::new();
    for &z in &zs {
        let s = v.slice(vz(z));
        let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
        let t = table_contours(&bone_loops(&s, &m, BONE_THRESHOLD_HU), None).unwrap();
        sections.push(t.outer);
    }
    let heights: Vec<f64> = zs.iter().map(|&z| vz(z) as f64 * v.spacing.z).collect();
    let mesh = loft(&sections, &heights, 200).unwrap();
    assert!(mesh.is_watertight() && mesh.is_consistently_oriented());
    // Volume ≈ trapezoidal integral of the section areas.
    let areas: Vec<f64> = sections.iter().map(|p| p.signed_area()).collect();
    let trap: f64 = areas
        .windows(2)
        .map(|w| (w[0] + w[1]) / 2.0 * v.spacing.z)
        .sum();
    assert!(
        (mesh.signed_volume() - trap).abs() / trap < 0.03,
        "{} vs {trap}",
        mesh.signed_volume()
    );
    // Voxelising the sections gives the head (bone and cavity) of each slice.
    let secs: Vec<(usize, Polyline)> = zs
        .iter()
        .zip(&sections)
        .map(|(&z, p)| (vz(z), p.clone()))
        .collect();
    let vox = voxelise(&secs, v.nx, v.ny, v.nz, v.spacing);
    for (k, &z) in zs.iter().enumerate() {
        let n = vox.slice(vz(z)).count() as f64 * v.spacing.x * v.spacing.y;
        assert!(
            (n - areas[k]).abs() / areas[k] < 0.02,
            "z={z}: {n} vs {}",
            areas[k]
        );
    }
}
