//! The growth job (`softway grow`): a built scenario with a `[growth]` and a `[wear]` table,
//! its pass runner (the wheel on its rigid base for `kind = "wheel"`), the pass-by-pass
//! study of [`crate::growth`] into an output folder that keeps its checkpoint (so that
//! `--resume` goes on from it), and the files of [`crate::growth::report`].

use super::{Cancel, RunError};
use crate::growth::report::{self, GrowthSummary};
use crate::growth::{run_study, GrowthError, PassLine, PassRunner};
use crate::scenario::Scenario;
use std::path::{Path, PathBuf};

pub use crate::growth::GrowOptions;

/// What a growth job reports back.
#[derive(Debug, Clone)]
pub struct GrowReport {
    /// The summary.
    pub summary: GrowthSummary,
    /// Files written.
    pub files: Vec<PathBuf>,
    /// Stopped by Ctrl-C.
    pub interrupted: bool,
    /// Passes run by this call.
    pub passes_run: usize,
    /// Wall-clock time of the reference pass run by this call, s.
    pub reference_wall_s: f64,
}

/// Runs the growth study of `sc` into `out` (module docs), calling `progress` with a line
/// after every pass: [`Study::prepare`], then [`Study::run`].
///
/// # Errors
/// [`GrowthError`]: a scenario without `[growth]`, a model that cannot be built, a pass that
/// fails, a checkpoint that cannot be resumed, an output that cannot be written.
pub fn grow(
    sc: &Scenario,
    out: &Path,
    opts: &GrowOptions,
    cancel: &Cancel,
    progress: impl FnMut(&PassLine),
) -> Result<GrowReport, GrowthError> {
    Study::prepare(sc, opts)?.run(out, cancel, progress)
}

/// A growth study built and checked, nothing written yet: its pass runner (the model
/// built) and its configuration checked against the runner's grid. The command line
/// claims the output folder only once a study is prepared, so that bad input writes
/// nothing.
pub struct Study<'a> {
    sc: &'a Scenario,
    opts: GrowOptions,
    config: crate::growth::GrowthConfig,
    runner: Box<dyn PassRunner>,
}

impl<'a> Study<'a> {
    /// Builds the pass runner of `sc` and checks the study against its grid.
    ///
    /// # Errors
    /// [`GrowthError`]: a scenario without `[growth]`, a key the study cannot carry out
    /// (named), a model that cannot be built.
    pub fn prepare(sc: &'a Scenario, opts: &GrowOptions) -> Result<Self, GrowthError> {
        let config = sc.growth.clone().ok_or_else(|| {
            GrowthError::Run(RunError::input(
                &sc.path,
                "no [growth] table: softway grow needs [growth] and [wear] (the book, docs/src/growth.md)",
            ))
        })?;
        let run = sc.runs.first().ok_or_else(|| {
            GrowthError::Run(RunError::input(&sc.path, "the scenario has no run"))
        })?;
        let runner = pass_runner(sc, run, &config, opts)?;
        // What the runner's grid cannot carry out is refused by its key before anything is
        // written.
        if let Err((key, value, allowed)) = config.check_grid(runner.grid()) {
            // As the scenario's own refusals read (`ScenarioError::Invalid`).
            return Err(GrowthError::Run(RunError::Input {
                path: sc.path.clone(),
                message: format!("`{key}` = {value}: {allowed}"),
            }));
        }
        // So is an initial roughness the body cannot carry (a level of 400 dB was refused
        // as an inverted triangle of the mesh, -400 dB grew from rounding noise).
        let refuse = |key: &str, message: String| {
            Err(GrowthError::Run(RunError::Input {
                path: sc.path.clone(),
                message: format!("`{key}`: {message}"),
            }))
        };
        match crate::growth::roughness::realise(&config.roughness, runner.grid()) {
            Ok(z) => {
                if let Err(m) = runner.check_profile(&z) {
                    let from = match &config.roughness {
                        crate::growth::Roughness::Csv { path } => {
                            format!(" (from {})", path.display())
                        }
                        _ => String::new(),
                    };
                    return refuse(
                        config.roughness_key,
                        format!("the initial roughness{from} does not fit the body: {m}"),
                    );
                }
            }
            // A spectrum the grid cannot realise (a band of no whole order, an open
            // profile's sampling or stretch) is its wavelengths' doing; a file's, the file's.
            Err(m) => {
                let key = match config.roughness_key {
                    "growth.level" => "growth.min_wavelength`/`growth.max_wavelength",
                    "growth.band_levels" => "growth.band_wavelengths",
                    k => k,
                };
                return refuse(key, format!("the initial roughness cannot be made: {m}"));
            }
        }
        Ok(Study {
            sc,
            opts: opts.clone(),
            config,
            runner,
        })
    }

