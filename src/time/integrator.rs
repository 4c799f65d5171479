//! The integrator contract: what every time integrator of softway provides to the driver
//! ([`crate::simulation`]): set up once for a model and a step length, then a step per
//! call (the structure of MFEM's `ODESolver`, `Init` then `Step`).
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
//!   `U`, `V` and the free solution `x_free = A^{-1} b`; it *returns* the step it predicted
//!   ([`Step`]: `t0`, `h`, the maps `mu_u`, `mu_v`, the force per unit multiplier and the
//!   displacement weight), a value that the caller hands on to the rows and to `finish`:
//!   the integrator keeps no state between the two calls;
//! - [`TimeIntegrator::step_at`]: the same [`Step`] for a step starting at `t0`, without
//!   predicting (the soft way's braking law, Eq. 26, needs `beta` of the interval it repeats);
//! - [`TimeIntegrator::inverse_column`]: a column `z_d = A^{-1} e_d` (zero on a dof with a
//!   prescribed velocity, whose row of `A` is the identity);
//! - [`TimeIntegrator::finish`]: the end state `u1 = U + mu_u x`, `v1 = V + mu_v x` from the
//!   predictors and the corrected `x`, with the maps of the [`Step`] that `predict` returned;
//! - [`TimeIntegrator::stiffness_point`]: where the scheme evaluates `K u` (penalty springs
//!   act there, so they are integrated like the elastic forces);
//! - [`TimeIntegrator::set_step`]: another step length on the same symbolic analysis (a
//!   numeric refactorization only; the subdivision of the paper's Fig. 5 uses it);
//! - [`TimeIntegrator::initialize`] (once, before the first step) and
//!   [`TimeIntegrator::counts`] (after the run).
//!
//! An integrator allocates its work memory when built; none of the per-step calls allocates.

use crate::linalg::LinalgError;
use crate::model::LoadFn;
pub use crate::model::State;
use serde::Serialize;

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

/// One step as the integrator predicted it ([`TimeIntegrator::predict`],
/// [`TimeIntegrator::step_at`]): what the rows, the treatments and
/// [`TimeIntegrator::finish`] read of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// Start of the step `t0`, s.
    pub t0: f64,
    /// Length `h`, s.
    pub h: f64,
    /// The maps of the step (they may change with `gamma`'s schedule).
    pub maps: Maps,
    /// The weight of `x` in the displacement update per unit `h`: `beta` of Eq. (24) for the
    /// space-time scheme (`u1 = U + h beta v1`, so `mu_u = h beta`; the soft way's braking and
    /// holding laws need it), `beta_N h` for the generalized-alpha family (`mu_u = beta_N h^2`).
    pub weight: f64,
    /// The unit of a multiplier.
    pub unit: MultiplierUnit,
    /// True when the matrix is diagonal (the explicit central difference).
    pub explicit: bool,
}

/// Factorizations of a run ([`TimeIntegrator::counts`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FactorCounts {
    /// Numeric factorizations of a system matrix.
    pub numeric: usize,
    /// Symbolic analyses (1 for a run of a sparse factor, whatever the steps; 0 for a
    /// diagonal matrix).
    pub symbolic: usize,
}

/// The factor a scheme's free step solves with ([`TimeIntegrator::factor_size`]): what a
/// run's cost record reports beside the step's time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct FactorSize {
    /// The factorization.
    pub kind: crate::linalg::FactorKind,
    /// Its stored entries (`L + U`, or `L` for Cholesky).
    pub nnz: usize,
    /// The bytes a free step reads (the factor as a solve reads it, the right-hand side's
    /// rows, the passes over the state): its floor is these over the memory's bandwidth.
    pub free_step_bytes: usize,
}

/// A time integrator (module docs).
pub trait TimeIntegrator: Send {
    /// The name used in tables, e.g. `space_time(alpha=0.8 gamma=0)`, `newmark`.
    fn name(&self) -> String;
    /// The current step length, s.
    fn h(&self) -> f64;
    /// The step of the current length starting at `t0`, as [`TimeIntegrator::predict`]
    /// would return it.
    fn step_at(&self, t0: f64) -> Step;
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
    /// using `f` as scratch; returns the step (`step_at(t0)`), to be passed to
    /// [`TimeIntegrator::finish`].
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
    ) -> Step;
    /// The predictors of the step from `(t0, s0)` into `pred`, as [`TimeIntegrator::predict`]
    /// makes them, without its solve, and the gain `g` of its extra forces in `x_free`
    /// (`x_free = A^{-1} (... + g extra)` on the dofs without a prescribed velocity): for
    /// a prediction made again from a known one of the same `A`, `t0` and `s0` whose extra
    /// forces differ ([`crate::contact::context::Context::predict`]). `None` (the default):
    /// the scheme's `x_free` is not of that form, and it predicts again in full.
    fn repredict(&self, _t0: f64, _s0: &State, _pred: &mut State) -> Option<(Step, f64)> {
        None
    }
    /// `col <- A^{-1} e_dof`; `col` is zero and no solve is made (returns false) when `dof`
    /// has a prescribed velocity (its row of `A` is the identity and its value is lifted).
    fn inverse_column(&mut self, dof: usize, col: &mut [f64]) -> bool;
    /// [`TimeIntegrator::inverse_column`] for each of `dofs`, column `c` into
    /// `cols[c n..(c + 1) n]`; returns the number of solves made. One column at a time
    /// unless the scheme solves them as a block.
    fn inverse_columns(&mut self, dofs: &[usize], cols: &mut [f64]) -> usize {
        let n = cols.len() / dofs.len().max(1);
        dofs.iter()
            .zip(cols.chunks_exact_mut(n.max(1)))
            .map(|(&d, col)| usize::from(self.inverse_column(d, col)))
            .sum()
    }
    /// The end state of `step` (returned by [`TimeIntegrator::predict`]) from the start
    /// state, the predictors and `x`.
    fn finish(&self, step: &Step, s0: &State, pred: &State, x: &[f64], s1: &mut State);
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
    /// Factorizations so far.
    fn counts(&self) -> FactorCounts;
    /// The factor of the run's step and the bytes a free step reads; `None` (the default)
    /// for a scheme that does not report them.
    fn factor_size(&self) -> Option<FactorSize> {
        None
    }
    /// Runs the integrator's two-part work on `team`'s threads, if it has any (the same bits
    /// on any team; by default nothing changes).
    fn set_team(&mut self, _team: &crate::linalg::team::Team) {}
}
