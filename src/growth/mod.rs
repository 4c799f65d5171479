//! Growth studies: the pass-by-pass feedback between a surface profile, the dynamic contact
//! it excites, and the wear (and plastic flow) that contact leaves on the profile, each
//! body in a frame of its own ([`crate::bodies`]).
//!
//! **The loop.** A study holds a [`SurfaceProfile`] `z_p` over the rolling coordinate (the
//! wheel's rim, [`crate::kinds::wheel::growth`]; a rail, the track's runner). Each simulated pass `p` runs one
//! dynamic pass over `z_p` ([`PassRunner::run_pass`]) and returns the depth worn per sample
//! `w_p` and the permanent plastic displacement `d_p`; then
//! $$z_{p+1} = z_p - N_w\\,\big(S(w_p) - \overline{S(w_p)}\big) + d_p$$
//! with `N_w` real passes per simulated pass (`growth.passes_per_pass`, the wear step) and
//! `S` the smoothing and the cutoff below. The mean `N_w mean(S[w_p])` is a uniform loss (a radius or a
//! rail height worn evenly): it is taken out of the profile and reported separately
//! (`uniform_loss_m`), so that the profile is the roughness alone.
//!
//! **Plastic flow** (`d_p`, a plastic wheel: [`crate::kinds::wheel::growth`]) is the change of the rim's
//! permanent displacement over the pass, with its mean taken out (reported as
//! `plastic_mean_m`); it is not scaled by `N_w` nor smoothed: the runner carries the
//! plastic state itself from pass to pass ([`PassRunner::carried_state`], checkpointed), so
//! a simulated pass is one real pass for the plastic flow and the state's residual stresses
//! decide whether the next pass flows again (shakedown) or not (ratcheting).
//!
//! **Smoothing** ([`spectrum::smooth`]): a triangular window, the centred moving average
//! over `m = 2 floor(w / (2 dx)) + 1` samples (`w` = `growth.smoothing`, metres) applied
//! twice (periodic profiles wrap round; an open one averages what lies inside the window
//! near its ends). On a periodic profile of `n` samples it multiplies the harmonic of order
//! `k` (wavelength `n dx / k`) by `(sin(pi m k / n) / (m sin(pi k / n)))^2`: 1 at long
//! wavelengths, 0 at the wavelength `m dx`, small and never negative below (a test checks
//! this gain). A single moving average would not do: its gain turns negative beyond
//! `k = n / m`, and a negative gain turns a wear that flattens those wavelengths into one
//! that roughens them (measured: on 288 rim nodes with `m = 3` every order above 96 grew,
//! the near-Nyquist ones by 1e4 dB per 1e5 passes). The smoothing stands for what one wear
//! step must not do: amplify the sample-to-sample noise of a pass (the node-by-node
//! stick/slip, the rim pitch) `N_w` times. Choose `w` below the contact patch length `2a`
//! (the contact filter removes shorter wavelengths anyway) and state it.
//!
//! **Cutoff** (`growth.cutoff`, m; default 0: none): after the smoothing, the wear's DFT
//! components shorter than this wavelength are removed ([`spectrum::low_pass`]), so those
//! wavelengths of the profile do not evolve at all; the fastest growth is then sought at
//! the wavelengths at or above it. It keeps the study to what the mesh resolves: a node
//! contact at a rim pitch `p` resolves nothing below a few pitches, and the growth measured
//! there is the mesh's (on the paper's wheel with 288 rim nodes the zig-zag of period two
//! pitches grew by 1e4 dB per 1e5 passes under either smoothing).
//!
//! **Reference pass** (`growth.reference = true`): before the first pass the runner runs
//! once on the smooth profile (`z = 0`); the wear pattern it leaves (minus its mean) is
//! what the discretisation makes on a perfectly even surface (the mesh's rim pitch, its
//! interior pattern): it is subtracted from every pass's wear, so that the profile grows by
//! the feedback of its own roughness alone. Its RMS is reported (`reference_wear_rms_m`).
//!
//! **Initial roughness** ([`roughness`]): a harmonic, a CSV of `x_m,z_m`, a spectrum of
//! one-third-octave band levels (dB re 1 um) with a seed, or EN ISO 3095's limit spectrum.
//!
//! **Checkpoints.** After every pass the study's state ([`StudyState`]: every profile so
//! far, the uniform loss, the reference wear, bit for bit as `u64` so that JSON keeps every
//! bit) is written atomically to `checkpoint.json` in the output folder; `--resume` reads it
//! and goes on, giving the same bits as an uninterrupted study (`tests/growth.rs`). An
//! interrupted pass (Ctrl-C) is dropped whole; the finished ones stay.
//!
//! **What a researcher reads** ([`report`]): per pass the roughness spectrum in one-third
//! octave bands (dB re 1 um against the band's centre wavelength), the growth rate per band
//! (dB per 1e5 real passes: the least-squares slope of the band level against the real
//! passes), the profile; at the end the growth rate against wavelength, the wavelength of
//! fastest growth and its frequency `V / lambda`, and for a periodic profile (the wheel)
//! the polygon orders (harmonics per revolution, by DFT) and their growth.

