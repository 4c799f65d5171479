//! The wheel's side of a growth study on the track (`growth.surface = "wheel"`): the
//! wheel's out-of-roundness grows pass by pass on the rail on its pads, sleepers and
//! ballast, where the track's resonances (P2, the rail on its pads, the pinned-pinned
//! mode) are, not on the rigid base of [`crate::kinds::wheel::growth`] where no resonance
//! below the wheel's own modes exists.
//!
//! **The profile** is the rim's radial deviation, one sample per rim node in the rim's
//! order (periodic, `dx = 2 pi R / n`, `R` the wheel's radius, `n` its rim nodes): its
//! Fourier orders are the polygon's. It enters a pass as the rigid-base study's does: the
//! rim nodes moved radially by `z` on the stress-free mesh
//! (`kinds::track::rolling::wheel_model_with`), the model rebuilt for each pass.
//!
//! **A pass** is the track scenario's passage (`vehicle.settle_bays` then
//! `vehicle.travel_bays`; the rail's own irregularity, `track.irregularity`, in the gap
//! when given) with friction and a creepage (`contact.friction`, `vehicle.creepage`): the
//! wear needs the slip. Each rim node's wear is summed over the last full turn of the
//! wheel, `2 pi / omega` with `omega = V (1 + xi) / R_s`, so that every node crosses the
//! patch once: per step, from its [`crate::model::PairState`] (the normal force, the
//! friction force, the slip speed `P / |T|`, over its tributary area `dx w`) through the
//! scenario's wear law ([`crate::kinds::track::growth::node_sample`]), times the step.
//! The recorded travel must hold a full turn.
//!
//! The wheel's growth frequencies are `V n / (2 pi R)` for order `n` (the study's
//! `orders.csv`); the track's P2 and pinned-pinned frequencies come from its receptance
//! (`softway receptance`).

use crate::growth::{PassResult, PassRunner, SurfaceProfile};
use crate::kinds::track::growth::node_sample;
use crate::kinds::track::rolling::{passage_of, wheel_model, wheel_model_with};
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::scenario::{Scenario, TrackScenario, VehicleModel};
use crate::wear::WearLaw;
use std::f64::consts::PI;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// One pass of the out-of-round wheel over the track (module docs).
#[derive(Debug, Clone)]
pub struct WheelTrackPass {
    sc: Scenario,
    ts: TrackScenario,
    opts: RunOptions,
    law: WearLaw,
    density: f64,
    n: usize,
    dx: f64,
}

impl WheelTrackPass {
    /// The passes of the first run of the track scenario `sc`, wearing the wheel by `law`
    /// (the wheel's `density`, kg/m^3, for the mass-based laws).
    ///
    /// # Errors
    /// [`RunError::Input`]: not a track scenario with the wheel, no friction or creepage,
    /// a recorded travel shorter than a turn, a rim that is not evenly spaced, a bad law.
    pub fn new(
        sc: &Scenario,
        law: WearLaw,
        density: f64,
        opts: RunOptions,
    ) -> Result<Self, RunError> {
        let input = |m: String| RunError::input(&sc.path, m);
        let run = sc.runs.first().ok_or_else(|| input("no run".into()))?;
        let ts = run
            .model
            .get::<TrackScenario>()
            .filter(|t| t.vehicle.model == VehicleModel::Wheel)
            .cloned()
            .ok_or_else(|| {
                input("a wheel's growth study on the track needs kind = \"track\" with vehicle.model = \"wheel\"".into())
            })?;
        law.check().map_err(input)?;
        if let Some(l) = ts.vehicle.wheelbase {
            return Err(input(format!(
                "vehicle.wheelbase = {l}: growth.surface = \"wheel\" grows one wheel's profile; the second wheel is for the rail's growth (remove vehicle.wheelbase)"
            )));
        }
        if run.friction.is_none_or(|l| !l.is_active()) || ts.vehicle.creepage == 0.0 {
            return Err(input(format!(
                "growth.surface = \"wheel\" wears the wheel by the run's own friction: set contact.friction > 0 and vehicle.creepage (with vehicle.suspension_stiffness > 0 and time.gamma > 0, as scenarios/track-traction.toml); this scenario has contact.friction {} and vehicle.creepage = {}",
                if run.friction.is_some_and(|l| l.is_active()) { "> 0" } else { "= 0" },
                ts.vehicle.creepage
            )));
        }
        let radius = ts.vehicle.wheel_radius;
        let recorded = ts.travel() - ts.settle_distance();
        let turn = 2.0 * PI * radius;
        if recorded < turn {
            return Err(input(format!(
                "vehicle.travel_bays = {}: the wheel's study records its last full turn after the settling, {turn:.3} m of travel, and {} bays hold {recorded:.3} m (at least {} bays)",
                ts.vehicle.travel_bays,
                ts.vehicle.travel_bays,
                (turn / ts.spec.spacing).ceil()
            )));
        }
        let smooth = wheel_model(&ts).map_err(input)?;
        let n = smooth.rim.len();
        if let Some((k, d)) = crate::growth::uneven_rim(&smooth.mesh, &smooth.rim) {
            return Err(input(format!("the rim's nodes are not evenly spaced (node {k} of {n} is {d:.3e} rad off): the wheel's study needs one profile sample per rim node at one pitch")));
        }
        Ok(Self {
            sc: sc.clone(),
            ts,
            opts,
            law,
            density,
            n,
            dx: turn / n as f64,
        })
    }
}

