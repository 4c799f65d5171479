//! Outputs: CSV histories, JSON summaries, VTK files for ParaView, PNG plots.
//!
//! Every file is written atomically (to a temporary name, then renamed), so an interrupted or
//! failed run never leaves a half-written result behind.

pub mod files;
pub mod plot;
pub mod stability;
pub mod vtk;
