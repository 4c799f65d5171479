//! The driver: the step loop of the space-time scheme with the soft-way contact of Table 1
//! (go on, repeat the step, or step back and repeat the previous one).
//!
//! States are kept for `t_{k-2}`, `t_{k-1}` and `t_k` in three preallocated snapshots; a step
//! is reported to the observer only when it can no longer be revised (when the next step
//! has been accepted without stepping back), so outputs never hold a step that was undone.
//!
//! One interval `[t0, t1]` is solved by [`Simulation`] as follows (Table 1):
//! 1. the pairs' modes at `t0` give the constraints (brake, hold) and the forces given back;
//! 2. solve; a held pair with a tensile multiplier is released and the step solved again
//!    with the momentum taken at its arrival given back as a force (item 7; see
//!    [`crate::contact::softway`], Release);
//! 3. a free pair found penetrating at `t1` is, with the soft way, braked in the previous
//!    interval `[t_{-1}, t0]` (Eq. 26), which is solved again (items 4-5), and the interval
//!    is solved again with the pair held (item 6). Without a previous interval (first step),
//!    or for the exact method, the pair is held at once in the current interval.

use crate::contact::softway::{braking_velocity, holding_velocity};
use crate::contact::{ContactMethod, Obstacle, PairMode, PairState};
use crate::linalg::{quadratic_form, LinalgError};
use crate::time::params::beta;
use crate::time::step::{LinearModel, Stepper, VelocityConstraint};
use crate::time::SpaceTimeParams;
use std::sync::atomic::{AtomicBool, Ordering};

/// External force at time `t` (s), written into the slice (N per dof; overwrite it).
pub type LoadFn = Box<dyn Fn(f64, &mut [f64]) + Send + Sync>;

/// A contact pair: a node against an obstacle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ContactPair {
    /// The node.
    pub node: usize,
    /// Index into [`Problem::obstacles`].
    pub obstacle: usize,
}

/// Everything the driver needs: the model, the scheme, supports, loads, obstacles, contact
/// pairs and the initial state.
pub struct Problem {
    /// Spatial dimension (1 or 2).
    pub dim: usize,
    /// Reference positions of the nodes, flat (`dim` per node), m.
    pub reference: Vec<f64>,
    /// The semi-discrete model.
    pub model: LinearModel,
    /// `alpha` and `h` (fixed), and the initial `gamma`.
    pub params: SpaceTimeParams,
    /// `gamma` from given instants on: `(t_from, gamma)`, sorted by time; before the first,
    /// `params.gamma`.
    pub gamma_schedule: Vec<(f64, f64)>,
    /// Prescribed velocities `(dof, value m/s)`.
    pub dirichlet: Vec<(usize, f64)>,
    /// External load.
    pub load: LoadFn,
    /// Rigid obstacles.
    pub obstacles: Vec<Box<dyn Obstacle>>,
    /// Contact pairs.
    pub pairs: Vec<ContactPair>,
    /// Contact treatment.
    pub contact: ContactMethod,
    /// Initial displacement, m.
    pub u0: Vec<f64>,
    /// Initial velocity, m/s.
    pub v0: Vec<f64>,
    /// Start time, s.
    pub t0: f64,
    /// Number of steps.
    pub steps: usize,
    /// Gap below `-gap_tol` (m) counts as penetration.
    pub gap_tol: f64,
    /// Stiffness of the reported strain energy `u^T K u / 2` (on the model's pattern);
    /// `None`: the model's `K` (in a rotating frame `K` holds spin terms: pass the elastic
    /// stiffness here).
    pub energy_stiffness: Option<Vec<f64>>,
}

impl std::fmt::Debug for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Problem")
            .field("dim", &self.dim)
            .field("dofs", &self.model.n())
            .field("params", &self.params)
            .field("pairs", &self.pairs.len())
            .field("steps", &self.steps)
            .finish()
    }
}

impl Problem {
    /// `gamma` in force for the step starting at `t`.
    pub fn gamma_at(&self, t: f64) -> f64 {
        let mut g = self.params.gamma;
        for &(t_from, gm) in &self.gamma_schedule {
            if t + 1e-12 * self.params.h >= t_from {
                g = gm;
            }
        }
        g
    }
}