pub mod checkpoint;
pub mod config;
pub mod report;
pub mod roughness;
pub mod spectrum;

pub use checkpoint::{
    Bits, PassRecord, StudyState, CHECKPOINT, CHECKPOINT_VERSION, MAX_CHECKPOINT_BYTES,
};
pub use config::{GrowthConfig, Roughness};

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Options of a growth job.
#[derive(Debug, Clone)]
pub struct GrowOptions {
    /// Simulated passes in all (`None`: the scenario's `growth.passes`).
    pub passes: Option<usize>,
    /// Go on from the output folder's checkpoint.
    pub resume: bool,
    /// Draw the PNGs.
    pub plots: bool,
    /// Threads of each pass.
    pub par: crate::linalg::team::Par,
}

/// A surface profile over the rolling coordinate: evenly spaced samples. Positive `z` is
/// material standing proud (a bump on the wheel's rim, a rail surface higher), m.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SurfaceProfile {
    /// Abscissa of the first sample, m.
    pub x0: f64,
    /// Sample spacing, m.
    pub dx: f64,
    /// Heights, m.
    pub z: Vec<f64>,
    /// The profile closes on itself (a wheel's rim): sample `n` is sample 0.
    pub periodic: bool,
}

impl SurfaceProfile {
    /// The abscissa of sample `i`, m.
    pub fn x(&self, i: usize) -> f64 {
        self.x0 + i as f64 * self.dx
    }

    /// Length covered, m: `n dx` for a periodic profile (one period), `(n - 1) dx` else.
    pub fn length(&self) -> f64 {
        let n = self.z.len() as f64;
        if self.periodic {
            n * self.dx
        } else {
            (n - 1.0).max(0.0) * self.dx
        }
    }

    /// Root mean square of the heights, m.
    pub fn rms(&self) -> f64 {
        spectrum::rms(&self.z)
    }
}

/// What one simulated pass gives, per sample of the profile's grid.
pub struct PassResult {
    /// Depth worn in this one simulated pass, m (>= 0), before the wear step's scaling.
    pub wear_depth: Vec<f64>,
    /// Permanent surface displacement of plastic flow in this pass, m (+ = proud); zeros without plasticity.
    pub plastic: Vec<f64>,
    /// Scalars of the pass for the per-pass table (name, value), e.g. mean force, max force.
    pub scalars: Vec<(String, f64)>,
}

