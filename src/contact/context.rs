//! What a contact treatment works with: a narrow [`Context`] that the driver
//! ([`crate::simulation`]) builds from its engine for each step (references only, no
//! allocation), instead of the engine itself.
//!
//! A treatment sees the pairs and their geometry ([`Context::geometry`],
//! [`Context::tangent`], [`Context::gap`], [`Context::gaps_into`]), the constraint rows and
//! their solver ([`RowSolver`]), the integrator through a handle ([`Integ`]: the step
//! length, the [`Step`] of an instant, the stiffness point) and the step's three calls of
//! the integrator contract ([`crate::time::integrator`]), the prediction
//! ([`Context::predict`]), the solve with the contact rows ([`Context::solve`]) and the
//! update of the state ([`Context::finish`]):
//! $$x_{free} = A^{-1} b,\qquad x = x_{free} + \sum_q z_q \lambda_q,\qquad
//!   u_1 = U + \mu_u x,\ v_1 = V + \mu_v x,$$
//! the extra nodal forces of the next prediction (the soft way's restore), the run's step,
//! the gap tolerance, and the counters it keeps ([`Counts`]). Errors are
//! [`ContactError`]s.

use super::interface::Interface;
use super::obstacle::{HalfSpace, Obstacle};
use super::pair::{Geometry, Pair};
use super::rows::RowSolver;
use crate::linalg::LinalgError;
use crate::model::{LinearModel, LoadFn, Nonlinear, State};
use crate::time::integrator::{Step, TimeIntegrator};

/// The events a treatment counts (the driver reports them in its run statistics).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counts {
    /// Steps stepped back and repeated (braking, Table 1 item 4).
    pub step_backs: usize,
    /// Extra solves of the same interval (active-set changes, releases, immediate holds).
    pub resolves: usize,
    /// Braking events.
    pub brakings: usize,
    /// Entries into contact.
    pub entries: usize,
    /// Releases.
    pub releases: usize,
    /// Predictions solved ([`Context::predict`]).
    pub predictions: usize,
    /// Predictions made again from a known one of the same start state, without a solve
    /// ([`Context::predict`]).
    pub predictions_again: usize,
}

/// Errors of a contact treatment.
#[derive(Debug, thiserror::Error)]
pub enum ContactError {
    /// A matrix could not be factored (a sub-step's `A`, the mass matrix of a velocity jump).
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// A contact interface lost a node's target ([`super::interface`]).
    #[error(transparent)]
    Interface(#[from] super::interface::InterfaceError),
}

/// The integrator as a treatment sees it: its step length, the [`Step`] of an instant and
/// the point where it evaluates `K u` (the predictions, solves and end states go through
/// [`Context`]).
pub struct Integ<'a>(&'a mut dyn TimeIntegrator);

impl<'a> Integ<'a> {
    /// The handle of `integ`.
    pub fn new(integ: &'a mut dyn TimeIntegrator) -> Self {
        Self(integ)
    }

    /// The current step length, s.
    pub fn h(&self) -> f64 {
        self.0.h()
    }

    /// The step of the current length starting at `t0` ([`TimeIntegrator::step_at`]).
    pub fn step_at(&self, t0: f64) -> Step {
        self.0.step_at(t0)
    }

    /// [`TimeIntegrator::stiffness_point`].
    pub fn stiffness_point(&self, s0: &State, pred: &State, p: &mut [f64]) -> f64 {
        self.0.stiffness_point(s0, pred, p)
    }
}

impl std::fmt::Debug for Integ<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("Integ").field(&self.0.name()).finish()
    }
}

/// The driver's scratch for a [`Context`]: the load vector and the obstacles' half-spaces of
/// one instant, and the last two predictions (allocated once, [`Scratch::new`]).
#[derive(Debug, Clone)]
pub struct Scratch {
    f: Vec<f64>,
    half_spaces: Vec<Option<HalfSpace>>,
    known: [Known; 2],
    clock: u64,
    /// Predictions made again when one serves ([`Scratch::set_predictions_again`]).
    again: bool,
    /// The time spent in the predictions solved ([`Context::predict`]), s.
    predict_s: f64,
}

