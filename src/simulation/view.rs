//! What an observer sees of a final step ([`StepView`]) and a run's counters
//! ([`RunStats`]).

use crate::linalg::team::Team;
use crate::linalg::{quadratic_form, quadratic_forms};
use crate::model::{LinearModel, Nonlinear, Snapshot};

/// What an observer sees of a final step. The energies are computed when asked
/// ([`StepView::kinetic`], [`StepView::strain`]: one sparse quadratic form each), so an
/// observer that writes them every n-th step does not pay for them at every step.
#[derive(Debug)]
pub struct StepView<'a> {
    /// The state.
    pub state: &'a Snapshot,
    /// The model integrated (its `M`).
    pub model: &'a LinearModel,
    /// The stiffness of the reported strain energy.
    pub energy_stiffness: &'a [f64],
    /// True for the last step of the run (the one reported after the loop).
    pub last: bool,
    /// Energy stored in penalty springs, J.
    pub penalty: f64,
    /// Sum of the pairs' constraint forces (braking included), N.
    pub contact_force: f64,
    /// Pairs held on their obstacle (carrying a reaction).
    pub held: usize,
    /// Frictional dissipation of the step that ended here, summed over the pairs, W
    /// ([`crate::model::PairState::slip_power`]).
    pub slip_power: f64,
    /// Energy dissipated by friction since the start, summed over the pairs, J
    /// ([`crate::model::PairState::dissipated`]).
    pub friction_dissipated: f64,
    /// The angle the mesh's frame has turned by with a moving refined zone, rad (the
    /// relocations so far times their step, [`super::Relocation`]; 0 without a zone): the
    /// obstacles are turned back by it, so a direction `e(t)` of the base in the laboratory's
    /// wheel frame is `e(t)` turned by `-frame_angle` in the mesh's.
    pub frame_angle: f64,
    /// The contact interfaces, their targets those of the latest refresh (the newest step's
    /// start: the final step's own, or one step later when the treatment stepped back).
    pub interfaces: &'a [crate::contact::Interface],
    /// The run's threads ([`super::Simulation::set_par`]), for [`StepView::energies`].
    pub(super) team: &'a Team,
    /// The nonlinear internal force and the ring slot of this step's state, when set
    /// ([`StepView::internal_state`]).
    pub(super) internal: Option<(&'a Nonlinear, usize)>,
}

impl StepView<'_> {
    /// Kinetic energy `v^T M v / 2`, J.
    pub fn kinetic(&self) -> f64 {
        0.5 * quadratic_form(self.model.pattern(), &self.model.m, &self.state.v)
    }

    /// Strain energy `u^T K u / 2`, J (`K`: the energy stiffness of the problem), with a
    /// nonlinear internal force's correction (a plastic body: the elastic part of the
    /// strain only, [`crate::model::InternalForce::energy_correction`]).
    pub fn strain(&self) -> f64 {
        let correction = self
            .internal
            .map_or(0.0, |(nl, i)| nl.energy_correction(i, &self.state.u));
        0.5 * quadratic_form(self.model.pattern(), self.energy_stiffness, &self.state.u)
            + correction
    }

    /// The state of the nonlinear internal force at this step (a plastic body:
    /// [`crate::plasticity::STATE_LEN`] numbers per element), when there is one.
    pub fn internal_state(&self) -> Option<&[f64]> {
        self.internal.map(|(nl, i)| nl.state(i))
    }

    /// The run's threads (an observer whose work divides may use them).
    pub fn team(&self) -> &Team {
        self.team
    }

    /// `(kinetic, strain)`: from `ENERGIES_SIDE_BY_SIDE_MIN` dofs on, side by side on two
    /// threads (the run's [`Team`]), with the same values.
    pub fn energies(&self) -> (f64, f64) {
        if self.state.v.len() < ENERGIES_SIDE_BY_SIDE_MIN {
            // Both forms in one pass over the pattern, each with the bits of its own.
            let (mv, ku) = quadratic_forms(
                self.model.pattern(),
                (&self.model.m, &self.state.v),
                (self.energy_stiffness, &self.state.u),
            );
            let correction = self
                .internal
                .map_or(0.0, |(nl, i)| nl.energy_correction(i, &self.state.u));
            return (0.5 * mv, 0.5 * ku + correction);
        }
        let (mut kinetic, mut strain) = (0.0, 0.0);
        self.team
            .join(|| kinetic = self.kinetic(), || strain = self.strain());
        (kinetic, strain)
    }
}

