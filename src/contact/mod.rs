//! Contact: pairs, obstacles, constraint rows and the treatments that impose them.
//!
//! - [`obstacle`]: the [`Obstacle`] trait (a supporting half-space that may move in time)
//!   and the walls and lines of the paper's examples.
//! - [`pair`]: the pairs of both kinds (node against obstacle, node against node) and their
//!   geometry (row, offset, boundary velocity).
//! - [`rows`]: constraint rows (equality, unilateral, bounded) solved through the factored
//!   matrix of any integrator.
//! - [`friction`]: the friction law (Coulomb, or falling with the slip speed).
//! - [`treatment`]: the contract of a contact treatment and the choice of one.
//! - [`softway`]: the soft way (Table 1, Eqs. 26-27) and the space-time exact hold.
//! - [`complementarity`]: exact enforcement for the generalized-alpha family, penalty,
//!   Moreau-Jean.
//! - [`mass_redistribution`]: massless contact nodes.
//! - [`subdivision`]: the paper's Fig. 5.
//! - [`statics`]: static frictionless contact by an active set.

pub mod complementarity;
pub mod friction;
pub mod mass_redistribution;
pub mod obstacle;
pub mod pair;
pub mod rows;
pub mod search;
pub mod softway;
pub mod statics;
pub mod subdivision;
pub mod treatment;

pub use friction::FrictionLaw;
pub use obstacle::{HalfSpace, Obstacle, Plane, RotatingLine, Vector, Wall};
pub use pair::{Geometry, Pair};
pub use softway::{PairMode, PairState, Restore};
pub use treatment::{ContactTreatment, Treatment};
