//! The driver: one step loop for every integrator and every contact treatment.
//!
//! A [`Problem`] names the model, the integrator ([`Integrator`]: the space-time scheme or
//! a member of the generalized-alpha family), the contact treatment ([`Treatment`]: the
//! soft way and its variants, exact enforcement, penalty, mass redistribution, Moreau-Jean,
//! the paper's subdivision), the obstacles and the contact pairs (node against obstacle,
//! node against node). [`Simulation::new`] builds the integrator through its contract
//! ([`TimeIntegrator`]) and the treatment through its own ([`ContactTreatment`]), allocates
//! all work memory, and [`Simulation::run`] steps.
//!
//! States are kept for `t_{k-2}`, `t_{k-1}` and `t_k` in three preallocated snapshots (the
//! ring): the soft way may step back and repeat the previous interval (Table 1, item 4). A
//! step is reported to the observer only when it can no longer be revised, so outputs never
//! hold a step that was undone.
//!
//! The [`Engine`] owns the integrator, the pairs and obstacles, the constraint rows and
//! their solution ([`RowSolver`]), the loads and the work vectors; for each step it lends the
//! treatment a [`Context`] (references into it, no allocation), the treatment's whole view
//! of the engine. The treatment's counters ([`Counts`]) and errors
//! ([`crate::contact::ContactError`]) are contact's own; the run reports them in [`RunStats`]
//! and [`SimError`]. The model, the load and the states ([`LinearModel`], [`LoadFn`],
//! [`State`], [`Snapshot`]) are in [`crate::model`] (re-exported here: `LoadFn`,
//! `Snapshot`).

use crate::contact::build as build_treatment;
use crate::contact::context::{ContactError, Context, Counts, Integ, Scratch};
use crate::contact::cyclic::{CyclicColumns, CyclicSymmetry};
use crate::contact::mass_redistribution::redistribute_mass;
use crate::contact::pair::Pair;
use crate::contact::rows::RowSolver;
use crate::contact::treatment::{ContactTreatment, Treatment};
use crate::contact::{FrictionLaw, Interface, InterfaceError, Obstacle};
use crate::guard::{Cause, Diverged, DivergenceGuard, GuardMode};
use crate::linalg::team::{Par, Team};
use crate::linalg::{quadratic_form, Backend, LinalgError};
use crate::mesh::zone::Source;
use crate::model::{InternalForce, LinearModel, Nonlinear, PairState, State};
pub use crate::model::{LoadFn, Snapshot};

pub mod behind;
mod relocation;
mod ring;
mod setup;
mod view;

use crate::time::choice::{BuildError, Integrator};
use crate::time::classic::{ClassicError, ClassicStepper, Dirichlet, Kinematic};
use crate::time::integrator::TimeIntegrator;
use crate::time::step::{FactorChoice, Stepper};
use crate::time::SpaceTimeParams;
use relocation::Relocating;
pub use relocation::Relocation;
pub use ring::RingShift;
pub use setup::{build_integrator, build_integrator_on, Problem, Settings, SimError};
use std::sync::atomic::{AtomicBool, Ordering};
pub use view::{RunStats, StepView};

/// What the driver owns and lends to the treatment as a [`Context`] each step (module docs).
pub struct Engine {
    /// Spatial dimension.
    pub dim: usize,
    /// Reference positions, m.
    pub reference: Vec<f64>,
    /// The integrator.
    pub integ: Box<dyn TimeIntegrator>,
    /// The run's step, s.
    pub h: f64,
    /// The model actually integrated (after any mass redistribution).
    pub model: LinearModel,
    /// External load.
    pub load: LoadFn,
    /// Obstacles.
    pub obstacles: Vec<Box<dyn Obstacle>>,
    /// Contact interfaces.
    pub interfaces: Vec<Interface>,
    /// Pairs.
    pub pairs: Vec<Pair>,
    /// Penetration tolerance, m.
    pub gap_tol: f64,
    /// The constraint rows and their solver.
    pub rows: RowSolver,
    /// Counters.
    pub stats: RunStats,
    /// The treatment's counters.
    counts: Counts,
    /// Nodal forces added to the load in the next prediction (the soft way's restore), N.
    extra: Vec<f64>,
    /// Predictors `U`, `V`.
    pred: State,
    /// The free solution `x_free`.
    xfree: Vec<f64>,
    /// `x` of the last solve.
    x: Vec<f64>,
    /// The context's scratch (load vector, the obstacles' half-spaces of one instant).
    scratch: Scratch,
    /// A nonlinear internal force and its iteration ([`Simulation::set_internal_force`]).
    nonlinear: Option<Nonlinear>,
}

