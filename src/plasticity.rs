//! J2 (von Mises) elastic-plastic material for the triangles, integrated by radial return,
//! and the plastic body that the driver solves on the elastic factor
//! ([`crate::model::InternalForce`]).
//!
//! # The material point ([`J2Material::update`])
//!
//! Small strains, additive split $\varepsilon = \varepsilon^e + \varepsilon^p$, isotropic
//! elasticity $\sigma = \lambda\,\mathrm{tr}\,\varepsilon^e I + 2\mu\,\varepsilon^e$, the
//! yield function with the backstress $\beta$ (deviatoric) and the equivalent plastic strain
//! $\bar\varepsilon^p$
//! $$f = \lVert s - \beta \rVert - \sqrt{\tfrac23}\\,\sigma_Y(\bar\varepsilon^p),\qquad
//!   \sigma_Y = \sigma_y + H\bar\varepsilon^p + Q\\,(1 - e^{-b\bar\varepsilon^p}),$$
//! (linear isotropic hardening `H`, Voce's `Q`, `b`; none: `H = Q = 0`), associated flow
//! $\dot\varepsilon^p = \dot\lambda\, n$, $n = (s-\beta)/\lVert s-\beta\rVert$,
//! $\dot{\bar\varepsilon}{}^p = \sqrt{2/3}\,\dot\lambda$, and the Armstrong-Frederick
//! backstress $\dot\beta = \tfrac23 C\,\dot\varepsilon^p - \gamma\,\beta\,
//! \dot{\bar\varepsilon}{}^p$ (Prager's linear kinematic hardening: $\gamma = 0$). In
//! uniaxial stress the backstress $X = \tfrac32\beta_{xx}$ obeys $dX = C\,d\varepsilon^p -
//! \gamma X |d\varepsilon^p|$: slope `C` (Prager), saturation at `C / gamma` (AF).
//!
//! **Radial return** (backward Euler). With the trial deviator $s^{tr} = 2\mu\,
//! \mathrm{dev}(\varepsilon - \varepsilon^p_n)$ and $\theta = 1/(1 + \gamma\sqrt{2/3}\,
//! \Delta\lambda)$, $\beta_{n+1} = \theta(\beta_n + \tfrac23 C\Delta\lambda\, n)$, so
//! $\xi_{n+1} = s_{n+1} - \beta_{n+1} = \eta - (2\mu + \tfrac23\theta C)\Delta\lambda\, n$
//! with $\eta = s^{tr} - \theta\beta_n$: $n = \eta/\lVert\eta\rVert$ and $\Delta\lambda$ is
//! the root of the scalar
//! $$g(\Delta\lambda) = \lVert\eta\rVert - (2\mu + \tfrac23\theta C)\Delta\lambda -
//!   \sqrt{\tfrac23}\\,\sigma_Y(\bar\varepsilon^p_n + \sqrt{\tfrac23}\Delta\lambda) = 0.$$
//! Linear hardening ($\gamma = 0$, $Q = 0$): closed form
//! $\Delta\lambda = f^{tr}/(2\mu + \tfrac23 C + \tfrac23 H)$. Otherwise a safeguarded scalar
//! Newton (bisection when a step leaves the bracket) to $|g| \le$ [`RETURN_TOL`]
//! $\sigma_y$. Either way the returned state is on the yield surface to that tolerance.
//!
//! **Plane strain** ([`PlaneModel::Strain`]): the 3D return with $\varepsilon_{zz} = 0$;
//! the out-of-plane stress $\sigma_{zz}$ is kept ([`PointResult::szz`]) and the plastic
//! strain has its $zz$ component. **Plane stress** ([`PlaneModel::Stress`]): the same 3D
//! return with an outer iteration on the total $\varepsilon_{zz}$ until $\sigma_{zz} = 0$
//! (a safeguarded secant on the monotone $\sigma_{zz}(\varepsilon_{zz})$, starting from the
//! elastic plane-stress value, to $|\sigma_{zz}| \le$ [`PLANE_STRESS_TOL`] $\sigma_y$), not
//! the projected return of Simo & Taylor: one return for every hardening law.
//!
//! No call allocates.
//!
//! # The plastic body ([`PlasticBody`])
//!
//! The triangles' internal force is $f_{int}(u) = \sum_e A_e t\, B^T\sigma_e = K u - f_p$
//! with the pseudo-load $f_p = \sum_e A_e t\, B^T (D\varepsilon_e - \sigma_e)$ (for a
//! return without new flow, $D\varepsilon^p$ in plane stress and $2\mu\varepsilon^p$ in
//! plane strain, since $\mathrm{tr}\,\varepsilon^p = 0$). The step stays on the elastic
//! factor: $f_p$ is a load, corrected by the initial-stress iteration of
//! [`crate::model::Nonlinear`].
//!
//! # After a pass
//!
//! [`permanent_radial_displacement`] gives the rim's permanent radial surface displacement
//! (the growth driver's input).

