//! What a simulation is set up from: the [`Problem`] (model, integrator, contact), the
//! [`Settings`] every run gives it, the integrator's construction and the errors.

use super::*;

/// Everything the driver needs: the model, the integrator and the contact treatment,
/// supports, loads, obstacles, contact pairs and the initial state.
pub struct Problem {
    /// Spatial dimension (1, 2 or 3).
    pub dim: usize,
    /// Reference positions of the nodes, flat (`dim` per node), m.
    pub reference: Vec<f64>,
    /// The semi-discrete model.
    pub model: LinearModel,
    /// The integrator and its parameters.
    pub integrator: Integrator,
    /// Time step, s.
    pub h: f64,
    /// Space-time scheme: `gamma` from given instants on, `(t_from, gamma)` sorted by time.
    pub gamma_schedule: Vec<(f64, f64)>,
    /// Prescribed velocities `(dof, value m/s)`.
    pub dirichlet: Vec<(usize, f64)>,
    /// External load.
    pub load: LoadFn,
    /// Rigid obstacles.
    pub obstacles: Vec<Box<dyn Obstacle>>,
    /// Contact interfaces between bodies, searched at the start of every step
    /// ([`crate::contact::interface`]; their pairs are [`Pair::Searched`]).
    pub interfaces: Vec<Interface>,
    /// Contact pairs.
    pub pairs: Vec<Pair>,
    /// Contact treatment.
    pub treatment: Treatment,
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
    /// The friction law of every pair (scenario keys `contact.friction`,
    /// `contact.friction_kinetic`, `contact.friction_velocity`; `Some(mu.into())`: Coulomb);
    /// `None` or a zero law: frictionless, exactly the rows without friction. Needs a 2D or
    /// 3D model and a treatment that carries it ([`Treatment::check_friction`]).
    pub friction: Option<FrictionLaw>,
}

impl std::fmt::Debug for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Problem")
            .field("dim", &self.dim)
            .field("dofs", &self.model.n())
            .field("integrator", &self.integrator)
            .field("treatment", &self.treatment)
            .field("h", &self.h)
            .field("pairs", &self.pairs.len())
            .field("steps", &self.steps)
            .finish()
    }
}

