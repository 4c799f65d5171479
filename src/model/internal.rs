//! A nonlinear internal force solved on the elastic factor: the contract
//! ([`InternalForce`]) and the initial-stress iteration of a step ([`Nonlinear`]).
//!
//! # The contract
//!
//! The body's internal force is `f_int(u) = K u - f_nl(u; s)`: the elastic `K u` that the
//! integrator's factored matrix holds, less a pseudo-load `f_nl` that depends on the
//! displacement and on a state `s` of fixed length (a plastic body:
//! [`crate::plasticity::PlasticBody`], `f_nl = sum_e A_e t B^T (D eps_e - sigma_e)`).
//! [`InternalForce::evaluate`] returns the trial state and `f_nl` at a displacement from a
//! committed state; [`InternalForce::pseudo_load`] the `f_nl` of a state with no new flow.
//!
//! # The iteration (initial stress, on the elastic factor)
//!
//! The step's equation has `K u_k` at the integrator's stiffness point `u_k = P + mu_k x`
//! ([`crate::time::integrator::TimeIntegrator::stiffness_point`]: `u(t0 + alpha h)` for the
//! space-time scheme, `u1` for the generalized-alpha family); the nonlinear part enters as
//! the load `f_nl` there, so the committed state of a step is the return at `u_k` from the
//! state at the step's start. Each solve of the step ([`crate::contact::Context::solve`],
//! with whatever rows the treatment posed):
//!
//! 1. predict with the load plus `f^0`, the pseudo-load of the start state
//!    ([`Nonlinear::begin`]);
//! 2. solve the rows, form `u_k`, evaluate: trial state and `f^{i+1} = f_nl(u_k)`;
//! 3. stop when `|r^i| <= tol (|f_int(u_k)| + |f_nl(u_k)|)` with the residual
//!    `r^i = f_nl(u_k) - f^i` (Euclidean norms; the scale bounds the elastic force
//!    `|K u_k|`, and stays that of the residual stresses when the body is unloaded, where
//!    `f_int` alone vanishes; `tol` default [`DEFAULT_TOL`]), else predict again with
//!    `f^{i+1} = f^i + omega_i r^i` (the same factor: a right-hand side and one solve) and go
//!    to 2. The relaxation `omega_i` is Aitken's (Irons & Tuck):
//!    `omega_0 = 1`, `omega_i = -omega_{i-1} r^{i-1}.(r^i - r^{i-1}) / |r^i - r^{i-1}|^2`,
//!    kept within [`AITKEN_BOUNDS`]: the plain initial-stress iteration (`omega = 1`)
//!    contracts slowly where the plastic zone is large (the error's dominant component
//!    decays by a factor close to 1 each time), and Aitken's secant estimate of that factor
//!    removes most of it.
//!
//! The residual of the step's equation at `u_k` is exactly `f^{i+1} - f^i`, since everything
//! else in it is linear and was solved exactly. The step's end ([`crate::contact::Context::finish`])
//! commits the trial state to the end snapshot.
//!
//! # The states travel with the snapshots
//!
//! The driver keeps three snapshots (`t_{k-2}`, `t_{k-1}`, `t_k`) so that the soft way can
//! step back and repeat the previous interval; [`Nonlinear`] keeps one state for each, in
//! the same ring (rotated with it: [`Nonlinear::rotate`]). A prediction from the snapshot
//! at `t0` starts from the state of the slot at `t0`, and the step's end commits into the
//! next slot, so a repeated interval starts again from the state before it and a step back
//! restores the plastic state with `u` and `v`. Steps that do not start at a snapshot (the
//! subdivision's sub-steps) are refused by the driver.
//!
//! No call allocates.

use super::State;
use crate::model::LoadFn;
use crate::time::integrator::{Step, TimeIntegrator};

/// Default tolerance of the iteration: the residual's norm relative to the internal force's
/// and the pseudo-load's, `1e-8` (module docs).
pub const DEFAULT_TOL: f64 = 1e-8;

/// The bounds of Aitken's relaxation factor.
pub const AITKEN_BOUNDS: (f64, f64) = (0.1, 20.0);

/// Default cap on the corrections of one solve.
pub const DEFAULT_MAX_ITERATIONS: usize = 200;

/// A nonlinear internal force `K u - f_nl(u; s)` (module docs).
pub trait InternalForce: Send + Sync {
    /// Length of the state vector.
    fn state_len(&self) -> usize;
    /// `f_nl` of the state `s` with no new flow, into `f_nl` (N per dof; overwritten).
    fn pseudo_load(&self, s: &[f64], f_nl: &mut [f64]);
    /// From the committed state `s0` and the displacement `u`: the trial state into `s1`,
    /// `f_nl` into `f_nl` and the internal force `f_int = K u - f_nl` of the body into
    /// `f_int` (N per dof; both overwritten); returns the number of points that flowed.
    fn evaluate(
        &self,
        s0: &[f64],
        u: &[f64],
        s1: &mut [f64],
        f_nl: &mut [f64],
        f_int: &mut [f64],
    ) -> usize;
    /// The stored energy of the state `s` at `u` less the elastic `u^T K u / 2` of the
    /// body, J (zero without inelastic strain).
    fn energy_correction(&self, s: &[f64], u: &[f64]) -> f64;
    /// How many nodal vectors of the model's dofs the state is, when it is nothing else:
    /// a moving refined zone ([`crate::simulation::Relocation`]) then relabels each with
    /// the nodes. `None` (the default): the state holds what a relabelling of the nodes
    /// cannot carry (the elements' plastic strains), and the zone is refused.
    fn nodal_state(&self) -> Option<usize> {
        None
    }
}

