//! The J2 (von Mises) elastic-plastic material point of [`crate::plasticity`] on a full 3D
//! strain, for the solid elements: [`j2_update_3d`].
//!
//! # Reusing the 2D code's return
//!
//! [`J2Material::return_3d`] works on a 3D state with one shear component (`[xx, yy, zz,
//! xy]`). The radial return (module docs of [`crate::plasticity`]) only ever combines the
//! trial deviator $s^{tr}$ and the backstress $\beta_n$ linearly and uses their Frobenius
//! inner products: the new plastic strain increment, backstress and stress deviator all lie
//! in $\operatorname{span}\{s^{tr}, \beta_n\}$, and $\Delta\lambda$ depends on $|s^{tr}|$,
//! $|\beta_n|$, $s^{tr}:\beta_n$ and $\bar\varepsilon^p_n$ only. So the 6-component problem
//! is carried exactly onto a 4-component one: an orthonormal (Frobenius) deviatoric basis
//! $e_1, e_2$ of that span (Gram-Schmidt) is mapped onto the orthonormal deviatoric
//! $f_1 = \mathrm{diag}(1, -1, 0)/\sqrt2$ and $f_2$ (unit $xy$ shear), `return_3d` runs there
//! with every hardening law it knows (linear and Voce isotropic, Prager and
//! Armstrong-Frederick kinematic), and the answer is mapped back. The volumetric part is
//! elastic: $\sigma = K\\,\mathrm{tr}\\,\varepsilon\\,I + s$.
//!
//! # Consistent tangent
//!
//! Without Armstrong-Frederick recall ($\gamma = 0$; any isotropic law), with
//! $\xi^{tr} = s^{tr} - \beta_n$, $n = \xi^{tr}/|\xi^{tr}|$ and the slope $H' =
//! \sigma_Y'(\bar\varepsilon^p_{n+1})$ (Simo and Hughes, *Computational Inelasticity*,
//! 1998, Box 3.2):
//!
//! $$C = K\\,1\otimes1 + 2\mu\beta\\,I_{dev} - 2\mu\bar\gamma\\,n\otimes n,\qquad
//!   \beta = 1 - \frac{2\mu\Delta\lambda}{|\xi^{tr}|},\qquad
//!   \bar\gamma = \frac{2\mu}{2\mu + \tfrac23(C_k + H')} + \beta - 1,$$
//!
//! in the Voigt order of [`super::solid`] (engineering shear strains: the shear rows and
//! columns of $2\mu I_{dev}$ are $\mu$, and $n\otimes n$ uses the tensor components of $n$).
//! With $\gamma \ne 0$ the tangent is the central difference of the return (step
//! $10^{-8}$ of the strain's size; documented as such in [`PointResult3d::tangent`]).
//!
//! No call allocates.

use crate::plasticity::{J2Material, PointState};

const SQRT_HALF: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The state of one 3D material point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PointState3d {
    /// Total strain, Voigt `[xx, yy, zz, yz, xz, xy]` (engineering shears).
    pub strain: [f64; 6],
    /// Plastic strain, same order (engineering shears).
    pub plastic: [f64; 6],
    /// Backstress, Voigt stress order, Pa (deviatoric).
    pub back: [f64; 6],
    /// Equivalent plastic strain.
    pub eq: f64,
}

impl PointState3d {
    /// Numbers in [`Self::read`]'s layout: strain, plastic strain, backstress, `eq`.
    pub const LEN: usize = 19;

    /// From [`Self::LEN`] numbers.
    pub fn read(s: &[f64]) -> Self {
        let six = |k: usize| std::array::from_fn(|i| s[k + i]);
        Self {
            strain: six(0),
            plastic: six(6),
            back: six(12),
            eq: s[18],
        }
    }

    /// Into [`Self::LEN`] numbers.
    pub fn write(&self, s: &mut [f64]) {
        s[..6].copy_from_slice(&self.strain);
        s[6..12].copy_from_slice(&self.plastic);
        s[12..18].copy_from_slice(&self.back);
        s[18] = self.eq;
    }
}

