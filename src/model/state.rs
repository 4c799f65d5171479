//! States: `(u, v, a)` at one instant, and the state at the end of a step with the contact
//! pairs' states (the ring of the driver, [`crate::simulation`], holds three of them so that a
//! treatment may step back and repeat the previous interval: the pairs' modes travel with the
//! state, so stepping back restores them too).

use super::Terms;

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

/// The state at the end of a step, with the pairs' states.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Step index (0: the initial state).
    pub k: usize,
    /// Time, s.
    pub t: f64,
    /// `u`, `v`, `a`.
    pub state: State,
    /// Contact pairs.
    pub pairs: Vec<PairState>,
}

impl std::ops::Deref for Snapshot {
    type Target = State;
    fn deref(&self) -> &State {
        &self.state
    }
}

/// The constraint a contact pair gets in the next step.
// `Brake` carries a row of up to `MAX_TERMS` (15: a node against a 3D facet) terms; the
// mode stays `Copy`, one per pair.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PairMode {
    /// No constraint.
    Free,
    /// Braking: `c . v = q` at the end of the step (Eq. 26).
    Brake {
        /// Prescribed normal velocity, m/s.
        q: f64,
        /// The row `c` at the instant of arrival.
        terms: Terms,
        /// The boundary's normal velocity at the instant of arrival, m/s.
        w: f64,
    },
    /// Held on the obstacle: relative normal velocity zero at the end of the step, with a
    /// deadbeat correction of any gap drift ([`crate::contact::softway::holding_velocity`]).
    Hold,
}

impl PairMode {
    /// `*self = *src`, a braking row copied by its terms in use ([`Terms::assign`]).
    pub fn assign(&mut self, src: &PairMode) {
        match (&mut *self, src) {
            (
                PairMode::Brake { q, terms, w },
                PairMode::Brake {
                    q: q2,
                    terms: t2,
                    w: w2,
                },
            ) => {
                *q = *q2;
                terms.assign(t2);
                *w = *w2;
            }
            (_, PairMode::Free) => *self = PairMode::Free,
            (_, PairMode::Hold) => *self = PairMode::Hold,
            (_, PairMode::Brake { .. }) => *self = *src,
        }
    }
}

/// The state of one contact pair at the end of a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairState {
    /// The constraint for the next step.
    pub mode: PairMode,
    /// Force to add along `brake_row` in the next step (the arrival momentum given back), N.
    pub restore: Option<f64>,
    /// The force `R = lambda_s / h` (N, along `brake_row`) to give back at release, kept since
    /// the last braking ([`crate::contact::softway`], Release).
    pub brake_force: f64,
    /// The row of the last braking.
    pub brake_row: Terms,
    /// Constraint force of the step that ended here (N, positive when compressive), braking
    /// included.
    pub force: f64,
    /// Carrying a reaction (held on its obstacle) at the end of the step.
    pub held: bool,
    /// Braked in the step that ended here.
    pub braked: bool,
    /// Released in the step that ended here.
    pub released: bool,
    /// Gap at the end of the step, m (negative: penetration).
    pub gap: f64,
    /// Friction force of the step that ended here along the pair's tangent
    /// ([`crate::contact::Pair::tangent`]: the normal turned by +90 degrees), N; 0 without
    /// friction.
    pub tangential_force: f64,
    /// Friction force along the pair's second tangent (3D: `t2 = n x t1`,
    /// [`crate::contact::pair::tangent_basis`]), N; 0 in 2D and without friction.
    pub tangential_force_2: f64,
    /// Sliding (the friction force on the Coulomb bound) in the step that ended here.
    pub sliding: bool,
    /// Frictional dissipation in the step that ended here, W: `-F_t s_1` with `F_t` the
    /// tangential force and `s_1 = c_t.v1 - w_t` the slip rate at the step's end, the one
    /// the friction row holds (stick: `s_1 = 0`; slip: `F_t` opposes `s_1`), less the
    /// growth of an elastic stick's spring energy over `h`
    /// ([`crate::contact::treatment::record_friction`]). `>= 0` by construction of the
    /// discrete Coulomb law, but for the round-off residual `s_1` of a sticking pair.
    pub slip_power: f64,
    /// Energy dissipated by friction at this pair since the start, J (the sum of
    /// `slip_power h` over the final steps; it is part of the state, so a repeated step
    /// does not count twice).
    pub dissipated: f64,
    /// With a friction memory, the pair's coefficient at the end of the step, the bound of
    /// its next ([`crate::contact::FrictionLaw::memory`]), carried through steps out of
    /// contact; `None`: at rest (the static coefficient; a pair that never slid), or no
    /// memory.
    pub friction_coefficient: Option<f64>,
}

impl Default for PairState {
    fn default() -> Self {
        Self {
            mode: PairMode::Free,
            restore: None,
            brake_force: 0.0,
            brake_row: Terms::default(),
            force: 0.0,
            held: false,
            braked: false,
            released: false,
            gap: f64::INFINITY,
            tangential_force: 0.0,
            tangential_force_2: 0.0,
            sliding: false,
            slip_power: 0.0,
            dissipated: 0.0,
            friction_coefficient: None,
        }
    }
}
