//! Element kernels: each fills a buffer the caller owns.
//!
//! - [`bar2`]: two-node axial bar (1D).
//! - [`tri3`]: three-node constant-strain triangle (plane stress / plane strain).

pub mod bar2;
pub mod tri3;