/// The state at the end of a step.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Step index (0: the initial state).
    pub k: usize,
    /// Time, s.
    pub t: f64,
    /// Displacement, m.
    pub u: Vec<f64>,
    /// Velocity, m/s.
    pub v: Vec<f64>,
    /// Contact pairs.
    pub pairs: Vec<PairState>,
}

/// What an observer sees of a final step.
#[derive(Debug)]
pub struct StepView<'a> {
    /// The state.
    pub state: &'a Snapshot,
    /// Kinetic energy `v^T M v / 2`, J.
    pub kinetic: f64,
    /// Strain energy `u^T K u / 2`, J.
    pub strain: f64,
    /// Sum of the pairs' constraint forces (braking included), N.
    pub contact_force: f64,
    /// Pairs held on their obstacle.
    pub held: usize,
}

/// Counters of a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct RunStats {
    /// Steps taken.
    pub steps: usize,
    /// Steps stepped back and repeated (braking, Table 1 item 4).
    pub step_backs: usize,
    /// Extra solves of the same interval (releases, immediate holds).
    pub resolves: usize,
    /// Braking events.
    pub brakings: usize,
    /// Releases.
    pub releases: usize,
    /// True when the run stopped on an interrupt.
    pub interrupted: bool,
}

/// Errors of a run.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The system matrix could not be factored.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// The observer failed (writing output).
    #[error("writing results failed: {0}")]
    Output(#[from] std::io::Error),
    /// The solution blew up.
    #[error("the solution is not finite at step {step} (t = {t:e} s): the time step is beyond the stability limit of (alpha, gamma) or the model is ill-posed")]
    NotFinite {
        /// Step.
        step: usize,
        /// Time, s.
        t: f64,
    },
}

struct Work {
    f: Vec<f64>,
    rhs: Vec<f64>,
    cons: Vec<VelocityConstraint>,
    cons_pair: Vec<usize>,
    lambda: Vec<f64>,
    modes: Vec<PairMode>,
    restore: Vec<Option<[f64; 2]>>,
    released: Vec<bool>,
    pen: Vec<usize>,
    pen_saved: Vec<usize>,
    // The braking step solved again with the braking pairs stopped (`n.v = w`): its
    // multipliers are the impulses given back at release.
    rhs_stop: Vec<f64>,
    cons_stop: Vec<VelocityConstraint>,
    lambda_stop: Vec<f64>,
}

/// The step loop over a [`Problem`].
pub struct Simulation {
    problem: Problem,
    stepper: Stepper,
    snaps: [Snapshot; 3],
    work: Work,
    stats: RunStats,
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("problem", &self.problem)
            .finish()
    }
}

const MAX_RESOLVES: usize = 32;

impl Simulation {
    /// Factors the system and allocates all work memory.
    ///
    /// # Errors
    /// [`SimError::Linalg`] when `A` is singular.
    pub fn new(problem: Problem) -> Result<Self, SimError> {
        let n = problem.model.n();
        let np = problem.pairs.len();
        let mut contact_nodes: Vec<usize> = problem.pairs.iter().map(|p| p.node).collect();
        contact_nodes.sort_unstable();
        contact_nodes.dedup();
        // Cache all contact nodes' columns when that fits in 256 MiB, else 64 of them.
        let per_node = problem.dim * n * 8;
        let cache = if contact_nodes.len() * per_node <= 256 << 20 {
            contact_nodes.len()
        } else {
            64
        };
        let stepper = Stepper::new(
            &problem.model,
            problem.dim,
            problem.params,
            &problem.dirichlet,
            np,
            cache,
        )?;
        let snap = Snapshot {
            k: 0,
            t: problem.t0,
            u: problem.u0.clone(),
            v: problem.v0.clone(),
            pairs: vec![PairState::default(); np],
        };
        let mut sim = Self {
            stepper,
            snaps: [snap.clone(), snap.clone(), snap],
            work: Work {
                f: vec![0.0; n],
                rhs: vec![0.0; n],
                cons: Vec::with_capacity(np),
                cons_pair: Vec::with_capacity(np),
                lambda: vec![0.0; np.max(1)],
                modes: vec![PairMode::Free; np],
                restore: vec![None; np],
                released: vec![false; np],
                pen: Vec::with_capacity(np),
                pen_saved: Vec::with_capacity(np),
                rhs_stop: vec![0.0; n],
                cons_stop: Vec::with_capacity(np),
                lambda_stop: vec![0.0; np.max(1)],
            },
            problem,
            stats: RunStats::default(),
        };
        // Initial gaps.
        for p in 0..np {
            let g = sim.gap(&sim.snaps[1], p);
            sim.snaps[1].pairs[p].gap = g;
        }
        Ok(sim)
    }

