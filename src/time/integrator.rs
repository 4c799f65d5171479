//! The integrator contract: what every time integrator of softway provides to the driver
//! ([`crate::simulation`]), after MFEM's `ODESolver` (`Init`, then `Step`).
//!
//! # One step as one factored linear system
//!
//! Every integrator here solves, per step `[t0, t0 + h]`, one linear system with a constant,
//! factored matrix, in an unknown `x` that fixes the end state linearly:
//! $$A x = b + \sum_p c_p^T \lambda_p,\qquad u_1 = U + \mu_u x,\qquad v_1 = V + \mu_v x,$$
//! where `U`, `V` (the *predictors*) depend only on the start state and the loads, `c_p` is a
//! constraint row (a contact pair's normal on its dofs) and `lambda_p` its multiplier.
//!
//! | integrator | `x` | `U` | `mu_u` | `V` | `mu_v` | `lambda` | force per `lambda` |
//! |---|---|---|---|---|---|---|---|
//! | space-time (Eqs. 6-10, 24) | `v1` | `u0 + h(1-beta) v0` | `h beta` | 0 | 1 | impulse, N s | `1/h` |
//! | generalized-alpha family ([`super::classic`]) | `a1` | `u0 + h v0 + h^2(1/2-beta_N) a0` | `beta_N h^2` | `v0 + h(1-gamma_N) a0` | `gamma_N h` | force, N | 1 |
//!
//! So `x = x_free + sum_q z_q lambda_q` with `z_q = A^{-1} c_q^T`: contact needs only the
//! free solve, columns of `A^{-1}` (cached while `A` does not change) and a small dense system
//! on the active rows ([`crate::contact::rows`]).
//!
//! # The contract
//!
//! - [`TimeIntegrator::predict`]: from the state at `t0` and the loads, the predictors
//!   `U`, `V` and the free solution `x_free = A^{-1} b`;
//! - [`TimeIntegrator::apply_inverse`]: `r <- A^{-1} r` (a column `z_q`);
//! - [`TimeIntegrator::finish`]: the end state from the predictors and the corrected `x`;
//! - [`TimeIntegrator::maps`]: `mu_u`, `mu_v` and the force per unit multiplier, and
//!   [`TimeIntegrator::unit`]: whether a multiplier is an impulse or a force;
//! - [`TimeIntegrator::stiffness_point`]: where the scheme evaluates `K u` (penalty springs
//!   act there, so they are integrated like the elastic forces);
//! - [`TimeIntegrator::set_step`]: another step length on the same symbolic analysis (a
//!   numeric refactorization only; the subdivision of the paper's Fig. 5 uses it).
//!
//! An integrator allocates its work memory when built; none of these calls allocates.

use crate::linalg::LinalgError;
use crate::simulation::LoadFn;
use crate::time::classic::{ClassicError, ClassicParams};
use crate::time::Coriolis;
use serde::Serialize;

/// The state `(u, v, a)` at one time (`a` is kept by the classic integrators; the space-time
/// scheme stores the mean acceleration of the step).
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// Displacements, m.
    pub u: Vec<f64>,
    /// Velocities, m/s.
    pub v: Vec<f64>,
    /// Accelerations, m/s^2.
    pub a: Vec<f64>,
}

impl State {
    /// Zero state of `n` dofs.
    pub fn zeros(n: usize) -> Self {
        Self {
            u: vec![0.0; n],
            v: vec![0.0; n],
            a: vec![0.0; n],
        }
    }
}

/// What a constraint multiplier of an integrator is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MultiplierUnit {
    /// An impulse over the step, N s (the space-time scheme: `b` holds `h f`).
    Impulse,
    /// A force, N (the generalized-alpha family).
    Force,
}

/// The linear maps of the module table: `u1 = U + mu_u x`, `v1 = V + mu_v x`, and the
/// force (N) of a unit multiplier.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Maps {
    /// `d u1 / d x`.
    pub mu_u: f64,
    /// `d v1 / d x`.
    pub mu_v: f64,
    /// Force per unit multiplier: `1/h` for an impulse, 1 for a force.
    pub force: f64,
}