impl std::fmt::Debug for Engine {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Engine")
            .field("dim", &self.dim)
            .field("integrator", &self.integ.name())
            .field("pairs", &self.pairs.len())
            .finish()
    }
}

impl Engine {
    /// The gap of pair `p` at time `t` in the configuration `u`, m.
    pub fn gap(&self, p: usize, t: f64, u: &[f64]) -> f64 {
        self.pairs[p].gap(
            &self.obstacles,
            &self.interfaces,
            self.dim,
            &self.reference,
            u,
            t,
        )
    }

    /// Searches every interface at time `t` in the configuration `u` and freezes the
    /// targets for the step that starts there ([`Interface::refresh`]).
    ///
    /// # Errors
    /// [`SimError::Contact`] when a node near a surface loses it.
    fn refresh_interfaces(&mut self, t: f64, u: &[f64]) -> Result<(), SimError> {
        for i in &mut self.interfaces {
            i.refresh(t, u)?;
        }
        Ok(())
    }

    /// The treatment's view of the engine for one step (references only).
    fn context(&mut self) -> Context<'_> {
        Context {
            dim: self.dim,
            reference: &self.reference,
            obstacles: &self.obstacles,
            interfaces: &self.interfaces,
            pairs: &self.pairs,
            model: &self.model,
            load: &self.load,
            integ: Integ::new(self.integ.as_mut()),
            rows: &mut self.rows,
            extra: &mut self.extra,
            pred: &mut self.pred,
            xfree: &mut self.xfree,
            x: &mut self.x,
            h: self.h,
            gap_tol: self.gap_tol,
            counts: &mut self.counts,
            scratch: &mut self.scratch,
            nonlinear: self.nonlinear.as_mut(),
        }
    }
}

/// The share of the machine's memory the columns kept for a moving zone may take
/// ([`Simulation::set_relocation`]); the cost estimate counts it
/// ([`crate::scenario::kind::Size::kept_columns`]).
pub const KEPT_COLUMNS_SHARE: f64 = 0.125;

/// The bytes the columns kept for a moving zone may take: [`KEPT_COLUMNS_SHARE`] of the
/// machine's memory.
pub fn kept_columns_bytes() -> f64 {
    KEPT_COLUMNS_SHARE * crate::linalg::bandwidth::memory_bytes_or_default()
}

/// The step loop over a [`Problem`].
pub struct Simulation {
    engine: Engine,
    treatment: Box<dyn ContactTreatment>,
    choice: Treatment,
    energy_stiffness: Option<Vec<f64>>,
    steps: usize,
    snaps: [Snapshot; 3],
    massless: Vec<usize>,
    relocation: Option<Relocating>,
    ring: Option<ring::Shifting>,
    /// The threads of the run's two-part work ([`Simulation::set_par`]).
    team: Team,
    /// The divergence guard ([`crate::guard`]).
    guard: DivergenceGuard,
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("engine", &self.engine)
            .field("treatment", &self.treatment.name())
            .finish()
    }
}

impl Simulation {
    /// [`Simulation::new`] with a run's [`Settings`] applied: the one set-up every kind's
    /// run goes through.
    ///
    /// # Errors
    /// As [`Simulation::new`].
    pub fn with_settings(problem: Problem, settings: Settings) -> Result<Self, SimError> {
        let mut sim = Self::build(problem, settings.solver)?;
        sim.set_par(settings.par);
        sim.set_guard(settings.guard);
        Ok(sim)
    }

    /// Checks the combination, lets the treatment adjust the model (mass redistribution),
    /// builds and factors the integrator, completes the initial state and allocates all work
    /// memory.
    ///
    /// # Errors
    /// [`SimError::Unsupported`] for a combination that does not exist; [`SimError`] when a
    /// matrix is singular.
    pub fn new(problem: Problem) -> Result<Self, SimError> {
        Self::build(problem, Backend::Softway)
    }