    /// The problem.
    pub fn problem(&self) -> &Problem {
        &self.problem
    }

    fn node_pos(pb: &Problem, s: &Snapshot, node: usize) -> [f64; 2] {
        let mut x = [0.0; 2];
        for c in 0..pb.dim {
            x[c] = pb.reference[pb.dim * node + c] + s.u[pb.dim * node + c];
        }
        x
    }

    fn node_vel(pb: &Problem, s: &Snapshot, node: usize) -> [f64; 2] {
        let mut v = [0.0; 2];
        for c in 0..pb.dim {
            v[c] = s.v[pb.dim * node + c];
        }
        v
    }

    fn gap(&self, s: &Snapshot, p: usize) -> f64 {
        let pair = self.problem.pairs[p];
        let x = Self::node_pos(&self.problem, s, pair.node);
        self.problem.obstacles[pair.obstacle]
            .half_space(s.t, x)
            .gap(x)
    }

    /// Runs all steps, calling `observer` once per final step (the initial state included).
    /// Stops early, with `interrupted` set, when `interrupt` becomes true.
    ///
    /// # Errors
    /// [`SimError`] on a non-finite solution or an observer failure.
    pub fn run<F>(&mut self, interrupt: &AtomicBool, mut observer: F) -> Result<RunStats, SimError>
    where
        F: FnMut(&StepView) -> Result<(), std::io::Error>,
    {
        // snaps[0] = t_{k-2}, snaps[1] = t_{k-1}, snaps[2] = t_k.
        let mut have_prev = false;
        for _ in 0..self.problem.steps {
            if interrupt.load(Ordering::Relaxed) {
                self.stats.interrupted = true;
                break;
            }
            self.advance(have_prev)?;
            let k = self.snaps[2].k;
            if !self.snaps[2].v.iter().all(|x| x.is_finite()) {
                return Err(SimError::NotFinite {
                    step: k,
                    t: self.snaps[2].t,
                });
            }
            self.emit(1, &mut observer)?;
            self.snaps.rotate_left(1);
            have_prev = true;
            self.stats.steps += 1;
        }
        self.emit(1, &mut observer)?;
        Ok(self.stats)
    }

    fn emit<F>(&self, i: usize, observer: &mut F) -> Result<(), std::io::Error>
    where
        F: FnMut(&StepView) -> Result<(), std::io::Error>,
    {
        let s = &self.snaps[i];
        let m = &self.problem.model;
        let kinetic = 0.5 * quadratic_form(m.pattern(), &m.m, &s.v);
        let k = self.problem.energy_stiffness.as_deref().unwrap_or(&m.k);
        let strain = 0.5 * quadratic_form(m.pattern(), k, &s.u);
        let contact_force = s.pairs.iter().map(|p| p.force).sum();
        let held = s.pairs.iter().filter(|p| p.held).count();
        observer(&StepView {
            state: s,
            kinetic,
            strain,
            contact_force,
            held,
        })
    }

