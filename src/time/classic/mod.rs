//! The classic time integrators of structural dynamics on the same [`LinearModel`] as the
//! space-time step: Newmark, HHT-alpha, generalized-alpha (Chung-Hulbert) and the explicit
//! central difference, with Dirichlet conditions and node constraints imposed through the
//! factored effective matrix (the machinery of [`crate::time::step`]).
//!
//! # The family
//!
//! All four methods are members of the generalized-alpha family (Chung & Hulbert 1993) for
//! `M a + C v + K u = f(t) + r`: with the Newmark updates
//! $$u_1 = u_0 + h v_0 + h^2\big[(\tfrac12 - \beta) a_0 + \beta a_1\big],\qquad
//!   v_1 = v_0 + h\big[(1-\gamma) a_0 + \gamma a_1\big],$$
//! the balance is enforced at the shifted times
//! $$M a_{1-\alpha_m} + C v_{1-\alpha_f} + K u_{1-\alpha_f} = f_{1-\alpha_f} + r,\qquad
//!   x_{1-\alpha} = (1-\alpha) x_1 + \alpha x_0 .$$
//! Writing the predictors `u* = u0 + h v0 + h^2 (1/2 - beta) a0`, `v* = v0 + h (1 - gamma) a0`,
//! the unknown is the end acceleration `a1`:
//! $$A a_1 = b,\qquad A = (1-\alpha_m) M + (1-\alpha_f)(\gamma h C + \beta h^2 K),$$
//! $$b = (1-\alpha_f) f_1 + \alpha_f f_0 - \alpha_m M a_0 - C[\alpha_f v_0 + (1-\alpha_f) v^\*]
//!   \\;-\\; K[\alpha_f u_0 + (1-\alpha_f) u^\*] + r,$$
//! then `u1 = u* + beta h^2 a1`, `v1 = v* + gamma h a1`.
//!
//! | method | `alpha_m` | `alpha_f` | `beta` | `gamma` |
//! |---|---|---|---|---|
//! | Newmark | 0 | 0 | `beta` | `gamma_N` |
//! | HHT-alpha (`alpha_H` in [-1/3, 0]) | 0 | `-alpha_H` | `(1 - alpha_H)^2 / 4` | `1/2 - alpha_H` |
//! | generalized-alpha (`rho_inf` in [0, 1]) | `(2 rho - 1)/(rho + 1)` | `rho/(rho + 1)` | `(1 - alpha_m + alpha_f)^2/4` | `1/2 - alpha_m + alpha_f` |
//! | central difference | 0 | 0 | 0 | 1/2 |
//!
//! `A` depends on the parameters and `h` only: it is factored once ([`SparseLu`]), or, when
//! it is diagonal (central difference with a lumped mass and a diagonal or zero `C`),
//! inverted entry by entry: the explicit method. The step allocates nothing.
//!
//! # Dirichlet conditions
//!
//! A prescribed acceleration, velocity or displacement of a dof at `t1` fixes that dof of
//! `a1` (`a1 = (g - v*)/(gamma h)` or `(g - u*)/(beta h^2)`); the rows and columns of `A` are
//! replaced by the identity and the value is lifted into `b`, as in [`crate::time::step`].
//! A prescribed displacement needs `beta > 0` (not the central difference, whose `u1` does
//! not depend on `a1`); [`ClassicStepper::new`] rejects it otherwise.
//!
//! # Constraints (exact enforcement of contact)
//!
//! A constraint row `c . a1 = g'` on the end acceleration (a velocity or displacement target
//! turned into one through the Newmark updates, `g' = (g - c . v*)/(gamma h)` or
//! `(g - c . u*)/(beta h^2)`) is imposed by a Lagrange multiplier through the factored `A`
//! ([`crate::contact::rows`]). **The multiplier is a force** (N): the reaction `r` in the
//! balance equation, acting at the shifted time `t0 + (1 - alpha_f) h` (at `t1` for Newmark
//! and the central difference); its impulse over the step is about `h lambda`.
//! [`ClassicStepper`] implements the [`TimeIntegrator`] contract with `x = a1`.