pub mod shakedown;

use crate::element::tri3::{strain, Tri3Geometry};
use crate::linalg::{LinalgError, Pattern, SparseLu};
use crate::material::{Elastic, PlaneModel};
use crate::model::InternalForce;

/// Tolerance of the scalar return, relative to the initial yield stress: `|g| <= 1e-12
/// sigma_y` (module docs).
pub const RETURN_TOL: f64 = 1e-12;

/// Tolerance of the plane-stress iteration, relative to the initial yield stress:
/// `|sigma_zz| <= 1e-11 sigma_y`.
pub const PLANE_STRESS_TOL: f64 = 1e-11;

/// Most Newton (return) or secant (plane stress) iterations before giving up with the
/// last iterate (never reached in the tests; counted in [`PointResult::unconverged`]).
const MAX_ITER: usize = 60;

const SQRT_2_3: f64 = 0.816_496_580_927_726;

/// Isotropic hardening: `sigma_Y = sigma_y + H eps_bar + Q (1 - exp(-b eps_bar))`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Isotropic {
    /// Linear modulus `H`, Pa (0: none).
    pub modulus: f64,
    /// Voce's saturation stress `Q`, Pa (0: none).
    pub voce_q: f64,
    /// Voce's rate `b`, dimensionless.
    pub voce_b: f64,
}

/// Kinematic hardening (Armstrong-Frederick; Prager for `gamma = 0`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Kinematic {
    /// `C`, Pa (0: none).
    pub c: f64,
    /// `gamma`, dimensionless (0: Prager's linear rule).
    pub gamma: f64,
}

/// A J2 elastic-plastic material (module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct J2Material {
    /// Elastic constants.
    pub elastic: Elastic,
    /// Initial yield stress `sigma_y` (uniaxial), Pa.
    pub yield_stress: f64,
    /// Isotropic hardening.
    pub isotropic: Isotropic,
    /// Kinematic hardening.
    pub kinematic: Kinematic,
}

/// Per material point: plastic strain (tensor components `[xx, yy, zz, xy]`), backstress
/// (Pa, same order), equivalent plastic strain and, in plane stress, the total
/// out-of-plane strain.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PointState {
    /// Plastic strain `[xx, yy, zz, xy]` (tensor shear, half the engineering one).
    pub eps_p: [f64; 4],
    /// Backstress `[xx, yy, zz, xy]`, Pa (deviatoric).
    pub back: [f64; 4],
    /// Equivalent plastic strain `eps_bar`.
    pub eq: f64,
    /// Total `eps_zz` (plane stress; 0 in plane strain).
    pub ezz: f64,
}

/// Numbers of one [`PointState`] in a flat state vector.
pub const STATE_LEN: usize = 10;

impl PointState {
    /// From `STATE_LEN` numbers.
    pub fn read(s: &[f64]) -> Self {
        Self {
            eps_p: [s[0], s[1], s[2], s[3]],
            back: [s[4], s[5], s[6], s[7]],
            eq: s[8],
            ezz: s[9],
        }
    }

    /// Into `STATE_LEN` numbers.
    pub fn write(&self, s: &mut [f64]) {
        s[..4].copy_from_slice(&self.eps_p);
        s[4..8].copy_from_slice(&self.back);
        s[8] = self.eq;
        s[9] = self.ezz;
    }
}

/// What [`J2Material::update`] returns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointResult {
    /// The new state.
    pub state: PointState,
    /// In-plane stress `[sxx, syy, txy]`, Pa.
    pub stress: [f64; 3],
    /// Out-of-plane stress `sigma_zz`, Pa (0 in plane stress, to the tolerance).
    pub szz: f64,
    /// True when the step flowed plastically.
    pub plastic: bool,
    /// True when an iteration stopped at its cap.
    pub unconverged: bool,
}

fn dot4(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2.0 * a[3] * b[3]
}

fn norm4(a: &[f64; 4]) -> f64 {
    dot4(a, a).sqrt()
}