/// Counters of the iteration.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct NonlinearStats {
    /// Corrections (a prediction and a solve each) over the run.
    pub iterations: usize,
    /// Evaluations of the internal force.
    pub evaluations: usize,
    /// Solves whose iteration stopped at the cap.
    pub unconverged: usize,
    /// Most corrections in one solve.
    pub max_in_one_solve: usize,
}

/// The initial-stress iteration and the states of the driver's ring (module docs).
pub struct Nonlinear {
    force: Box<dyn InternalForce>,
    tol: f64,
    max_iterations: usize,
    ring: [Vec<f64>; 3],
    ring_t: [f64; 3],
    trial: Vec<f64>,
    start: usize,
    t0: f64,
    s0: State,
    f_used: Vec<f64>,
    f_new: Vec<f64>,
    /// The last residual `r^{i-1}` and relaxation `omega_{i-1}`.
    r_prev: Vec<f64>,
    omega: f64,
    f_int: Vec<f64>,
    total: Vec<f64>,
    point: Vec<f64>,
    iterations_now: usize,
    stats: NonlinearStats,
}

impl std::fmt::Debug for Nonlinear {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Nonlinear")
            .field("tol", &self.tol)
            .field("stats", &self.stats)
            .finish()
    }
}

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

impl Nonlinear {
    /// The iteration of `force` on `n` dofs, the three states zero at the start time `t0`,
    /// with the tolerance `tol` (> 0) and at most `max_iterations` corrections a solve.
    pub fn new(
        force: Box<dyn InternalForce>,
        n: usize,
        t0: f64,
        tol: f64,
        max_iterations: usize,
    ) -> Self {
        let m = force.state_len();
        Self {
            force,
            tol,
            max_iterations,
            ring: [vec![0.0; m], vec![0.0; m], vec![0.0; m]],
            ring_t: [t0; 3],
            trial: vec![0.0; m],
            start: 1,
            t0: f64::NAN,
            s0: State::zeros(n),
            f_used: vec![0.0; n],
            f_new: vec![0.0; n],
            r_prev: vec![0.0; n],
            omega: 1.0,
            f_int: vec![0.0; n],
            total: vec![0.0; n],
            point: vec![0.0; n],
            iterations_now: 0,
            stats: NonlinearStats::default(),
        }
    }

    /// Sets every slot of the ring to the state `s` (a body that starts with the state a
    /// previous run left: a plastic wheel's next pass in a growth study).
    ///
    /// # Panics
    /// If `s` is not [`InternalForce::state_len`] long.
    pub fn set_states(&mut self, s: &[f64]) {
        for slot in &mut self.ring {
            slot.copy_from_slice(s);
        }
    }

    /// The counters.
    pub fn stats(&self) -> NonlinearStats {
        self.stats
    }

    /// The most corrections a solve may take.
    pub fn max_iterations(&self) -> usize {
        self.max_iterations
    }

    /// The state of the ring's slot `i` (0: `t_{k-2}`, 1: `t_{k-1}`, 2: `t_k`).
    pub fn state(&self, i: usize) -> &[f64] {
        &self.ring[i]
    }

    /// The internal force.
    pub fn force(&self) -> &dyn InternalForce {
        self.force.as_ref()
    }

    /// The energy correction ([`InternalForce::energy_correction`]) of slot `i` at `u`, J.
    pub fn energy_correction(&self, i: usize, u: &[f64]) -> f64 {
        self.force.energy_correction(&self.ring[i], u)
    }

    /// Relabels the ring's states with the nodes (a moving refined zone), `f` applied to
    /// each of their nodal vectors ([`InternalForce::nodal_state`]); the next step's start
    /// is evaluated afresh. `false`, and nothing done, when the state is not nodal.
    pub fn relabel(&mut self, mut f: impl FnMut(&mut [f64])) -> bool {
        let Some(k) = self.force.nodal_state().filter(|&k| k > 0) else {
            return false;
        };
        for slot in &mut self.ring {
            let n = slot.len() / k;
            for v in slot.chunks_exact_mut(n) {
                f(v);
            }
        }
        self.t0 = f64::NAN;
        true
    }

    /// Rotates the ring with the driver's snapshots.
    pub fn rotate(&mut self) {
        self.ring.rotate_left(1);
        self.ring_t.rotate_left(1);
    }

