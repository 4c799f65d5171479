//! The wheel on the rail head: Hertz's elliptic point contact, linearised about the static
//! load (the contact spring `k_H` of the P2 resonance, [`super::receptance`]).
//!
//! Two steel bodies (Young's modulus `E`, Poisson's ratio `nu` each, so
//! `1 / E* = 2 (1 - nu^2) / E`) touch with the gap `h = A x^2 + B y^2`: the wheel's radius
//! `R_w` along the rail (`x`) and the rail head's transverse radius `R_r` across it (`y`)
//! give `A = 1 / (2 R_w)`, `B = 1 / (2 R_r)` (the wheel's tread and the rail's running
//! direction straight). Under the load `P` the contact is an ellipse of semi-axes `a >= b`
//! (`a` along the smaller relative curvature), eccentricity `e = sqrt(1 - b^2/a^2)`, with the
//! semi-ellipsoidal pressure of peak `p0 = 3 P / (2 pi a b)`; K. L. Johnson, *Contact
//! Mechanics*, Cambridge University Press 1985, §4.2, Eq. (4.39):
//! $$A = \frac{p_0\\,b}{E^\* e^2 a^2}\big[K(e) - E(e)\big],\qquad
//!   B = \frac{p_0\\,b}{E^\* e^2 a^2}\Big[\frac{a^2}{b^2}E(e) - K(e)\Big],\qquad
//!   \delta = \frac{p_0\\,b}{E^\*}K(e),$$
//! with `K`, `E` the complete elliptic integrals of the first and second kind (modulus `e`)
//! and `delta` the approach of the two bodies. The ratio `B / A` fixes `e` (solved by
//! bisection); then `a^3 = 3 P (K - E) / (2 pi e^2 E* A)` and
//! `delta = 3 P K / (2 pi a E*)`. Since `delta ∝ P^(2/3)`, the contact spring linearised
//! about `P` is
//! $$k_H = \frac{dP}{d\delta} = \frac{3P}{2\\,\delta}.$$
//! (Written with an empirical constant `G` in `delta = G P^(2/3)`, as Jenkins et al. 1974 do
//! for worn wheels and rails, the same derivative reads `k_H = 3/2 P^(1/3) / G`.) For a
//! circle (`A = B = 1/(2R)`) this is `a^3 = 3 P R / (4 E*)`, `delta = a^2 / R` (Johnson
//! Eq. 4.22), a check of the tests. The UIC60 head (`R_r = 0.3 m`) under a wheel of
//! `R_w = 0.46 m` at `P = 100 kN` gives `k_H ≈ 1.4e9 N/m`.

pub use crate::contact::hertz::elliptic_integrals;

/// Hertz's contact of a wheel on the rail head under a load (module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct HertzContact {
    /// The larger semi-axis `a`, m.
    pub a: f64,
    /// The smaller semi-axis `b`, m.
    pub b: f64,
    /// The eccentricity `e = sqrt(1 - b^2 / a^2)`.
    pub eccentricity: f64,
    /// The approach `delta`, m.
    pub approach: f64,
    /// The peak pressure `p0`, Pa.
    pub peak_pressure: f64,
    /// The linearised contact stiffness `k_H = 3 P / (2 delta)`, N/m.
    pub stiffness: f64,
}

/// The contact of a wheel of radius `wheel_radius` (m) on a rail head of transverse radius
/// `head_radius` (m) under `load` (N), both of steel of `young` (Pa) and `poisson` (module
/// docs). `None` when a value is not positive and finite.
pub fn contact(
    load: f64,
    wheel_radius: f64,
    head_radius: f64,
    young: f64,
    poisson: f64,
) -> Option<HertzContact> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if !(ok(load) && ok(wheel_radius) && ok(head_radius) && ok(young)) {
        return None;
    }
    let e_star = young / (2.0 * (1.0 - poisson * poisson));
    let h =
        crate::contact::hertz::Hertz::from_radii(wheel_radius, head_radius, e_star, load).ok()?;
    Some(HertzContact {
        a: h.a,
        b: h.b,
        eccentricity: h.eccentricity,
        approach: h.approach,
        peak_pressure: h.peak_pressure,
        stiffness: 1.5 * load / h.approach,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A nearly circular contact tends to the circle's closed form; the UIC60 head under
    /// 100 kN is near the sphere of the geometric-mean radius (Johnson: within a few per
    /// cent for `B / A < 5`) and the load's 2/3 power holds.
    #[test]
    fn the_ellipse_tends_to_the_circle_and_scales_with_the_load() {
        let (e, nu, p) = (210e9, 0.3, 100e3);
        let circle = contact(p, 0.46, 0.46, e, nu).unwrap();
        let near = contact(p, 0.46, 0.46 * (1.0 - 1e-6), e, nu).unwrap();
        assert!((near.approach / circle.approach - 1.0).abs() < 1e-5);
        assert!((near.a / circle.a - 1.0).abs() < 1e-5);
        let e_star = e / (2.0 * (1.0 - nu * nu));
        let a = (3.0 * p * 0.46 / (4.0 * e_star)).cbrt();
        assert!((circle.approach - a * a / 0.46).abs() < 1e-15);
        let c = contact(p, 0.46, 0.3, e, nu).unwrap();
        let r = (0.46f64 * 0.3).sqrt();
        let a_eq = (3.0 * p * r / (4.0 * e_star)).cbrt();
        let delta_eq = a_eq * a_eq / r;
        assert!((c.approach / delta_eq - 1.0).abs() < 0.02, "{c:?}");
        let c2 = contact(8.0 * p, 0.46, 0.3, e, nu).unwrap();
        assert!((c2.approach / c.approach - 4.0).abs() < 1e-9);
        assert!((c2.stiffness / c.stiffness - 2.0).abs() < 1e-9);
        assert!(c.stiffness > 1.3e9 && c.stiffness < 1.5e9, "{c:?}");
    }
}
