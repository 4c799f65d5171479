//! Model kinds as units: what a scenario's `kind = "..."` names, each kind in its own module,
//! and the one list of them, the [`Registry`].
//!
//! A kind is two contracts, in the spirit of MFEM's two-method ODE solver:
//!
//! - [`Kind`]: the kind's name, the tables it reads and how they become a validated model
//!   ([`Kind::model`]: the tables into a [`Model`], every value under its key);
//! - [`Spec`]: what a validated model answers for the generic layers: its dimension, its end
//!   time, its rules for a run (the integrators and contact treatments it runs with, the
//!   settings it refuses), its size for the cost estimate, and its run
//!   ([`Spec::record`]: a built scenario into [`Results`]).
//!
//! `scenario`, `build`, `run`, the commands and Python are generic over these two: no code
//! outside this folder matches on a kind. A new kind is a module implementing the two
//! traits plus one line in [`Registry::builtin`] (or, for a kind of one's own, one
//! [`Registry::with`] call: `tests/kinds.rs` adds a kind that exists only there, parses a
//! scenario of it and runs it).
//!
//! The built-in kinds: [`sdof`] (the paper's one degree of freedom, Eqs. 9-10), [`bar`]
//! (`bar_impact`, the bar against a wall of Fig. 8, and `two_bars`), [`wheel`] (the elastic
//! wheel rolling in its frame, Figs. 10-17, on its rigid base or pressed into an elastic
//! block) and [`track`] (a load or the wheel moving along a rail on its sleepers).

use crate::output::table::Columns;
use crate::run::provenance::stamp_provenance;
use crate::run::results::Results;
pub use crate::scenario::kind::{FreeStep, Kind, KindInput, Model, Registry, RunView, Size, Spec};
use crate::scenario::{Override, RunSpec, Scenario, ScenarioError};
use std::path::Path;

pub mod bar;
pub mod press;
pub mod rolling3d;
pub mod sdof;
pub mod track;
pub mod wheel;

impl Registry {
    /// softway's kinds.
    pub fn builtin() -> Self {
        Self::new(vec![
            &sdof::SdofKind,
            &bar::BarImpactKind,
            &bar::TwoBarsKind,
            &wheel::WheelKind,
            &track::TrackKind,
            &press::PressKind,
            &rolling3d::Rolling3dKind,
        ])
    }
}

/// Reading a scenario of softway's kinds ([`Registry::builtin`]; a kind of one's own:
/// [`Scenario::from_str_in`]).
impl Scenario<RunSpec> {
    /// Reads, parses and validates a scenario file (no model is built).
    ///
    /// # Errors
    /// [`ScenarioError`] naming the file, the key and what is allowed.
    pub fn from_file(path: &Path) -> Result<Self, ScenarioError> {
        let text = crate::scenario::read_text(path).map_err(|source| ScenarioError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_str(&text, path)
    }

    /// Reads a scenario file with the command line's `--set` overrides written into it
    /// ([`crate::scenario::overrides::read_with`]): validated as the file would be with those values.
    ///
    /// # Errors
    /// [`ScenarioError`]; a key or value the parser refuses is named by its `--set`.
    pub fn from_file_with(path: &Path, sets: &[Override]) -> Result<Self, ScenarioError> {
        let text = crate::scenario::read_text(path).map_err(|source| ScenarioError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Ok(crate::scenario::overrides::read_with(&text, path, sets, &Registry::builtin())?.0)
    }

    /// Parses and validates scenario text; `path` names it in errors (no model is built).
    ///
    /// # Errors
    /// [`ScenarioError`].
    pub fn from_str(text: &str, path: &Path) -> Result<Self, ScenarioError> {
        Self::from_str_in(text, path, &Registry::builtin())
    }
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
    ) -> Results {
        stamp_provenance(&mut summary, sc);
        Results::with_panels(
            (sc.runs[0].model.kind(), summary),
            history,
            lines,
            interrupted,
            false,
            ("figure.png", Vec::new(), (800, 600)),
        )
    }
}

impl Default for Registry {
    fn default() -> Self {
        Self::builtin()
    }
}