/// A time integrator (module docs).
pub trait TimeIntegrator: Send {
    /// The name used in tables, e.g. `space_time(alpha=0.8 gamma=0)`, `newmark`.
    fn name(&self) -> String;
    /// Number of dofs.
    fn n(&self) -> usize;
    /// The current step length, s.
    fn h(&self) -> f64;
    /// The unit of a multiplier.
    fn unit(&self) -> MultiplierUnit;
    /// The maps of the current step (they may change with `gamma`'s schedule).
    fn maps(&self) -> Maps;
    /// The weight of `x` in the displacement update of the step starting at `t0`, per unit
    /// `h`: `beta` of Eq. (24) for the space-time scheme (`u1 = U + h beta v1`; the soft
    /// way's braking and holding laws need it), `beta_N h` for the generalized-alpha family.
    fn displacement_weight(&self, t0: f64) -> f64;
    /// True when the matrix is diagonal (the explicit central difference).
    fn is_explicit(&self) -> bool {
        false
    }
    /// True when `dof` has a prescribed velocity (its row of `A` is the identity).
    fn is_fixed(&self, dof: usize) -> bool;
    /// Completes the initial state (the classic integrators' consistent acceleration, zero
    /// on the fixed and the `massless` dofs). Allocates (call once).
    ///
    /// # Errors
    /// [`LinalgError`] when the mass matrix on the other dofs is singular.
    fn initialize(
        &mut self,
        _t0: f64,
        _s0: &mut State,
        _load: &LoadFn,
        _massless: &[usize],
    ) -> Result<(), LinalgError> {
        Ok(())
    }
    /// The predictors `U`, `V` into `pred.u`, `pred.v` and `x_free = A^{-1} b` into `x`, for
    /// the step from `(t0, s0)` with the external load plus the nodal forces `extra` (N),
    /// using `f` as scratch.
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
    );
    /// `r <- A^{-1} r` with the fixed rows of `r` zeroed first.
    fn apply_inverse(&mut self, r: &mut [f64]);
    /// The end state from the predictors and `x`.
    fn finish(&self, s0: &State, pred: &State, x: &[f64], s1: &mut State);
    /// The displacement where the scheme evaluates `K u`, as `P + mu_k x`: `P` into `p`,
    /// returns `mu_k`. Space-time: `u0 + h(alpha - alpha^2/2) v0 + (h alpha^2/2) v1` (the `K`
    /// terms of Eq. 9); generalized-alpha family: the step end `u1`.
    fn stiffness_point(&self, s0: &State, pred: &State, p: &mut [f64]) -> f64;
    /// Rebuilds `A` for the step length `h` on the same symbolic analysis (numeric
    /// refactorization; a second numeric factor is kept so that going back to the run's
    /// step costs nothing).
    ///
    /// # Errors
    /// [`LinalgError`] when the new `A` is singular.
    fn set_step(&mut self, h: f64) -> Result<(), LinalgError>;
    /// Numeric factorizations so far.
    fn factorizations(&self) -> usize;
    /// Symbolic analyses so far (1 for a run, whatever the steps).
    fn symbolic_analyses(&self) -> usize;
    /// Runs the integrator's two-part work on `team`'s threads, if it has any (the same bits
    /// on any team; by default nothing changes).
    fn set_team(&mut self, _team: &crate::linalg::team::Team) {}
}

/// The choice of an integrator, with its parameters (scenario key `integrator`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "name", rename_all = "snake_case")]
pub enum Integrator {
    /// The space-time velocity scheme (Eqs. 6-10, 24).
    SpaceTime {
        /// `alpha` in (0, 1].
        alpha: f64,
        /// `gamma` in [0, 1].
        gamma: f64,
        /// Where the Coriolis term goes (`time.coriolis`).
        coriolis: Coriolis,
    },
    /// A member of the generalized-alpha family ([`crate::time::classic`]).
    Classic {
        /// Short name.
        kind: ClassicKind,
        /// Its parameters.
        params: ClassicParams,
    },
}

/// The classic integrators by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ClassicKind {
    /// Newmark average acceleration (`beta = 1/4`, `gamma = 1/2`).
    Newmark,
    /// Newmark with `gamma_N > 1/2`.
    NewmarkDissipative,
    /// HHT-alpha.
    Hht,
    /// Generalized-alpha (Chung-Hulbert).
    GeneralizedAlpha,
    /// Explicit central difference.
    CentralDifference,
}

impl Integrator {
    /// The name used in tables.
    pub fn name(&self) -> String {
        match self {
            Integrator::SpaceTime {
                alpha,
                gamma,
                coriolis: Coriolis::Implicit,
            } => format!("space_time(alpha={alpha} gamma={gamma})"),
            Integrator::SpaceTime {
                alpha,
                gamma,
                coriolis,
            } => format!(
                "space_time(alpha={alpha} gamma={gamma} coriolis={})",
                coriolis.name()
            ),
            Integrator::Classic { kind, params } => match kind {
                ClassicKind::Newmark => "newmark".into(),
                ClassicKind::NewmarkDissipative => format!("newmark({:.2})", params.gamma),
                ClassicKind::Hht => format!("hht({:.3})", -params.alpha_f),
                ClassicKind::GeneralizedAlpha => {
                    format!("gen_alpha({:.2})", crate::time::classic::rho_inf(*params))
                }
                ClassicKind::CentralDifference => "central_difference".into(),
            },
        }
    }

    /// True for the explicit central difference.
    pub fn is_explicit(&self) -> bool {
        matches!(self, Integrator::Classic { params, .. } if params.is_explicit())
    }

    /// True for the space-time scheme.
    pub fn is_space_time(&self) -> bool {
        matches!(self, Integrator::SpaceTime { .. })
    }
}

/// Errors of building an integrator.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// A matrix could not be factored.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// A classic integrator could not be set up.
    #[error(transparent)]
    Classic(#[from] ClassicError),
}
