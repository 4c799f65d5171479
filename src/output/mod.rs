//! Outputs: CSV histories (every CSV line through [`csv`]), JSON summaries, VTK files for ParaView, PNG plots; tables of
//! results in memory ([`table`]) and the writing of a run's [`crate::Results`] ([`save`]).
//!
//! Every file is written atomically (to a temporary name, then renamed), so an interrupted or
//! failed run never leaves a half-written result behind.

pub mod csv;
pub mod files;
pub mod job;
pub mod save;
pub mod stability;
pub mod staging;
pub mod table;
pub mod terminal;
pub mod vtk;

/// PNG figures: the `softway-plot` workspace crate (crates/softway-plot),
/// re-exported so that `output::plot::…` paths name it.
pub use softway_plot as plot;

/// Writes one line to standard error without panicking when it is closed (`softway ... 2>&1 |
/// head`): a progress or warning line is dropped, the run goes on and its files are written.
pub fn note(line: std::fmt::Arguments) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "{line}");
}