/// Where a pass runs: the wheel on its rigid base ([`crate::kinds::wheel::growth::WheelPassRunner`]), a wheel on a
/// track ([`crate::kinds::track::growth::TrackPass`]).
///
/// **The contract.** [`run_study`] calls, in this order: [`PassRunner::grid`] once;
/// [`PassRunner::restore_state`] once when resuming, before any pass; [`PassRunner::run_reference`]
/// once when `growth.reference` asks for it and the state holds no reference wear yet;
/// then per pass [`PassRunner::run_pass`] followed by [`PassRunner::carried_state`], whose
/// value is checkpointed with the pass. The study's caller ([`crate::run::grow`]) then calls
/// [`PassRunner::extra_outputs`] once after a study that was not interrupted. A runner must:
///
/// - `run_pass`: advance its carried state (if any) by the pass;
/// - `run_reference`: leave its carried state exactly as it was (the reference pass
///   measures the discretisation's wear on a smooth surface; it is not a pass of the study);
/// - `carried_state`: return every number a resumed study needs to go on as an
///   uninterrupted one would (bit for bit), or `None` when its passes depend on the profile
///   alone;
/// - `restore_state`: take back exactly what `carried_state` gave, and refuse a state that
///   does not fit it ([`no_carried_state`] for a runner that carries none);
/// - `extra_outputs`: write its own files, or none.
///
/// **No defaults.** Every method is required, on purpose: a default here is a place where
/// an implementor, or a wrapper that forwards to another runner (a boxed one), silently
/// gets a behaviour it did not choose. A wrapper that forwarded `run_pass` but not
/// `run_reference` / `carried_state` / `restore_state` once made a plastic wheel's study
/// through `softway grow` commit its reference pass's plastic flow and checkpoint no
/// plastic state (so `--resume` went on from an unstrained wheel). With every method
/// required such a partial forwarder does not compile; and [`run_study`] takes a
/// `&mut dyn PassRunner` directly, so a boxed runner needs no wrapper at all.
pub trait PassRunner {
    /// The profile's grid: (x0, dx, n, periodic), fixed for the study.
    fn grid(&self) -> (f64, f64, usize, bool);
    /// The rolling speed of the pass, m/s (for wavelength -> frequency).
    fn speed(&self) -> f64;
    /// Runs one pass over `profile`, advancing the carried state (if any); `pass` counts
    /// from 0; stops within a step when `interrupt` is set.
    ///
    /// # Errors
    /// [`crate::run::error::RunError`].
    fn run_pass(
        &mut self,
        profile: &SurfaceProfile,
        pass: usize,
        interrupt: &std::sync::atomic::AtomicBool,
    ) -> Result<PassResult, crate::run::error::RunError>;

    /// Runs the reference pass on the smooth profile (`growth.reference`): like
    /// [`PassRunner::run_pass`], but the carried state (a plastic wheel's) is left exactly
    /// as it was. A runner that carries no state may run its ordinary pass 0.
    ///
    /// # Errors
    /// [`crate::run::error::RunError`].
    fn run_reference(
        &mut self,
        profile: &SurfaceProfile,
        interrupt: &std::sync::atomic::AtomicBool,
    ) -> Result<PassResult, crate::run::error::RunError>;

    /// The state the runner carries from pass to pass (a plastic wheel's plastic state),
    /// checkpointed bit for bit after every pass; `None` for a runner whose passes depend on
    /// the profile alone.
    fn carried_state(&self) -> Option<Vec<f64>>;

    /// Restores the carried state from a checkpoint before a resumed study goes on: what
    /// [`PassRunner::carried_state`] returned, bit for bit.
    ///
    /// # Errors
    /// A message when `state` does not fit the runner (its length, or a state where the
    /// runner carries none, or none where it carries one).
    fn restore_state(&mut self, state: Option<&[f64]>) -> Result<(), String>;

    /// Whether a profile `z` (m, on the grid) can be carried by the runner's body: the rim
    /// moved by it still a mesh, its heights neither beyond [`PROFILE_MAX_OF_RADIUS`] of
    /// the wheel's radius nor all below [`PROFILE_MIN_OF_RADIUS`] of it (lost in the
    /// rounding of the coordinates) unless all zero. Asked of the initial roughness before
    /// anything is written, of a checkpoint's profile on `--resume` and of the profile
    /// after every wear step, so that each is refused by what made it (the roughness's key,
    /// the checkpoint's field, the wear's keys), not as a mesh's inverted triangle.
    ///
    /// # Errors
    /// What does not fit, in words.
    fn check_profile(&self, z: &[f64]) -> Result<(), String>;

    /// Files of the runner's own written into `out` after the study (the track's
    /// prediction from its receptance), given the study's band rates `(centre wavelength m,
    /// dB per 1e5 real passes)`; an empty list for a runner that writes none.
    ///
    /// # Errors
    /// [`crate::run::error::RunError`].
    fn extra_outputs(
        &mut self,
        out: &std::path::Path,
        bands: &[(f64, f64)],
        plots: bool,
        interrupt: &std::sync::atomic::AtomicBool,
    ) -> Result<Vec<std::path::PathBuf>, crate::run::error::RunError>;
}

/// The largest profile height a runner accepts, as a fraction of its wheel's radius
/// ([`PassRunner::check_profile`]): 1 %, a millimetre on the paper's 0.1 m wheel, ten times
/// a severe polygon or corrugation.
pub const PROFILE_MAX_OF_RADIUS: f64 = 1e-2;

