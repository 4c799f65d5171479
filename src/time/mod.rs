//! Time integration by the space-time finite element method in the velocity formulation
//! (paper §2).
//!
//! - [`params`]: the parameters `alpha`, `beta`, `gamma` (Eqs. 8, 10, 24).
//! - [`sdof`]: the one-degree-of-freedom scheme in closed form (Eqs. 9-10) and its
//!   amplification matrix: spectral radius, algorithmic damping, period error, stability.
//! - [`integrator`]: the integrator contract ([`TimeIntegrator`]) every integrator below
//!   implements; [`choice`]: the choice of one ([`Integrator`]).
//! - [`step`]: the multi-degree-of-freedom space-time step `A v1 = b` with Dirichlet
//!   velocities (Eqs. 6-10, 24).
//! - [`classic`]: Newmark, HHT-alpha, generalized-alpha and the central difference on the
//!   same model, and their amplification matrices.

pub mod choice;
pub mod classic;
pub mod integrator;
pub mod params;
pub mod sdof;
pub mod step;

pub use choice::{ClassicKind, Integrator};
pub use integrator::{State, TimeIntegrator};
pub use params::{Coriolis, SpaceTimeParams};
