//! Contact of nodes with rigid obstacles (the one-body case, as rapier's
//! `one_body_constraint`).
//!
//! - [`obstacle`]: the [`Obstacle`] trait (a supporting half-space that may move in time)
//!   and the walls and lines of the paper's examples.
//! - [`softway`]: the per-node state of the soft way (Table 1) and its braking law
//!   (Eqs. 26-27, generalised to moving obstacles).

pub mod obstacle;
pub mod softway;
pub mod statics;

pub use obstacle::{HalfSpace, Obstacle, Plane, RotatingLine, Wall};
pub use softway::{ContactMethod, PairMode, PairState};