impl J2Material {
    fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.elastic.young, self.elastic.poisson);
        (
            e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            e / (2.0 * (1.0 + nu)),
        )
    }

    /// The yield stress `sigma_Y(eps_bar)` and its slope, Pa.
    pub fn flow_stress(&self, eq: f64) -> (f64, f64) {
        let i = &self.isotropic;
        let ex = (-i.voce_b * eq).exp();
        (
            self.yield_stress + i.modulus * eq + i.voce_q * (1.0 - ex),
            i.modulus + i.voce_q * i.voce_b * ex,
        )
    }

    /// The yield function `|s - beta| - sqrt(2/3) sigma_Y` of the 3D stress `sigma`
    /// (`[xx, yy, zz, xy]`) at the state `st`, Pa.
    pub fn yield_function(&self, sigma: &[f64; 4], st: &PointState) -> f64 {
        let p = (sigma[0] + sigma[1] + sigma[2]) / 3.0;
        let xi = [
            sigma[0] - p - st.back[0],
            sigma[1] - p - st.back[1],
            sigma[2] - p - st.back[2],
            sigma[3] - st.back[3],
        ];
        norm4(&xi) - SQRT_2_3 * self.flow_stress(st.eq).0
    }

    /// The radial return of the total 3D strain `eps` (`[xx, yy, zz, xy]`, tensor shear)
    /// from the state `st0`: the new state (its `ezz` untouched), the 3D stress, flowed,
    /// unconverged.
    pub fn return_3d(
        &self,
        eps: &[f64; 4],
        st0: &PointState,
    ) -> (PointState, [f64; 4], bool, bool) {
        let (lam, mu) = self.lame();
        let ee = [
            eps[0] - st0.eps_p[0],
            eps[1] - st0.eps_p[1],
            eps[2] - st0.eps_p[2],
            eps[3] - st0.eps_p[3],
        ];
        let tr = ee[0] + ee[1] + ee[2];
        let m = tr / 3.0;
        let s_tr = [
            2.0 * mu * (ee[0] - m),
            2.0 * mu * (ee[1] - m),
            2.0 * mu * (ee[2] - m),
            2.0 * mu * ee[3],
        ];
        let sig_tr = [
            lam * tr + 2.0 * mu * ee[0],
            lam * tr + 2.0 * mu * ee[1],
            lam * tr + 2.0 * mu * ee[2],
            2.0 * mu * ee[3],
        ];
        let b0 = st0.back;
        let xi_tr = [
            s_tr[0] - b0[0],
            s_tr[1] - b0[1],
            s_tr[2] - b0[2],
            s_tr[3] - b0[3],
        ];
        let (sy0, h0) = self.flow_stress(st0.eq);
        let f_tr = norm4(&xi_tr) - SQRT_2_3 * sy0;
        if f_tr <= 0.0 {
            return (*st0, sig_tr, false, false);
        }
        let (c, gm) = (self.kinematic.c, self.kinematic.gamma);
        let linear = gm == 0.0 && self.isotropic.voce_q == 0.0;
        // eta(dl), theta(dl), g(dl) and g'(dl) of the module docs.
        let eval = |dl: f64| {
            let theta = 1.0 / (1.0 + gm * SQRT_2_3 * dl);
            let dtheta = -gm * SQRT_2_3 * theta * theta;
            let eta = [
                s_tr[0] - theta * b0[0],
                s_tr[1] - theta * b0[1],
                s_tr[2] - theta * b0[2],
                s_tr[3] - theta * b0[3],
            ];
            let ne = norm4(&eta);
            let (sy, hy) = self.flow_stress(st0.eq + SQRT_2_3 * dl);
            let g = ne - (2.0 * mu + 2.0 / 3.0 * theta * c) * dl - SQRT_2_3 * sy;
            let dne = if ne > 0.0 {
                -dtheta * dot4(&eta, &b0) / ne
            } else {
                0.0
            };
            let dg = dne - 2.0 * mu - 2.0 / 3.0 * c * (theta + dtheta * dl) - 2.0 / 3.0 * hy;
            (g, dg, theta, eta, ne)
        };
        let mut dl = f_tr / (2.0 * mu + 2.0 / 3.0 * (c + h0));
        let mut unconverged = false;
        if !linear {
            let tol = RETURN_TOL * self.yield_stress;
            let (mut lo, mut hi) = (0.0, f64::INFINITY);
            let mut it = 0;
            loop {
                let (g, dg, ..) = eval(dl);
                if g.abs() <= tol {
                    break;
                }
                if g > 0.0 {
                    lo = dl;
                } else {
                    hi = hi.min(dl);
                }
                it += 1;
                if it >= MAX_ITER {
                    unconverged = true;
                    break;
                }
                let mut next = dl - g / dg;
                if !(next > lo && next < hi) || dg >= 0.0 {
                    next = if hi.is_finite() {
                        0.5 * (lo + hi)
                    } else {
                        2.0 * dl.max(lo)
                    };
                }
                dl = next;
            }
        }
        let (_, _, theta, eta, ne) = eval(dl);
        let n = [eta[0] / ne, eta[1] / ne, eta[2] / ne, eta[3] / ne];
        let mut st = *st0;
        let kc = 2.0 / 3.0 * c * dl;
        for i in 0..4 {
            st.eps_p[i] += dl * n[i];
            st.back[i] = theta * (b0[i] + kc * n[i]);
        }
        st.eq += SQRT_2_3 * dl;
        let sig = [
            sig_tr[0] - 2.0 * mu * dl * n[0],
            sig_tr[1] - 2.0 * mu * dl * n[1],
            sig_tr[2] - 2.0 * mu * dl * n[2],
            sig_tr[3] - 2.0 * mu * dl * n[3],
        ];
        (st, sig, true, unconverged)
    }

    /// The material point's response to the in-plane strain `eps = [exx, eyy, gxy]`
    /// (engineering shear) from the state `st0`, in plane strain or plane stress (module
    /// docs). No allocation.
    pub fn update(&self, plane: PlaneModel, eps: [f64; 3], st0: &PointState) -> PointResult {
        let e3 = |ezz: f64| [eps[0], eps[1], ezz, 0.5 * eps[2]];
        match plane {
            PlaneModel::Strain => {
                let (state, s, plastic, unconverged) = self.return_3d(&e3(0.0), st0);
                PointResult {
                    state,
                    stress: [s[0], s[1], s[3]],
                    szz: s[2],
                    plastic,
                    unconverged,
                }
            }
            PlaneModel::Stress => {
                let (lam, mu) = self.lame();
                let k_el = lam + 2.0 * mu;
                // Elastic plane stress: sigma_zz = 0 with the plastic strain frozen.
                let ep = st0.eps_p;
                let z0 = ep[2] - lam / k_el * (eps[0] - ep[0] + eps[1] - ep[1]);
                let tol = PLANE_STRESS_TOL * self.yield_stress;
                let (mut z, mut r) = (z0, self.return_3d(&e3(z0), st0));
                let mut unconverged = r.3;
                let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
                let mut prev: Option<(f64, f64)> = None;
                let mut it = 0;
                while r.1[2].abs() > tol {
                    let szz = r.1[2];
                    if szz > 0.0 {
                        hi = hi.min(z);
                    } else {
                        lo = lo.max(z);
                    }
                    it += 1;
                    if it >= MAX_ITER {
                        unconverged = true;
                        break;
                    }
                    let slope = match prev {
                        Some((zp, sp)) if z != zp && (szz - sp) / (z - zp) > 0.0 => {
                            (szz - sp) / (z - zp)
                        }
                        _ => k_el,
                    };
                    let mut next = z - szz / slope;
                    if !(next > lo && next < hi) {
                        next = if lo.is_finite() && hi.is_finite() {
                            0.5 * (lo + hi)
                        } else {
                            z - szz / k_el
                        };
                    }
                    prev = Some((z, szz));
                    z = next;
                    r = self.return_3d(&e3(z), st0);
                    unconverged |= r.3;
                }
                let (mut state, s, plastic, _) = r;
                state.ezz = z;
                PointResult {
                    state,
                    stress: [s[0], s[1], s[3]],
                    szz: s[2],
                    plastic,
                    unconverged,
                }
            }
        }
    }
}