    /// Solves `[t_{k-1}, t_k]` into `snaps[2]`, stepping back into `[t_{k-2}, t_{k-1}]` when
    /// the soft way asks for it.
    fn advance(&mut self, have_prev: bool) -> Result<(), SimError> {
        let mut step_backs = 0;
        let mut immediate = 0;
        loop {
            let npen = self.solve_interval(1, 2);
            if npen == 0 {
                return Ok(());
            }
            let mut pen = std::mem::take(&mut self.work.pen_saved);
            pen.clear();
            pen.extend_from_slice(&self.work.pen);
            if self.problem.contact.brakes() && have_prev && step_backs < 2 {
                step_backs += 1;
                self.stats.step_backs += 1;
                self.stats.brakings += pen.len();
                let h = self.problem.params.h;
                let t_arrive = self.snaps[2].t;
                let bt = beta(
                    self.problem.params.alpha,
                    self.problem.gamma_at(self.snaps[0].t),
                );
                for &p in &pen {
                    let pair = self.problem.pairs[p];
                    let obst = &self.problem.obstacles[pair.obstacle];
                    let x_pred = Self::node_pos(&self.problem, &self.snaps[2], pair.node);
                    let hs = obst.half_space(t_arrive, x_pred);
                    let w = obst.surface_normal_velocity(t_arrive, x_pred);
                    let xm1 = Self::node_pos(&self.problem, &self.snaps[0], pair.node);
                    let vm1 = Self::node_vel(&self.problem, &self.snaps[0], pair.node);
                    let n = hs.normal;
                    let q = braking_velocity(
                        hs.offset,
                        n[0] * xm1[0] + n[1] * xm1[1],
                        n[0] * vm1[0] + n[1] * vm1[1],
                        w,
                        h,
                        bt,
                    );
                    self.snaps[0].pairs[p].mode = PairMode::Brake { q, normal: n, w };
                }
                // Repeat the previous step with the braking; a pair found penetrating at
                // t_{k-1} in that repetition is held at once.
                let mut guard = 0;
                loop {
                    let np = self.solve_interval(0, 1);
                    if np == 0 || guard >= MAX_RESOLVES {
                        break;
                    }
                    guard += 1;
                    self.stats.resolves += 1;
                    for i in 0..self.work.pen.len() {
                        let p = self.work.pen[i];
                        self.snaps[0].pairs[p].mode = PairMode::Hold;
                    }
                }
            } else {
                immediate += 1;
                self.stats.resolves += 1;
                for &p in &pen {
                    self.snaps[1].pairs[p].mode = PairMode::Hold;
                }
                if immediate > MAX_RESOLVES {
                    self.work.pen_saved = pen;
                    return Ok(());
                }
            }
            // Give the buffer back (no allocation in the loop).
            self.work.pen_saved = pen;
        }
    }

