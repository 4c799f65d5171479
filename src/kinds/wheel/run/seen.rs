//! What the wheel's observers read of a final step, copied out of the driver's ring so that
//! they can run behind the loop ([`crate::simulation::behind`]): one [`Seen`] slot per step
//! in flight, its vectors sized once.
//!
//! The state's vectors are copied only on the steps whose observers read them (the
//! energies' steps and the last full turn, which the turn average and the velocity
//! snapshots read), the pairs' states on the tables' steps (every step with friction); on
//! the other steps the observers see empty slices, so that an observer reading them there
//! fails loudly (an index out of bounds, a length mismatch) instead of reading a stale
//! step.

use super::observers::WheelStep;
use crate::linalg::team::Team;
use crate::model::PairState;

/// One final step as the observers read it ([`WheelStep`]'s fields, owned).
#[derive(Debug, Clone)]
pub(super) struct Seen {
    pub k: usize,
    pub t: f64,
    pub u: Vec<f64>,
    pub v: Vec<f64>,
    /// The energies when computed on the stepping thread (a plastic wheel).
    pub energy: Option<(f64, f64)>,
    /// The step's energies are reported (computed behind the loop unless `energy` holds
    /// them).
    pub want_energy: bool,
    /// `u` and `v` were copied (else the observers see empty slices: module docs).
    pub fields: bool,
    /// `pairs` were copied (else empty).
    pub with_pairs: bool,
    pub penalty: f64,
    pub contact_force: f64,
    pub held: usize,
    pub min_gap: f64,
    pub pairs: Vec<PairState>,
    pub slip_power: f64,
    pub friction_dissipated: f64,
    pub frame_angle: f64,
}

impl Seen {
    /// A slot for `n` dofs and `pairs` contact pairs.
    pub fn new(n: usize, pairs: usize) -> Self {
        Self {
            k: 0,
            t: 0.0,
            u: vec![0.0; n],
            v: vec![0.0; n],
            energy: None,
            want_energy: false,
            fields: false,
            with_pairs: false,
            penalty: 0.0,
            contact_force: 0.0,
            held: 0,
            min_gap: 0.0,
            pairs: Vec::with_capacity(pairs),
            slip_power: 0.0,
            friction_dissipated: 0.0,
            frame_angle: 0.0,
        }
    }

    /// The observers' view of the step, with its `energy` and the `team` of the thread
    /// that observes it (none behind the loop).
    pub fn step<'a>(&'a self, energy: Option<(f64, f64)>, team: Option<&'a Team>) -> WheelStep<'a> {
        WheelStep {
            k: self.k,
            t: self.t,
            u: if self.fields { &self.u } else { &[] },
            v: if self.fields { &self.v } else { &[] },
            energy,
            penalty: self.penalty,
            contact_force: self.contact_force,
            held: self.held,
            min_gap: self.min_gap,
            pairs: if self.with_pairs { &self.pairs } else { &[] },
            slip_power: self.slip_power,
            friction_dissipated: self.friction_dissipated,
            frame_angle: self.frame_angle,
            team,
        }
    }
}

/// Steps handed to the observers' thread at once (a batch: one hand-off, one wake).
#[derive(Debug)]
pub(super) struct Batch {
    pub items: Vec<Seen>,
    /// Steps filled.
    pub len: usize,
}

/// The batches in flight for `n` dofs and `pairs` pairs: steps of up to [`BATCH_BYTES`] a
/// batch (1 to 32), batches of up to [`SEEN_BYTES`] in all (3 to 16).
pub(super) fn batches(n: usize, pairs: usize) -> Vec<Batch> {
    let bytes = 16 * n + pairs * std::mem::size_of::<PairState>() + 256;
    let steps = (BATCH_BYTES / bytes).clamp(1, 32);
    let count = (SEEN_BYTES / (steps * bytes)).clamp(3, 16);
    (0..count)
        .map(|_| Batch {
            items: (0..steps).map(|_| Seen::new(n, pairs)).collect(),
            len: 0,
        })
        .collect()
}

/// The memory of one batch, bytes.
const BATCH_BYTES: usize = 256 << 10;

/// The memory the batches in flight may take, bytes.
const SEEN_BYTES: usize = 8 << 20;
