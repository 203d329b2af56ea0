//! Bone, defect, contours and the mirror: the head holder dropped, the defect
//! found where it is, marching squares and the mirrored template.

use super::*;

/// Tolerance of the automatic end points: 3 pixels (Chebyshev).
const END_TOL_PX: usize = 3;

fn px_dist(a: (usize, usize), b: (usize, usize)) -> usize {
    a.0.abs_diff(b.0).max(a.1.abs_diff(b.1))
}

#[test]
fn bone_mask_drops_the_head_holder() {
    let v = ct0051();
    for z in [64, 72, 80, 89] {
        let s = v.slice(vz(z));
        let t = threshold_slice(&s, BONE_THRESHOLD_HU);
        let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
        // The holder arc runs along the top rows of the image, far from the head.
        let top = |mask: &Mask2| {
            (0..15)
                .flat_map(|r| (0..256).map(move |c| (r, c)))
                .filter(|&(r, c)| mask.get(r, c))
                .count()
        };
        assert!(top(&t) >= 20, "z={z}: the threshold should see the holder");
        assert_eq!(top(&m), 0, "z={z}: the holder must drop out");
        assert!(m.count() > 2500 && m.count() < t.count(), "z={z}");
    }
    // Same in 3D (26-connected) on a few slices around the defect.
    let sub = v.sub_z(vz(60), vz(92));
    let m3 = bone_mask_volume(&sub, BONE_THRESHOLD_HU).unwrap();
    for z in 0..sub.nz {
        let m2 = m3.slice(z);
        assert!(
            (0..15).all(|r| (0..256).all(|c| !m2.get(r, c))),
            "3D, slice {z}"
        );
        assert!(m2.count() > 2500, "3D, slice {z}: skull kept");
    }
    // No bone above an impossible threshold.
    let e = bone_mask_slice(&v.slice(0), 4000).unwrap_err();
    assert!(
        matches!(
            e,
            CtError::NoBone {
                slice: 0,
                threshold: 4000
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("no bone"), "{e}");
}

#[test]
fn defect_ends_match_the_measured_points() {
    let v = ct0051();
    for (z, p, q) in CT0051_MEASURED_ENDS {
        let s = v.slice(vz(z));
        let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
        let d = detect_defect(&m, s.sx, s.sy, &DefectParams::default())
            .unwrap_or_else(|| panic!("z={z}: defect not found"));
        // Unordered pair.
        let err = (px_dist(d.a, p).max(px_dist(d.b, q))).min(px_dist(d.a, q).max(px_dist(d.b, p)));
        eprintln!(
            "z={z}: A={:?} B={:?} reference {p:?} {q:?}, error {err} px, width {:.1} mm",
            d.a,
            d.b,
            d.width_mm()
        );
        assert!(
            err <= END_TOL_PX,
            "z={z}: {:?} {:?} vs {p:?} {q:?}",
            d.a,
            d.b
        );
        // A and B lie on the bone, and the mm positions agree with the pixels.
        assert!(m.get(d.a.0, d.a.1) && m.get(d.b.0, d.b.1));
        assert_eq!(d.a_mm, s.to_mm(d.a.0 as f64, d.a.1 as f64));
    }
}

#[test]
fn defect_spans_the_documented_slices_and_intact_slices_have_none() {
    let v = ct0051();
    let params = DefectParams::default();
    let found = |z: usize| {
        let s = v.slice(vz(z));
        let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
        detect_defect(&m, s.sx, s.sy, &params)
    };
    for z in 88..=90 {
        assert_eq!(found(z), None, "z={z} is intact");
    }
    // The gap narrows from ~25 mm (z=64) to ~12 mm (z=80), on one side.
    let w64 = found(64).unwrap().width_mm();
    let w72 = found(72).unwrap().width_mm();
    let w80 = found(80).unwrap().width_mm();
    assert!((22.0..28.0).contains(&w64), "{w64}");
    assert!((19.0..25.0).contains(&w72), "{w72}");
    assert!((10.0..16.0).contains(&w80), "{w80}");
    for z in (56..=84).step_by(4) {
        let d = found(z).unwrap_or_else(|| panic!("z={z}: no defect"));
        // Left-posterior side of the image: columns < 128, rows > 150.
        assert!(
            d.a.1 < 128 && d.b.1 < 128 && d.a.0 > 150 && d.b.0 > 150,
            "z={z}: {d:?}"
        );
    }
}

#[test]
fn defect_detection_on_a_synthetic_ring() {
    // Ring of radii 40..50 px around (100, 100) with a 30° gap centred at 90°
    // (straight down in the image); ends are known in closed form.
    let ring = |gap: bool| {
        Mask2::from_fn(200, 200, |r, c| {
            let (dy, dx) = (r as f64 - 100.0, c as f64 - 100.0);
            let rad = dx.hypot(dy);
            let ang = dy.atan2(dx).to_degrees();
            (40.0..=50.0).contains(&rad) && !(gap && (75.0..=105.0).contains(&ang))
        })
    };
    assert_eq!(
        detect_defect(&ring(false), 1.0, 1.0, &DefectParams::default()),
        None
    );
    let d = detect_defect(&ring(true), 1.0, 1.0, &DefectParams::default()).unwrap();
    // The narrowest chord joins the inner corners at radius 40, angles 75° and 105°.
    let expect_w = 2.0 * 40.0 * (15f64).to_radians().sin();
    assert!(
        (d.width_mm() - expect_w).abs() < 2.5,
        "{} vs {expect_w}",
        d.width_mm()
    );
    assert!((d.gap_width_deg - 30.0).abs() < 8.0, "{}", d.gap_width_deg);
    assert!(d.a.0 > 100 && d.b.0 > 100);
}

// ---------------------------------------------------------------- contours

#[test]
fn marching_squares_on_a_disc_is_subpixel_and_oriented() {
    // f = R − distance from the centre (a cone): the 0-level set is the circle
    // of radius R; linear interpolation along edges is exact to O(h²/R).
    let (n, r0, sx, sy) = (100usize, 20.3, 0.5, 0.75);
    let (cy, cx) = (48.7, 50.2);
    let f: Vec<f64> = (0..n * n)
        .map(|i| {
            let (r, c) = ((i / n) as f64, (i % n) as f64);
            // Distance in mm, so the contour is a true circle in mm.
            r0 - ((c - cx) * sx).hypot((r - cy) * sy)
        })
        .collect();
    let loops = marching_squares(&f, n, n, 0.0, sx, sy);
    assert_eq!(loops.len(), 1);
    let l = &loops[0];
    assert!(l.closed);
    let c = Point::new(cx * sx, cy * sy);
    for p in &l.points {
        assert!(
            (p.distance(c) - r0).abs() < 0.02,
            "{} at {:?} px {:?}",
            p.distance(c),
            p,
            (p.y / sy, p.x / sx)
        );
    }
    let area = l.signed_area();
    assert!(area > 0.0, "outer boundary has positive area");
    assert!(
        (area - std::f64::consts::PI * r0 * r0).abs() / area < 2e-3,
        "{area}"
    );
    // The complement: a hole, negative area (inside on the left).
    let g: Vec<f64> = f.iter().map(|v| -v).collect();
    let holes = marching_squares(&g, n, n, 0.0, sx, sy);
    let hole = holes.iter().find(|l| l.signed_area() < 0.0).unwrap();
    assert!((hole.signed_area() + area).abs() < 1e-6);
}

#[test]
fn saddles_join_diagonal_bone_pixels() {
    // Two pixels touching at a corner are one 8-connected component: one loop.
    let m = Mask2::from_fn(4, 4, |r, c| (r, c) == (1, 1) || (r, c) == (2, 2));
    let f: Vec<f64> = m.data.iter().map(|&b| if b { 1.0 } else { 0.0 }).collect();
    let loops = marching_squares(&f, 4, 4, 0.5, 1.0, 1.0);
    assert_eq!(loops.len(), 1);
    assert_eq!(largest_component_2d(&m).count(), 2);
}

#[test]
fn table_contours_of_intact_and_defect_slices() {
    let v = ct0051();
    // Intact slice: two loops, the outer around the inner.
    let s = v.slice(vz(89));
    let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
    let loops = bone_loops(&s, &m, BONE_THRESHOLD_HU);
    let t = table_contours(&loops, None).unwrap();
    assert!(t.intact && t.outer.closed && t.inner.closed);
    assert!(t.outer.signed_area() > 0.0 && t.inner.signed_area() < 0.0);
    assert!(t.inner.points.iter().all(|&p| t.outer.contains(p)));
    // Bone ring area (outer − cavity) ≈ bone pixel count × pixel area.
    let ring = t.outer.signed_area() + t.inner.signed_area();
    let px = m.count() as f64 * s.sx * s.sy;
    assert!((ring - px).abs() / px < 0.1, "{ring} vs {px}");
    // Every contour vertex is within one pixel of a bone pixel boundary.
    for p in t.outer.points.iter().chain(&t.inner.points) {
        let (r, c) = s.to_pixel(*p);
        let near = (-1..=1).any(|dr| {
            (-1..=1).any(|dc| m.get_or_false(r.round() as i64 + dr, c.round() as i64 + dc))
        });
        assert!(near);
    }

    // Defect slice: one loop; split at the detected ends.
    let s = v.slice(vz(72));
    let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
    let loops = bone_loops(&s, &m, BONE_THRESHOLD_HU);
    let e = table_contours(&loops, None).unwrap_err();
    assert!(e.to_string().contains("open"), "{e}");
    let d = detect_defect(&m, s.sx, s.sy, &DefectParams::default()).unwrap();
    let t = table_contours(&loops, Some((d.a_mm, d.b_mm))).unwrap();
    assert!(!t.intact && !t.outer.closed && !t.inner.closed);
    let centre = d.centre;
    let mean_r = |p: &Polyline| {
        p.points.iter().map(|q| q.distance(centre)).sum::<f64>() / p.points.len() as f64
    };
    assert!(mean_r(&t.outer) > mean_r(&t.inner) + 3.0);
    // The two arcs start and end at the cut points near A and B.
    for arc in [&t.outer, &t.inner] {
        let ends = [arc.points[0], *arc.points.last().unwrap()];
        assert!(ends.iter().any(|p| p.distance(d.a_mm) < 1.0));
        assert!(ends.iter().any(|p| p.distance(d.b_mm) < 1.0));
    }
    // A point far from the contour is refused.
    let far = Point::new(128.0 * s.sx, 110.0 * s.sy);
    let e = table_contours(&loops, Some((far, d.b_mm))).unwrap_err();
    assert!(matches!(e, CtError::NotOnContour { what: "A", .. }), "{e}");
}
// ---------------------------------------------------------------- mirror

#[test]
fn midline_of_a_symmetric_synthetic_ring() {
    // Ellipse ring symmetric about column 60.25 (between pixel centres).
    for centre in [60.25, 61.0, 59.5] {
        let m = Mask2::from_fn(130, 120, |r, c| {
            let (dx, dy) = ((c as f64 - centre) / 45.0, (r as f64 - 55.0) / 40.0);
            let q = dx.hypot(dy);
            (0.8..=1.0).contains(&q)
        });
        let ml = estimate_midline(std::slice::from_ref(&m), 0.5).unwrap();
        assert!((ml.col - centre).abs() <= 0.25, "{} vs {centre}", ml.col);
        assert!((ml.x - ml.col * 0.5).abs() < 1e-12);
        // Exactly symmetric on the pixel grid when 2·centre is an integer.
        if (2.0 * centre).fract() == 0.0 {
            assert_eq!(ml.dice, 1.0);
        } else {
            assert!(ml.dice > 0.9);
        }
    }
    assert_eq!(reflect(Point::new(1.0, 2.0), 3.0), Point::new(5.0, 2.0));
}

#[test]
fn mirror_template_on_the_real_defect() {
    let v = ct0051();
    // M_x from intact slices (pooled): the head is centred near column 128.
    let masks: Vec<Mask2> = (88..=90)
        .map(|z| bone_mask_slice(&v.slice(vz(z)), BONE_THRESHOLD_HU).unwrap())
        .collect();
    let ml = estimate_midline(&masks, v.spacing.x).unwrap();
    eprintln!(
        "M_x: col {:.2}, x {:.2} mm, Dice {:.3}",
        ml.col, ml.x, ml.dice
    );
    assert!((110.0..146.0).contains(&ml.col), "{ml:?}");
    assert!(ml.dice > 0.8, "{ml:?}");
    // The estimate is stable between slice groups.
    let other: Vec<Mask2> = (92..=94)
        .map(|z| bone_mask_slice(&v.slice(vz(z)), BONE_THRESHOLD_HU).unwrap())
        .collect();
    let ml2 = estimate_midline(&other, v.spacing.x).unwrap();
    assert!((ml.col - ml2.col).abs() < 3.0, "{ml:?} {ml2:?}");

    let s = v.slice(vz(72));
    let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
    let d = detect_defect(&m, s.sx, s.sy, &DefectParams::default()).unwrap();
    let loops = bone_loops(&s, &m, BONE_THRESHOLD_HU);
    let t = table_contours(&loops, Some((d.a_mm, d.b_mm))).unwrap();
    let tpl = mirror_template(&t.outer, d.a_mm, d.b_mm, ml.x, 6.0).unwrap();
    // C and D are the reflections; the template runs from near A to near B
    // and bridges the gap with a curve of similar length on the other side.
    assert_eq!(tpl.c, reflect(d.a_mm, ml.x));
    assert!(
        tpl.c.x > ml.x && tpl.d.x > ml.x,
        "intact side is right of M_x"
    );
    let first = tpl.template.points[0];
    let last = *tpl.template.points.last().unwrap();
    assert!(
        first.distance(d.a_mm) < 6.0 && last.distance(d.b_mm) < 6.0,
        "{first:?} {last:?}"
    );
    let len = tpl.template.length();
    assert!(len > d.width_mm() && len < 2.0 * d.width_mm(), "{len}");
    for (p, q) in tpl.template.points.iter().zip(&tpl.intact_arc.points) {
        assert_eq!(*p, reflect(*q, ml.x));
    }
    // A defect across the midline is refused with a clear message.
    let e = mirror_template(&t.outer, d.a_mm, reflect(d.b_mm, ml.x), ml.x, 6.0).unwrap_err();
    assert!(matches!(e, CtError::DefectCrossesMidline { .. }));
    assert!(e.to_string().contains("explicit template"), "{e}");
    // A midline far off puts C, D away from the contour.
    let e = mirror_template(&t.outer, d.a_mm, d.b_mm, ml.x + 60.0, 6.0).unwrap_err();
    assert!(matches!(e, CtError::NotOnContour { .. }), "{e}");
}