/// The order from which [`StepView::energies`] runs its two quadratic forms on two threads:
/// that of the split factors.
const ENERGIES_SIDE_BY_SIDE_MIN: usize = crate::linalg::SPLIT_MIN_ORDER;

/// Counters of a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct RunStats {
    /// Steps taken.
    pub steps: usize,
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
    /// Stick/slip changes of friction rows, in all solves (each a dense re-solve of the
    /// active rows, no factorization; [`crate::contact::rows::RowSolver::stick_slip_changes`]).
    pub stick_slip_changes: usize,
    /// Columns `A^{-1} e_d` solved for the contact's rows ([`crate::contact::rows`]); not
    /// written when zero.
    #[serde(skip_serializing_if = "is_zero")]
    pub column_solves: usize,
    /// Columns turned from a cyclic symmetry's base sector instead of solved
    /// ([`super::Simulation::set_cyclic_symmetry`]); not written when zero.
    #[serde(skip_serializing_if = "is_zero")]
    pub columns_turned: usize,
    /// The base sector's (or station's) columns a cyclic symmetry holds, each solved once
    /// (those of the set-up's check among them), from which it turns the others; not
    /// written when zero.
    #[serde(skip_serializing_if = "is_zero")]
    pub base_columns: usize,
    /// Dense solves of the contact's active rows
    /// ([`crate::contact::rows::RowSolver::dense_solves`]); not written when zero.
    #[serde(skip_serializing_if = "is_zero")]
    pub dense_solves: usize,
    /// Solves of the contact's rows that stopped at their budget of changes or turns
    /// ([`crate::contact::rows::RowSolver::capped_solves`]); not written when zero.
    #[serde(skip_serializing_if = "is_zero")]
    pub capped_row_solves: usize,
    /// Predictions solved, each a read of the factor
    /// ([`crate::contact::context::Context::predict`]); not written when zero.
    #[serde(skip_serializing_if = "is_zero")]
    pub predictions: usize,
    /// Predictions made again from a known one without a solve (re-solves after a release,
    /// the interval repeated by a step back); not written when zero.
    #[serde(skip_serializing_if = "is_zero")]
    pub predictions_again: usize,
    /// Numeric factorizations of a system matrix.
    pub factorizations: usize,
    /// Symbolic analyses of a system matrix.
    pub symbolic_analyses: usize,
    /// Relocations of a moving refined zone ([`super::Relocation`]).
    pub relocations: usize,
    /// Shifts of a ring rail's labels by a station ([`super::RingShift`]); not written
    /// when zero.
    #[serde(skip_serializing_if = "is_zero")]
    pub ring_shifts: usize,
    /// True when the run stopped on an interrupt.
    pub interrupted: bool,
    /// Corrections of the plastic (nonlinear internal force) iteration over the run, each
    /// a prediction and a solve on the elastic factor ([`crate::model::internal`]); not
    /// written when zero.
    #[serde(skip_serializing_if = "is_zero")]
    pub plastic_iterations: usize,
    /// Solves whose plastic iteration stopped at its cap; not written when zero.
    #[serde(skip_serializing_if = "is_zero")]
    pub plastic_unconverged: usize,
    /// Most plastic corrections in one solve; not written when zero.
    #[serde(skip_serializing_if = "is_zero")]
    pub plastic_max_in_one_solve: usize,
    /// When the divergence guard found the energy past its bound, in
    /// [`crate::guard::GuardMode::Record`] (the run went on), s; not written when none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub diverged_at_s: Option<f64>,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}
