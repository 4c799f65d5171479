//! Hertz's point contact of two bodies whose principal curvatures differ: the elliptic patch,
//! its pressure and the approach (K. L. Johnson, *Contact Mechanics*, Cambridge University
//! Press 1985, §4.2).
//!
//! Two bodies touch at a point with the initial gap `h = A x^2 + B y^2` (the relative
//! curvatures: a rigid body of principal radii `R_x`, `R_y` on a flat gives
//! `A = 1 / (2 R_x)`, `B = 1 / (2 R_y)`). Their elastic constants enter through
//! `1 / E* = (1 - nu_1^2) / E_1 + (1 - nu_2^2) / E_2` ([`reduced_modulus`]; a rigid body on
//! steel: `E* = E / (1 - nu^2)`). Under the load `P` the patch is an ellipse of semi-axes
//! `a >= b` (`a` along the smaller curvature), eccentricity `e = sqrt(1 - b^2 / a^2)`,
//! with the semi-ellipsoidal pressure
//! $$p(x, y) = p_0 \sqrt{1 - x^2/a^2 - y^2/b^2},\qquad p_0 = \frac{3P}{2\pi a b}$$
//! (Eq. 4.36), and Eq. (4.39):
//! $$A = \frac{p_0\\,b}{E^\* e^2 a^2}\big[K(e) - E(e)\big],\qquad
//!   B = \frac{p_0\\,b}{E^\* e^2 a^2}\Big[\frac{a^2}{b^2}E(e) - K(e)\Big],\qquad
//!   \delta = \frac{p_0\\,b}{E^\*}K(e),$$
//! `K`, `E` the complete elliptic integrals of modulus `e` ([`elliptic_integrals`]) and
//! `delta` the approach of distant points of the two bodies. The ratio `B / A` fixes `e`
//! ([`eccentricity`]); then `a^3 = 3 P (K - E) / (2 pi e^2 E* A)` and
//! `delta = 3 P K / (2 pi a E*)`. For a circle (`A = B = 1 / (2R)`) these are Eq. (4.22):
//! `a^3 = 3 P R / (4 E*)`, `delta = a^2 / R`, `p0 = 3 P / (2 pi a^2)`.
//!
//! [`Hertz::axial_displacement`] is the half-space's displacement on the patch's axis at a
//! depth under Hertz's pressure (Boussinesq's kernel, Johnson Eq. 3.21c, integrated over the
//! ellipse): the part of the approach a finite block, held at that depth, does not see.

use std::f64::consts::PI;

/// The complete elliptic integrals `(K(e), E(e))` of modulus `e` in `[0, 1)`, by the
/// arithmetic-geometric mean (Abramowitz and Stegun 17.6): `K = pi / (2 M(1, e'))`,
/// `E = K (1 - sum 2^(n-1) c_n^2)`, `c_0 = e`.
pub fn elliptic_integrals(e: f64) -> (f64, f64) {
    let (mut a, mut b) = (1.0, (1.0 - e * e).sqrt());
    let mut sum = 0.5 * e * e;
    let mut pow = 0.5;
    for _ in 0..60 {
        let c = 0.5 * (a - b);
        pow *= 2.0;
        sum += pow * c * c;
        let (an, bn) = (0.5 * (a + b), (a * b).sqrt());
        a = an;
        b = bn;
        if c.abs() < 1e-17 * a {
            break;
        }
    }
    let k = PI / (2.0 * a);
    (k, k * (1.0 - sum))
}

