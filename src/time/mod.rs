//! Time integration by the space-time finite element method in the velocity formulation
//! (paper §2).
//!
//! - [`params`]: the parameters `alpha`, `beta`, `gamma` (Eqs. 8, 10, 24).
//! - [`sdof`]: the one-degree-of-freedom scheme in closed form (Eqs. 9-10) and its
//!   amplification matrix: spectral radius, algorithmic damping, period error, stability.
//! - [`step`]: the multi-degree-of-freedom step `A v1 = b` with Dirichlet velocities and
//!   velocity constraints imposed by Lagrange multipliers through the factored `A`.
//! - [`classic`]: Newmark, HHT-alpha, generalized-alpha and the central difference on the
//!   same model, with the same constraint machinery, and their amplification matrices.

pub mod classic;
pub mod constraints;
pub mod params;
pub mod sdof;
pub mod step;

pub use params::SpaceTimeParams;