use crate::linalg::{spmv_add, LinalgError, Pattern, SparseLu};
pub use crate::model::State;
use crate::model::{LinearModel, LoadFn};
use crate::time::integrator::{FactorCounts, Maps, MultiplierUnit, Step, TimeIntegrator};
use serde::Serialize;

mod spectrum;

pub use spectrum::{
    amplification, amplification_matrix, clustered_spectral_radius, eigenvalues, max_frequency,
    max_frequency_bound, rho_inf, sdof_step, stable_step, Amplification,
};

/// Errors of the classic integrators.
#[derive(Debug, thiserror::Error)]
pub enum ClassicError {
    /// The effective matrix is singular.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// A prescribed displacement with `beta = 0` (explicit): `u1` does not depend on `a1`.
    #[error("a prescribed displacement needs beta > 0 (dof {0})")]
    DisplacementNeedsImplicit(usize),
    /// The parameters are out of their range.
    #[error("invalid parameters: {0}")]
    InvalidParameters(String),
}

/// Parameters of the generalized-alpha family (dimensionless). See the module table.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ClassicParams {
    /// Weight `alpha_m` of `a0` in the inertia term.
    pub alpha_m: f64,
    /// Weight `alpha_f` of the start state in the internal and external forces.
    pub alpha_f: f64,
    /// Newmark `beta`: weight of `a1` in the displacement update.
    pub beta: f64,
    /// Newmark `gamma`: weight of `a1` in the velocity update.
    pub gamma: f64,
}

impl ClassicParams {
    /// Default `gamma_N` of the dissipative Newmark choice.
    pub const DEFAULT_DISSIPATIVE_GAMMA: f64 = 0.6;
    /// Default `alpha_H` of HHT-alpha.
    pub const DEFAULT_ALPHA_H: f64 = -0.1;
    /// Default `rho_inf` of generalized-alpha.
    pub const DEFAULT_RHO_INF: f64 = 0.8;

    /// Newmark with `beta` and `gamma_N` (`alpha_m = alpha_f = 0`). Unconditionally stable for
    /// `2 beta >= gamma_N >= 1/2`; second order only for `gamma_N = 1/2`.
    pub fn newmark(beta: f64, gamma: f64) -> Self {
        Self {
            alpha_m: 0.0,
            alpha_f: 0.0,
            beta,
            gamma,
        }
    }

    /// Newmark average acceleration (trapezoidal rule): `beta = 1/4`, `gamma_N = 1/2`;
    /// no dissipation, `rho_inf = 1`.
    pub fn average_acceleration() -> Self {
        Self::newmark(0.25, 0.5)
    }

    /// Dissipative Newmark: `gamma_N > 1/2`, `beta = (gamma_N + 1/2)^2 / 4` (default
    /// `gamma_N = 0.6`), unconditionally stable, **first order** (the `O(h)` velocity error
    /// of `gamma_N != 1/2`), `rho_inf = (3/2 - gamma_N)/(gamma_N + 1/2)`
    /// (0.818 for `gamma_N = 0.6`).
    pub fn newmark_dissipative(gamma: f64) -> Self {
        Self::newmark((gamma + 0.5).powi(2) / 4.0, gamma)
    }