/// The eccentricity `e` of Hertz's ellipse for the curvature ratio `B / A >= 1` (module
/// docs): the root of `(E / (1 - e^2) - K) / (K - E) = B / A`, by bisection on
/// `(1e-6, 1 - 1e-15)` (the left side grows from 1 at `e = 0` without bound). A ratio within
/// `1e-9` of 1 (or below) is a circle, `e = 0`.
pub fn eccentricity(ratio: f64) -> f64 {
    if ratio - 1.0 < 1e-9 {
        return 0.0;
    }
    let f = |e: f64| {
        let (k, ee) = elliptic_integrals(e);
        ((ee / (1.0 - e * e)) - k) / (k - ee)
    };
    let (mut lo, mut hi) = (1e-6, 1.0 - 1e-15);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < ratio {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The contact modulus `E*` of two bodies: `1 / E* = (1 - nu_1^2) / E_1 + (1 - nu_2^2) / E_2`
/// (Johnson Eq. 4.3). A rigid second body is `young_2 = f64::INFINITY`.
pub fn reduced_modulus(young_1: f64, poisson_1: f64, young_2: f64, poisson_2: f64) -> f64 {
    1.0 / ((1.0 - poisson_1 * poisson_1) / young_1 + (1.0 - poisson_2 * poisson_2) / young_2)
}

/// Input Hertz's solution cannot take.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HertzError {
    /// A curvature, modulus, load or approach that is not finite and positive.
    #[error("Hertz contact: `{name}` must be a finite number > 0, got {value}")]
    NotPositive {
        /// The input's name.
        name: &'static str,
        /// The value given.
        value: f64,
    },
}

fn positive(name: &'static str, value: f64) -> Result<f64, HertzError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(HertzError::NotPositive { name, value })
    }
}

/// Hertz's elliptic contact under one load (module docs). The body's axes are `x` and `y`
/// of the curvatures given; `a` lies along the smaller one.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Hertz {
    /// The load `P`, N.
    pub load: f64,
    /// The contact modulus `E*`, Pa.
    pub e_star: f64,
    /// The larger semi-axis `a`, m.
    pub a: f64,
    /// The smaller semi-axis `b`, m.
    pub b: f64,
    /// The eccentricity `e = sqrt(1 - b^2 / a^2)`.
    pub eccentricity: f64,
    /// The peak pressure `p0 = 3 P / (2 pi a b)`, Pa.
    pub peak_pressure: f64,
    /// The approach `delta` of distant points, m.
    pub approach: f64,
    /// Whether `a` lies along `x` (`A <= B`).
    pub a_along_x: bool,
}

impl Hertz {
    /// The contact of the relative curvatures `curvature_x = A`, `curvature_y = B` (1/m) with
    /// the contact modulus `e_star` (Pa) under `load` (N).
    ///
    /// # Errors
    /// [`HertzError::NotPositive`] naming the first input that is not finite and positive.
    pub fn new(
        curvature_x: f64,
        curvature_y: f64,
        e_star: f64,
        load: f64,
    ) -> Result<Self, HertzError> {
        positive("curvature_x", curvature_x)?;
        positive("curvature_y", curvature_y)?;
        positive("e_star", e_star)?;
        positive("load", load)?;
        let (a_curv, ratio) = (
            curvature_x.min(curvature_y),
            curvature_x.max(curvature_y) / curvature_x.min(curvature_y),
        );
        let e = eccentricity(ratio);
        let (k_int, a) = if e == 0.0 {
            // A circle: Johnson Eq. (4.22).
            let r = 0.5 / a_curv;
            (0.5 * PI, (3.0 * load * r / (4.0 * e_star)).cbrt())
        } else {
            let (k, ee) = elliptic_integrals(e);
            let a = (3.0 * load * (k - ee) / (2.0 * PI * e * e * e_star * a_curv)).cbrt();
            (k, a)
        };
        let b = a * (1.0 - e * e).sqrt();
        Ok(Hertz {
            load,
            e_star,
            a,
            b,
            eccentricity: e,
            peak_pressure: 3.0 * load / (2.0 * PI * a * b),
            approach: 3.0 * load * k_int / (2.0 * PI * a * e_star),
            a_along_x: curvature_x <= curvature_y,
        })
    }

