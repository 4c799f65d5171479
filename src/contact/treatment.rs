//! The contact-treatment contract, and the choice of a treatment.
//!
//! A treatment works with a narrow [`Context`] lent by the driver for each step (the pairs
//! and their geometry, the rows, the integrator's step, inverse, prediction and end state,
//! the extra forces; [`super::context`]), never with the driver's engine, and fails with a
//! [`ContactError`]. It turns the pairs and their states into constraint rows
//! ([`crate::contact::rows`]) to solve through the integrator's factored matrix, judges each
//! solution (accept it, solve the interval again with another active set, or step back and
//! repeat the previous interval), and records the pairs' states and reactions at the end of
//! the interval ([`PairState`]): the force of a pair is always a force (N, compressive
//! positive), whatever the unit of its multiplier.
//!
//! | treatment | file | rows | judge |
//! |---|---|---|---|
//! | soft way (three restore variants), space-time exact (and mass redistribution) | [`super::softway`] | equalities: braking (Eq. 26) and holding velocities | release on tension, hold on penetration, step back to brake |
//! | exact (generalized-alpha family), penalty, Moreau-Jean, mass redistribution | [`super::complementarity`] | unilateral rows, one complementarity problem per step | accept (the active set is solved exactly) |
//! | subdivision (Fig. 5) | [`super::subdivision`] | equalities on sub-steps | cut the step at entries and releases |
//!
//! The combinations that do not exist are refused by [`Treatment::check`], in one place.
//!
//! **Friction.** The Coulomb coefficient `mu` ([`crate::simulation::Problem::friction`],
//! scenario key `contact.friction`) is carried by the treatment, given at [`super::build`]; `None`
//! (or 0) builds exactly the frictionless rows. With `mu > 0` (2D models,
//! [`Treatment::check_friction`]) every pair that carries a normal row also gets a bounded
//! row ([`crate::contact::rows::RowKind::Bounded`], `|lambda_t| <= mu lambda_n`) on its
//! tangent ([`crate::contact::Pair::tangent`]) whose `y` is the slip velocity at the step
//! end written through the integrator's maps, `y = (c_t.V - w_t) + mu_v c_t.x`: stick
//! (`y = 0`) inside the bound, slip opposed by `mu lambda_n` on it, solved by the rows'
//! active set without refactorization. The exact (generalized-alpha family), penalty,
//! mass-redistribution and Moreau-Jean rows get it beside their unilateral normal row; the soft way and the
//! space-time exact hold beside the equality row of a held pair (the bound is then `mu`
//! times the normal impulse). The soft way's braking stays normal only: a braked pair gets
//! no friction row, and nothing tangential is braked or given back (the tangential motion is
//! no impact: it is continuous through the arrival, and friction acts from the first held
//! step on). A treatment records the tangential force, sliding flag, slip power and
//! dissipated energy of each pair ([`PairState`], [`record_friction`]): the power is that of
//! the force on the slip rate at the step's end that the row holds, `-F_t s_1`, never
//! negative (the mean slip of the step is not the row's and is not used).

use super::context::{ContactError, Context};
use super::friction::spring_energy;
use super::{FrictionLaw, PairState};
use crate::model::Snapshot;
use crate::time::choice::Integrator;
use serde::Serialize;

/// The choice of a contact treatment (scenario key `contact.method`), with its parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "name", rename_all = "snake_case")]
pub enum Treatment {
    /// The soft way (Table 1): brake in the step before impact, hold, release on tension,
    /// give back the momentum as `restore` says ([`Restore`]).
    SoftWay {
        /// What is given back at release.
        restore: Restore,
    },
    /// Exact enforcement by a Lagrange multiplier: space-time, the node is held from the
    /// step where penetration is found (a velocity jump), released on tension; the
    /// generalized-alpha family, Signorini on the step-end displacement (the central
    /// difference: on the next position, Carpenter's forward increment).
    Exact,
    /// Penalty.
    Penalty {
        /// Penalty stiffness, N/m.
        stiffness: f64,
    },
    /// Massless contact nodes (Khenous, Laborde & Renard), then exact enforcement.
    MassRedistribution,
    /// Velocity-level impulses with Newton's restitution (Moreau-Jean).
    MoreauJean {
        /// Restitution coefficient in [0, 1].
        restitution: f64,
    },
    /// Sub-steps at the instants of entering and leaving contact (the paper's Fig. 5).
    Subdivision,
}

impl Treatment {
    /// The paper's soft way with the stopping impulse given back.
    pub const SOFT_WAY: Treatment = Treatment::SoftWay {
        restore: Restore::StoppingImpulse,
    };

    /// The name used in tables and scenario files.
    pub fn name(&self) -> String {
        match self {
            Treatment::SoftWay { restore } => match restore {
                Restore::StoppingImpulse => "soft_way".into(),
                Restore::BrakingReaction => "soft_way_braking_restore".into(),
                Restore::Nothing => "soft_way_no_restore".into(),
                Restore::ApproachMomentum => "soft_way_momentum_restore".into(),
            },
            Treatment::Exact => "exact".into(),
            Treatment::Penalty { stiffness } => format!("penalty({stiffness:e})"),
            Treatment::MassRedistribution => "mass_redistribution".into(),
            Treatment::MoreauJean { restitution } => format!("moreau_jean({restitution})"),
            Treatment::Subdivision => "subdivision".into(),
        }
    }