    /// HHT-alpha (Hilber, Hughes & Taylor 1977) with `alpha_H` in [-1/3, 0] (default -0.1):
    /// `alpha_f = -alpha_H`, `gamma = 1/2 - alpha_H`, `beta = (1 - alpha_H)^2/4`;
    /// `rho_inf = (1 + alpha_H)/(1 - alpha_H)`.
    ///
    /// # Errors
    /// [`ClassicError::InvalidParameters`] outside [-1/3, 0].
    pub fn hht(alpha_h: f64) -> Result<Self, ClassicError> {
        if !(-1.0 / 3.0 - 1e-12..=0.0).contains(&alpha_h) {
            return Err(ClassicError::InvalidParameters(format!(
                "alpha_H = {alpha_h} not in [-1/3, 0]"
            )));
        }
        Ok(Self {
            alpha_m: 0.0,
            alpha_f: -alpha_h,
            beta: (1.0 - alpha_h).powi(2) / 4.0,
            gamma: 0.5 - alpha_h,
        })
    }

    /// Generalized-alpha (Chung & Hulbert 1993) with the high-frequency spectral radius
    /// `rho_inf` in [0, 1] (default 0.8): `alpha_m = (2 rho - 1)/(rho + 1)`,
    /// `alpha_f = rho/(rho + 1)`, `gamma = 1/2 - alpha_m + alpha_f`,
    /// `beta = (1 - alpha_m + alpha_f)^2/4`.
    ///
    /// # Errors
    /// [`ClassicError::InvalidParameters`] outside [0, 1].
    pub fn generalized_alpha(rho_inf: f64) -> Result<Self, ClassicError> {
        if !(0.0..=1.0).contains(&rho_inf) {
            return Err(ClassicError::InvalidParameters(format!(
                "rho_inf = {rho_inf} not in [0, 1]"
            )));
        }
        let am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
        let af = rho_inf / (rho_inf + 1.0);
        Ok(Self {
            alpha_m: am,
            alpha_f: af,
            beta: (1.0 - am + af).powi(2) / 4.0,
            gamma: 0.5 - am + af,
        })
    }

    /// Central difference: Newmark `beta = 0`, `gamma = 1/2`. Explicit with a lumped mass;
    /// stable for `omega_max h <= 2` ([`stable_step`]).
    pub fn central_difference() -> Self {
        Self::newmark(0.0, 0.5)
    }

    /// True for `beta = 0`, `alpha_m = alpha_f = 0` (the central difference).
    pub fn is_explicit(&self) -> bool {
        self.beta == 0.0 && self.alpha_m == 0.0 && self.alpha_f == 0.0
    }
}

/// What a Dirichlet condition prescribes at `t1`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Kinematic {
    /// Acceleration, m/s^2.
    Acceleration,
    /// Velocity, m/s.
    Velocity,
    /// Displacement, m (needs `beta > 0`).
    Displacement,
}

/// A Dirichlet condition: `dof` has the prescribed `kind` equal to `value` at every step end.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Dirichlet {
    /// The dof.
    pub dof: usize,
    /// The prescribed quantity.
    pub kind: Kinematic,
    /// The value (m/s^2, m/s or m).
    pub value: f64,
}

enum Solver {
    Lu(Box<SparseLu>),
    /// faer's LU ([`crate::linalg::Backend::Faer`]).
    Faer(Box<crate::linalg::FaerLu>),
    /// Inverse diagonal (explicit).
    Diagonal(Vec<f64>),
}

impl Solver {
    fn solve_in_place(&mut self, b: &mut [f64]) {
        match self {
            Solver::Lu(lu) => lu.solve_in_place(b),
            Solver::Faer(lu) => lu.solve_in_place(b),
            Solver::Diagonal(d) => {
                for (bi, di) in b.iter_mut().zip(d.iter()) {
                    *bi *= di;
                }
            }
        }
    }
}

/// A classic integrator on a [`LinearModel`]: the effective matrix factored once, the
/// Dirichlet conditions and all work memory.
pub struct ClassicStepper {
    params: ClassicParams,
    h: f64,
    n: usize,
    pattern: Pattern,
    m: Vec<f64>,
    c: Vec<f64>,
    k: Vec<f64>,
    a_orig: Vec<f64>,
    a_work: Vec<f64>,
    solver: Solver,
    bcs: Vec<Dirichlet>,
    is_bc: Vec<bool>,
    work: Vec<f64>,
    f1: Vec<f64>,
    factorizations: usize,
}