/// What [`j2_update_3d`] returns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointResult3d {
    /// The new state.
    pub state: PointState3d,
    /// Stress, Voigt order, Pa.
    pub stress: [f64; 6],
    /// `d sigma / d eps` (Voigt, engineering strains), Pa: the elastic `D` after an elastic
    /// step, the consistent tangent of the return after a plastic one (module docs).
    pub tangent: [[f64; 6]; 6],
    /// True when the step flowed plastically.
    pub plastic: bool,
    /// True when the return's iteration stopped at its cap.
    pub unconverged: bool,
}

/// Frobenius product of two symmetric tensors stored `[xx, yy, zz, yz, xz, xy]` (tensor
/// shears).
fn dot6(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2.0 * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5])
}

fn lame(m: &J2Material) -> (f64, f64) {
    let (e, nu) = (m.elastic.young, m.elastic.poisson);
    (
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        e / (2.0 * (1.0 + nu)),
    )
}

/// Engineering Voigt strain to tensor components.
fn tensor(e: &[f64; 6]) -> [f64; 6] {
    [e[0], e[1], e[2], 0.5 * e[3], 0.5 * e[4], 0.5 * e[5]]
}

/// The return itself (no tangent).
fn update(
    m: &J2Material,
    eps_v: &[f64; 6],
    st0: &PointState3d,
) -> (PointState3d, [f64; 6], bool, bool, f64, f64) {
    let (lam, mu) = lame(m);
    let eps = tensor(eps_v);
    let ep = tensor(&st0.plastic);
    let mut ee = [0.0; 6];
    for k in 0..6 {
        ee[k] = eps[k] - ep[k];
    }
    let tr = ee[0] + ee[1] + ee[2];
    let mut s_tr = ee.map(|v| 2.0 * mu * v);
    for v in &mut s_tr[..3] {
        *v -= 2.0 * mu * tr / 3.0;
    }
    let elastic = |state: PointState3d| {
        let mut sig = s_tr;
        for v in &mut sig[..3] {
            *v += (lam + 2.0 * mu / 3.0) * tr;
        }
        (state, sig, false, false, 0.0, 0.0)
    };
    let mut state = *st0;
    state.strain = *eps_v;
    let b0 = st0.back;
    // Orthonormal basis of span{s_tr, b0}.
    let (ns, nb) = (dot6(&s_tr, &s_tr).sqrt(), dot6(&b0, &b0).sqrt());
    let scale = ns.max(nb);
    if scale == 0.0 || !scale.is_finite() {
        return elastic(state);
    }
    let first = if ns >= 1e-14 * scale { s_tr } else { b0 };
    let n1 = dot6(&first, &first).sqrt();
    let e1 = first.map(|v| v / n1);
    let other = if ns >= 1e-14 * scale { b0 } else { s_tr };
    let p = dot6(&other, &e1);
    let mut r = other;
    for k in 0..6 {
        r[k] -= p * e1[k];
    }
    let nr = dot6(&r, &r).sqrt();
    let e2 = if nr > 1e-14 * scale {
        r.map(|v| v / nr)
    } else {
        [0.0; 6]
    };
    let (s1, s2) = (dot6(&s_tr, &e1), dot6(&s_tr, &e2));
    let (b1, b2) = (dot6(&b0, &e1), dot6(&b0, &e2));
    // In return_3d's [xx, yy, zz, xy] (tensor shear): f1 = [1, -1, 0, 0]/sqrt2, f2 = [0, 0,
    // 0, 1/sqrt2], orthonormal for its inner product (shear counted twice).
    let to4 = |c1: f64, c2: f64| [c1 * SQRT_HALF, -c1 * SQRT_HALF, 0.0, c2 * SQRT_HALF];
    let from4 = |v: &[f64; 4]| {
        let c1 = (v[0] - v[1]) * SQRT_HALF;
        let c2 = 2.0 * v[3] * SQRT_HALF;
        let mut t = [0.0; 6];
        for k in 0..6 {
            t[k] = c1 * e1[k] + c2 * e2[k];
        }
        t
    };
    let st4 = PointState {
        eps_p: [0.0; 4],
        back: to4(b1, b2),
        eq: st0.eq,
        ezz: 0.0,
    };
    let eps4 = to4(s1 / (2.0 * mu), s2 / (2.0 * mu));
    let (st4n, _, flowed, unconverged) = m.return_3d(&eps4, &st4);
    if !flowed {
        return elastic(state);
    }
    let dep = from4(&st4n.eps_p);
    let back = from4(&st4n.back);
    let mut sig = [0.0; 6];
    for k in 0..6 {
        sig[k] = s_tr[k] - 2.0 * mu * dep[k];
        state.plastic[k] += if k < 3 { dep[k] } else { 2.0 * dep[k] };
    }
    for v in &mut sig[..3] {
        *v += (lam + 2.0 * mu / 3.0) * tr;
    }
    state.back = back;
    state.eq = st4n.eq;
    // Delta lambda = |d eps_p|, and |xi_tr|.
    let dl = dot6(&dep, &dep).sqrt();
    let mut xi = s_tr;
    for k in 0..6 {
        xi[k] -= b0[k];
    }
    (state, sig, true, unconverged, dl, dot6(&xi, &xi).sqrt())
}