/// The triangles of one body made of a [`J2Material`]: the internal force's plastic part
/// (module docs, [`InternalForce`]). The body's node `i` has the dofs `2 i`, `2 i + 1` of
/// the driver's vector.
#[derive(Debug, Clone)]
pub struct PlasticBody {
    /// The material.
    pub material: J2Material,
    /// Plane stress or plane strain.
    pub plane: PlaneModel,
    /// The elastic `D` of the plane model.
    d: [[f64; 3]; 3],
    /// Thickness, m.
    pub thickness: f64,
    /// Triangles (node indices).
    pub triangles: Vec<[usize; 3]>,
    /// Their geometry.
    pub geometry: Vec<Tri3Geometry>,
}

impl PlasticBody {
    /// The body of `triangles` (with their `geometry`) of thickness `thickness` (m).
    ///
    /// # Panics
    /// If `triangles` and `geometry` differ in length.
    pub fn new(
        material: J2Material,
        plane: PlaneModel,
        thickness: f64,
        triangles: Vec<[usize; 3]>,
        geometry: Vec<Tri3Geometry>,
    ) -> Self {
        assert_eq!(triangles.len(), geometry.len());
        Self {
            d: plane.elasticity_matrix(&material.elastic),
            material,
            plane,
            thickness,
            triangles,
            geometry,
        }
    }