impl std::fmt::Debug for ClassicStepper {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ClassicStepper")
            .field("params", &self.params)
            .field("h", &self.h)
            .field("n", &self.n)
            .field("explicit", &self.is_diagonal())
            .finish()
    }
}

impl ClassicStepper {
    /// Builds and factors `A = (1 - alpha_m) M + (1 - alpha_f)(gamma h C + beta h^2 K)` for
    /// the step `h` (s), with the Dirichlet conditions `bcs` (the first of a dof wins). A
    /// diagonal `A` is inverted directly (explicit method).
    ///
    /// # Errors
    /// [`ClassicError`] when `A` is singular or a displacement is prescribed with `beta = 0`.
    pub fn new(
        model: &LinearModel,
        params: ClassicParams,
        h: f64,
        bcs: &[Dirichlet],
    ) -> Result<Self, ClassicError> {
        Self::with_backend(model, params, h, bcs, crate::linalg::Backend::Softway)
    }

    /// [`ClassicStepper::new`] with `A` factored by `backend`'s LU.
    ///
    /// # Errors
    /// As [`ClassicStepper::new`].
    pub fn with_backend(
        model: &LinearModel,
        params: ClassicParams,
        h: f64,
        bcs: &[Dirichlet],
        backend: crate::linalg::Backend,
    ) -> Result<Self, ClassicError> {
        let n = model.n();
        let pattern = model.pattern().clone();
        let mut is_bc = vec![false; n];
        let mut kept = Vec::with_capacity(bcs.len());
        for bc in bcs {
            if bc.kind == Kinematic::Displacement && params.beta == 0.0 {
                return Err(ClassicError::DisplacementNeedsImplicit(bc.dof));
            }
            if !is_bc[bc.dof] {
                is_bc[bc.dof] = true;
                kept.push(*bc);
            }
        }
        let nnz = model.m.len();
        let mut st = Self {
            params,
            h,
            n,
            pattern,
            m: model.m.clone(),
            c: model.c.clone(),
            k: model.k.clone(),
            a_orig: vec![0.0; nnz],
            a_work: vec![0.0; nnz],
            solver: Solver::Diagonal(vec![0.0; n]),
            bcs: kept,
            is_bc,
            work: vec![0.0; n],
            f1: vec![0.0; n],
            factorizations: 0,
        };
        st.operators(h);
        st.solver = match st.inverse_diagonal()? {
            Some(d) => Solver::Diagonal(d),
            None if backend == crate::linalg::Backend::Faer => Solver::Faer(Box::new(
                crate::linalg::FaerLu::new(&st.pattern, &st.a_work)?,
            )),
            None => Solver::Lu(Box::new(SparseLu::new(&st.pattern, &st.a_work)?)),
        };
        st.factorizations = 1;
        Ok(st)
    }

    /// `A` for the step `h` into `a_orig`, and with the Dirichlet identity rows into `a_work`.
    fn operators(&mut self, h: f64) {
        let ClassicParams {
            alpha_m,
            alpha_f,
            beta,
            gamma,
        } = self.params;
        for p in 0..self.m.len() {
            self.a_orig[p] = (1.0 - alpha_m) * self.m[p]
                + (1.0 - alpha_f) * (gamma * h * self.c[p] + beta * h * h * self.k[p]);
        }
        self.a_work.copy_from_slice(&self.a_orig);
        crate::linalg::set_identity_rows(&self.pattern, &mut self.a_work, &self.is_bc);
        self.h = h;
    }