    /// [`Simulation::new`] with the step matrix factored by `solver`'s factorizations.
    fn build(problem: Problem, solver: Backend) -> Result<Self, SimError> {
        let Problem {
            dim,
            reference,
            mut model,
            integrator,
            h,
            gamma_schedule,
            dirichlet,
            load,
            obstacles,
            interfaces,
            pairs,
            treatment,
            u0,
            v0,
            t0,
            steps,
            gap_tol,
            energy_stiffness,
            friction,
        } = problem;
        treatment
            .check(&integrator)
            .map_err(SimError::Unsupported)?;
        treatment
            .check_friction(friction, dim)
            .map_err(SimError::Unsupported)?;
        let friction = friction.filter(FrictionLaw::is_active);
        let n = model.n();
        let np = pairs.len();
        let n_obstacles = obstacles.len();
        let mut contact_nodes: Vec<usize> = pairs
            .iter()
            .flat_map(|p| {
                let (nodes, len) = p.nodes();
                nodes.into_iter().take(len)
            })
            .collect();
        for i in &interfaces {
            contact_nodes.extend(i.master_dofs().iter().map(|&d| d / dim));
        }
        contact_nodes.sort_unstable();
        contact_nodes.dedup();
        // Mass redistribution: the contact nodes massless before the integrator is built.
        let massless = if treatment.massless_contact() {
            redistribute_mass(&mut model, dim, &contact_nodes)
        } else {
            Vec::new()
        };
        let treat = build_treatment(treatment, &integrator, np, n, friction);
        let integ = build_integrator_on(integrator, &model, h, gamma_schedule, &dirichlet, solver)?;
        // The column cache may hold every contact dof (the reference of the complementarity
        // treatments' candidate search poses one row per pair, and needs them all in one
        // solve) when that fits in 1 GiB, else 256 of them; it grows only as far as the
        // rows of one solve need ([`RowSolver`]).
        let contact_dofs = contact_nodes.len() * dim;
        // Every contact dof's column when they fit in 1 GiB, else as many as fit (at least
        // 256); a patch that needs more at once grows the cache past it (`contact::rows`).
        let cache = if contact_dofs * n * 8 <= 1 << 30 {
            contact_dofs
        } else {
            ((1usize << 30) / (8 * n.max(1))).max(256).min(contact_dofs)
        };
        let mut state = State::zeros(n);
        state.u.copy_from_slice(&u0);
        state.v.copy_from_slice(&v0);
        let mut engine = Engine {
            dim,
            reference,
            integ,
            h,
            model,
            load,
            obstacles,
            interfaces,
            pairs,
            gap_tol,
            rows: RowSolver::new(
                n,
                np * if friction.is_some() { dim.max(2) } else { 1 },
                cache,
            ),
            extra: vec![0.0; n],
            pred: State::zeros(n),
            xfree: vec![0.0; n],
            x: vec![0.0; n],
            stats: RunStats::default(),
            counts: Counts::default(),
            scratch: Scratch::new(n, n_obstacles),
            nonlinear: None,
        };
        // The bodies numbered in turn (a wheel and its rail or twin): each contact column
        // is added on its own body's dofs.
        engine
            .rows
            .set_blocks(crate::linalg::diagonal_blocks(engine.model.pattern()));
        if !integrator.is_space_time() {
            for &(d, _) in &dirichlet {
                state.v[d] = 0.0;
            }
            engine
                .integ
                .initialize(t0, &mut state, &engine.load, &massless)?;
        }
        let mut snap = Snapshot {
            k: 0,
            t: t0,
            state,
            pairs: vec![PairState::default(); np],
        };
        engine.refresh_interfaces(t0, &snap.state.u)?;
        for p in 0..np {
            snap.pairs[p].gap = engine.gap(p, t0, &snap.state.u);
        }
        let n_guard = snap.state.u.len();
        Ok(Self {
            engine,
            treatment: treat,
            choice: treatment,
            energy_stiffness,
            steps,
            snaps: [snap.clone(), snap.clone(), snap],
            massless,
            relocation: None,
            ring: None,
            team: Team::default(),
            guard: DivergenceGuard::new(n_guard),
        })
    }