/// Errors of a run.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The system matrix could not be factored.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// The classic integrator could not be set up.
    #[error(transparent)]
    Classic(#[from] ClassicError),
    /// A combination that does not exist.
    #[error("{0}")]
    Unsupported(String),
    /// The observer failed (writing output).
    #[error("writing results failed: {0}")]
    Output(#[from] std::io::Error),
    /// A contact interface between bodies lost a node's target.
    #[error(transparent)]
    Interface(#[from] InterfaceError),
    /// The energy grew beyond what the work done on the system explains ([`crate::guard`]).
    #[error(transparent)]
    Diverged(#[from] Diverged),
    /// The solution blew up.
    #[error("the solution is not finite at step {step} (t = {t:e} s): the time step is beyond the stability limit of the integrator (with a penalty: of the penalty spring) or the model is ill-posed")]
    NotFinite {
        /// Step.
        step: usize,
        /// Time, s.
        t: f64,
    },
}

impl From<ContactError> for SimError {
    fn from(e: ContactError) -> Self {
        match e {
            ContactError::Linalg(l) => SimError::Linalg(l),
            ContactError::Interface(i) => SimError::Interface(i),
        }
    }
}

impl From<BuildError> for SimError {
    fn from(e: BuildError) -> Self {
        match e {
            BuildError::Linalg(l) => SimError::Linalg(l),
            BuildError::Classic(c) => SimError::Classic(c),
        }
    }
}

/// Builds the integrator of `choice` on `model` with the step `h`, the `gamma` schedule of
/// the space-time scheme and the prescribed velocities.
///
/// # Errors
/// [`BuildError`] when a matrix is singular or a parameter is invalid.
pub fn build_integrator(
    choice: Integrator,
    model: &LinearModel,
    h: f64,
    gamma_schedule: Vec<(f64, f64)>,
    dirichlet: &[(usize, f64)],
) -> Result<Box<dyn TimeIntegrator>, BuildError> {
    build_integrator_on(
        choice,
        model,
        h,
        gamma_schedule,
        dirichlet,
        Backend::Softway,
    )
}

/// [`build_integrator`] with the step matrix factored by `backend`'s factorizations.
///
/// # Errors
/// As [`build_integrator`].
pub fn build_integrator_on(
    choice: Integrator,
    model: &LinearModel,
    h: f64,
    gamma_schedule: Vec<(f64, f64)>,
    dirichlet: &[(usize, f64)],
    backend: Backend,
) -> Result<Box<dyn TimeIntegrator>, BuildError> {
    Ok(match choice {
        Integrator::SpaceTime {
            alpha,
            gamma,
            coriolis,
        } => Box::new(
            Stepper::with_options(
                model,
                SpaceTimeParams { alpha, gamma, h },
                dirichlet,
                FactorChoice::On(backend),
                coriolis,
            )?
            .with_schedule(gamma_schedule),
        ),
        Integrator::Classic { params, .. } => {
            let bcs: Vec<Dirichlet> = dirichlet
                .iter()
                .map(|&(dof, value)| Dirichlet {
                    dof,
                    kind: Kinematic::Velocity,
                    value,
                })
                .collect();
            Box::new(ClassicStepper::with_backend(
                model, params, h, &bcs, backend,
            )?)
        }
    })
}

/// What every run gives its simulation, whatever its kind (the one set-up,
/// [`Simulation::with_settings`]): its threads and what its divergence guard does. A run's
/// options give them ([`crate::run::RunOptions::settings`]), so that no kind can leave one
/// out (before this set-up, the wheel ignored a recording guard and the moving-load track
/// its threads).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Settings {
    /// The threads of the run's two-part work ([`Simulation::set_par`]).
    pub par: Par,
    /// What the divergence guard does past its bound ([`Simulation::set_guard`]).
    pub guard: GuardMode,
    /// Whose factorizations and solves the step matrix gets (softway's by default; faer's,
    /// the reference, with `--solver faer`).
    pub solver: Backend,
}

impl Default for Settings {
    /// The caller's pool ([`Par::current`]) and a guard that stops the run.
    fn default() -> Self {
        Settings {
            par: Par::current(),
            guard: GuardMode::default(),
            solver: Backend::Softway,
        }
    }
}

/// The contact's options of a built simulation (how its columns and predictions are made).
impl Simulation {
    /// Whether a prediction is made again from a known one of the same start, without a
    /// solve, when the contact's cached columns allow it (the default; [`Context::predict`]),
    /// or solved each time (the reference the same results to round-off are checked against).
    pub fn set_predictions_again(&mut self, on: bool) {
        self.engine.scratch.set_predictions_again(on);
    }

    /// Keeps a ring rail's seam ahead of the patch ([`super::RingShift`]).
    ///
    /// # Errors
    /// [`SimError::Unsupported`] unless the sources are a permutation of the model's nodes,
    /// the shift's pitch, speed and limit make sense, the model is linear (a nonlinear
    /// force's state is not relabelled here) and an interface's master frame translates.
    pub fn set_ring_shift(&mut self, spec: super::RingShift) -> Result<(), SimError> {
        let eng = &mut self.engine;
        let nodes = eng.reference.len() / eng.dim.max(1);
        let ok = spec.sources.len() == nodes
            && eng.nonlinear.is_none()
            && !eng.interfaces.is_empty()
            && eng
                .interfaces
                .iter_mut()
                .all(|i| i.shift_master_frame([0.0; 3]));
        let shifting = ok
            .then(|| super::ring::Shifting::new(spec, eng.dim))
            .flatten()
            .ok_or_else(|| {
                SimError::Unsupported(
                    "a ring's shift needs a source for every node (a permutation), a linear model, a limit past its start and a contact interface whose master frame translates".into(),
                )
            })?;
        self.ring = Some(shifting);
        Ok(())
    }

    /// Turns the contact's new columns from one sector's instead of solving them: the
    /// model repeats round its axle as `sym` says ([`crate::contact::cyclic`]). The claim is
    /// checked once: the column of a contact dof off the base sector, turned, against the
    /// same column solved (`dim + 1` solves, whose base columns are kept).
    ///
    /// # Errors
    /// [`SimError::Unsupported`] when `sym` is not on the model's dofs, covers nodes a
    /// moving refined zone relabels (its relabelling is another map of the nodes), or when
    /// the turned column differs from the solved one by more than `1e-9` of its largest
    /// entry: the model does not have the symmetry.
    pub fn set_cyclic_symmetry(&mut self, sym: CyclicSymmetry) -> Result<(), SimError> {
        // The check's node: a contact node off the base sector (else any node in copy 1).
        let node = self
            .engine
            .pairs
            .iter()
            .flat_map(|p| {
                let (nodes, len) = p.nodes();
                nodes.into_iter().take(len)
            })
            .find(|&m| sym.covers(sym.dim() * m) && sym.locate(sym.dim() * m).1 != 0)
            .unwrap_or_else(|| sym.dof(0, 1, 0) / sym.dim());
        self.set_cyclic_symmetry_at(sym, node)
    }

    /// [`Self::set_cyclic_symmetry`], its claim checked on the column of `node`'s first
    /// dof (a node the symmetry covers, off its base copy, and free: a node the contact
    /// meets, where the columns will be taken).
    ///
    /// # Errors
    /// As [`Self::set_cyclic_symmetry`], and when `node` is not covered or in the base copy.
    pub fn set_cyclic_symmetry_at(
        &mut self,
        sym: CyclicSymmetry,
        node: usize,
    ) -> Result<(), SimError> {
        let eng = &mut self.engine;
        let n = eng.model.n();
        if sym.dofs() != n || sym.dim() != eng.dim {
            return Err(SimError::Unsupported(format!(
                "a cyclic symmetry of {} dofs ({} per node) on a model of {n} ({} per node)",
                sym.dofs(),
                sym.dim(),
                eng.dim
            )));
        }
        if let Some(rel) = &self.relocation {
            // The zone relabels the nodes below `turned`; the symmetry may cover the others
            // (an elastic rail's, which keep their labels).
            if (0..rel.spec.turned).any(|m| sym.covers(sym.dim() * m)) {
                return Err(SimError::Unsupported(
                    "a cyclic symmetry of the nodes a moving refined zone relabels is not built"
                        .into(),
                ));
            }
        }
        let d = sym.dim() * node;
        if !sym.covers(d) || sym.locate(d).1 == 0 {
            return Err(SimError::Unsupported(format!(
                "the cyclic symmetry's check needs a node it covers off its base copy, not node {node}"
            )));
        }
        let cyc = CyclicColumns::checked(sym, &mut *eng.integ, d).map_err(SimError::Unsupported)?;
        eng.rows.set_cyclic(Some(cyc));
        Ok(())
    }
}