    /// The contact of a body of principal radii `radius_x`, `radius_y` (m) on a flat
    /// (`A = 1 / (2 R_x)`, `B = 1 / (2 R_y)`), as [`Hertz::new`].
    ///
    /// # Errors
    /// [`HertzError::NotPositive`] naming the first input that is not finite and positive.
    pub fn from_radii(
        radius_x: f64,
        radius_y: f64,
        e_star: f64,
        load: f64,
    ) -> Result<Self, HertzError> {
        positive("radius_x", radius_x)?;
        positive("radius_y", radius_y)?;
        Self::new(0.5 / radius_x, 0.5 / radius_y, e_star, load)
    }

    /// The contact of the same geometry and modulus under the load that gives the approach
    /// `approach` (m): `delta` grows as `P^(2/3)` at a fixed shape, so
    /// `P = P_1 (delta / delta_1)^(3/2)` from the unit load's `delta_1`.
    ///
    /// # Errors
    /// [`HertzError::NotPositive`] naming the first input that is not finite and positive.
    pub fn at_approach(
        curvature_x: f64,
        curvature_y: f64,
        e_star: f64,
        approach: f64,
    ) -> Result<Self, HertzError> {
        positive("approach", approach)?;
        let unit = Self::new(curvature_x, curvature_y, e_star, 1.0)?;
        Self::new(
            curvature_x,
            curvature_y,
            e_star,
            (approach / unit.approach).powf(1.5),
        )
    }

    /// The semi-axes along `x` and along `y`, m.
    pub fn semi_axes_xy(&self) -> (f64, f64) {
        if self.a_along_x {
            (self.a, self.b)
        } else {
            (self.b, self.a)
        }
    }

    /// The patch's area `pi a b`, m^2.
    pub fn area(&self) -> f64 {
        PI * self.a * self.b
    }

    /// The pressure at `(x, y)` (m, the body's axes; 0 outside the ellipse), Pa.
    pub fn pressure(&self, x: f64, y: f64) -> f64 {
        let (ax, ay) = self.semi_axes_xy();
        let s = 1.0 - (x / ax).powi(2) - (y / ay).powi(2);
        self.peak_pressure * s.max(0.0).sqrt()
    }

    /// The axial displacement (into the body, m) of an elastic half-space of `young` (Pa) and
    /// `poisson` at `depth` (m, `>= 0`) below the patch's centre under Hertz's pressure:
    /// Boussinesq's `u_z = P / (4 pi G) (z^2 / rho^3 + 2 (1 - nu) / rho)` (Johnson Eq. 3.21c)
    /// integrated over the ellipse (Gauss-Legendre in `x = a sin(phi) cos(t)`,
    /// `y = b sin(phi) sin(t)`, which takes the square root's edge out, on panels refined
    /// toward the axis where the depth is small). At `depth = 0` on a body pressed by a
    /// rigid one (`E* = E / (1 - nu^2)`) this is the approach `delta`.
    pub fn axial_displacement(&self, depth: f64, young: f64, poisson: f64) -> f64 {
        let shear = young / (2.0 * (1.0 + poisson));
        let z = depth.abs();
        let (gx, gw) = gauss_legendre::<24>();
        // Panels in s = sin(phi) with edges at z / a times powers of 4 (the kernel's scale).
        let mut edges = vec![0.0];
        let mut s = 0.25 * z / self.a;
        while s < 1.0 && z > 0.0 && edges.len() < 12 {
            if s > 1e-6 {
                edges.push(s);
            }
            s *= 4.0;
        }
        edges.push(1.0);
        let mut total = 0.0;
        for pair in edges.windows(2) {
            let (p0, p1) = (pair[0].asin(), pair[1].asin());
            for (xi, wi) in gx.iter().zip(&gw) {
                let phi = 0.5 * (p0 + p1) + 0.5 * (p1 - p0) * xi;
                let (s, c) = phi.sin_cos();
                let w_phi = 0.5 * (p1 - p0) * wi;
                for (tj, wj) in gx.iter().zip(&gw) {
                    // t over the quarter (0, pi/2), times 4 by symmetry.
                    let t = 0.25 * PI * (1.0 + tj);
                    let w_t = 0.25 * PI * wj;
                    let (x, y) = (self.a * s * t.cos(), self.b * s * t.sin());
                    let rho = (x * x + y * y + z * z).sqrt();
                    let kernel = z * z / rho.powi(3) + 2.0 * (1.0 - poisson) / rho;
                    // p = p0 cos(phi); dA = a b s ds dt, ds = cos(phi) dphi.
                    total +=
                        w_phi * w_t * self.peak_pressure * c * kernel * self.a * self.b * s * c;
                }
            }
        }
        4.0 * total / (4.0 * PI * shear)
    }
}