    /// The inverse diagonal of `a_work` when it is diagonal (explicit), else `None`.
    fn inverse_diagonal(&self) -> Result<Option<Vec<f64>>, ClassicError> {
        let cp = self.pattern.col_ptr();
        let ri = self.pattern.row_idx();
        let mut diag = vec![0.0; self.n];
        for j in 0..self.n {
            for p in cp[j]..cp[j + 1] {
                let i = ri[p];
                if i == j {
                    diag[j] = self.a_work[p];
                } else if self.a_work[p] != 0.0 {
                    return Ok(None);
                }
            }
        }
        if let Some(j) = diag.iter().position(|&d| d == 0.0) {
            return Err(ClassicError::Linalg(LinalgError::Singular(format!(
                "zero diagonal of the effective matrix at dof {j}"
            ))));
        }
        Ok(Some(diag.iter().map(|d| 1.0 / d).collect()))
    }

    /// The parameters.
    pub fn params(&self) -> ClassicParams {
        self.params
    }

    /// The time step, s.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// Number of dofs.
    pub fn n(&self) -> usize {
        self.n
    }

    /// True when the effective matrix is diagonal (explicit: no factorization).
    pub fn is_diagonal(&self) -> bool {
        matches!(self.solver, Solver::Diagonal(_))
    }

    /// True when the dof has a Dirichlet condition.
    pub fn is_dirichlet(&self, dof: usize) -> bool {
        self.is_bc[dof]
    }

    /// One unconstrained step `(u, v, a)(t0) -> (u, v, a)(t1)` with the external forces
    /// `f0 = f(t0)` and `f1 = f(t1)` (N per dof; the balance uses `(1 - alpha_f) f1 +
    /// alpha_f f0`). Allocates nothing. Constrained steps go through the driver
    /// ([`crate::simulation`]).
    pub fn step(&mut self, s0: &State, f0: &[f64], f1: &[f64], s1: &mut State) {
        self.predict(s0, f0, f1, s1);
        self.finish(s1);
    }

    /// The unconstrained part of a step: the predictors `u* = u0 + h v0 + h^2 (1/2 - beta) a0`
    /// and `v* = v0 + h (1 - gamma) a0` into `s1.u`, `s1.v`, and the end acceleration without
    /// constraints, `a1 = A^{-1} b`, into `s1.a`. A reaction `r` (N) added later changes `a1`
    /// by `A^{-1} r` ([`ClassicStepper::apply_inverse`]); [`ClassicStepper::finish`] then
    /// completes `u1 = u* + beta h^2 a1`, `v1 = v* + gamma h a1`.
    pub fn predict(&mut self, s0: &State, f0: &[f64], f1: &[f64], s1: &mut State) {
        let ClassicParams {
            alpha_m,
            alpha_f,
            beta,
            gamma,
        } = self.params;
        let h = self.h;
        let n = self.n;
        for i in 0..n {
            s1.u[i] = s0.u[i] + h * s0.v[i] + h * h * (0.5 - beta) * s0.a[i];
            s1.v[i] = s0.v[i] + h * (1.0 - gamma) * s0.a[i];
        }
        let b = &mut s1.a;
        for i in 0..n {
            b[i] = (1.0 - alpha_f) * f1[i] + alpha_f * f0[i];
        }
        if alpha_m != 0.0 {
            spmv_add(&self.pattern, &self.m, -alpha_m, &s0.a, b);
        }
        for i in 0..n {
            self.work[i] = alpha_f * s0.v[i] + (1.0 - alpha_f) * s1.v[i];
        }
        spmv_add(&self.pattern, &self.c, -1.0, &self.work, b);
        for i in 0..n {
            self.work[i] = alpha_f * s0.u[i] + (1.0 - alpha_f) * s1.u[i];
        }
        spmv_add(&self.pattern, &self.k, -1.0, &self.work, b);
        // Dirichlet: target accelerations, lifted.
        let cp = self.pattern.col_ptr();
        let ri = self.pattern.row_idx();
        for bc in &self.bcs {
            let j = bc.dof;
            let g = target_acc(bc.kind, bc.value, s1.u[j], s1.v[j], beta, gamma, h);
            self.work[j] = g;
            if g != 0.0 {
                for p in cp[j]..cp[j + 1] {
                    let i = ri[p];
                    if !self.is_bc[i] {
                        b[i] -= self.a_orig[p] * g;
                    }
                }
            }
        }
        for bc in &self.bcs {
            b[bc.dof] = self.work[bc.dof];
        }
        self.solver.solve_in_place(b);
    }