    /// True when the contact nodes are made massless before the integrator is built (mass
    /// redistribution, [`super::mass_redistribution`]).
    pub fn massless_contact(&self) -> bool {
        matches!(self, Treatment::MassRedistribution)
    }

    /// True for the soft way family.
    pub fn is_soft_way(&self) -> bool {
        matches!(self, Treatment::SoftWay { .. })
    }

    /// Refuses the combinations that do not exist, with the reason (the one place where
    /// they are listed):
    /// - the soft way and the subdivision with an integrator other than the space-time
    ///   scheme (their formulas, Eqs. 26-27 and Fig. 5, are the space-time scheme's);
    /// - mass redistribution and Moreau-Jean with the explicit central difference (a
    ///   massless node divides by zero; the explicit step has no implicit velocity level);
    /// - a penalty stiffness that is not finite and positive, a restitution outside [0, 1].
    ///
    /// # Errors
    /// The reason, one line.
    pub fn check(&self, integrator: &Integrator) -> Result<(), String> {
        let st = integrator.is_space_time();
        match *self {
            Treatment::SoftWay { .. } if !st => Err(format!(
                "the soft way (Eqs. 26-27) is a space-time treatment, not one of {}: use integrator = \"space_time\"",
                integrator.name()
            )),
            Treatment::Subdivision if !st => Err(format!(
                "subdivision of the time step (the paper's Fig. 5) is a space-time treatment, not one of {}: use integrator = \"space_time\"",
                integrator.name()
            )),
            Treatment::MassRedistribution if integrator.is_explicit() => Err(
                "mass redistribution makes the contact nodes massless: the explicit central difference would divide by a zero mass; use an implicit integrator".into(),
            ),
            Treatment::MoreauJean { .. } if integrator.is_explicit() => Err(
                "Moreau-Jean works at the velocity level of an implicit step; not available with the explicit central difference".into(),
            ),
            Treatment::Penalty { stiffness } if !(stiffness.is_finite() && stiffness > 0.0) => {
                Err(format!("the penalty stiffness must be > 0 N/m, got {stiffness}"))
            }
            Treatment::MoreauJean { restitution } if !(0.0..=1.0).contains(&restitution) => Err(
                format!("the restitution must be in [0, 1], got {restitution}"),
            ),
            _ => Ok(()),
        }
    }
}

impl Treatment {
    /// Refuses a friction coefficient `friction` (`contact.friction`) that is not finite and
    /// `>= 0`, friction on a model of dimension other than 2 (a 1D model has no tangent; 3D
    /// needs two tangents and a cone: future work), and friction with the subdivision (the
    /// paper's Fig. 5 cuts a step at the instants a node enters or leaves contact, found from
    /// its normal motion; a stick/slip change would need sub-steps of its own, which it does
    /// not have: the other treatments solve stick and slip within the step). Mass
    /// redistribution carries friction as exact enforcement does, on its massless contact
    /// nodes (`tests/friction.rs` runs the block with both). `None` and `Some(0)` are always
    /// accepted (frictionless).
    ///
    /// # Errors
    /// The reason, one line.
    pub fn check_friction(&self, friction: Option<FrictionLaw>, dim: usize) -> Result<(), String> {
        let Some(law) = friction else { return Ok(()) };
        law.check()?;
        if !law.is_active() {
            return Ok(());
        }
        if dim == 1 {
            return Err(
                "contact.friction needs a 2D model (a 1D model has no tangential direction); remove the key or set it to 0".to_string()
            );
        }
        if dim > 3 {
            return Err(format!(
                "contact.friction needs a 2D or 3D model, got {dim}D; remove the key or set it to 0"
            ));
        }
        match self {
            Treatment::Subdivision => Err(format!(
                "contact.friction is not available with {} (its sub-steps are cut at entries and releases only); use soft_way, exact, penalty, mass_redistribution or moreau_jean",
                self.name()
            )),
            _ => Ok(()),
        }
    }
}

/// The contract of a contact treatment (module docs).
pub trait ContactTreatment: Send {
    /// The name used in tables.
    fn name(&self) -> String;

    /// Solves the interval from `from` into `to`: builds the rows, solves, judges (solving
    /// again while the active set changes), and records the pairs' states at the end.
    ///
    /// # Errors
    /// [`ContactError`] when a matrix cannot be factored (subdivision).
    fn solve_interval(
        &mut self,
        ctx: &mut Context<'_>,
        from: &Snapshot,
        to: &mut Snapshot,
    ) -> Result<(), ContactError>;

