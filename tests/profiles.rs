//! The wheel and rail profiles against their published dimensions and the continuity of
//! their pieces.
//!
//! Sources of the numbers asserted:
//! - S1002 (EN 13715; nominal flange dimensions of EN 15313 / UIC 510-2): flange height
//!   Sh = 28 mm, flange thickness Sd = 32.5 mm (measured 10 mm above the taping line from
//!   the flange's back, 70 mm from the taping line), flange slope qR = 10.8 mm (between
//!   the flange's face 10 mm above the taping line and 2 mm below the flange's tip), the
//!   1:15 chamfer of the field side.
//! - 60E1 (EN 13674-1): head width 72 mm, 14.3 mm below the crown where the gauge-corner
//!   arcs meet the flanks, crown radius 300 mm.

use softway::mesh::profiles::section::{graded, graded_about};
use softway::mesh::profiles::{self, by_name, conical, s1002, uic60, uic60_head};

const MM: f64 = 1e-3;

/// `y` (m) where the profile, between `a` and `b` (m), reaches the height `z` (m), by
/// bisection (the profile monotone there).
fn crossing(p: &profiles::Profile, a: f64, b: f64, z: f64) -> f64 {
    let f = |y: f64| p.height(y).unwrap() - z;
    let (mut lo, mut hi) = (a, b);
    assert!(f(lo) * f(hi) <= 0.0, "no crossing of {z} in [{a}, {b}]");
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(lo) * f(mid) <= 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn s1002_has_the_published_flange_height_thickness_and_slope() {
    let p = s1002();
    assert_eq!(p.domain(), (-70.0 * MM, 60.0 * MM));
    // Flange height: the highest point of the profile, 28 mm at y = -55 mm.
    let (mut top, mut at) = (f64::MIN, 0.0);
    for k in 0..=13_000 {
        let y = -70.0 * MM + k as f64 * 0.01 * MM;
        let z = p.height(y.min(60.0 * MM)).unwrap();
        if z > top {
            (top, at) = (z, y);
        }
    }
    assert!((top - 28.0 * MM).abs() < 1e-9, "flange height {top}");
    assert!((at + 55.0 * MM).abs() < 0.02 * MM, "flange top at {at}");
    // The taping line is the reference: zero height at y = 0.
    assert!(p.height(0.0).unwrap().abs() < 1e-15);
    // Flange thickness at 10 mm height, from the back at y = -70 mm.
    let face10 = crossing(&p, -45.0 * MM, -30.0 * MM, 10.0 * MM);
    let sd = face10 + 70.0 * MM;
    assert!((sd - 32.5 * MM).abs() < 0.01 * MM, "Sd = {} mm", sd / MM);
    // qR: from the face at 10 mm height to the face 2 mm below the tip (26 mm).
    let face26 = crossing(&p, -55.0 * MM, -45.0 * MM, 26.0 * MM);
    let qr = face10 - face26;
    assert!((qr - 10.8 * MM).abs() < 0.05 * MM, "qR = {} mm", qr / MM);
    // The field side's chamfer falls 1:15.
    assert!((p.slope(50.0 * MM).unwrap() + 1.0 / 15.0).abs() < 1e-8);
    // The flange's back is vertical at y = -70 mm: the slope grows without bound.
    assert!(p.slope(-69.999 * MM).unwrap() > 100.0);
}

#[test]
fn s1002_pieces_join_in_height_and_slope() {
    let p = s1002();
    let jumps = p.joint_jumps();
    assert_eq!(jumps.len(), 7);
    for (y, zl, zr, sl, sr) in jumps {
        // The published coefficients are rounded: the sections meet within 0.2 um in
        // height and 1e-4 in slope (the largest jumps are at y = -35 mm: 0.12 um, 8e-6).
        assert!((zl - zr).abs() < 2e-7, "height jump {} at y = {y}", zl - zr);
        assert!((sl - sr).abs() < 1e-4, "slope jump {} at y = {y}", sl - sr);
    }
}

#[test]
fn the_conical_tread_falls_one_in_forty() {
    let c = conical(1.0 / 40.0, 0.065).unwrap();
    for y in [-0.06, -0.01, 0.0, 0.02, 0.065] {
        assert!((c.height(y).unwrap() + y / 40.0).abs() < 1e-15);
        assert_eq!(c.slope(y), Some(-1.0 / 40.0));
    }
    assert_eq!(c.height(0.07), None);
    assert!(conical(f64::NAN, 0.065).is_none() && conical(0.025, 0.0).is_none());
    assert_eq!(by_name("S1002").unwrap().name, "S1002");
    assert_eq!(by_name("60E1").unwrap().name, "UIC60");
    assert!(by_name("S1003").is_none());
    assert_eq!(s1002().height(f64::NAN), None);
}

#[test]
fn uic60_head_is_72_mm_wide_14_3_mm_below_its_crown() {
    let p = uic60_head();
    let (a, b) = p.domain();
    // The published head width and the depth of the flanks' top: consequences of the
    // radii, the arcs' widths and the 1:20 flanks (the derivation's check).
    assert!(
        (b - a - 72.0 * MM).abs() < 0.001 * MM,
        "width {}",
        (b - a) / MM
    );
    assert!((p.height(b).unwrap() + 14.3 * MM).abs() < 0.001 * MM);
    assert!((p.height(a).unwrap() + 14.3 * MM).abs() < 0.001 * MM);
    // The flank's slope at the joint: 1:20 from the vertical (dz/dy = -20 on the right).
    assert!((p.slope(b).unwrap() + 20.0).abs() < 1e-6);
    assert!((p.slope(a).unwrap() - 20.0).abs() < 1e-6);
    // The crown: top at 0, curvature 1/300 mm.
    assert!(p.height(0.0).unwrap().abs() < 1e-15);
    let h = 1.0 * MM;
    let curv =
        (p.height(h).unwrap() - 2.0 * p.height(0.0).unwrap() + p.height(-h).unwrap()) / (h * h);
    assert!(
        (curv + 1.0 / (300.0 * MM)).abs() < 1e-3 / (300.0 * MM),
        "curvature {curv}"
    );
    // The crown's 300 mm arc ends 10.228 mm from the centre, the 80 mm arcs 26.0265 mm.
    let j = p.joints_m();
    assert!((j[3] - 10.228 * MM).abs() < 1e-12 && (j[4] - 26.0265 * MM).abs() < 1e-12);
    // Symmetric.
    for y in [1.0, 7.0, 15.0, 30.0, 35.5] {
        let (l, r) = (p.height(-y * MM).unwrap(), p.height(y * MM).unwrap());
        assert!((l - r).abs() < 1e-15);
    }
    for (y, zl, zr, sl, sr) in p.joint_jumps() {
        assert!(
            (zl - zr).abs() < 1e-12 && (sl - sr).abs() < 1e-9,
            "joint at {y}"
        );
    }
    let g = uic60::head_geometry();
    assert!((g.flank_top[0] - 36.0).abs() < 1e-3);
}

/// The polyline follows the profile: its points lie on it, joints included.
#[test]
fn polylines_lie_on_their_profiles() {
    for p in [s1002(), uic60_head()] {
        let line = p.polyline(50);
        assert_eq!(line.len(), 50 * p.pieces.len() + 1);
        for q in &line {
            assert!((p.height(q[0]).unwrap() - q[1]).abs() < 1e-9, "{}", p.name);
        }
        assert!(line.windows(2).all(|w| w[1][0] >= w[0][0]));
    }
}

/// The graded spacings: the fine steps where asked, growth by at most the factor (and the
/// rescaling of the last steps), the ends exact.
#[test]
fn graded_spacings_end_exactly_and_grow_by_at_most_the_factor() {
    let x = graded(1.0, 0.01, 0.1, 1.2, 0.1);
    assert_eq!((x[0], *x.last().unwrap()), (0.0, 1.0));
    assert!((x[1] - 0.01).abs() < 1e-15 && (x[10] - 0.1).abs() < 1e-12);
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(h.iter().all(|&d| d > 0.0 && d < 0.1 * 1.1));
    assert!(h.windows(2).all(|w| w[1] / w[0] < 1.2 * 1.1));
    let y = graded_about(-1.0, 2.0, 0.5, 0.01, 0.05, 1.3, 0.2);
    assert_eq!((y[0], *y.last().unwrap()), (-1.0, 2.0));
    assert!(y.windows(2).all(|w| w[1] > w[0]));
    let k = y.iter().position(|&v| v == 0.5).unwrap();
    assert!((y[k + 1] - y[k] - 0.01).abs() < 1e-15 && (y[k] - y[k - 1] - 0.01).abs() < 1e-15);
    // A focus at an end: one-sided.
    let z = graded_about(0.0, 1.0, 1.0, 0.01, 0.02, 1.5, 0.3);
    assert!((z[z.len() - 1] - z[z.len() - 2] - 0.01).abs() < 1e-12 && z[0] == 0.0);
}

/// The curvatures: the S1002 flange's arcs have the standard's radii (sections D to H:
/// 13 mm root, 20 mm face, 12 mm tip, 20.5 mm back; the root concave, the others
/// convex), the 60E1 crown 300 mm, its side arcs 80 mm, its corners 13 mm; the polynomial
/// tread's curvature against a finite difference of its slope.
#[test]
fn curvatures_are_the_published_radii() {
    let p = s1002();
    for (y_mm, radius_mm) in [(-36.0, -13.0), (-45.0, 20.0), (-55.0, 12.0), (-66.0, 20.5)] {
        let k = p.curvature(y_mm * MM).unwrap();
        assert!(
            (k + 1.0 / (radius_mm * MM)).abs() < 1e-9 / MM,
            "y {y_mm}: {k}"
        );
    }
    let h = 1e-6;
    for y in [-0.03, -0.01, 0.0, 0.02, 0.03] {
        let s = p.slope(y).unwrap();
        let d2 = (p.slope(y + h).unwrap() - p.slope(y - h).unwrap()) / (2.0 * h);
        let k = d2 / (1.0 + s * s).powf(1.5);
        assert!(
            (p.curvature(y).unwrap() - k).abs() < 1e-6 * k.abs().max(1.0),
            "y {y}"
        );
    }
    let r = uic60_head();
    for (y_mm, radius_mm) in [
        (0.0, 300.0),
        (5.0, 300.0),
        (20.0, 80.0),
        (-20.0, 80.0),
        (33.0, 13.0),
    ] {
        let k = r.curvature(y_mm * MM).unwrap();
        assert!(
            (k + 1.0 / (radius_mm * MM)).abs() < 1e-9 / MM,
            "y {y_mm}: {k}"
        );
    }
    assert_eq!(conical(0.025, 0.065).unwrap().curvature(0.01), Some(0.0));
    assert_eq!(r.curvature(0.05), None);
}