    /// `r <- A^{-1} r` with the Dirichlet rows of `r` set to zero first (the response of the
    /// end acceleration to a reaction `r`, N).
    pub fn apply_inverse(&mut self, r: &mut [f64]) {
        for (ri, &bc) in r.iter_mut().zip(&self.is_bc) {
            if bc {
                *ri = 0.0;
            }
        }
        self.solver.solve_in_place(r);
    }

    /// Completes a step from the predictors in `s1.u`, `s1.v` and the end acceleration in
    /// `s1.a`: `u1 = u* + beta h^2 a1`, `v1 = v* + gamma h a1`.
    pub fn finish(&self, s1: &mut State) {
        let (beta, gamma, h) = (self.params.beta, self.params.gamma, self.h);
        for i in 0..self.n {
            s1.u[i] += beta * h * h * s1.a[i];
            s1.v[i] += gamma * h * s1.a[i];
        }
    }
}

impl TimeIntegrator for ClassicStepper {
    fn name(&self) -> String {
        format!(
            "classic(alpha_m={} alpha_f={} beta={} gamma={})",
            self.params.alpha_m, self.params.alpha_f, self.params.beta, self.params.gamma
        )
    }
    fn h(&self) -> f64 {
        self.h
    }
    fn step_at(&self, t0: f64) -> Step {
        Step {
            t0,
            h: self.h,
            maps: Maps {
                mu_u: self.params.beta * self.h * self.h,
                mu_v: self.params.gamma * self.h,
                force: 1.0,
            },
            weight: self.params.beta * self.h,
            unit: MultiplierUnit::Force,
            explicit: self.is_diagonal(),
        }
    }
    fn initialize(
        &mut self,
        t0: f64,
        s0: &mut State,
        load: &LoadFn,
        massless: &[usize],
    ) -> Result<(), LinalgError> {
        let mut f = vec![0.0; self.n];
        load(t0, &mut f);
        let mut bc: Vec<usize> = (0..self.n).filter(|&d| self.is_bc[d]).collect();
        bc.extend_from_slice(massless);
        let mats = (&self.pattern, &self.m[..], &self.c[..], &self.k[..]);
        s0.a = acceleration_of(mats, &bc, &s0.u, &s0.v, &f)?;
        Ok(())
    }
    #[allow(clippy::too_many_arguments)]
    fn predict(
        &mut self,
        t0: f64,
        s0: &State,
        load: &LoadFn,
        extra: &[f64],
        f: &mut [f64],
        pred: &mut State,
        x: &mut [f64],
    ) -> Step {
        let h = self.h;
        load(t0, f);
        let mut f1 = std::mem::take(&mut self.f1);
        load(t0 + h, &mut f1);
        for ((fi, gi), ei) in f.iter_mut().zip(f1.iter_mut()).zip(extra) {
            *fi += ei;
            *gi += ei;
        }
        ClassicStepper::predict(self, s0, f, &f1, pred);
        self.f1 = f1;
        x.copy_from_slice(&pred.a);
        self.step_at(t0)
    }
    fn inverse_column(&mut self, dof: usize, col: &mut [f64]) -> bool {
        col.fill(0.0);
        if self.is_bc[dof] {
            return false;
        }
        col[dof] = 1.0;
        ClassicStepper::apply_inverse(self, col);
        true
    }
    fn finish(&self, step: &Step, _s0: &State, pred: &State, x: &[f64], s1: &mut State) {
        let Maps { mu_u, mu_v, .. } = step.maps;
        for i in 0..self.n {
            s1.u[i] = pred.u[i] + mu_u * x[i];
            s1.v[i] = pred.v[i] + mu_v * x[i];
        }
        s1.a.copy_from_slice(x);
    }
    fn stiffness_point(&self, _s0: &State, pred: &State, p: &mut [f64]) -> f64 {
        p.copy_from_slice(&pred.u);
        self.params.beta * self.h * self.h
    }
    fn set_step(&mut self, h: f64) -> Result<(), LinalgError> {
        if h == self.h {
            return Ok(());
        }
        self.operators(h);
        match &mut self.solver {
            Solver::Lu(lu) => lu.refactor(&self.pattern, &self.a_work)?,
            Solver::Faer(lu) => lu.refactor(&self.pattern, &self.a_work)?,
            Solver::Diagonal(_) => {
                let d = self.inverse_diagonal().map_err(|e| match e {
                    ClassicError::Linalg(l) => l,
                    other => LinalgError::Singular(other.to_string()),
                })?;
                self.solver = Solver::Diagonal(d.unwrap_or_default());
            }
        }
        self.factorizations += 1;
        Ok(())
    }
    fn counts(&self) -> FactorCounts {
        FactorCounts {
            numeric: self.factorizations,
            symbolic: match &self.solver {
                Solver::Lu(lu) => crate::linalg::Factorization::symbolic_analyses(&**lu),
                Solver::Faer(lu) => crate::linalg::Factorization::symbolic_analyses(&**lu),
                Solver::Diagonal(_) => 0,
            },
        }
    }
}