    /// One step of the ring `[t_{k-2}, t_{k-1}, t_k]`: solves `ring[1] -> ring[2]`. A
    /// treatment that steps back (the soft way) may also solve `ring[0] -> ring[1]` again.
    ///
    /// # Errors
    /// As [`ContactTreatment::solve_interval`].
    fn advance(
        &mut self,
        ctx: &mut Context<'_>,
        ring: &mut [Snapshot; 3],
        _have_prev: bool,
    ) -> Result<(), ContactError> {
        let (lo, hi) = ring.split_at_mut(2);
        self.solve_interval(ctx, &lo[1], &mut hi[0])
    }

    /// Poses rows only for the candidate pairs (`true`, the default) or for every pair at
    /// every step (`false`: the reference of the search). A no-op for the treatments that
    /// pose rows for their held and braked pairs only (the soft way, subdivision).
    fn set_candidate_search(&mut self, _on: bool) {}

    /// Energy stored by the treatment in the state (penalty springs), J.
    fn stored_energy(&self, _s: &Snapshot) -> f64 {
        0.0
    }
}

/// What the soft way gives back at release ([`super::softway`], Release).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Restore {
    /// The impulse that would have stopped the node in the braking step (`soft_way`): the
    /// same whatever the phase of the arrival inside the step.
    StoppingImpulse,
    /// Table 1's braking reaction alone (`soft_way_braking_restore`).
    BrakingReaction,
    /// Nothing (`soft_way_no_restore`; exact enforcement).
    Nothing,
    /// The impulse that would have stopped the node's approach velocity alone, at the
    /// start of the braking step (`soft_way_momentum_restore`): the stopping impulse
    /// without the impulse of the forces acting during that step.
    ApproachMomentum,
}

/// Records the friction of pair state `st` for a step of length `h`: the tangential force
/// `force` (N), whether it slides, and the dissipation (W) from `slip`, the slip rate at the
/// step's end `s_1 = c_t.v1 - w_t` (m/s) with the row's own `c_t` and `w_t`, the quantity the
/// friction row bounds ([`super::rows::RowKind::Bounded`]), added to the dissipated energy
/// (`st.dissipated` holds the value at the start of the step on entry).
///
/// **The dissipation of the discrete law.** The friction impulse `lambda_t` of a step is the
/// multiplier of a row on the end velocity `v1` (the space-time scheme's velocity unknown,
/// Eqs. 18-24; the generalized-alpha family's rows likewise), so the law is Coulomb's at
/// `t1`: `|lambda_t| <= mu lambda_n`, `s_1 = 0` inside the bound, `lambda_t s_1 <= 0` on it.
/// Its dissipation is `D = -F_t s_1 h >= 0` per pair and step (the discrete form of the
/// maximum dissipation principle: `-lambda_t s_1 = mu lambda_n |s_1|` sliding, 0 sticking).
/// With an elastic stick (`kt > 0`, spring force `f0` at the step start; [`super::friction`])
/// the growth of the spring's energy over the step is taken out: `D = -F_t s_1 h - (F_t^2 -
/// f0^2)/(2 kt)`, which is `(F_t - f0)^2/(2 kt) >= 0` sticking (`s_1 h = -(F_t - f0)/kt`)
/// and that plus `|F_t|` times the plastic slip sliding (the return mapping's dissipation).
///
/// The mean slip of the step, `c_t.(u1 - u0)/h - w_t`, is not this rate and not a
/// dissipation: with `u1 = u0 + h[(1 - beta) v0 + beta v1]` (Eq. 10) it is `beta s_1 + (1 -
/// beta)(c_t.v0 - w_t)`, and a node that stuck in the previous step has `c_t.v0` equal to
/// that step's `w_t`, not this one's. On the rolling wheel the rail's tangential velocity
/// seen from the wheel's frame changes with the distance from the axle (`-omega e.(x - c)`,
/// [`super::RotatingLine`]) while a held node follows the turning base's normal motion
/// (`omega s`), so `w_t` changes by about `omega^2 s h` per step and the mean read `(1 -
/// beta)` of it as slip of every sticking node: a power of either sign, negative in the
/// majority of the steps.
///
/// A 3D pair's second tangent (`tangent = 1`) is recorded after its first: its force in
/// [`PairState::tangential_force_2`], its power and dissipation added to the first's.
pub fn record_friction(
    st: &mut PairState,
    (tangent, force): (usize, f64),
    sliding: bool,
    slip: f64,
    h: f64,
    (kt, f0): (f64, f64),
) {
    let stored = spring_energy(kt, force) - spring_energy(kt, f0);
    let power = -force * slip - stored / h;
    if tangent == 0 {
        st.tangential_force = force;
        st.sliding = sliding;
        st.slip_power = power;
    } else {
        st.tangential_force_2 = force;
        st.sliding |= sliding;
        st.slip_power += power;
    }
    st.dissipated += h * power;
}

/// Records a pair's state from its mode at the end of an interval (shared by the
/// treatments without the soft way's modes): force, reaction flag, gap.
pub fn plain_state(force: f64, held: bool, gap: f64) -> PairState {
    PairState {
        force,
        held,
        gap,
        ..PairState::default()
    }
}
