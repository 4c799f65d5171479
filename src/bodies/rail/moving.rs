//! A constant vertical load moving along the rail at a constant speed, through the driver
//! ([`crate::simulation::Simulation`]).
//!
//! The load `P` (N, downwards) at `x(t) = x0 + V t` acts on the element under it, spread to
//! its four dofs by the beam's own deflection shape functions
//! ([`crate::element::beam::shape_functions`]): `f(t) = -P N_w(x(t))` ([`load_fn`], a
//! function of its own so that a rolling wheel's contact force can take its place later).
//! The run starts from the static deflection under the load at `x0` (at rest), so that the
//! start's transient is only the difference between the moving and the static deflection.
//!
//! Each step records ([`Sample`]) the load's position, the rail's deflection under it
//! (downwards positive), the static deflection under a load standing there (one solve with
//! the factored static stiffness), the force in the pad nearest the load and in the pad of
//! the middle sleeper.

use super::receptance::Pencil;
use super::{Track, TrackError};
use crate::contact::Treatment;
use crate::model::LoadFn;
use crate::simulation::{RunStats, SimError, Simulation};
use crate::time::Integrator;
use std::sync::atomic::AtomicBool;

/// A constant load moving at constant speed.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct MovingLoad {
    /// The load `P`, N (downwards).
    pub force: f64,
    /// The speed `V`, m/s.
    pub speed: f64,
    /// Where it starts, `x0`, m.
    pub start: f64,
}

impl MovingLoad {
    /// Its position at `t` (s), m.
    pub fn position(&self, t: f64) -> f64 {
        self.start + self.speed * t
    }
}

/// The load vector of `load` on `track` at time `t`: `-P N_w(x(t))` on the element under the
/// load, zero elsewhere (and everywhere once the load is off the rail). Allocates nothing
/// per call beyond the closure's capture.
pub fn load_fn(track: &Track, load: MovingLoad) -> LoadFn {
    let xs = track.xs.clone();
    let phi = track.phi.clone();
    let length = track.length();
    Box::new(move |t, f| {
        f.iter_mut().for_each(|v| *v = 0.0);
        let x = load.position(t);
        if !(x.is_finite() && (0.0..=length).contains(&x)) {
            return;
        }
        let ne = xs.len() - 1;
        let e = ((x / (length / ne as f64)).floor() as usize).min(ne - 1);
        let le = xs[e + 1] - xs[e];
        let xi = ((x - xs[e]) / le).clamp(0.0, 1.0);
        let (nw, _) = crate::element::beam::shape_functions(phi[e], le, xi);
        for a in 0..4 {
            f[2 * e + a] = -load.force * nw[a];
        }
    })
}

/// What one step of the passage records (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Time, s.
    pub t: f64,
    /// The load's position, m.
    pub x: f64,
    /// The rail's deflection under the load, m (downwards positive).
    pub deflection: f64,
    /// The static deflection under a load standing at `x`, m (downwards positive; NaN when
    /// not asked for).
    pub static_deflection: f64,
    /// The sleeper nearest the load.
    pub nearest: usize,
    /// The force in its pad, N (compression positive).
    pub pad_force_nearest: f64,
    /// The force in the middle sleeper's pad, N (compression positive).
    pub pad_force_middle: f64,
}

/// How to run a passage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Passage {
    /// The load.
    pub load: MovingLoad,
    /// The distance it travels, m.
    pub distance: f64,
    /// The integrator (the space-time scheme: `alpha = 0.8`).
    pub integrator: Integrator,
    /// The time step, s.
    pub h: f64,
    /// Also compute the static deflection under the load at every step.
    pub static_reference: bool,
}

impl Passage {
    /// The number of steps: the distance over the speed, over the step.
    pub fn steps(&self) -> usize {
        (self.distance / (self.load.speed * self.h))
            .round()
            .max(1.0) as usize
    }
}

/// Runs the passage on `track` through the driver, calling `observe` with each step's
/// [`Sample`] (the initial state first); stops early when `cancel` is set.
///
/// # Errors
/// [`TrackError`]: a load off the rail, a failed solve, an observer's error.
pub fn run(
    track: &Track,
    passage: &Passage,
    settings: crate::simulation::Settings,
    cancel: &AtomicBool,
    mut observe: impl FnMut(&Sample) -> std::io::Result<()>,
) -> Result<RunStats, TrackError> {
    let load = passage.load;
    let end = load.position(passage.steps() as f64 * passage.h);
    for x in [load.start, end] {
        track.element_at(x)?;
    }
    let mut pencil = Pencil::new(track)?;
    pencil.factor(0.0)?;
    let u0 = pencil.static_displacement(track, load.start, -load.force)?;
    let treatment = if passage.integrator.is_space_time() {
        Treatment::SOFT_WAY
    } else {
        Treatment::Exact
    };
    let mut problem = track.joined.problem(
        &track.bodies,
        (Vec::new(), Vec::new()),
        (passage.integrator, passage.h, passage.steps()),
    );
    problem.load = load_fn(track, load);
    problem.u0 = u0;
    problem.treatment = treatment;
    let mut sim = Simulation::with_settings(problem, settings).map_err(sim_error)?;
    let middle = track.middle_sleeper();
    let mut failure = None;
    let stats = sim
        .run(cancel, |s| {
            let st = &s.state.state;
            let x = load.position(s.state.t);
            let sample = (|| -> Result<Sample, TrackError> {
                let statics = if passage.static_reference {
                    let u = pencil.static_displacement(track, x, -load.force)?;
                    -track.deflection_under_load(&u, x, -load.force)?
                } else {
                    f64::NAN
                };
                let nearest = track.sleeper_near(x);
                Ok(Sample {
                    t: s.state.t,
                    x,
                    deflection: -track.deflection_under_load(&st.u, x, -load.force)?,
                    static_deflection: statics,
                    nearest,
                    pad_force_nearest: track.pad_force(&st.u, &st.v, nearest),
                    pad_force_middle: track.pad_force(&st.u, &st.v, middle),
                })
            })();
            match sample {
                Ok(sample) => observe(&sample),
                Err(e) => {
                    let msg = e.to_string();
                    failure = Some(e);
                    Err(std::io::Error::other(msg))
                }
            }
        })
        .map_err(|e| failure.take().unwrap_or_else(|| sim_error(e)))?;
    Ok(stats)
}

fn sim_error(e: SimError) -> TrackError {
    TrackError::Solve(format!("the passage: {e}"))
}