/// The `N`-point Gauss-Legendre rule on `[-1, 1]` (nodes, weights), by Newton's iteration on
/// the Legendre polynomial from Tricomi's initial guesses.
fn gauss_legendre<const N: usize>() -> ([f64; N], [f64; N]) {
    let (mut x, mut w) = ([0.0; N], [0.0; N]);
    let n = N as f64;
    for i in 0..N {
        let mut t = (PI * (i as f64 + 0.75) / (n + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, t);
            for k in 2..=N {
                let k = k as f64;
                let p2 = ((2.0 * k - 1.0) * t * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (t * p1 - p0) / (t * t - 1.0);
            let dt = p1 / dp;
            t -= dt;
            if dt.abs() < 1e-16 {
                break;
            }
        }
        x[i] = t;
        w[i] = 2.0 / ((1.0 - t * t) * dp * dp);
    }
    (x, w)
}

#[cfg(test)]
mod tests {
    use super::*;

    const E: f64 = 210e9;
    const NU: f64 = 0.3;

    fn rel(a: f64, b: f64) -> f64 {
        (a / b - 1.0).abs()
    }

    /// `K(0) = E(0) = pi/2`, and `K(sin 45°)`, `E(sin 45°)` of the tables (Abramowitz and
    /// Stegun 1964, Table 17.5).
    #[test]
    fn elliptic_integrals_of_the_tables() {
        let (k, e) = elliptic_integrals(0.0);
        assert!((k - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!((e - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let (k, e) = elliptic_integrals(0.5f64.sqrt());
        assert!((k - 1.854_074_677_301_372).abs() < 1e-13, "{k}");
        assert!((e - 1.350_643_881_047_675).abs() < 1e-13, "{e}");
    }

    /// A rigid sphere on steel: Johnson Eq. (4.22) in closed form.
    #[test]
    fn the_sphere_is_johnsons_circle() {
        let e_star = reduced_modulus(E, NU, f64::INFINITY, 0.0);
        assert!(rel(e_star, E / (1.0 - NU * NU)) < 1e-15);
        let (r, p) = (0.1, 1e3);
        let h = Hertz::from_radii(r, r, e_star, p).unwrap();
        let a = (3.0 * p * r / (4.0 * e_star)).cbrt();
        assert!(rel(h.a, a) < 1e-14 && rel(h.b, a) < 1e-14);
        assert!(rel(h.approach, a * a / r) < 1e-14);
        assert!(rel(h.peak_pressure, 3.0 * p / (2.0 * PI * a * a)) < 1e-14);
        // scipy (validation/hertz.py): a = 0.6875344335370708 mm, p0 = 1.0100723413228695 GPa.
        assert!(rel(h.a, 6.875_344_335_370_708e-4) < 1e-12);
        assert!(rel(h.peak_pressure, 1.010_072_341_322_869_5e9) < 1e-12);
        // The load is the pressure's integral: 2/3 p0 pi a b.
        assert!(rel(2.0 / 3.0 * h.peak_pressure * h.area(), p) < 1e-14);
        assert_eq!(h.pressure(a, 0.0), 0.0);
        assert!(rel(h.pressure(0.0, 0.5 * a), h.peak_pressure * 0.75f64.sqrt()) < 1e-14);
    }

    /// The rigid 0.46 m by 0.30 m body on steel against scipy's elliptic integrals and root
    /// finder (validation/hertz.py, `scipy.special.ellipk`/`ellipe`, `brentq`).
    #[test]
    fn the_ellipse_against_scipy() {
        let e_star = E / (1.0 - NU * NU);
        // (P, a, b, p0, delta) printed by validation/hertz.py.
        let cases = [
            (
                10e3,
                0.002_638_384_079_475_111,
                0.001_984_651_210_535_22,
                911_841_124.645_008_7,
                1.413_111_507_930_657_5e-5,
            ),
            (
                100e3,
                0.005_684_226_186_449_018,
                0.004_275_801_415_590_85,
                1_964_502_150.732_893_5,
                6.559_082_595_860_656e-5,
            ),
        ];
        for (p, a, b, p0, delta) in cases {
            let h = Hertz::from_radii(0.46, 0.30, e_star, p).unwrap();
            assert!((h.eccentricity - 0.658_909_466_859_304_4).abs() < 1e-10);
            assert!(rel(h.a, a) < 1e-10, "{h:?}");
            assert!(rel(h.b, b) < 1e-10, "{h:?}");
            assert!(rel(h.peak_pressure, p0) < 1e-10, "{h:?}");
            assert!(rel(h.approach, delta) < 1e-10, "{h:?}");
            assert!(h.a_along_x);
            assert_eq!(h.semi_axes_xy(), (h.a, h.b));
            // Eq. (4.39)'s curvatures back from the solution.
            let (k, ee) = elliptic_integrals(h.eccentricity);
            let c = h.peak_pressure * h.b / (e_star * h.eccentricity.powi(2) * h.a * h.a);
            assert!(rel(c * (k - ee), 0.5 / 0.46) < 1e-9);
            assert!(rel(c * (h.a * h.a / (h.b * h.b) * ee - k), 0.5 / 0.30) < 1e-9);
            // The approach gives the load back.
            let back = Hertz::at_approach(0.5 / 0.46, 0.5 / 0.30, e_star, h.approach).unwrap();
            assert!(rel(back.load, p) < 1e-12);
        }
        // Swapped axes: a along y.
        let h = Hertz::from_radii(0.30, 0.46, e_star, 10e3).unwrap();
        assert!(!h.a_along_x && h.semi_axes_xy().1 == h.a);
    }

    /// The half-space's axial displacement: the approach at the surface (Johnson Eq. 4.39's
    /// `delta` for a rigid indenter), scipy's `dblquad` of the same kernel at 1 mm and 10 cm
    /// (validation/hertz.py), Boussinesq's point load far away.
    #[test]
    fn the_axial_displacement_of_the_half_space() {
        let e_star = E / (1.0 - NU * NU);
        let h = Hertz::from_radii(0.46, 0.30, e_star, 100e3).unwrap();
        assert!(rel(h.axial_displacement(0.0, E, NU), h.approach) < 1e-6);
        assert!(rel(h.axial_displacement(1e-3, E, NU), 5.981_857_858_775e-5) < 1e-7);
        assert!(rel(h.axial_displacement(1e-2, E, NU), 2.175_333_931_821e-5) < 1e-7);
        assert!(rel(h.axial_displacement(1e-1, E, NU), 2.362_398_068_710e-6) < 1e-7);
        let g = E / (2.0 * (1.0 + NU));
        let far = 10.0;
        let point = 100e3 * (3.0 - 2.0 * NU) / (4.0 * PI * g * far);
        assert!(rel(h.axial_displacement(far, E, NU), point) < 1e-6);
        let s = Hertz::from_radii(0.1, 0.1, e_star, 1e3).unwrap();
        assert!(rel(s.axial_displacement(0.0, E, NU), s.approach) < 1e-6);
    }

    #[test]
    fn bad_input_is_named() {
        let e = Hertz::from_radii(0.46, -1.0, 1e11, 1e3).unwrap_err();
        assert!(e.to_string().contains("`radius_y`"), "{e}");
        let e = Hertz::new(1.0, 1.0, 1e11, f64::NAN).unwrap_err();
        assert!(matches!(e, HertzError::NotPositive { name: "load", .. }));
        assert!(Hertz::at_approach(1.0, 1.0, 1e11, 0.0).is_err());
    }
}