    /// Runs the study into `out` (created and marked as needed; with `opts.resume` from its
    /// checkpoint), calling `progress` with a line after every pass.
    ///
    /// # Errors
    /// [`GrowthError`]: a pass that fails, a checkpoint that cannot be resumed, an output
    /// that cannot be written.
    pub fn run(
        self,
        out: &Path,
        cancel: &Cancel,
        mut progress: impl FnMut(&PassLine),
    ) -> Result<GrowReport, GrowthError> {
        let Study {
            sc,
            opts,
            config,
            mut runner,
        } = self;
        mark_study_folder(out)?;
        let target = opts.passes.unwrap_or(config.passes);
        let speed = runner.speed();
        let outcome = run_study(
            &mut *runner,
            &config,
            target,
            out,
            opts.resume,
            &sc.source_sha256,
            cancel.flag(),
            |state, line| {
                // Not yet at the target: a study killed here stopped short of it.
                let short = state.passes.len() < target;
                report::write_all(out, state, &config, speed, (opts.plots, short))?;
                progress(line);
                Ok(())
            },
        )
        // A study stopped by its keys after a pass names its scenario file, as every
        // refusal does (it read "pass 0: ..." alone).
        .map_err(|e| match e {
            GrowthError::NotFinite { pass, message } => {
                GrowthError::Run(RunError::input(&sc.path, format!("pass {pass}: {message}")))
            }
            e => e,
        })?;
        // The as-run scenario once the study (a resumed one: its checkpoint) was accepted: a
        // refused `--resume` leaves the folder's copy of the scenario it was run with.
        let mut files = vec![super::write_scenario_copy(sc, out)?];
        files.push(out.join(crate::growth::CHECKPOINT));
        files.extend(report::write_all(
            out,
            &outcome.state,
            &config,
            speed,
            (opts.plots, outcome.interrupted),
        )?);
        let summary = GrowthSummary {
            interrupted: outcome.interrupted,
            ..report::summary(&outcome.state, &config, speed)
        };
        if !outcome.interrupted {
            let bands: Vec<(f64, f64)> = summary
                .bands
                .iter()
                .map(|b| (b.centre_wavelength_m, b.rate_db_per_1e5))
                .collect();
            files.extend(runner.extra_outputs(out, &bands, opts.plots, cancel.flag())?);
        }
        Ok(GrowReport {
            summary,
            files,
            interrupted: outcome.interrupted,
            passes_run: outcome.passes_run,
            reference_wall_s: outcome.reference_wall_s,
        })
    }
}

/// The pass runner of a growth study of `sc`'s run `run`: the wheel on its rigid base
/// (`kind = "wheel"`, whole turns) or the wheel on the track (`kind = "track"`), each with
/// the `[growth]` keys it reads and none that it does not.
///
/// # Errors
/// [`GrowthError::Run`]: a key of the other runner, a key missing, another kind, a model
/// that cannot be built.
fn pass_runner(
    sc: &Scenario,
    run: &crate::scenario::Run,
    config: &crate::growth::GrowthConfig,
    opts: &GrowOptions,
) -> Result<Box<dyn PassRunner>, GrowthError> {
    run.model.growth_runner(sc, config, opts)
}

/// Creates the study folder `out` as needed and marks it as softway's (its marker, where it
/// has none), so that `softway grow --resume` goes on in it: a study started from Python or
/// the library, or a state saved from Python, is resumed by the command line as its own.
///
/// # Errors
/// [`GrowthError::Output`] when the folder or its marker cannot be written.
pub fn mark_study_folder(out: &Path) -> Result<(), GrowthError> {
    std::fs::create_dir_all(out).map_err(|e| GrowthError::output(out, e))?;
    let marker = out.join(crate::output::staging::MARKER);
    if !marker.exists() {
        crate::output::staging::write_marker(out, false)
            .map_err(|e| GrowthError::output(&marker, e))?;
    }
    Ok(())
}

/// Claims the folder `out` for a new study's files under the rules every command keeps (the crate's
/// `output::job`, the command line's path): a folder of the user's files refused unless `force`,
/// the current and the home folder never replaced; an older study there is replaced whole. The
/// folder is then empty and marked (what the Python package's `GrowthResult.save` does before it
/// writes a state).
///
/// # Errors
/// [`GrowthError::Output`] naming the folder and why it is refused.
pub fn claim_study_folder(out: &Path, force: bool) -> Result<(), GrowthError> {
    crate::output::job::StudyFolder::fresh("grow", out, force, &[])
        .map(|_| ())
        .map_err(|e| GrowthError::output(out, e))
}

/// Screen lines of a study's summary.
pub fn summary_lines(s: &GrowthSummary) -> Vec<String> {
    let mut l = vec![format!(
        "{} passes x {} = {} real passes at V = {:.2} m/s; RMS roughness {:.4} -> {:.4} um; uniform loss {}; {} a pass",
        s.passes,
        crate::output::terminal::grouped_or_sci(s.passes_per_pass),
        crate::output::terminal::grouped_or_sci(s.real_passes),
        s.speed_m_s,
        s.rms_initial_m * 1e6,
        s.rms_final_m * 1e6,
        crate::output::terminal::quantity(s.uniform_loss_m, "m"),
        crate::output::terminal::quantity(s.mean_pass_wall_s, "s")
    )];
    if let Some(b) = &s.fastest_band {
        l.push(format!(
            "fastest band: {:.2} mm ({:.0} Hz at V), {:+.3} dB per 1e5 passes",
            b.centre_wavelength_m * 1e3,
            b.frequency_hz,
            b.rate_db_per_1e5
        ));
    }
    if let Some(o) = &s.fastest_order {
        l.push(format!(
            "fastest polygon order: {} ({:.2} mm, {:.0} Hz at V), {:+.3} dB per 1e5 passes",
            o.order,
            o.wavelength_m * 1e3,
            o.frequency_hz,
            o.rate_db_per_1e5
        ));
    }
    l
}
