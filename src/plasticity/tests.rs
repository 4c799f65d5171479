//! The material point against exact answers (uniaxial stress and the plane-strain bar,
//! Bauschinger, Armstrong-Frederick's saturation, the return on the yield surface) and the
//! plastic body's pseudo-load.

use super::*;

const E: f64 = 200e9;
const NU: f64 = 0.3;
const SY: f64 = 250e6;
const EY: f64 = SY / E;

fn mat(h: f64, c: f64, gamma: f64) -> J2Material {
    J2Material {
        elastic: Elastic {
            young: E,
            poisson: NU,
            density: 7850.0,
        },
        yield_stress: SY,
        isotropic: Isotropic {
            modulus: h,
            voce_q: 0.0,
            voce_b: 0.0,
        },
        kinematic: Kinematic { c, gamma },
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// Uniaxial stress `sigma_xx` in plane stress: `eps_yy` found (secant, outside the material)
/// so that `sigma_yy = 0`. Returns the result at `exx` from `st`.
fn uniaxial(m: &J2Material, exx: f64, st: &PointState) -> PointResult {
    let f = |eyy: f64| m.update(PlaneModel::Stress, [exx, eyy, 0.0], st);
    let (mut a, mut b) = (-NU * exx, -0.5 * exx);
    let (mut fa, mut fb) = (f(a).stress[1], f(b).stress[1]);
    for _ in 0..100 {
        if fb.abs() <= 1e-9 * SY || fa == fb {
            break;
        }
        let c = b - fb * (b - a) / (fb - fa);
        (a, fa) = (b, fb);
        b = c;
        fb = f(b).stress[1];
    }
    let r = f(b);
    assert!(r.stress[1].abs() <= 1e-8 * SY, "sigma_yy {}", r.stress[1]);
    r
}

/// `(H_iso, C)` cases: isotropic and Prager kinematic, both with slope 10 GPa.
const H: f64 = 10e9;

#[test]
fn uniaxial_stress_loading_unloading_reloading_follow_the_exact_curve() {
    for (h, c) in [(H, 0.0), (0.0, H)] {
        let m = mat(h, c, 0.0);
        let st0 = PointState::default();
        // Elastic up to yield.
        let r = uniaxial(&m, 0.999 * EY, &st0);
        assert!(!r.plastic && rel(r.stress[0], 0.999 * SY) < 1e-8);
        // Loading past yield: sigma = sigma_y + E_t (eps - eps_y), E_t = E K / (E + K).
        let e1 = 5.0 * EY;
        let r1 = uniaxial(&m, e1, &st0);
        let et = E * H / (E + H);
        let s1 = SY + et * (e1 - EY);
        assert!(
            r1.plastic && rel(r1.stress[0], s1) < 1e-8,
            "{} {s1}",
            r1.stress[0]
        );
        let ep1 = e1 - s1 / E;
        assert!(rel(r1.state.eps_p[0], ep1) < 1e-8);
        assert!(rel(r1.state.eq, ep1) < 1e-8);
        // Plastic incompressibility: eps_p_yy = eps_p_zz = -eps_p_xx / 2.
        assert!(rel(r1.state.eps_p[1], -0.5 * ep1) < 1e-8);
        assert!(rel(r1.state.eps_p[2], -0.5 * ep1) < 1e-8);
        // Unloading is elastic, slope E, down to zero stress at eps_p.
        let r2 = uniaxial(&m, e1 - 0.5 * s1 / E, &r1.state);
        assert!(!r2.plastic && rel(r2.stress[0], 0.5 * s1) < 1e-8);
        let r0 = uniaxial(&m, ep1, &r1.state);
        assert!(!r0.plastic && r0.stress[0].abs() < 1e-7 * SY);
        // Reloading is elastic up to the previous maximum, then on the monotonic curve.
        let r3 = uniaxial(&m, e1, &r2.state);
        assert!(!r3.plastic && rel(r3.stress[0], s1) < 1e-8);
        let e4 = 8.0 * EY;
        let r4 = uniaxial(&m, e4, &r3.state);
        assert!(r4.plastic && rel(r4.stress[0], SY + et * (e4 - EY)) < 1e-8);
        // Reverse yield: isotropic at -(sigma_y + H eps_p), kinematic at sigma_max - 2 sigma_y.
        let rev = if h > 0.0 {
            -(SY + H * ep1)
        } else {
            s1 - 2.0 * SY
        };
        let e_rev = ep1 + rev / E;
        let before = uniaxial(&m, e_rev + 1e-6 * EY, &r1.state);
        let after = uniaxial(&m, e_rev - 1e-6 * EY, &r1.state);
        assert!(!before.plastic, "{h} {c}: no flow before {rev:e}");
        assert!(after.plastic, "{h} {c}: flow past {rev:e}");
        assert!(rel(before.stress[0], rev) < 1e-5);
    }
}

#[test]
fn bauschinger_shift_of_kinematic_hardening_against_isotropic() {
    // The same monotonic curve; after loading to sigma_max the reverse yield differs:
    // isotropic -(sigma_y + H eps_p) (the elastic range grew), kinematic sigma_max - 2 sigma_y
    // (the elastic range 2 sigma_y moved with the backstress).
    let e1 = 10.0 * EY;
    let st0 = PointState::default();
    let (iso, kin) = (mat(H, 0.0, 0.0), mat(0.0, H, 0.0));
    let (ri, rk) = (uniaxial(&iso, e1, &st0), uniaxial(&kin, e1, &st0));
    assert!(rel(ri.stress[0], rk.stress[0]) < 1e-8);
    let smax = ri.stress[0];
    let ep = ri.state.eps_p[0];
    // The uniaxial backstress X = 3/2 beta_xx = C eps_p (Prager).
    assert!(rel(1.5 * rk.state.back[0], H * ep) < 1e-8);
    // Unload far: to the strain where the kinematic one yields in reverse.
    let e_k = ep + (smax - 2.0 * SY) / E;
    let e_past = e_k - 0.5 * EY;
    let (ri2, rk2) = (
        uniaxial(&iso, e_past, &ri.state),
        uniaxial(&kin, e_past, &rk.state),
    );
    assert!(!ri2.plastic, "isotropic still elastic");
    assert!(rk2.plastic, "kinematic flowed in reverse");
    // The kinematic reverse flow: sigma = sigma_max - 2 sigma_y - E_t (e_k - e).
    let et = E * H / (E + H);
    assert!(rel(rk2.stress[0], smax - 2.0 * SY - et * (e_k - e_past)) < 1e-7);
    assert!(rel(ri2.stress[0], smax + E * (e_past - e1)) < 1e-8);
}

#[test]
fn armstrong_frederick_backstress_saturates_at_c_over_gamma() {
    let (c, gamma) = (40e9, 200.0);
    let m = mat(0.0, c, gamma);
    let mut st = PointState::default();
    let mut x_prev = 0.0;
    let mut ep_prev = 0.0;
    let n = 4000;
    let e_end = 0.05;
    for k in 1..=n {
        let e = e_end * k as f64 / n as f64;
        let r = uniaxial(&m, e, &st);
        st = r.state;
        let ep = st.eps_p[0];
        let x = 1.5 * st.back[0];
        // Backward Euler's recurrence X1 = (X0 + C d) / (1 + gamma d), d = d eps_p.
        let d = ep - ep_prev;
        if d > 0.0 {
            let x_be = (x_prev + c * d) / (1.0 + gamma * d);
            assert!((x - x_be).abs() <= 1e-9 * c / gamma, "{x} {x_be}");
            // On the yield surface: sigma = sigma_y + X.
            assert!(rel(r.stress[0], SY + x) < 1e-9);
            // The exact integral X = C/gamma (1 - exp(-gamma eps_p)), to the steps' error.
            let exact = c / gamma * (1.0 - (-gamma * ep).exp());
            assert!((x - exact).abs() <= 2e-3 * c / gamma, "{x} {exact}");
        }
        (x_prev, ep_prev) = (x, ep);
    }
    // Saturated: gamma eps_p ~ 8, X = C/gamma to exp(-8).
    assert!(gamma * ep_prev > 7.0);
    assert!(rel(x_prev, c / gamma) < 1e-3);
}

#[test]
fn voce_and_small_gamma_take_the_newton_path_to_the_closed_forms() {
    // Voce: in uniaxial stress sigma = sigma_Y(eps_bar) exactly (consistency).
    let mut m = mat(2e9, 0.0, 0.0);
    m.isotropic.voce_q = 150e6;
    m.isotropic.voce_b = 300.0;
    let mut st = PointState::default();
    for k in 1..=20 {
        let r = uniaxial(&m, k as f64 * EY, &st);
        st = r.state;
        if r.plastic {
            let ep = st.eq;
            let sy = SY + 2e9 * ep + 150e6 * (1.0 - (-300.0 * ep).exp());
            assert!(rel(r.stress[0], sy) < 1e-9, "{} {sy}", r.stress[0]);
        }
    }
    // AF with gamma -> 0 by Newton against Prager's closed form, a 2D strain path.
    let (pr, af) = (mat(0.0, H, 0.0), mat(0.0, H, 1e-9));
    let (mut sp, mut sa) = (PointState::default(), PointState::default());
    for k in 0..30 {
        let t = k as f64 * 0.4;
        let eps = [
            6.0 * EY * t.sin(),
            -3.0 * EY * (0.7 * t).cos(),
            5.0 * EY * (1.3 * t).sin(),
        ];
        for plane in [PlaneModel::Strain, PlaneModel::Stress] {
            let (a, b) = (pr.update(plane, eps, &sp), af.update(plane, eps, &sa));
            for i in 0..3 {
                assert!((a.stress[i] - b.stress[i]).abs() < 1e-6 * SY);
            }
            if plane == PlaneModel::Stress {
                (sp, sa) = (a.state, b.state);
            }
        }
    }
}

#[test]
fn plane_strain_bar_first_yield_and_limit_stress() {
    // A bar in plane strain, the lateral sigma_yy = 0: elastic sigma_zz = nu sigma_xx, first
    // yield at sigma_xx = sigma_y / sqrt(1 - nu + nu^2); perfectly plastic, the flow tends
    // to sigma_zz = sigma_xx / 2 with sigma_xx -> 2 sigma_y / sqrt(3).
    let m = mat(0.0, 0.0, 0.0);
    let sx_first = SY / (1.0 - NU + NU * NU).sqrt();
    let ex_first = sx_first * (1.0 - NU * NU) / E;
    let bar = |exx: f64, st: &PointState| {
        let f = |eyy: f64| m.update(PlaneModel::Strain, [exx, eyy, 0.0], st);
        // sigma_yy is increasing in eps_yy: bisection.
        let (mut a, mut b) = (-2.0 * exx.abs() - 1e-3, 2.0 * exx.abs() + 1e-3);
        for _ in 0..200 {
            let c = 0.5 * (a + b);
            if f(c).stress[1] > 0.0 {
                b = c;
            } else {
                a = c;
            }
        }
        f(0.5 * (a + b))
    };
    let st0 = PointState::default();
    let r = bar(0.9999 * ex_first, &st0);
    assert!(!r.plastic && rel(r.szz, NU * r.stress[0]) < 1e-6);
    assert!(bar(1.0001 * ex_first, &st0).plastic);
    let mut st = st0;
    let mut r = r;
    for k in 1..=400 {
        r = bar(k as f64 * 0.5 * EY, &st);
        st = r.state;
    }
    let limit = 2.0 * SY / 3f64.sqrt();
    assert!(rel(r.stress[0], limit) < 1e-6, "{} {limit}", r.stress[0]);
    assert!(rel(r.szz, 0.5 * r.stress[0]) < 1e-6);
    // On the yield surface all along: von Mises of (sxx, 0, szz) = sigma_y.
    let vm = crate::material::von_mises(r.stress[0], r.stress[1], r.stress[2], r.szz);
    assert!(rel(vm, SY) < 1e-10);
}

/// Deterministic pseudo-random numbers in [-1, 1) (xorshift64*).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (v >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

#[test]
fn the_return_stays_on_the_yield_surface_to_1e_10() {
    let mut voce = mat(1e9, 20e9, 100.0);
    voce.isotropic.voce_q = 100e6;
    voce.isotropic.voce_b = 50.0;
    let cases = [
        mat(0.0, 0.0, 0.0),
        mat(H, 0.0, 0.0),
        mat(0.0, H, 0.0),
        mat(0.0, 40e9, 200.0),
        voce,
    ];
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut flowed = 0;
    for m in &cases {
        for plane in [PlaneModel::Strain, PlaneModel::Stress] {
            let mut st = PointState::default();
            let mut eps = [0.0; 3];
            for _ in 0..300 {
                for e in &mut eps {
                    *e += 2.0 * EY * rng.next();
                }
                let r = m.update(plane, eps, &st);
                assert!(!r.unconverged);
                if plane == PlaneModel::Stress {
                    assert!(r.szz.abs() <= 1e-10 * SY, "sigma_zz {}", r.szz);
                }
                let s3 = [r.stress[0], r.stress[1], r.szz, r.stress[2]];
                let f = m.yield_function(&s3, &r.state);
                let sy = m.flow_stress(r.state.eq).0;
                if r.plastic {
                    flowed += 1;
                    assert!(f.abs() <= 1e-10 * sy, "{plane:?} f = {f:e}");
                    // eps_p stays deviatoric.
                    let tr = r.state.eps_p[0] + r.state.eps_p[1] + r.state.eps_p[2];
                    assert!(tr.abs() <= 1e-12 * r.state.eq.max(EY));
                } else {
                    assert!(f <= 1e-10 * sy);
                }
                st = r.state;
            }
        }
    }
    assert!(flowed > 1000, "{flowed}");
}

#[test]
fn body_pseudo_load_and_internal_force_add_up_to_k_u() {
    use crate::element::tri3::{geometry, stiffness_into};
    // Two triangles of a unit square; a plastic state from a large shear, then a small
    // displacement with no new flow: f_nl = pseudo_load(state), f_int + f_nl = K u.
    let x = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let tris = vec![[0, 1, 2], [0, 2, 3]];
    for plane in [PlaneModel::Strain, PlaneModel::Stress] {
        let geo: Vec<_> = tris
            .iter()
            .map(|t| geometry(&t.map(|i| x[i])).unwrap())
            .collect();
        let body = PlasticBody::new(mat(H, H, 0.0), plane, 0.01, tris.clone(), geo.clone());
        let n = 8;
        let big: Vec<f64> = (0..n)
            .map(|i| 8.0 * EY * x[i / 2][1 - i % 2] * if i % 2 == 0 { 1.0 } else { 0.3 })
            .collect();
        let s0 = vec![0.0; body.state_len()];
        let (mut s1, mut fnl, mut fint) = (s0.clone(), vec![0.0; n], vec![0.0; n]);
        assert!(body.evaluate(&s0, &big, &mut s1, &mut fnl, &mut fint) > 0);
        // A displacement back towards zero stress: elastic.
        let small: Vec<f64> = big.iter().map(|v| 0.9 * v).collect();
        let mut s2 = s1.clone();
        assert_eq!(body.evaluate(&s1, &small, &mut s2, &mut fnl, &mut fint), 0);
        assert_eq!(s1, s2);
        let mut pl = vec![0.0; n];
        body.pseudo_load(&s1, &mut pl);
        let d = plane.elasticity_matrix(&body.material.elastic);
        let mut ku = vec![0.0; n];
        for (t, g) in tris.iter().zip(&geo) {
            let mut ke = [[0.0; 6]; 6];
            stiffness_into(g, &d, 0.01, &mut ke);
            for a in 0..6 {
                for b in 0..6 {
                    ku[2 * t[a / 2] + a % 2] += ke[a][b] * small[2 * t[b / 2] + b % 2];
                }
            }
        }
        let scale = ku.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for i in 0..n {
            assert!((fnl[i] - pl[i]).abs() <= 1e-9 * scale, "{plane:?} {i}");
            assert!((fint[i] + fnl[i] - ku[i]).abs() <= 1e-9 * scale);
        }
    }
}
