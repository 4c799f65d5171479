//! Element kernels: each fills a buffer the caller owns.
//!
//! - [`continuum`]: the contract of a continuum element of any dimension ([`Continuum`]),
//!   the operators that assemble it, and its implementation for the plane triangle.
//! - [`bar2`]: two-node axial bar (1D).
//! - [`beam`]: two-node beam in 2D, Euler-Bernoulli and Timoshenko, with rotations.
//! - [`discrete`]: point masses, spring-dampers and rigid hubs.
//! - [`tri3`]: three-node constant-strain triangle (plane stress / plane strain).

pub mod bar2;
pub mod beam;
pub mod continuum;
pub mod discrete;
pub mod tri3;

pub use continuum::{CellError, CellStresses, Continuum};