/// A prediction made: what it was made from (the start, the step, the columns' epoch of
/// `A`, the extra forces) and its `x_free`.
#[derive(Debug, Clone)]
struct Known {
    /// When it was last made or used (0: never).
    used: u64,
    t0: f64,
    h: f64,
    epoch: u64,
    s0: State,
    extra: Vec<f64>,
    xfree: Vec<f64>,
}

impl Known {
    fn new(n: usize) -> Self {
        Self {
            used: 0,
            t0: 0.0,
            h: 0.0,
            epoch: 0,
            s0: State::zeros(n),
            extra: vec![0.0; n],
            xfree: vec![0.0; n],
        }
    }

    /// Made from the same start on the same `A` (bit for bit).
    fn is_from(&self, t0: f64, h: f64, epoch: u64, s0: &State) -> bool {
        let same = |a: &[f64], b: &[f64]| {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
        };
        self.used != 0
            && self.t0.to_bits() == t0.to_bits()
            && self.h.to_bits() == h.to_bits()
            && self.epoch == epoch
            && same(&self.s0.u, &s0.u)
            && same(&self.s0.v, &s0.v)
            && same(&self.s0.a, &s0.a)
    }
}

impl Scratch {
    /// For `n` dofs and `obstacles` obstacles.
    pub fn new(n: usize, obstacles: usize) -> Self {
        Self {
            f: vec![0.0; n],
            half_spaces: Vec::with_capacity(obstacles),
            known: [Known::new(n), Known::new(n)],
            clock: 0,
            again: true,
            predict_s: 0.0,
        }
    }

    /// The time spent in the predictions solved so far (their right-hand sides and
    /// solves, each a free step), s.
    pub fn prediction_seconds(&self) -> f64 {
        self.predict_s
    }

    /// Whether [`Context::predict`] makes a prediction again from a known one when it can
    /// (the default), or solves each.
    pub fn set_predictions_again(&mut self, on: bool) {
        self.again = on;
        self.known.iter_mut().for_each(|k| k.used = 0);
    }
}

/// What a treatment works with (module docs).
pub struct Context<'a> {
    /// Spatial dimension.
    pub dim: usize,
    /// Reference positions of the nodes, m.
    pub reference: &'a [f64],
    /// The obstacles.
    pub obstacles: &'a [Box<dyn Obstacle>],
    /// The contact interfaces between bodies (searched at the start of the step).
    pub interfaces: &'a [Interface],
    /// The contact pairs.
    pub pairs: &'a [Pair],
    /// The model integrated (after any mass redistribution).
    pub model: &'a LinearModel,
    /// The external load.
    pub load: &'a LoadFn,
    /// The integrator.
    pub integ: Integ<'a>,
    /// The constraint rows and their solver.
    pub rows: &'a mut RowSolver,
    /// Nodal forces added to the load in the next prediction (the soft way's restore), N.
    pub extra: &'a mut [f64],
    /// Predictors `U`, `V` of the last prediction.
    pub pred: &'a mut State,
    /// The free solution `x_free` of the last prediction.
    pub xfree: &'a mut [f64],
    /// `x` of the last solve.
    pub x: &'a mut [f64],
    /// The run's step, s.
    pub h: f64,
    /// Gap below `-gap_tol` (m) counts as penetration.
    pub gap_tol: f64,
    /// The treatment's counters.
    pub counts: &'a mut Counts,
    /// The driver's scratch.
    pub scratch: &'a mut Scratch,
    /// A nonlinear internal force and its iteration ([`crate::model::internal`]), run by
    /// [`Context::predict`], [`Context::solve`] and [`Context::finish`]; `None`: linear.
    pub nonlinear: Option<&'a mut Nonlinear>,
}

impl std::fmt::Debug for Context<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Context")
            .field("dim", &self.dim)
            .field("integ", &self.integ)
            .field("pairs", &self.pairs.len())
            .field("h", &self.h)
            .finish()
    }
}

