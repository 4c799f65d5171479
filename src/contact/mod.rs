//! Contact: pairs, obstacles, constraint rows and the treatments that impose them.
//!
//! - [`obstacle`]: the [`Obstacle`] trait (a supporting half-space that may move in time)
//!   and the walls and lines of the paper's examples.
//! - [`pair`]: the pairs of both kinds (node against obstacle, node against node) and their
//!   geometry (row, offset, boundary velocity).
//! - [`search`]: contact search between bodies, each in a frame of its own (fixed,
//!   translating, rotating): a node's closest segment of another body's surface, and the
//!   row of the pair.
//! - [`facets`]: a 3D body's surface facets (triangles, quadrilaterals) and the search of
//!   another body's nodes against them, the same contract as [`search`].
//! - [`interface`]: one body's contact nodes against another's surface, searched at the
//!   start of each step ([`Pair::Searched`]).
//! - [`rows`]: constraint rows (equality, unilateral, bounded) solved through the factored
//!   matrix of any integrator.
//! - [`cyclic`]: the columns of a model that repeats round its axle, turned from one
//!   sector's.
//! - [`friction`]: the friction law (Coulomb, or falling with the slip speed).
//! - [`context`]: what a treatment works with ([`Context`]), its counters and errors.
//! - [`treatment`]: the contract of a contact treatment and the choice of one.
//! - [`softway`]: the soft way (Table 1, Eqs. 26-27) and the space-time exact hold.
//! - [`complementarity`]: exact enforcement for the generalized-alpha family, penalty,
//!   Moreau-Jean.
//! - [`mass_redistribution`]: massless contact nodes.
//! - [`subdivision`]: the paper's Fig. 5.
//! - [`statics`]: static frictionless contact by an active set.
//! - [`hertz`]: Hertz's elliptic point contact (the semi-axes, pressure and approach).

pub mod complementarity;
pub mod context;
pub mod cyclic;
pub mod facets;
pub mod friction;
pub mod hertz;
pub mod interface;
pub mod mass_redistribution;
pub mod obstacle;
pub mod pair;
pub mod profile;
pub mod rows;
pub mod search;
pub mod softway;
pub mod statics;
pub mod subdivision;
pub mod treatment;

pub use context::{ContactError, Context, Counts};
pub use friction::FrictionLaw;
pub use interface::{Interface, InterfaceError};
pub use obstacle::{
    BaseFrame, HalfSpace, Obstacle, Plane, RotatingBase, RotatingLine, Vector, Wall,
};
pub use pair::{Geometry, Pair};
pub use softway::{PairMode, PairState};
pub use treatment::{ContactTreatment, Restore, Treatment};

use crate::time::choice::Integrator;

/// Builds the treatment of `choice` for `integrator`, `pairs` contact pairs and `n` dofs,
/// with the Coulomb coefficient `friction` (`None`: frictionless; checked by
/// [`Treatment::check_friction`] first). Mass redistribution is exact enforcement on a model
/// whose contact nodes the driver made massless ([`Treatment::massless_contact`]).
pub fn build(
    choice: Treatment,
    integrator: &Integrator,
    pairs: usize,
    n: usize,
    friction: Option<FrictionLaw>,
) -> Box<dyn ContactTreatment> {
    use complementarity::{Complementarity, Law};
    use softway::SoftWay;
    let st = integrator.is_space_time();
    let mu = friction.filter(FrictionLaw::is_active);
    match choice {
        Treatment::SoftWay { restore } => {
            Box::new(SoftWay::new(true, restore, pairs).with_friction(mu))
        }
        Treatment::Exact | Treatment::MassRedistribution if st => {
            Box::new(SoftWay::new(false, Restore::Nothing, pairs).with_friction(mu))
        }
        Treatment::Exact | Treatment::MassRedistribution => {
            Box::new(Complementarity::new(Law::Exact, pairs, n).with_friction(mu))
        }
        Treatment::Penalty { stiffness } => {
            Box::new(Complementarity::new(Law::Penalty { stiffness }, pairs, n).with_friction(mu))
        }
        Treatment::MoreauJean { restitution } => Box::new(
            Complementarity::new(Law::MoreauJean { restitution }, pairs, n).with_friction(mu),
        ),
        Treatment::Subdivision => Box::new(subdivision::Subdivision::new(pairs)),
    }
}