/// The smallest largest profile height a runner accepts (other than none at all), as a
/// fraction of its wheel's radius ([`PassRunner::check_profile`]): below it the heights are
/// lost in the rounding of the coordinates they are added to, and the levels' growth
/// would be measured from noise.
pub const PROFILE_MIN_OF_RADIUS: f64 = 1e-12;

/// The common part of [`PassRunner::check_profile`]: `z`'s largest height against a wheel
/// of `radius` m.
///
/// # Errors
/// What does not fit, in words.
pub fn check_profile_height(z: &[f64], radius: f64) -> Result<(), String> {
    if let Some(i) = z.iter().position(|v| !v.is_finite()) {
        return Err(format!("its height at sample {i} is {}", z[i]));
    }
    let peak = z.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if peak > PROFILE_MAX_OF_RADIUS * radius {
        return Err(format!(
            "its largest height, {peak:.3e} m, is over {} % of the wheel's radius ({radius} m)",
            PROFILE_MAX_OF_RADIUS * 1e2
        ));
    }
    if peak > 0.0 && peak < PROFILE_MIN_OF_RADIUS * radius {
        return Err(format!(
            "its largest height, {peak:.3e} m, is below {PROFILE_MIN_OF_RADIUS:e} of the wheel's radius ({radius} m): lost in the rounding of the coordinates"
        ));
    }
    Ok(())
}

/// The first rim node (its index in `rim` and its angle off, rad) that is not at its place
/// on a rim of evenly spaced nodes (`2 pi k / n` from the first, within 1e-6 rad): a
/// wheel's profile is one sample per rim node at one pitch. `None` when all are.
pub fn uneven_rim(mesh: &crate::mesh::Mesh, rim: &[usize]) -> Option<(usize, f64)> {
    use std::f64::consts::PI;
    let angle = |i: usize| {
        let p = mesh.point(i);
        p[1].atan2(p[0])
    };
    let a0 = angle(*rim.first()?);
    let n = rim.len();
    rim.iter().enumerate().find_map(|(k, &i)| {
        let want = a0 + 2.0 * PI * k as f64 / n as f64;
        let d = (angle(i) - want + PI).rem_euclid(2.0 * PI) - PI;
        (d.abs() > 1e-6).then_some((k, d))
    })
}

/// [`PassRunner::restore_state`] of a runner that carries no state: accepts a checkpoint
/// without one, refuses one with a runner state (a plastic wheel's).
///
/// # Errors
/// The message naming the carried state the checkpoint has.
pub fn no_carried_state(state: Option<&[f64]>) -> Result<(), String> {
    match state {
        None => Ok(()),
        Some(_) => Err("the checkpoint carries a runner state (a plastic wheel's) that this scenario's runner does not have".into()),
    }
}