    /// Moves a refined zone with the obstacle ([`Relocation`]).
    ///
    /// # Errors
    /// [`SimError::Unsupported`] unless the model is 2D or 3D with one node per pair, the sources
    /// cover its nodes, every obstacle can turn with the frame, and an internal force's
    /// state is nodal ([`crate::model::InternalForce::nodal_state`]: the large-deformation
    /// body's is, relabelled with the nodes; a plastic body's is not).
    pub fn set_relocation(&mut self, spec: Relocation) -> Result<(), SimError> {
        let eng = &mut self.engine;
        let nodes = eng.reference.len() / eng.dim.max(1);
        if !(eng.dim == 2 || eng.dim == 3)
            || spec.sources.len() != nodes
            || spec.omega.is_nan()
            || spec.omega <= 0.0
        {
            return Err(SimError::Unsupported(
                "a moving refined zone needs a 2D or 3D model, a source for every node and a turning obstacle".into(),
            ));
        }
        if eng
            .nonlinear
            .as_ref()
            .is_some_and(|nl| nl.force().nodal_state().is_none())
        {
            return Err(SimError::Unsupported(
                "a plastic body in a moving refined zone is not built (the zone's relabelling carries nodal states, not element states)".into(),
            ));
        }
        if !spec.other_body_kept(&mut eng.interfaces) {
            return Err(SimError::Unsupported(
                "a moving refined zone turns one body (and its twin) against its base, or against another body through an interface whose slave it is, the other body's nodes their own sources".into(),
            ));
        }
        if let Some(c) = eng.rows.cyclic() {
            let sym = c.symmetry();
            if (0..spec.turned.min(nodes)).any(|m| sym.covers(sym.dim() * m)) {
                return Err(SimError::Unsupported(
                    "a cyclic symmetry of the nodes a moving refined zone relabels is not built"
                        .into(),
                ));
            }
        }
        if !eng.obstacles.iter_mut().all(|o| o.turn_frame(0.0)) {
            return Err(SimError::Unsupported(
                "a moving refined zone needs obstacles that turn about the origin (the wheel's base)".into(),
            ));
        }
        let mut pair_of_node = vec![None; nodes];
        for (p, pair) in eng.pairs.iter().enumerate() {
            // A split pair goes with its normal row's node (its shadow's state is carried
            // by the sources of the twin's nodes).
            match (pair, pair.nodes()) {
                (_, (n, 1)) | (Pair::Split { .. }, (n, 2)) => pair_of_node[n[0]] = Some(p),
                _ => return Err(SimError::Unsupported(
                    "a moving refined zone carries node pairs and split pairs only (not segments)"
                        .into(),
                )),
            }
        }
        let mut node_map = vec![None; nodes];
        for (n, src) in spec.sources.iter().enumerate() {
            if let Source::Node(m) = *src {
                node_map[m] = Some(n);
            }
        }
        let pairs: Vec<Option<usize>> = eng
            .pairs
            .iter()
            .map(|pair| match spec.sources[pair.nodes().0[0]] {
                Source::Node(m) => pair_of_node[m],
                Source::Triangle { .. } => None,
            })
            .collect();
        // The pairs no pair takes its state from (left behind by the zone) and those that
        // start fresh (ahead of it): as many of each, a relabelling of the rim.
        let mut taken = vec![false; eng.pairs.len()];
        for q in pairs.iter().flatten() {
            taken[*q] = true;
        }
        let dropped = (0..taken.len()).filter(|&q| !taken[q]).collect();
        let fresh = (0..pairs.len()).filter(|&p| pairs[p].is_none()).collect();
        // The patch stays on the zone's nodes: keep their columns for the run. The band it
        // sweeps between two relocations holds more dofs than one patch (a well-resolved
        // patch's band, with a twin's dofs, may pass the 1 GiB of the cache's first bound),
        // and it comes back to them after each relocation: the kept columns may take up to
        // KEPT_COLUMNS_SHARE of the machine's memory.
        eng.rows.set_keep_columns(true);
        let n = eng.model.n();
        eng.rows
            .raise_column_bound((kept_columns_bytes() / (8.0 * n.max(1) as f64)) as usize);
        let (c, s) = (spec.step.cos(), spec.step.sin());
        self.relocation = Some(Relocating {
            dropped,
            fresh,
            done: 0,
            pairs,
            node_map,
            dim: eng.dim,
            rot: [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]],
            scratch: vec![0.0; eng.dim * nodes],
            pair_scratch: vec![PairState::default(); eng.pairs.len()],
            spec,
        });
        Ok(())
    }

    /// Adds a nonlinear internal force `K u - f_nl(u; s)` (a plastic body:
    /// [`crate::plasticity::PlasticBody`]), solved on the elastic factor by the
    /// initial-stress iteration of [`crate::model::internal`] to the relative tolerance
    /// `tol` with at most `max_iterations` corrections a solve. Its states travel with the
    /// snapshots (a step back restores them).
    ///
    /// # Errors
    /// [`SimError::Unsupported`] with a moving refined zone when the force's state is not
    /// nodal (its relabelling does not carry element states), the subdivision (its sub-steps do not start at snapshots), a
    /// tolerance that is not positive, or a force on another number of dofs.
    pub fn set_internal_force(
        &mut self,
        force: Box<dyn InternalForce>,
        tol: f64,
        max_iterations: usize,
    ) -> Result<(), SimError> {
        if self.relocation.is_some() && force.nodal_state().is_none() {
            return Err(SimError::Unsupported(
                "a plastic body in a moving refined zone is not built (the zone's relabelling carries nodal states, not element states)".into(),
            ));
        }
        if matches!(self.choice, Treatment::Subdivision) {
            return Err(SimError::Unsupported(
                "a plastic body with the subdivision treatment is not built (its sub-steps do not start at the snapshots that carry the plastic state)".into(),
            ));
        }
        if !(tol > 0.0 && tol.is_finite()) {
            return Err(SimError::Unsupported(format!(
                "the plastic iteration's tolerance must be positive and finite, not {tol}"
            )));
        }
        let n = self.engine.model.n();
        self.engine.nonlinear = Some(Nonlinear::new(
            force,
            n,
            self.snaps[1].t,
            tol,
            max_iterations,
        ));
        Ok(())
    }

    /// Starts the nonlinear internal force from the state `s` instead of zero (a plastic
    /// body carried over from a previous run); call after [`Simulation::set_internal_force`]
    /// and before [`Simulation::run`]. The initial displacement must be in equilibrium with
    /// it (the residual displacement of its pseudo-load added to the problem's `u0`).
    ///
    /// # Errors
    /// [`SimError::Unsupported`] without an internal force, or for a state of another length.
    pub fn set_internal_state(&mut self, s: &[f64]) -> Result<(), SimError> {
        let Some(nl) = self.engine.nonlinear.as_mut() else {
            return Err(SimError::Unsupported(
                "an internal state without an internal force (set_internal_force first)".into(),
            ));
        };
        let m = nl.force().state_len();
        if s.len() != m {
            return Err(SimError::Unsupported(format!(
                "the internal state has {} numbers, the internal force {m}",
                s.len()
            )));
        }
        nl.set_states(s);
        Ok(())
    }

    /// The matrices of the energies a step reports ([`StepView::energies`]): the model's
    /// pattern, its `M` and the energy stiffness; `None` with a nonlinear internal force,
    /// whose state corrects the strain energy.
    pub fn energy_matrices(&self) -> Option<(&crate::linalg::Pattern, &[f64], &[f64])> {
        if self.engine.nonlinear.is_some() {
            return None;
        }
        let m = &self.engine.model;
        let k = self.energy_stiffness.as_deref().unwrap_or(&m.k);
        Some((m.pattern(), &m.m, k))
    }

    /// The nonlinear internal force's iteration, when set ([`Simulation::set_internal_force`];
    /// after [`Simulation::run`], its slot 1 holds the state of the last step).
    pub fn nonlinear(&self) -> Option<&Nonlinear> {
        self.engine.nonlinear.as_ref()
    }

    /// The time the run's predictions solved took, s ([`crate::contact::context::Scratch::prediction_seconds`]):
    /// over [`RunStats::predictions`], the mean free step as the loop ran it.
    pub fn prediction_seconds(&self) -> f64 {
        self.engine.scratch.prediction_seconds()
    }

    /// The newest state: after [`Simulation::run`], the last step's.
    pub fn last_state(&self) -> &State {
        &self.snaps[1].state
    }

    /// The newest snapshot (state and pairs): after [`Simulation::run`], the last step's.
    pub fn last_snapshot(&self) -> &Snapshot {
        &self.snaps[1]
    }

    /// The engine (integrator, pairs, model).
    pub fn engine(&self) -> &Engine {
        &self.engine
    }

    /// The dofs made massless by mass redistribution.
    pub fn massless_dofs(&self) -> &[usize] {
        &self.massless
    }

    /// Poses contact rows for the candidate pairs only (`true`, the default) or for every
    /// pair at every step (`false`, the reference: [`crate::contact::complementarity`]).
    pub fn set_candidate_search(&mut self, on: bool) {
        self.treatment.set_candidate_search(on);
    }

    /// The constraint rows' solver (its column cache: [`RowSolver::cached_columns`]).
    pub fn rows(&self) -> &RowSolver {
        &self.engine.rows
    }

    /// What the divergence guard does past its bound ([`crate::guard`]; default: stop the
    /// run with [`SimError::Diverged`]).
    pub fn set_guard(&mut self, mode: GuardMode) {
        self.guard.set_mode(mode);
    }

    /// Runs the parallel work of the steps (the split factor's sweeps and the contact rows'
    /// columns in two parts, the energies' two forms, the right-hand side in as many parts
    /// as threads) on `par`'s threads: a [`Team`] of the run's own, whose helper threads
    /// (`n - 1` with `Par::Threads(n)`) end with the simulation. Until
    /// called, that work goes through `rayon::join` in the caller's pool. The results are
    /// the same bits for every `par`. Below `SPLIT_MIN_ORDER` dofs nothing is split, and
    /// no helper thread is started.
    pub fn set_par(&mut self, par: Par) {
        let split = self.engine.model.n() >= crate::linalg::SPLIT_MIN_ORDER;
        self.team = Team::new(if split { par } else { Par::Seq });
        self.engine.integ.set_team(&self.team);
        self.engine.rows.set_team(&self.team);
    }

    /// The treatment's name.
    pub fn treatment_name(&self) -> String {
        self.choice.name()
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
        for _ in 0..self.steps {
            if interrupt.load(Ordering::Relaxed) {
                self.engine.stats.interrupted = true;
                break;
            }
            let s1 = &self.snaps[1];
            self.engine.refresh_interfaces(s1.t, &s1.state.u)?;
            let mut ctx = self.engine.context();
            self.treatment
                .advance(&mut ctx, &mut self.snaps, have_prev)?;
            let k = self.snaps[2].k;
            if !self.snaps[2].v.iter().all(|x| x.is_finite()) {
                return Err(SimError::NotFinite {
                    step: k,
                    t: self.snaps[2].t,
                });
            }
            if let Some(nl) = self.engine.nonlinear.as_ref() {
                if nl.stats().unconverged > 0 {
                    return Err(SimError::Diverged(Diverged {
                        step: k,
                        t: self.snaps[2].t,
                        cause: Cause::Unconverged {
                            iterations: nl.max_iterations(),
                        },
                    }));
                }
            }
            self.guard_step(have_prev, false)?;
            self.emit(1, false, &mut observer)?;
            if let Some(rel) = self.relocation.as_mut() {
                let eng = &mut self.engine;
                if rel.relocate_if_due(
                    &mut self.snaps,
                    eng.nonlinear.as_mut(),
                    &mut eng.obstacles,
                    &mut eng.interfaces,
                ) {
                    eng.stats.relocations += 1;
                }
            }
            if let Some(r) = self.ring.as_mut() {
                self.engine.stats.ring_shifts +=
                    r.shift_if_due(&mut self.snaps, &mut self.engine.interfaces);
            }
            self.snaps.rotate_left(1);
            if let Some(nl) = self.engine.nonlinear.as_mut() {
                nl.rotate();
            }
            have_prev = true;
            self.engine.stats.steps += 1;
        }
        self.guard_step(have_prev, true)?;
        self.emit(1, true, &mut observer)?;
        let mut stats = self.engine.stats;
        let counts = self.engine.counts;
        stats.step_backs = counts.step_backs;
        stats.resolves = counts.resolves;
        stats.brakings = counts.brakings;
        stats.entries = counts.entries;
        stats.releases = counts.releases;
        stats.predictions = counts.predictions;
        stats.predictions_again = counts.predictions_again;
        let factors = self.engine.integ.counts();
        stats.factorizations = factors.numeric;
        stats.symbolic_analyses = factors.symbolic;
        stats.stick_slip_changes = self.engine.rows.stick_slip_changes();
        stats.column_solves = self.engine.rows.column_solves();
        stats.columns_turned = self.engine.rows.columns_turned();
        stats.base_columns = self.engine.rows.cyclic().map_or(0, |c| c.held());
        stats.dense_solves = self.engine.rows.dense_solves();
        stats.capped_row_solves = self.engine.rows.capped_solves();
        stats.diverged_at_s = self.guard.first().map(|d| d.t);
        if let Some(nl) = &self.engine.nonlinear {
            let ns = nl.stats();
            stats.plastic_iterations = ns.iterations;
            stats.plastic_unconverged = ns.unconverged;
            stats.plastic_max_in_one_solve = ns.max_in_one_solve;
        }
        Ok(stats)
    }

    /// The energy of snapshot `i` (kinetic, strain on the energy stiffness, penalty, the
    /// nonlinear force's correction of the strain energy), J.
    fn energy(&self, i: usize) -> f64 {
        let s = &self.snaps[i];
        let m = &self.engine.model;
        let k = self.energy_stiffness.as_deref().unwrap_or(&m.k);
        let correction = self
            .engine
            .nonlinear
            .as_ref()
            .map_or(0.0, |nl| nl.energy_correction(i, &s.state.u));
        0.5 * quadratic_form(m.pattern(), &m.m, &s.state.v)
            + 0.5 * quadratic_form(m.pattern(), k, &s.state.u)
            + self.treatment.stored_energy(s)
            + correction
    }

    /// The divergence guard on the final step `snaps[1]` ([`crate::guard`]): its work bound
    /// since `snaps[0]` (when `have_prev`), and its energy every `CHECK_STRIDE` steps and at
    /// the `last`.
    fn guard_step(&mut self, have_prev: bool, last: bool) -> Result<(), SimError> {
        if !have_prev {
            let e0 = self.energy(1);
            self.guard.start(e0);
            return Ok(());
        }
        let e = &self.engine;
        let (s0, s1) = (&self.snaps[0], &self.snaps[1]);
        let (t, u) = (s1.t, &s1.state.u);
        let mut power = 0.0;
        let (mut push, mut pull) = (0.0, 0.0);
        for (p, ps) in e.pairs.iter().zip(&s1.pairs) {
            let (dim, r) = (e.dim, &e.reference);
            if ps.force > 0.0 {
                push += ps.force;
            } else {
                pull += ps.force;
            }
            if ps.force != 0.0 {
                let g = p.geometry(&e.obstacles, &e.interfaces, dim, r, u, t);
                power += (ps.force * g.w).abs();
            }
            for (k, f) in [ps.tangential_force, ps.tangential_force_2]
                .into_iter()
                .enumerate()
            {
                if f != 0.0 {
                    if let Some(g) = p.tangent(&e.obstacles, &e.interfaces, dim, r, u, t, k) {
                        power += (f * g.w).abs();
                    }
                }
            }
        }
        let h = s1.t - s0.t;
        self.guard.check_forces(s1.k, s1.t, push, pull)?;
        (e.load)(t, self.guard.load_mut());
        let due = self
            .guard
            .add_step(&s0.state.u, &s1.state.u, h.abs() * power);
        if due || last {
            let energy = self.energy(1);
            self.guard.check(s1.k, s1.t, energy)?;
        }
        Ok(())
    }

    fn emit<F>(&self, i: usize, last: bool, observer: &mut F) -> Result<(), std::io::Error>
    where
        F: FnMut(&StepView) -> Result<(), std::io::Error>,
    {
        let s = &self.snaps[i];
        let m = &self.engine.model;
        let k = self.energy_stiffness.as_deref().unwrap_or(&m.k);
        let contact_force = s.pairs.iter().map(|p| p.force).sum();
        let held = s.pairs.iter().filter(|p| p.held).count();
        let slip_power = s.pairs.iter().map(|p| p.slip_power).sum();
        let friction_dissipated = s.pairs.iter().map(|p| p.dissipated).sum();
        let frame_angle = self
            .relocation
            .as_ref()
            .map_or(0.0, |r| r.spec.step * r.done as f64);
        observer(&StepView {
            state: s,
            model: m,
            energy_stiffness: k,
            last,
            penalty: self.treatment.stored_energy(s),
            contact_force,
            held,
            slip_power,
            friction_dissipated,
            frame_angle,
            interfaces: &self.engine.interfaces,
            team: &self.team,
            internal: self.engine.nonlinear.as_ref().map(|nl| (nl, i)),
        })
    }
}
