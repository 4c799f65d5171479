//! What slides the rail in a growth pass ([`Sliding`]): the classic steady creepage, or each
//! rim node's own friction in the run with friction (`growth.sliding = "dynamic"`).
//!
//! **Dynamic.** The pass rolls with the scenario's friction (`contact.friction`) and
//! creepage (`vehicle.creepage`, the axle held by the suspension: as
//! `scenarios/track-traction.toml`), so the friction rows on the rail are built and every
//! rim node's [`PairState`] holds, at the end of each step, its normal force `N`, its
//! friction force `T` and its frictional power `P = T s` (the slip rate the friction row
//! holds; zero in stick). A node in contact and in slip is a contact sample of its own
//! ([`node_sample`]): `N`, `|T|`, the slip speed `P / |T|`, over its tributary area (the
//! rim's pitch times the wheel's thickness); the wear law ([`crate::wear::WearLaw`]) turns
//! it into a depth rate, times the step. The rail therefore wears where the rim slides and
//! as fast as it slides, with the stick zone at the patch's leading edge unworn and the
//! traction's own variation (the creep force follows the normal force, the slip area the
//! creep force) in the wear, as in the wheel's polygon study on its rigid base
//! ([`crate::kinds::wheel::growth`]).
//!
//! Where the worn volume goes on the rail is the study's `growth.patch`:
//! - `nodes`: each node's volume as a hat of half-width one pitch around its point of
//!   contact (resolved as well as the rim resolves the patch);
//! - `hertz` (the default): the step's worn volume, summed over the nodes, spread over
//!   Hertz's line patch of the step's contact force as the pressure passes the rail (the
//!   steady model's spreading; exact for Archard's law when the slip speed is uniform over
//!   the patch), so that the rim's pitch puts no ripple into the wear.
//!
//! In steady rolling the frictional power is the creep force's work on the rigid slip,
//! `sum P = Q xi V` (Kalker; the elastic energy of the patch does not change): the pass
//! reports both sides (`frictional_power_w`, `creep_power_w`).

use crate::model::PairState;
use crate::wear::ContactSample;

/// The tangential side of the rail's wear in a pass (module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum Sliding {
    /// The steady creepage and traction coefficient of `[growth]`
    /// ([`super::RailSliding`]) under the dynamic normal force.
    Steady(super::RailSliding),
    /// Each rim node's own friction in the run (module docs); the rail's density, kg/m^3
    /// (the mass-based wear laws).
    Dynamic {
        /// kg/m^3.
        density: f64,
    },
}

impl Sliding {
    /// The rail's density, kg/m^3.
    pub fn density(&self) -> f64 {
        match self {
            Sliding::Steady(s) => s.density,
            Sliding::Dynamic { density } => *density,
        }
    }
}

/// A rim node's contact sample from its pair's state at the end of a step: `None` when it
/// carries no normal force or does not slip (module docs).
pub fn node_sample(ps: &PairState, area: f64, rolling_speed: f64) -> Option<ContactSample> {
    let t_abs = ps.tangential_force.abs();
    (ps.force > 0.0 && t_abs > 0.0 && ps.slip_power > 0.0).then(|| ContactSample {
        normal_force: ps.force,
        tangential_force: t_abs,
        slip_speed: ps.slip_power / t_abs,
        area,
        rolling_speed,
    })
}

/// The friction tallies of a dynamic pass over the recorded steps.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FrictionTally {
    /// Sum over the steps of the rim's friction force along the rail (N, signed).
    pub traction: f64,
    /// Sum over the steps of the nodes' frictional power, W.
    pub power: f64,
    /// Sum over the steps of the normal force carried by nodes in slip, N.
    pub sliding_force: f64,
}

impl FrictionTally {
    /// Adds a step's pairs (one wheel's rim).
    pub fn add(&mut self, pairs: &[PairState]) {
        for ps in pairs {
            self.traction -= ps.tangential_force;
            self.power += ps.slip_power;
            if ps.sliding && ps.force > 0.0 {
                self.sliding_force += ps.force;
            }
        }
    }
}
