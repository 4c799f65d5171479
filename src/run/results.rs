//! The results of a run, in memory: what [`crate::run::run`] returns and
//! [`Results::save`] writes as the command line's files.
//!
//! | item | file of the command line |
//! |---|---|
//! | [`Results::summary`] | `summary.json` |
//! | [`Results::history`] | `history.csv` |
//! | [`Results::contact_nodes`] | `contact_nodes.csv` (wheel) |
//! | [`Results::traction_history`] | `traction_history.csv` (wheel with friction) |
//! | [`Results::rim_profile`] | `j2_rim_profile.csv` (wheel) |
//! | [`Results::fields`] | the VTU files and `velocity.pvd` (wheel) |
//! | [`Results::lines`], [`Results::interrupted`] | the screen summary, the exit code |

use crate::mesh::Mesh;
use crate::output::plot::Panel;
use crate::output::table::Columns;
use crate::run::error::RunError;
use std::path::{Path, PathBuf};

/// The results of one scenario's run.
#[derive(Debug)]
pub struct Results {
    /// The model's kind: `sdof`, `bar_impact`, `two_bars`, `wheel` or `track`.
    pub kind: &'static str,
    /// The key figures: the object written as `summary.json` (units in its `units` entry).
    pub summary: serde_json::Value,
    /// The history over time (`history.csv`): one row every `output.history_stride` steps;
    /// the bar's and the oscillator's rows are keyed by the run's label (`run`).
    pub history: Columns,
    /// Per contact node (wheel, `contact_nodes.csv`): one row per rim node carrying a
    /// reaction or held, every `output.history_stride` steps, keyed by the node's index.
    pub contact_nodes: Option<Columns>,
    /// The traction over time (wheel with friction, `traction_history.csv`).
    pub traction_history: Option<Columns>,
    /// The turn-averaged `J2` and von Mises at the rim nodes against their angle (wheel,
    /// `j2_rim_profile.csv`; none with a moving zone).
    pub rim_profile: Option<Columns>,
    /// The fields on the mesh (wheel: the turn averages and the velocity snapshots).
    pub fields: Fields,
    /// The screen summary, one line per entry.
    pub lines: Vec<String>,
    /// True when the run was stopped by an interrupt (the results hold the steps computed).
    pub interrupted: bool,
    /// Warnings for the user (the library prints nothing; the CLI prints these).
    pub warnings: Vec<String>,
    /// Write the PNG figures on [`Results::save`] (`output.plots`).
    pub plots: bool,
    /// What the figures need, per kind.
    pub(crate) detail: Detail,
}

impl Results {
    /// The results of a job with a history and one figure of panels (the oscillator, the
    /// bars, the track, the wheel on its block): no per-node tables, no fields, no warnings.
    pub(crate) fn with_panels(
        (kind, summary): (&'static str, serde_json::Value),
        history: Columns,
        lines: Vec<String>,
        interrupted: bool,
        plots: bool,
        (file, panes, size): (&'static str, Vec<Panel>, (u32, u32)),
    ) -> Self {
        Results {
            kind,
            summary,
            history,
            contact_nodes: None,
            traction_history: None,
            rim_profile: None,
            fields: Fields::default(),
            lines,
            interrupted,
            warnings: Vec::new(),
            plots,
            detail: Detail::Panels { file, panes, size },
        }
    }
}

/// Fields on a mesh at output times (the VTU files of the command line).
#[derive(Debug, Clone, Default)]
pub struct Fields {
    /// The mesh (none when the run has no fields).
    pub mesh: Option<Mesh>,
    /// The frames, in the order written.
    pub frames: Vec<FieldFrame>,
}

/// One set of fields on the mesh: one VTU file.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldFrame {
    /// The file's name (e.g. `velocity_003.vtu`).
    pub file: String,
    /// The instant, s (none for an average over a window, such as a turn); frames with an
    /// instant are listed in `velocity.pvd`.
    pub time: Option<f64>,
    /// The displacement of every dof, m (the points are drawn displaced), if any.
    pub displacement: Option<Vec<f64>>,
    /// Arrays on the points.
    pub point_data: Vec<FieldArray>,
    /// Arrays on the cells.
    pub cell_data: Vec<FieldArray>,
}

/// A named array of a field: `components` values per point or cell.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldArray {
    /// Name (with its unit, e.g. `J2_turn_average_MPa2`; `velocity` is in m/s).
    pub name: String,
    /// Values per point or cell.
    pub components: usize,
    /// The values, point (cell) after point (cell).
    pub values: Vec<f64>,
}

/// A kind's own files and figures, written by [`Results::save`] after `history.csv` and
/// before `summary.json`.
pub(crate) trait OwnFiles: std::fmt::Debug + Send + Sync {
    /// Writes them into `out`; returns the files in the order the command line lists them.
    ///
    /// # Errors
    /// [`RunError::Output`] naming the file.
    fn save(&self, results: &Results, out: &Path) -> Result<Vec<PathBuf>, RunError>;
}

/// What each kind's figures and extra files need beyond the public items.
#[derive(Debug)]
pub(crate) enum Detail {
    /// A kind's own files and figures after `history.csv` (the wheel's: the contact nodes,
    /// the traction, the fields, the rim profile, its figures), then `summary.json`.
    Own(Box<dyn OwnFiles>),
    /// Panels drawn one above the other into `file` (the oscillator's, the bar's, the
    /// wheel on a block's; none drawn when empty).
    Panels {
        /// The PNG's name.
        file: &'static str,
        /// The panels.
        panes: Vec<Panel>,
        /// The image's size, pixels.
        size: (u32, u32),
    },
}