impl PassRunner for WheelTrackPass {
    fn grid(&self) -> (f64, f64, usize, bool) {
        (0.0, self.dx, self.n, true)
    }

    fn speed(&self) -> f64 {
        self.ts.vehicle.speed
    }

    fn run_reference(
        &mut self,
        profile: &SurfaceProfile,
        interrupt: &AtomicBool,
    ) -> Result<PassResult, RunError> {
        self.run_pass(profile, 0, interrupt)
    }

    /// None: a pass depends on the wheel's profile alone.
    fn carried_state(&self) -> Option<Vec<f64>> {
        None
    }

    /// The heights against the wheel's radius.
    fn check_profile(&self, z: &[f64]) -> Result<(), String> {
        crate::growth::check_profile_height(z, self.ts.vehicle.wheel_radius)
    }

    fn restore_state(&mut self, state: Option<&[f64]>) -> Result<(), String> {
        crate::growth::no_carried_state(state)
    }

    /// The wheel writes no files of its own.
    fn extra_outputs(
        &mut self,
        _out: &std::path::Path,
        _bands: &[(f64, f64)],
        _plots: bool,
        _interrupt: &AtomicBool,
    ) -> Result<Vec<std::path::PathBuf>, RunError> {
        Ok(Vec::new())
    }

    fn run_pass(
        &mut self,
        profile: &SurfaceProfile,
        _pass: usize,
        interrupt: &AtomicBool,
    ) -> Result<PassResult, RunError> {
        let input = |m: String| RunError::input(&self.sc.path, m);
        if profile.z.len() != self.n {
            return Err(input(format!(
                "the wheel's profile has {} samples, its rim {} nodes",
                profile.z.len(),
                self.n
            )));
        }
        let run = &self.sc.runs[0];
        let wheel = wheel_model_with(&self.ts, Some(&profile.z)).map_err(input)?;
        let (wot, mut sim, steps) = passage_of(&self.sc, run, &self.ts, &self.opts, None, wheel)?;
        let h = run.params.h;
        let v = &self.ts.vehicle;
        let omega = v.speed * (1.0 + v.creepage) / wot.rim_radius;
        let t_end = steps as f64 * h;
        let t_from = t_end - 2.0 * PI / omega.abs() - 0.5 * h;
        let area = self.dx * v.wheel.thickness;
        let (law, density, speed) = (self.law, self.density, v.speed);
        let mut wear = vec![0.0; self.n];
        let mut t = Tally::default();
        let clock = Instant::now();
        let stats = sim
            .run(interrupt, |s| {
                let st = s.state;
                if st.t <= t_from {
                    return Ok(());
                }
                let c = Instant::now();
                for (w, ps) in wear.iter_mut().zip(&st.pairs) {
                    t.traction -= ps.tangential_force;
                    t.power += ps.slip_power;
                    if ps.sliding && ps.force > 0.0 {
                        t.sliding += ps.force;
                    }
                    if let Some(sample) = node_sample(ps, area, speed) {
                        *w += law.depth_rate(&sample, density) * h;
                    }
                }
                t.bookkeeping += c.elapsed();
                let f = s.contact_force;
                t.f_sum += f;
                t.f2_sum += f * f;
                t.f_max = t.f_max.max(f);
                t.f_min = t.f_min.min(f);
                t.count += 1;
                Ok(())
            })
            .map_err(|source| RunError::Simulation {
                run: run.label.clone(),
                source,
            })?;
        let wall = clock.elapsed().as_secs_f64();
        if stats.interrupted {
            // Stopped within a step: the study drops this pass whole.
            return Ok(PassResult {
                wear_depth: vec![0.0; self.n],
                plastic: vec![0.0; self.n],
                scalars: Vec::new(),
            });
        }
        let m = t.count.max(1) as f64;
        let mean = t.f_sum / m;
        Ok(PassResult {
            wear_depth: wear,
            plastic: vec![0.0; self.n],
            scalars: vec![
                ("mean_force_n".into(), mean),
                (
                    "std_force_n".into(),
                    (t.f2_sum / m - mean * mean).max(0.0).sqrt(),
                ),
                ("max_force_n".into(), t.f_max),
                ("min_force_n".into(), t.f_min),
                ("mean_traction_n".into(), t.traction / m),
                ("traction_ratio".into(), t.traction / t.f_sum),
                ("frictional_power_w".into(), t.power / m),
                ("sliding_share".into(), t.sliding / t.f_sum),
                ("turn_steps".into(), m),
                ("loop_s".into(), wall),
                ("wear_bookkeeping_s".into(), t.bookkeeping.as_secs_f64()),
            ],
        })
    }
}

/// The tallies of a pass's recorded turn.
struct Tally {
    traction: f64,
    power: f64,
    sliding: f64,
    f_sum: f64,
    f2_sum: f64,
    f_max: f64,
    f_min: f64,
    count: usize,
    bookkeeping: std::time::Duration,
}

impl Default for Tally {
    fn default() -> Self {
        Self {
            traction: 0.0,
            power: 0.0,
            sliding: 0.0,
            f_sum: 0.0,
            f2_sum: 0.0,
            f_max: f64::NEG_INFINITY,
            f_min: f64::INFINITY,
            count: 0,
            bookkeeping: std::time::Duration::ZERO,
        }
    }
}