/// The elastic `D` of the material.
fn elastic_tangent(m: &J2Material) -> [[f64; 6]; 6] {
    super::solid::elasticity_3d(&m.elastic)
}

/// The state, stress (Voigt, Pa) and whether it flowed at the total strain `eps` (Voigt,
/// engineering shears) from the state `st0`: [`j2_update_3d`]'s return without its tangent.
pub fn j2_stress_3d(
    m: &J2Material,
    eps: &[f64; 6],
    st0: &PointState3d,
) -> (PointState3d, [f64; 6], bool) {
    let (state, stress, plastic, _, _, _) = update(m, eps, st0);
    (state, stress, plastic)
}

/// The J2 material point's response to the strain increment `d_strain` (Voigt, engineering
/// shears) from the state `st0`: radial return of [`J2Material::return_3d`] carried onto the
/// full 3D state (module docs), and the consistent tangent. No allocation.
pub fn j2_update_3d(m: &J2Material, d_strain: &[f64; 6], st0: &PointState3d) -> PointResult3d {
    let mut eps = st0.strain;
    for k in 0..6 {
        eps[k] += d_strain[k];
    }
    let (state, stress, plastic, unconverged, dl, nxi) = update(m, &eps, st0);
    let mut tangent = elastic_tangent(m);
    if plastic {
        if m.kinematic.gamma == 0.0 {
            let (lam, mu) = lame(m);
            let kb = lam + 2.0 * mu / 3.0;
            let hp = m.flow_stress(state.eq).1;
            let beta = 1.0 - 2.0 * mu * dl / nxi;
            let gbar =
                2.0 * mu / (2.0 * mu + 2.0 / 3.0 * (m.kinematic.c + hp)) - 2.0 * mu * dl / nxi;
            // n: the tensor components of xi_tr / |xi_tr| = the flow direction d eps_p / dl.
            let dep = {
                let mut d = [0.0; 6];
                for k in 0..6 {
                    let p = state.plastic[k] - st0.plastic[k];
                    d[k] = if k < 3 { p } else { 0.5 * p } / dl;
                }
                d
            };
            for r in 0..6 {
                for c in 0..6 {
                    let idev = if r < 3 && c < 3 {
                        f64::from(u8::from(r == c)) - 1.0 / 3.0
                    } else if r == c {
                        0.5
                    } else {
                        0.0
                    };
                    let vol = if r < 3 && c < 3 { kb } else { 0.0 };
                    tangent[r][c] =
                        vol + 2.0 * mu * beta * idev - 2.0 * mu * gbar * dep[r] * dep[c];
                }
            }
        } else {
            let size = eps.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(1e-6);
            let h = 1e-8 * size;
            for c in 0..6 {
                let mut ep = eps;
                let mut em = eps;
                ep[c] += h;
                em[c] -= h;
                let sp = update(m, &ep, st0).1;
                let sm = update(m, &em, st0).1;
                for r in 0..6 {
                    tangent[r][c] = (sp[r] - sm[r]) / (2.0 * h);
                }
            }
        }
    }
    PointResult3d {
        state,
        stress,
        tangent,
        plastic,
        unconverged,
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // index loops read best for small dense matrices
mod tests {
    use super::*;
    use crate::material::Elastic;
    use crate::plasticity::{Isotropic, Kinematic};

    const E: f64 = 200e9;
    const SY: f64 = 250e6;

    fn material(h: f64, c: f64, voce: (f64, f64)) -> J2Material {
        J2Material {
            elastic: Elastic {
                young: E,
                poisson: 0.3,
                density: 7800.0,
            },
            yield_stress: SY,
            isotropic: Isotropic {
                modulus: h,
                voce_q: voce.0,
                voce_b: voce.1,
            },
            kinematic: Kinematic { c, gamma: 0.0 },
        }
    }

    /// One step of a uniaxial stress path: the axial strain increment `dx` with the lateral
    /// strains found by Newton on the consistent tangent so that sigma_yy = sigma_zz = 0.
    fn uniaxial_step(m: &J2Material, st: &PointState3d, dx: f64) -> PointResult3d {
        let (mut dy, mut dz) = (-0.3 * dx, -0.3 * dx);
        for _ in 0..50 {
            let r = j2_update_3d(m, &[dx, dy, dz, 0.0, 0.0, 0.0], st);
            let (fy, fz) = (r.stress[1], r.stress[2]);
            if fy.abs().max(fz.abs()) < 1e-6 {
                return r;
            }
            let t = r.tangent;
            let det = t[1][1] * t[2][2] - t[1][2] * t[2][1];
            dy -= (t[2][2] * fy - t[1][2] * fz) / det;
            dz -= (t[1][1] * fz - t[2][1] * fy) / det;
        }
        panic!("uniaxial Newton did not converge");
    }

    #[test]
    fn uniaxial_stress_against_the_closed_form_elastic_plastic_answers() {
        let ey = SY / E;
        // (H, C): perfectly plastic, linear isotropic, linear kinematic (Prager).
        for (h, c) in [(0.0, 0.0), (10e9, 0.0), (0.0, 10e9)] {
            let m = material(h, c, (0.0, 0.0));
            let hk = h + c;
            // Monotone loading: sigma = E eps below yield, sigma_y + E Hk / (E + Hk)
            // (eps - eps_y) above (eps_p = eps - sigma / E, sigma = sigma_y + Hk eps_p).
            let closed = |eps: f64| {
                if eps <= ey {
                    E * eps
                } else {
                    SY + E * hk / (E + hk) * (eps - ey)
                }
            };
            let mut st = PointState3d::default();
            let n = 50;
            let de = 5.0 * ey / n as f64;
            for k in 1..=n {
                let r = uniaxial_step(&m, &st, de);
                st = r.state;
                let eps = k as f64 * de;
                assert!(
                    (r.stress[0] - closed(eps)).abs() < 1e-9 * SY,
                    "H {h} C {c} eps {eps}: {} vs {}",
                    r.stress[0],
                    closed(eps)
                );
                assert!(r.stress[3..].iter().all(|v| v.abs() < 1e-6));
                // Plastic incompressibility: lateral plastic strains are -1/2 the axial one.
                let p = st.plastic;
                assert!((p[1] + 0.5 * p[0]).abs() < 1e-15 && (p[2] + 0.5 * p[0]).abs() < 1e-15);
                assert!((st.eq - p[0]).abs() < 1e-15, "{} vs {}", st.eq, p[0]);
            }
            let smax = closed(5.0 * ey);
            // Unloading: elastic until the reverse yield stress, sigma_max - 2 sigma_y for
            // the kinematic rule (the surface translated), -sigma_max for the isotropic one
            // (expanded), -sigma_y for no hardening.
            let reverse = if c > 0.0 { smax - 2.0 * SY } else { -smax };
            let mut last = smax;
            let step = -ey / 20.0;
            loop {
                let r = uniaxial_step(&m, &st, step);
                if r.plastic {
                    // The elastic prediction of this step crossed the reverse yield stress.
                    assert!(
                        last >= reverse - 1e-9 * SY && last + E * step <= reverse + 1e-9 * SY,
                        "H {h} C {c}: reverse yield between {last} and {}, expected {reverse}",
                        last + E * step
                    );
                    break;
                }
                assert!((r.stress[0] - (last + E * step)).abs() < 1e-6 * SY);
                last = r.stress[0];
                st = r.state;
                assert!(last > -2.0 * smax, "no reverse yield");
            }
        }
    }

    #[test]
    fn a_rotated_uniaxial_path_gives_the_rotated_stress() {
        // Isotropy: the axis-aligned uniaxial strain history diag(e1, e2, e2) turned to the
        // direction a gives sigma a (x) a, with all six components non-zero, through the
        // general (two-direction) embedding of return_3d.
        let m = material(5e9, 20e9, (100e6, 30.0));
        let a = {
            let v = [0.3f64, -0.5, 0.8];
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            v.map(|x| x / n)
        };
        let voigt = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];
        let turn = |e1: f64, e2: f64| {
            voigt.map(|(i, j)| {
                let t = (e1 - e2) * a[i] * a[j] + if i == j { e2 } else { 0.0 };
                if i == j {
                    t
                } else {
                    2.0 * t
                }
            })
        };
        let (mut st, mut sr) = (PointState3d::default(), PointState3d::default());
        let ey = SY / E;
        for k in 0..60 {
            let dx = if k < 40 { ey / 8.0 } else { -ey / 4.0 };
            let r = uniaxial_step(&m, &st, dx);
            let d = [0, 1, 2, 3, 4, 5].map(|c| r.state.strain[c] - st.strain[c]);
            st = r.state;
            let rr = j2_update_3d(&m, &turn(d[0], d[1]), &sr);
            sr = rr.state;
            let expect = voigt.map(|(i, j)| r.stress[0] * a[i] * a[j]);
            for c in 0..6 {
                assert!(
                    (rr.stress[c] - expect[c]).abs() < 1e-6 * SY,
                    "step {k}: {:?} vs {expect:?}",
                    rr.stress
                );
            }
            assert!((rr.state.eq - st.eq).abs() < 1e-12);
        }
        assert!(st.eq > 2.0 * ey, "the path went plastic both ways");
    }

    #[test]
    fn the_consistent_tangent_is_the_derivative_of_the_return() {
        let m = material(8e9, 15e9, (80e6, 40.0));
        // A plastic state reached along a non-proportional path.
        let mut st = PointState3d::default();
        let path = [
            [2e-3, -6e-4, -6e-4, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 3e-3, 0.0, 0.0],
            [-5e-4, 1e-3, 0.0, 0.0, -2e-3, 1e-3],
        ];
        for d in &path {
            st = j2_update_3d(&m, d, &st).state;
        }
        assert!(st.eq > 0.0);
        let d = [4e-4, -2e-4, 1e-4, 6e-4, -3e-4, 2e-4];
        let r = j2_update_3d(&m, &d, &st);
        assert!(r.plastic);
        let mu = E / 2.6;
        let h = 1e-9;
        for c in 0..6 {
            let mut dp = d;
            let mut dm = d;
            dp[c] += h;
            dm[c] -= h;
            let sp = j2_update_3d(&m, &dp, &st).stress;
            let sm = j2_update_3d(&m, &dm, &st).stress;
            for row in 0..6 {
                let fd = (sp[row] - sm[row]) / (2.0 * h);
                assert!(
                    (fd - r.tangent[row][c]).abs() < 1e-5 * mu,
                    "C[{row}][{c}] = {} vs FD {fd}",
                    r.tangent[row][c]
                );
            }
        }
        // The elastic tangent after an elastic step.
        let r = j2_update_3d(
            &m,
            &[1e-5, 0.0, 0.0, 0.0, 0.0, 0.0],
            &PointState3d::default(),
        );
        assert!(!r.plastic);
        assert_eq!(r.tangent, super::super::solid::elasticity_3d(&m.elastic));
    }
}