impl Context<'_> {
    /// The geometry of pair `p` at time `t` in the configuration `u`.
    pub fn geometry(&self, p: usize, t: f64, u: &[f64]) -> Geometry {
        self.pairs[p].geometry(
            self.obstacles,
            self.interfaces,
            self.dim,
            self.reference,
            u,
            t,
        )
    }

    /// The tangential row of pair `p` at time `t` in the configuration `u` along its
    /// tangent `k` (`None` past the model's `dim - 1` tangents; [`Pair::tangent`]).
    pub fn tangent(&self, p: usize, t: f64, u: &[f64], k: usize) -> Option<Geometry> {
        self.pairs[p].tangent(
            self.obstacles,
            self.interfaces,
            self.dim,
            self.reference,
            u,
            t,
            k,
        )
    }

    /// The gap of pair `p` at time `t` in the configuration `u`, m.
    pub fn gap(&self, p: usize, t: f64, u: &[f64]) -> f64 {
        self.pairs[p].gap(
            self.obstacles,
            self.interfaces,
            self.dim,
            self.reference,
            u,
            t,
        )
    }

    /// The gaps of every pair at time `t` in the configuration `u` into `out` (m): the same
    /// values as [`Context::gap`] pair by pair, each obstacle's half-space evaluated once.
    pub fn gaps_into(&mut self, t: f64, u: &[f64], out: &mut [f64]) {
        super::pair::gaps_into(
            self.pairs,
            self.obstacles,
            self.interfaces,
            self.dim,
            self.reference,
            u,
            t,
            &mut self.scratch.half_spaces,
            out,
        );
    }

    /// Predicts the step from `(t0, s0)` (loads plus [`Context::extra`]) into
    /// [`Context::pred`] and [`Context::xfree`]; returns the step, for [`Context::finish`]
    /// and the rows' maps.
    ///
    /// With a nonlinear internal force, the load holds its pseudo-load of the state at `t0`
    /// ([`Nonlinear::begin`]).
    ///
    /// Made again: when one of the last two predictions (of a linear model) was made from the
    /// same `t0`, `s0` and `A`, and its extra forces differ only on dofs whose columns
    /// `A^{-1} e_d` the rows have cached (a re-solve after a release gives back a braking
    /// force; a step back repeats the interval before), `x_free` is that prediction's plus
    /// those columns times the change ([`TimeIntegrator::repredict`]), without a solve. The
    /// same `x_free` to round-off.
    pub fn predict(&mut self, t0: f64, s0: &State) -> Step {
        if self.nonlinear.is_none() && self.scratch.again {
            if let Some(step) = self.predict_again(t0, s0) {
                self.counts.predictions_again += 1;
                return step;
            }
        }
        self.counts.predictions += 1;
        let extra: &[f64] = match self.nonlinear.as_deref_mut() {
            Some(nl) => nl.begin(t0, s0, self.extra),
            None => self.extra,
        };
        let clock = std::time::Instant::now();
        let step = self.integ.0.predict(
            t0,
            s0,
            self.load,
            extra,
            &mut self.scratch.f,
            self.pred,
            self.xfree,
        );
        self.scratch.predict_s += clock.elapsed().as_secs_f64();
        if self.nonlinear.is_none() && self.scratch.again {
            // Kept in the least recently used of the two (a scheme that cannot make it
            // again, `repredict` `None`, only finds it unused).
            let sc = &mut *self.scratch;
            sc.clock += 1;
            let k = usize::from(sc.known[1].used < sc.known[0].used);
            let known = &mut sc.known[k];
            known.used = sc.clock;
            known.t0 = t0;
            known.h = step.h;
            known.epoch = self.rows.epoch();
            known.s0.u.copy_from_slice(&s0.u);
            known.s0.v.copy_from_slice(&s0.v);
            known.s0.a.copy_from_slice(&s0.a);
            known.extra.copy_from_slice(self.extra);
            known.xfree.copy_from_slice(self.xfree);
        }
        step
    }

    /// [`Context::predict`] made again from a known prediction, if one serves.
    fn predict_again(&mut self, t0: f64, s0: &State) -> Option<Step> {
        let (h, epoch) = (self.integ.h(), self.rows.epoch());
        let sc = &mut *self.scratch;
        let k = (0..2).find(|&k| sc.known[k].is_from(t0, h, epoch, s0))?;
        let (step, gain) = self.integ.0.repredict(t0, s0, self.pred)?;
        let known = &mut sc.known[k];
        self.xfree.copy_from_slice(&known.xfree);
        if !self
            .rows
            .add_cached(gain, self.extra, &known.extra, self.xfree)
        {
            return None;
        }
        sc.clock += 1;
        known.used = sc.clock;
        known.extra.copy_from_slice(self.extra);
        known.xfree.copy_from_slice(self.xfree);
        Some(step)
    }

    /// Solves the rows in [`Context::rows`] from `xfree` into `x`; returns the active-set
    /// changes. With a nonlinear internal force, the initial-stress iteration
    /// ([`Nonlinear::iterate`]): the rows are solved again after each correction of the
    /// pseudo-load, on the same factor.
    pub fn solve(&mut self, tol: f64) -> usize {
        match self.nonlinear.as_deref_mut() {
            None => {
                let changes = self.solve_multipliers(tol);
                self.form_x();
                changes
            }
            Some(nl) => {
                let rows = &mut *self.rows;
                nl.iterate(
                    &mut *self.integ.0,
                    self.load,
                    self.extra,
                    &mut self.scratch.f,
                    self.pred,
                    self.xfree,
                    self.x,
                    |integ, xfree, x| {
                        x.copy_from_slice(xfree);
                        rows.solve(integ, x, tol)
                    },
                )
            }
        }
    }

    /// The rows' multipliers of [`Context::solve`] alone, without forming `x` (the rows'
    /// columns times the multipliers, `n` values a column); with a nonlinear internal force,
    /// [`Context::solve`] itself (its iteration needs `x`); without, `x` is left as it was
    /// until [`Context::form_x`].
    pub fn solve_multipliers(&mut self, tol: f64) -> usize {
        match self.nonlinear {
            None => self
                .rows
                .solve_multipliers(&mut *self.integ.0, self.xfree, tol),
            Some(_) => self.solve(tol),
        }
    }

    /// The rows' multipliers with `x_free` replaced by `x0` (the space-time scheme's velocity
    /// at the interval's start: what the rows would meet if no force acted in the step);
    /// with a nonlinear internal force or a scheme whose unknown is not the velocity,
    /// [`Context::solve_multipliers`].
    pub fn solve_multipliers_at(&mut self, x0: &[f64], tol: f64) -> usize {
        let velocity =
            self.integ.step_at(0.0).unit == crate::time::integrator::MultiplierUnit::Impulse;
        match self.nonlinear {
            None if velocity => self.rows.solve_multipliers(&mut *self.integ.0, x0, tol),
            _ => self.solve_multipliers(tol),
        }
    }

    /// `x` of the last [`Context::solve_multipliers`]: then the same as [`Context::solve`]'s,
    /// bit for bit (with a nonlinear internal force it is already formed).
    pub fn form_x(&mut self) {
        if self.nonlinear.is_none() {
            self.x.copy_from_slice(self.xfree);
            self.rows.add_solution(self.x);
        }
    }

    /// The end state of `step` (returned by [`Context::predict`]) from `pred` and `x`; with
    /// a nonlinear internal force, its state of the last solve is committed to the step's
    /// end ([`Nonlinear::commit`]).
    pub fn finish(&mut self, step: &Step, s0: &State, s1: &mut State) {
        self.integ.0.finish(step, s0, self.pred, self.x, s1);
        if let Some(nl) = self.nonlinear.as_deref_mut() {
            nl.commit(step.t0 + step.h);
        }
    }

    /// Switches the integrator to the step `h` (a numeric refactorization at most; the
    /// cached columns are dropped).
    ///
    /// # Errors
    /// [`ContactError::Linalg`] when the new matrix is singular.
    pub fn set_step(&mut self, h: f64) -> Result<(), ContactError> {
        if h != self.integ.h() {
            self.integ.0.set_step(h)?;
            self.rows.invalidate();
        }
        Ok(())
    }
}
