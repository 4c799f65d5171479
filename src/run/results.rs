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
use crate::output::table::{Columns, Rows};
use crate::run::wheel::figures::RimProfile;
use crate::run::wheel::traction::{TractionProfile, TractionSummary};
use crate::run::wheel::{WheelResults, WheelSummary};
use crate::run::RunError;
use crate::scenario::Scenario;
use crate::wheel::WheelModel;
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
    /// The results of a run of a kind of one's own ([`crate::kinds`]): its summary (stamped
    /// with the provenance every `summary.json` carries: version, scenario SHA-256, peak
    /// memory), its history and its screen lines; no figure, no per-node tables, no fields.
    pub fn of_kind(
        sc: &Scenario,
        mut summary: serde_json::Value,
        history: Columns,
        lines: Vec<String>,
        interrupted: bool,
    ) -> Self {
        super::stamp_provenance(&mut summary, sc);
        Self::with_panels(
            (sc.runs[0].model.kind(), summary),
            history,
            lines,
            interrupted,
            false,
            ("figure.png", Vec::new(), (800, 600)),
        )
    }

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

/// What each kind's figures and extra files need beyond the public items.
#[derive(Debug)]
pub(crate) enum Detail {
    /// The wheel: its model and the observers' results.
    Wheel(Box<WheelDetail>),
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

/// The wheel's model and its observers' results, for the figures and the profiles.
#[derive(Debug)]
pub(crate) struct WheelDetail {
    pub wm: WheelModel,
    pub results: WheelResults,
    pub summary: WheelSummary,
    pub profile: RimProfile,
    pub traction: Option<(TractionSummary, TractionProfile)>,
    /// The plastic wheel's rim permanent radial displacement
    /// (`rim_permanent_displacement.csv`).
    pub plastic_rim: Option<Columns>,
}

/// The history of a scenario's runs, one row every `history_stride` steps keyed by the
/// run's label, with the columns `columns` (name, unit): streamed to `stream/history.csv`
/// when given, else held, with room reserved for every run's rows. Returns the table and
/// the path its errors name.
///
/// # Errors
/// [`RunError`] when the file cannot be created.
pub(crate) fn keyed_history(
    sc: &Scenario,
    stream: Option<&Path>,
    columns: &[(&str, &str)],
) -> Result<(Rows, PathBuf), RunError> {
    let hist = stream.map(|out| out.join("history.csv"));
    let labels = sc.runs.iter().map(|r| r.label.clone()).collect();
    let rows: usize = sc
        .runs
        .iter()
        .map(|r| (r.t_end / r.params.h).round() as usize / sc.history_stride.max(1) + 1)
        .sum();
    let name = hist.clone().unwrap_or_else(|| "history.csv".into());
    let csv = Rows::open(
        Columns::keyed("run", labels, columns),
        hist.as_deref(),
        rows,
    )
    .map_err(|e| RunError::output(&name, e))?;
    Ok((csv, name))
}