    /// Solves the interval from `snaps[from]` into `snaps[to]`; returns the number of free
    /// pairs found penetrating at the end (listed in `work.pen`).
    fn solve_interval(&mut self, from: usize, to: usize) -> usize {
        let pb = &self.problem;
        let (fs, ts) = {
            let (lo, hi) = self.snaps.split_at_mut(to);
            (&lo[from], &mut hi[0])
        };
        let w = &mut self.work;
        let h = pb.params.h;
        let t0 = fs.t;
        let t1 = t0 + h;
        let bt = beta(pb.params.alpha, pb.gamma_at(t0));
        let np = pb.pairs.len();
        for p in 0..np {
            w.modes[p] = fs.pairs[p].mode;
            w.restore[p] = fs.pairs[p].restore;
            w.released[p] = false;
        }
        for _ in 0..MAX_RESOLVES {
            (pb.load)(t0 + pb.params.alpha * h, &mut w.f);
            for p in 0..np {
                if let Some(r) = w.restore[p] {
                    let node = pb.pairs[p].node;
                    for c in 0..pb.dim {
                        w.f[pb.dim * node + c] += r[c];
                    }
                }
            }
            self.stepper.rhs_into(&fs.u, &fs.v, &w.f, &mut w.rhs);
            w.cons.clear();
            w.cons_pair.clear();
            for p in 0..np {
                let pair = pb.pairs[p];
                match w.modes[p] {
                    PairMode::Free => {}
                    PairMode::Brake { q, normal, .. } => {
                        w.cons.push(VelocityConstraint {
                            node: pair.node,
                            normal,
                            rhs: q,
                        });
                        w.cons_pair.push(p);
                    }
                    PairMode::Hold => {
                        let obst = &pb.obstacles[pair.obstacle];
                        let x0 = Self::node_pos(pb, fs, pair.node);
                        let v0 = Self::node_vel(pb, fs, pair.node);
                        let hs = obst.half_space(t1, x0);
                        let n = hs.normal;
                        let wn = obst.surface_normal_velocity(t1, x0);
                        let g = holding_velocity(
                            hs.offset,
                            n[0] * x0[0] + n[1] * x0[1],
                            n[0] * v0[0] + n[1] * v0[1],
                            wn,
                            h,
                            bt,
                        );
                        w.cons.push(VelocityConstraint {
                            node: pair.node,
                            normal: n,
                            rhs: g,
                        });
                        w.cons_pair.push(p);
                    }
                }
            }
            // In a braking step, the impulses that would stop the braked nodes (relative
            // normal velocity 0 at t1): lambda_s = S^-1 (w - C A^-1 b), given back at release.
            let braking = w
                .cons_pair
                .iter()
                .any(|&p| matches!(w.modes[p], PairMode::Brake { .. }));
            if braking && pb.contact.restores_stopping_impulse() {
                w.rhs_stop.copy_from_slice(&w.rhs);
                w.cons_stop.clear();
                for (c, &p) in w.cons.iter().zip(&w.cons_pair) {
                    let mut c = *c;
                    if let PairMode::Brake { w: wn, .. } = w.modes[p] {
                        c.rhs = wn;
                    }
                    w.cons_stop.push(c);
                }
                self.stepper
                    .solve(&mut w.rhs_stop, &w.cons_stop, &mut w.lambda_stop);
            }
            self.stepper.solve(&mut w.rhs, &w.cons, &mut w.lambda);
            ts.v.copy_from_slice(&w.rhs);
            self.stepper
                .update_displacement(bt, &fs.u, &fs.v, &ts.v, &mut ts.u);
            ts.t = t1;
            ts.k = fs.k + 1;
            // Tension: release (Table 1, item 7).
            let mut changed = false;
            for (i, &p) in w.cons_pair.iter().enumerate() {
                if w.modes[p] == PairMode::Hold && w.lambda[i] < 0.0 {
                    w.modes[p] = PairMode::Free;
                    w.released[p] = true;
                    let bf = fs.pairs[p].brake_force;
                    if pb.contact.restores() && (bf[0] != 0.0 || bf[1] != 0.0) {
                        w.restore[p] = Some(bf);
                    }
                    changed = true;
                    self.stats.releases += 1;
                }
            }
            if changed {
                self.stats.resolves += 1;
                continue;
            }
            // Penetration of free pairs at t1.
            w.pen.clear();
            for p in 0..np {
                if w.modes[p] != PairMode::Free {
                    continue;
                }
                let pair = pb.pairs[p];
                let x1 = Self::node_pos(pb, ts, pair.node);
                let g = pb.obstacles[pair.obstacle].half_space(t1, x1).gap(x1);
                if g < -pb.gap_tol {
                    if w.released[p] {
                        // Released in this very step and penetrating again: hold it.
                        w.modes[p] = PairMode::Hold;
                        w.restore[p] = None;
                        changed = true;
                    } else {
                        w.pen.push(p);
                    }
                }
            }
            if changed {
                self.stats.resolves += 1;
                continue;
            }
            break;
        }
        // Record the pairs' states at t1 and their modes for the next step.
        for p in 0..np {
            let prev = fs.pairs[p];
            let i = w.cons_pair.iter().position(|&q| q == p);
            let lam = i.map(|i| w.lambda[i]).unwrap_or(0.0);
            let pair = pb.pairs[p];
            let x1 = Self::node_pos(pb, ts, pair.node);
            let gap = pb.obstacles[pair.obstacle].half_space(t1, x1).gap(x1);
            let mut st = PairState {
                mode: w.modes[p],
                restore: None,
                brake_force: prev.brake_force,
                force: lam / h,
                held: false,
                braked: false,
                released: w.released[p],
                gap,
            };
            match w.modes[p] {
                PairMode::Brake { normal, .. } => {
                    st.braked = true;
                    let ls = match i {
                        Some(i) if pb.contact.restores_stopping_impulse() => w.lambda_stop[i],
                        _ => lam,
                    };
                    st.brake_force = [ls / h * normal[0], ls / h * normal[1]];
                    st.mode = PairMode::Hold;
                }
                PairMode::Hold => st.held = true,
                PairMode::Free => {
                    if w.released[p] {
                        st.brake_force = [0.0; 2];
                    }
                }
            }
            ts.pairs[p] = st;
        }
        w.pen.len()
    }
}