    /// Element `e`'s state in the flat state vector `s`.
    pub fn point(s: &[f64], e: usize) -> PointState {
        PointState::read(&s[e * STATE_LEN..(e + 1) * STATE_LEN])
    }

    /// The equivalent plastic strain of every element of the state `s` into `out`.
    pub fn equivalent_plastic_strain_into(&self, s: &[f64], out: &mut [f64]) {
        for (e, o) in out.iter_mut().enumerate().take(self.triangles.len()) {
            *o = s[e * STATE_LEN + 8];
        }
    }

    /// The element's strain `[exx, eyy, gxy]` in `u`.
    fn element_strain(&self, e: usize, u: &[f64]) -> [f64; 3] {
        let t = self.triangles[e];
        let ue = crate::element::tri3::element_displacements(u, &t);
        strain(&self.geometry[e], &ue)
    }

    /// `y[dofs of e] += A t B^T s`.
    fn scatter(&self, e: usize, s: [f64; 3], y: &mut [f64]) {
        let (g, t) = (&self.geometry[e], self.triangles[e]);
        let w = g.area * self.thickness;
        for (i, &[nx, ny]) in g.grad.iter().enumerate() {
            y[2 * t[i]] += w * (nx * s[0] + ny * s[2]);
            y[2 * t[i] + 1] += w * (ny * s[1] + nx * s[2]);
        }
    }

    fn elastic_stress(&self, eps: [f64; 3]) -> [f64; 3] {
        let d = &self.d;
        [0, 1, 2].map(|r| d[r][0] * eps[0] + d[r][1] * eps[1] + d[r][2] * eps[2])
    }
}

impl InternalForce for PlasticBody {
    fn state_len(&self) -> usize {
        self.triangles.len() * STATE_LEN
    }

    fn pseudo_load(&self, s: &[f64], f_nl: &mut [f64]) {
        f_nl.fill(0.0);
        let mu = self.material.lame().1;
        for e in 0..self.triangles.len() {
            let st = Self::point(s, e);
            if st.eq == 0.0 {
                continue;
            }
            let ep = st.eps_p;
            let sp = match self.plane {
                // 3D `C eps_p` in plane, `tr eps_p = 0`.
                PlaneModel::Strain => [2.0 * mu * ep[0], 2.0 * mu * ep[1], 2.0 * mu * ep[3]],
                PlaneModel::Stress => self.elastic_stress([ep[0], ep[1], 2.0 * ep[3]]),
            };
            self.scatter(e, sp, f_nl);
        }
    }

    fn evaluate(
        &self,
        s0: &[f64],
        u: &[f64],
        s1: &mut [f64],
        f_nl: &mut [f64],
        f_int: &mut [f64],
    ) -> usize {
        f_nl.fill(0.0);
        f_int.fill(0.0);
        let mut plastic = 0;
        for e in 0..self.triangles.len() {
            let eps = self.element_strain(e, u);
            let st0 = Self::point(s0, e);
            let r = self.material.update(self.plane, eps, &st0);
            r.state.write(&mut s1[e * STATE_LEN..(e + 1) * STATE_LEN]);
            // No plastic strain: sigma = D eps, nothing to add to the pseudo-load.
            if r.state.eq != 0.0 {
                let se = self.elastic_stress(eps);
                let sp = [
                    se[0] - r.stress[0],
                    se[1] - r.stress[1],
                    se[2] - r.stress[2],
                ];
                self.scatter(e, sp, f_nl);
            }
            self.scatter(e, r.stress, f_int);
            plastic += usize::from(r.plastic);
        }
        plastic
    }