    /// Starts the solves of the step from `(t0, s0)` with the nodal forces `extra` (N):
    /// the start slot is the one at `t0` (of `t_{k-2}`, `t_{k-1}`; a tie: the later), the
    /// pseudo-load of its state (kept from the last solve when this is the same interval
    /// again); returns the forces to predict with, `extra + f^0`.
    ///
    /// # Panics
    /// When `t0` is not the time of the first two snapshots (to `1e-9` of the gap between
    /// them, or absolutely when they coincide).
    pub fn begin(&mut self, t0: f64, s0: &State, extra: &[f64]) -> &[f64] {
        let d0 = (self.ring_t[0] - t0).abs();
        let d1 = (self.ring_t[1] - t0).abs();
        let start = if d1 <= d0 { 1 } else { 0 };
        let scale = (self.ring_t[2] - self.ring_t[0])
            .abs()
            .max(t0.abs())
            .max(1e-300);
        assert!(
            (self.ring_t[start] - t0).abs() <= 1e-9 * scale,
            "a nonlinear step must start at a snapshot (t0 = {t0:e} s)"
        );
        if !(start == self.start && t0 == self.t0) {
            self.force.pseudo_load(&self.ring[start], &mut self.f_used);
        }
        self.start = start;
        self.t0 = t0;
        self.s0.u.copy_from_slice(&s0.u);
        self.s0.v.copy_from_slice(&s0.v);
        self.s0.a.copy_from_slice(&s0.a);
        self.iterations_now = 0;
        for ((t, e), f) in self.total.iter_mut().zip(extra).zip(&self.f_used) {
            *t = e + f;
        }
        &self.total
    }

    /// After a solve (`x` with the predictors `pred` of `integ`): evaluates at the
    /// stiffness point; `true` when converged (or at the cap), else the forces to predict
    /// with again are updated (`extra + f^{i+1}`) and `false` is returned.
    fn converged(
        &mut self,
        integ: &dyn TimeIntegrator,
        pred: &State,
        x: &[f64],
        extra: &[f64],
    ) -> bool {
        let mu_k = integ.stiffness_point(&self.s0, pred, &mut self.point);
        for (p, xi) in self.point.iter_mut().zip(x) {
            *p += mu_k * xi;
        }
        self.force.evaluate(
            &self.ring[self.start],
            &self.point,
            &mut self.trial,
            &mut self.f_new,
            &mut self.f_int,
        );
        self.stats.evaluations += 1;
        let r = self
            .f_new
            .iter()
            .zip(&self.f_used)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        if r <= self.tol * (norm(&self.f_int) + norm(&self.f_new)) {
            return true;
        }
        if self.iterations_now >= self.max_iterations {
            self.stats.unconverged += 1;
            return true;
        }
        self.iterations_now += 1;
        self.stats.iterations += 1;
        self.stats.max_in_one_solve = self.stats.max_in_one_solve.max(self.iterations_now);
        // r = f_new - f_used into f_new; Aitken's omega from the last two residuals.
        for (n, u) in self.f_new.iter_mut().zip(&self.f_used) {
            *n -= u;
        }
        self.omega = if self.iterations_now == 1 {
            1.0
        } else {
            let (mut num, mut den) = (0.0, 0.0);
            for (r, rp) in self.f_new.iter().zip(&self.r_prev) {
                let d = r - rp;
                num += rp * d;
                den += d * d;
            }
            if den > 0.0 {
                (-self.omega * num / den).clamp(AITKEN_BOUNDS.0, AITKEN_BOUNDS.1)
            } else {
                1.0
            }
        };
        for ((f, r), rp) in self
            .f_used
            .iter_mut()
            .zip(&self.f_new)
            .zip(&mut self.r_prev)
        {
            *f += self.omega * r;
            *rp = *r;
        }
        for ((t, e), f) in self.total.iter_mut().zip(extra).zip(&self.f_used) {
            *t = e + f;
        }
        false
    }

    /// The iteration of one solve (module docs): `solve_rows` turns `xfree` into `x` with
    /// the step's rows and returns its active-set changes; between two solves the step is
    /// predicted again with the corrected pseudo-load. Returns the changes of all solves.
    #[allow(clippy::too_many_arguments)]
    pub fn iterate(
        &mut self,
        integ: &mut dyn TimeIntegrator,
        load: &LoadFn,
        extra: &[f64],
        f: &mut [f64],
        pred: &mut State,
        xfree: &mut [f64],
        x: &mut [f64],
        mut solve_rows: impl FnMut(&mut dyn TimeIntegrator, &[f64], &mut [f64]) -> usize,
    ) -> usize {
        let mut changes = 0;
        self.iterations_now = 0;
        loop {
            changes += solve_rows(integ, xfree, x);
            if self.converged(integ, pred, x, extra) {
                return changes;
            }
            let t0 = self.t0;
            let _: Step = integ.predict(t0, &self.s0, load, &self.total, f, pred, xfree);
        }
    }

    /// Commits the trial state of the last solve to the slot after the step's start, at
    /// `t1` (s).
    pub fn commit(&mut self, t1: f64) {
        let end = self.start + 1;
        self.ring[end].copy_from_slice(&self.trial);
        self.ring_t[end] = t1;
    }
}
