//! Element kernels: each fills a buffer the caller owns.
//!
//! - [`continuum`]: the contract of a continuum element of any dimension ([`Continuum`]),
//!   the operators that assemble it, and its implementation for the plane triangle.
//! - [`bar2`]: two-node axial bar (1D).
//! - [`beam`]: two-node beam in 2D, Euler-Bernoulli and Timoshenko, with rotations.
//! - [`discrete`]: point masses, spring-dampers and rigid hubs.
//! - [`hex8`]: eight-node trilinear hexahedron (3D solid), 2x2x2 Gauss.
//! - [`j2_solid`]: the J2 elastic-plastic material point on a full 3D strain (the solids').
//! - [`solid`]: what the 3D solids share: the 6x6 elasticity matrix, Voigt order, von Mises.
//! - [`tet10`]: ten-node quadratic tetrahedron (3D solid), straight- or curved-sided.
//! - [`tet4`]: four-node linear tetrahedron (3D solid, constant strain).
//! - [`tri3`]: three-node constant-strain triangle (plane stress / plane strain).

pub mod bar2;
pub mod beam;
pub mod continuum;
pub mod discrete;
pub mod hex8;
pub mod j2_solid;
pub mod solid;
pub mod tet10;
pub mod tet4;
pub mod tri3;

pub use continuum::{CellError, CellStresses, Continuum};