    fn energy_correction(&self, s: &[f64], u: &[f64]) -> f64 {
        let (lam, mu) = self.material.lame();
        let mut corr = 0.0;
        for e in 0..self.triangles.len() {
            let st = Self::point(s, e);
            if st.eq == 0.0 {
                continue;
            }
            let eps = self.element_strain(e, u);
            let ezz = match self.plane {
                PlaneModel::Strain => 0.0,
                PlaneModel::Stress => st.ezz,
            };
            let ee = [
                eps[0] - st.eps_p[0],
                eps[1] - st.eps_p[1],
                ezz - st.eps_p[2],
                0.5 * eps[2] - st.eps_p[3],
            ];
            let tr = ee[0] + ee[1] + ee[2];
            let stored = 0.5 * lam * tr * tr + mu * dot4(&ee, &ee);
            let se = self.elastic_stress(eps);
            let elastic = 0.5 * (se[0] * eps[0] + se[1] * eps[1] + se[2] * eps[2]);
            corr += self.geometry[e].area * self.thickness * (stored - elastic);
        }
        corr
    }
}

/// The residual displacement of the plastic state `state` with the load taken off: `u =
/// K^{-1} f_p`, its pseudo-load [`InternalForce::pseudo_load`] on the stiffness `k` (on
/// `pattern`) with the supported dofs `fixed` held (no contact, no other load). With the
/// elastic stiffness it is what the plastic strain leaves at rest; with a spinning wheel's
/// effective stiffness, the displacement to add to the spinning equilibrium so that a run
/// starting from `state` starts in equilibrium. Allocates (not for the time loop).
///
/// # Errors
/// [`LinalgError`] when `k` with `fixed` held is singular.
pub fn residual_displacement(
    body: &PlasticBody,
    state: &[f64],
    (pattern, k, fixed): (&Pattern, &[f64], &[usize]),
) -> Result<Vec<f64>, LinalgError> {
    let n = pattern.nrows();
    let mut is_fixed = vec![false; n];
    for &d in fixed {
        is_fixed[d] = true;
    }
    let mut u = vec![0.0; n];
    body.pseudo_load(state, &mut u);
    if u.iter().all(|&x| x == 0.0) {
        return Ok(u);
    }
    let mut a = k.to_vec();
    crate::linalg::set_identity_rows(pattern, &mut a, &is_fixed);
    let mut lu = SparseLu::new(pattern, &a)?;
    for (ui, &fx) in u.iter_mut().zip(&is_fixed) {
        if fx {
            *ui = 0.0;
        }
    }
    lu.solve_in_place(&mut u);
    Ok(u)
}

/// The rim's permanent radial surface displacement after a pass, with the load taken off:
/// the residual displacement ([`residual_displacement`]) of the plastic state `state` on
/// the elastic stiffness `k` (on `pattern`) with the supported dofs `fixed` held, read
/// radially at the rim nodes `rim` (ordered by angle; node `i` at `reference[2 i..2 i + 2]`
/// from the wheel's centre): `(arc length from the first rim node along the undeformed rim,
/// m; u_r . X / |X|, m, positive outwards)`, one per rim node. The growth driver's input
/// after a pass: the elastic flattening under the contact is not in it, only what the
/// plastic strain left. Allocates (call between passes, not in the time loop).
///
/// # Errors
/// [`LinalgError`] when `k` with `fixed` held is singular.
pub fn permanent_radial_displacement(
    body: &PlasticBody,
    state: &[f64],
    stiffness: (&Pattern, &[f64], &[usize]),
    reference: &[f64],
    rim: &[usize],
) -> Result<Vec<(f64, f64)>, LinalgError> {
    let u = residual_displacement(body, state, stiffness)?;
    let mut out = Vec::with_capacity(rim.len());
    let mut s = 0.0;
    let mut prev: Option<[f64; 2]> = None;
    for &node in rim {
        let x = [reference[2 * node], reference[2 * node + 1]];
        let r = x[0].hypot(x[1]);
        if let Some(p) = prev {
            let rp = p[0].hypot(p[1]);
            let c = ((p[0] * x[0] + p[1] * x[1]) / (r * rp)).clamp(-1.0, 1.0);
            s += 0.5 * (r + rp) * c.acos();
        }
        prev = Some(x);
        out.push((s, (u[2 * node] * x[0] + u[2 * node + 1] * x[1]) / r));
    }
    Ok(out)
}

#[cfg(test)]
mod tests;