/// The end acceleration that realises a prescribed quantity, given the predictors.
fn target_acc(
    kind: Kinematic,
    g: f64,
    u_pred: f64,
    v_pred: f64,
    beta: f64,
    gamma: f64,
    h: f64,
) -> f64 {
    match kind {
        Kinematic::Acceleration => g,
        Kinematic::Velocity => (g - v_pred) / (gamma * h),
        Kinematic::Displacement => {
            assert!(beta > 0.0, "a displacement constraint needs beta > 0");
            (g - u_pred) / (beta * h * h)
        }
    }
}

/// The consistent initial acceleration: `M a0 = f0 - C v0 - K u0` on the free dofs, `a0 = 0`
/// on the Dirichlet dofs (constant prescribed values). Factors `M` (allocates; call once).
///
/// # Errors
/// [`LinalgError`] when `M` restricted to the free dofs is singular.
pub fn initial_acceleration(
    model: &LinearModel,
    bc_dofs: &[usize],
    u0: &[f64],
    v0: &[f64],
    f0: &[f64],
) -> Result<Vec<f64>, LinalgError> {
    let mats = (model.pattern(), &model.m[..], &model.c[..], &model.k[..]);
    acceleration_of(mats, bc_dofs, u0, v0, f0)
}

/// [`initial_acceleration`] on the matrices `(pattern, M, C, K)`.
fn acceleration_of(
    (pattern, m, c, k): (&Pattern, &[f64], &[f64], &[f64]),
    bc_dofs: &[usize],
    u0: &[f64],
    v0: &[f64],
    f0: &[f64],
) -> Result<Vec<f64>, LinalgError> {
    let n = pattern.nrows();
    let mut is_bc = vec![false; n];
    for &d in bc_dofs {
        is_bc[d] = true;
    }
    let mut mv = m.to_vec();
    crate::linalg::set_identity_rows(pattern, &mut mv, &is_bc);
    let mut b = f0.to_vec();
    spmv_add(pattern, c, -1.0, v0, &mut b);
    spmv_add(pattern, k, -1.0, u0, &mut b);
    for (bi, &bc) in b.iter_mut().zip(&is_bc) {
        if bc {
            *bi = 0.0;
        }
    }
    SparseLu::new(pattern, &mv)?.solve_in_place(&mut b);
    Ok(b)
}