/// Errors of a study.
#[derive(Debug, thiserror::Error)]
pub enum GrowthError {
    /// A pass failed.
    #[error(transparent)]
    Run(#[from] crate::run::error::RunError),
    /// The initial roughness could not be made.
    #[error("{0}")]
    Roughness(String),
    /// The checkpoint cannot be resumed.
    #[error("{path}: {message}")]
    Checkpoint {
        /// The checkpoint file.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// A runner's result does not fit the grid.
    #[error("pass {pass}: the runner returned {got} samples of {what} for a grid of {n}")]
    Shape {
        /// Pass.
        pass: usize,
        /// Which vector.
        what: &'static str,
        /// Its length.
        got: usize,
        /// The grid's.
        n: usize,
    },
    /// A pass or its wear step gave values that are not finite.
    #[error("pass {pass}: {message}")]
    NotFinite {
        /// Pass (from 0).
        pass: usize,
        /// What, and the keys that set it.
        message: String,
    },
    /// An output file could not be written.
    #[error("cannot write {path}: {message}")]
    Output {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
}

impl GrowthError {
    pub(crate) fn output(path: &Path, e: impl std::fmt::Display) -> Self {
        GrowthError::Output {
            path: path.to_path_buf(),
            message: e.to_string(),
        }
    }
}

/// How a study ended.
#[derive(Debug, Clone)]
pub struct StudyOutcome {
    /// The state (every finished pass).
    pub state: StudyState,
    /// Passes run by this call (not counting those resumed from).
    pub passes_run: usize,
    /// Stopped by the interrupt before reaching the target.
    pub interrupted: bool,
    /// Wall-clock time of the reference pass, s (0 when none was run by this call).
    pub reference_wall_s: f64,
}

/// One line of progress after a pass.
#[derive(Debug, Clone)]
pub struct PassLine {
    /// The pass just finished (from 0).
    pub pass: usize,
    /// Passes asked for in all.
    pub target: usize,
    /// RMS roughness after it, m.
    pub rms: f64,
    /// Uniform loss so far, m.
    pub uniform_loss: f64,
    /// Wall-clock time of the pass, s.
    pub wall_s: f64,
    /// The runner's scalars.
    pub scalars: Vec<(String, f64)>,
}

/// A new state: the initial roughness of `config` on the runner's grid.
///
/// # Errors
/// [`GrowthError::Roughness`].
pub fn new_state(
    config: &GrowthConfig,
    grid: (f64, f64, usize, bool),
    scenario_sha256: &str,
) -> Result<StudyState, GrowthError> {
    let (x0, dx, n, periodic) = grid;
    let z = roughness::realise(&config.roughness, grid).map_err(GrowthError::Roughness)?;
    Ok(StudyState {
        version: CHECKPOINT_VERSION,
        scenario_sha256: scenario_sha256.to_string(),
        x0: Bits(vec![x0]),
        dx: Bits(vec![dx]),
        n,
        periodic,
        initial: Bits(z),
        reference: None,
        passes: Vec::new(),
        runner: None,
    })
}

/// Runs the study until `target` passes are finished (or the interrupt), checkpointing into
/// `out/checkpoint.json` and calling `after_pass` after each pass (the outputs, the
/// progress line). With `resume` the state is read from the checkpoint (same scenario text
/// and grid required) and the study goes on from its last finished pass. The runner is
/// called as [`PassRunner`]'s contract states; a boxed runner is passed as it is
/// (`&mut *boxed`, a `dyn PassRunner`).
///
/// # Errors
/// [`GrowthError`].
#[allow(clippy::too_many_arguments)]
pub fn run_study<R: PassRunner + ?Sized>(
    runner: &mut R,
    config: &GrowthConfig,
    target: usize,
    out: &Path,
    resume: bool,
    scenario_sha256: &str,
    interrupt: &AtomicBool,
    mut after_pass: impl FnMut(&StudyState, &PassLine) -> Result<(), GrowthError>,
) -> Result<StudyOutcome, GrowthError> {
    let grid = runner.grid();
    let ck = out.join(CHECKPOINT);
    let mut state = if resume {
        let s = StudyState::read(&ck)?;
        let err = |message: String| GrowthError::Checkpoint {
            path: ck.clone(),
            message,
        };
        if s.scenario_sha256 != scenario_sha256 {
            return Err(err(format!(
                "written for another scenario text (SHA-256 {}, this one {scenario_sha256}): resume with the same file and --set values, or start afresh without --resume",
                s.scenario_sha256
            )));
        }
        if (s.x0.0[0], s.dx.0[0], s.n, s.periodic) != grid {
            return Err(err(format!(
                "its grid ({}, {}, {}, periodic {}) is not the runner's {grid:?}",
                s.x0.0[0], s.dx.0[0], s.n, s.periodic
            )));
        }
        runner
            .restore_state(s.runner.as_ref().map(|b| b.0.as_slice()))
            .map_err(err)?;
        let field = match s.passes.len() {
            0 => "`initial`".to_string(),
            k => format!("`passes[{}].z`", k - 1),
        };
        runner
            .check_profile(&s.current().z)
            .map_err(|m| err(format!("its profile ({field}) does not fit the body: {m}")))?;
        s
    } else {
        new_state(config, grid, scenario_sha256)?
    };
    let n = grid.2;
    let mut reference_wall_s = 0.0;
    if config.reference && state.reference.is_none() {
        let flat = SurfaceProfile {
            z: vec![0.0; n],
            ..state.current()
        };
        let start = Instant::now();
        let r = runner.run_reference(&flat, interrupt)?;
        reference_wall_s = start.elapsed().as_secs_f64();
        if interrupt.load(Ordering::Relaxed) {
            return Ok(StudyOutcome {
                state,
                passes_run: 0,
                interrupted: true,
                reference_wall_s,
            });
        }
        check_shape(&r, 0, n)?;
        let mut w = spectrum::low_pass(
            &spectrum::smooth(&r.wear_depth, grid.1, config.smoothing_m, grid.3),
            grid.1,
            config.cutoff_m,
        );
        let mean = spectrum::mean(&w);
        w.iter_mut().for_each(|x| *x -= mean);
        state.reference = Some(Bits(w));
        state.write(&ck)?;
    } else if !resume {
        state.write(&ck)?;
    }
    let mut passes_run = 0;
    let mut interrupted = false;
    while state.passes.len() < target {
        let pass = state.passes.len();
        let profile = state.current();
        let start = Instant::now();
        let r = runner.run_pass(&profile, pass, interrupt)?;
        let wall_s = start.elapsed().as_secs_f64();
        if interrupt.load(Ordering::Relaxed) {
            interrupted = true;
            break;
        }
        check_shape(&r, pass, n)?;
        let record = advance(config, &state, &profile, &r, wall_s);
        // A wear step that leaves the profile not finite ends the study by its keys, before
        // the checkpoint takes it (`wear.k_mass = 1e300` ran to NaN results with exit 0).
        if let Some(i) = record.z.0.iter().position(|v| !v.is_finite()) {
            return Err(GrowthError::NotFinite {
                pass,
                message: format!(
                    "the profile after the wear step is {} at sample {i} (the pass's wear {:e} m there, times growth.passes_per_pass = {:e}): lower wear.k_mass (or the law's coefficient) or growth.passes_per_pass",
                    record.z.0[i], r.wear_depth[i], config.passes_per_pass
                ),
            });
        }
        // Likewise a profile the body cannot carry (a rim whose mesh the next pass could
        // not build), by the same keys.
        if let Err(m) = runner.check_profile(&record.z.0) {
            return Err(GrowthError::NotFinite {
                pass,
                message: format!(
                    "the profile after the wear step does not fit the body: {m} (growth.passes_per_pass = {:e}): lower wear.k_mass (or the law's coefficient) or growth.passes_per_pass",
                    config.passes_per_pass
                ),
            });
        }
        state.passes.push(record);
        state.runner = runner.carried_state().map(Bits);
        state.write(&ck)?;
        passes_run += 1;
        let line = PassLine {
            pass,
            target,
            rms: state.current().rms(),
            uniform_loss: state.uniform_loss(),
            wall_s,
            scalars: r.scalars,
        };
        after_pass(&state, &line)?;
    }
    Ok(StudyOutcome {
        state,
        passes_run,
        interrupted,
        reference_wall_s,
    })
}

/// The wear step (module docs): the profile after a pass.
fn advance(
    config: &GrowthConfig,
    state: &StudyState,
    profile: &SurfaceProfile,
    r: &PassResult,
    wall_s: f64,
) -> PassRecord {
    let mut w = spectrum::low_pass(
        &spectrum::smooth(
            &r.wear_depth,
            profile.dx,
            config.smoothing_m,
            profile.periodic,
        ),
        profile.dx,
        config.cutoff_m,
    );
    if let Some(reference) = &state.reference {
        w.iter_mut().zip(&reference.0).for_each(|(x, r)| *x -= r);
    }
    let mean = spectrum::mean(&w);
    let nw = config.passes_per_pass;
    let z: Vec<f64> = profile
        .z
        .iter()
        .zip(&w)
        .zip(&r.plastic)
        .map(|((z, w), d)| z - nw * (w - mean) + d)
        .collect();
    PassRecord {
        z: Bits(z),
        uniform_loss: Bits(vec![nw * mean]),
        wear: Bits(w),
        scalar_names: r.scalars.iter().map(|s| s.0.clone()).collect(),
        scalar_values: Bits(r.scalars.iter().map(|s| s.1).collect()),
        wall_s,
    }
}

fn check_shape(r: &PassResult, pass: usize, n: usize) -> Result<(), GrowthError> {
    for (what, v) in [("wear_depth", &r.wear_depth), ("plastic", &r.plastic)] {
        if v.len() != n {
            return Err(GrowthError::Shape {
                pass,
                what,
                got: v.len(),
                n,
            });
        }
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            let keys = if what == "wear_depth" {
                "the wear law's coefficients (wear.k_mass, wear.k, wear.k1..k4 as the law reads them) or the load"
            } else {
                "the material's plasticity (material.yield_stress, the hardening) or the load"
            };
            return Err(GrowthError::NotFinite {
                pass,
                message: format!("the pass's {what} is {} at sample {i}: check {keys}", v[i]),
            });
        }
    }
    Ok(())
}
