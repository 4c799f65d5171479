//! The rail's side of a growth study: one pass is the wheel of a track scenario
//! (`vehicle.model = "wheel"`, [`crate::bodies::rail::rolling`]) rolling over the recorded bays
//! of the track, whose rail top carries the study's profile in the contact gap; the rail
//! wears under the rim nodes in contact.
//!
//! # The profile
//!
//! The grid runs over the recorded passage (from the end of the settling to the end of the
//! run: `vehicle.travel_bays` bays) at `growth.dx`. The profile enters the search as the
//! rail's irregularity ([`crate::contact::profile::Profile::sampled`]: the point of
//! contact raised by `z` and the normal turned by `z'`), faded in and out by a raised
//! cosine over [`FADE_BAYS`] bays at each end of the grid so that the wheel does not meet a
//! step where the grid starts and ends (the growth analysis reads the inner part,
//! [`TrackPass::inner`]).
//!
//! # The wear
//!
//! The wheel on the track is frictionless (its friction rows on the rail's beams are not
//! built), so the tangential side of the contact is the classic one of roughness-growth
//! models (Nielsen 2003, Hempelmann and Knothe 1996): a steady longitudinal creepage
//! `gamma` (`growth.creepage`) and a traction `T = mu_t N` (`growth.traction_coefficient`),
//! the rim sliding over the rail at `gamma V`. The law of `[wear]`
//! ([`crate::wear::WearLaw`]) turns the pressure under a rail point, `T` and the slip speed
//! into a depth rate. Where the pressure comes from is [`WearPatch`]:
//!
//! - **`hertz`** (the default): the step's contact force `F` (the dynamic force of the FE
//!   contact) spread over Hertz's line-contact patch `p(s) = 2 P' sqrt(a^2 - s^2) / (pi a^2)`,
//!   `P' = F / w` per unit width (`w` the wheel's thickness), `a = sqrt(4 P' R / (pi E*))`
//!   with `R` the rim's radius and `E*` the wheel slice's own (`E / (1 - nu^2)` in plane
//!   strain, `E` in plane stress: the rail's beam has no local compliance, so this is the
//!   patch of the FE model), centred under the axle and moving with it over the step. Each
//!   rail point gets the step's mean pressure over the part of the patch that passed over it,
//!   integrated exactly (the patch's cumulative load is closed-form), so the wear does not
//!   depend on how the grid and the step's travel fall.
//! - **`nodes`**: each rim node in contact is a contact point of its own (its normal force,
//!   its rim pitch times the thickness as its area), its worn volume laid around its point of
//!   contact on the rail by a hat of half-width one pitch. It resolves the patch only as
//!   well as the rim does: on the shipped rim (4 mm pitch, two nodes in a 10 mm patch) the
//!   share of the force between the two nodes puts a ripple of 1-3% of the mean depth at
//!   10-30 mm into the wear, ten times the force's own content there (`tests`), which would
//!   read as growth at corrugation wavelengths; use it on rims with ten or more nodes in
//!   the patch.
//!
//! Either way, under a steady load the worn depth of a rail point over a pass is the
//! continuum's `k gamma P / (H w)` for Archard (a rail point spends `2a / V` in a patch of
//! mean pressure `P / (2 a w)` sliding `gamma V`): `tests/growth_track.rs`.
//!
//! What the wear responds to is therefore the normal force's variation along the rail: the
//! sleepers' passing, the P2 resonance, the pinned-pinned resonance, the profile itself
//! through the contact's filter, all of them in the wheel's dynamic contact.

use crate::contact::profile::Profile;
use crate::growth::{PassResult, PassRunner, SurfaceProfile};
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::scenario::{Scenario, TrackScenario, VehicleModel};
use crate::wear::{ContactSample, WearLaw};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

mod sliding;
mod wearing;
pub use sliding::{node_sample, FrictionTally, Sliding};
#[cfg(test)]
use wearing::lay_hat;
use wearing::Wearing;

/// The most samples of the rail's profile (`growth.dx` over the recorded bays): a million,
/// 0.1 mm over 100 m.
pub const MAX_SAMPLES: usize = 1_000_000;

/// The fade of the profile in the gap at each end of the grid, sleeper bays.
pub const FADE_BAYS: f64 = 0.5;

/// The tangential side of the rail's wear (module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RailSliding {
    /// Longitudinal creepage `gamma` (> 0), dimensionless.
    pub creepage: f64,
    /// Traction coefficient `mu_t = T / N` (>= 0).
    pub traction_coefficient: f64,
    /// The rail's density, kg/m^3 (the mass-based wear laws).
    pub density: f64,
}

pub use crate::growth::config::WearPatch;

/// Hertz's line contact of a force per unit width over a half-width `a` (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinePatch {
    /// Load per unit width, N/m.
    pub load: f64,
    /// Half-width, m.
    pub a: f64,
}

impl LinePatch {
    /// The patch of `force` (N) over a width `w` (m) on a cylinder of radius `r` (m) with
    /// contact modulus `e_star` (Pa).
    pub fn new(force: f64, w: f64, r: f64, e_star: f64) -> Self {
        let load = (force / w).max(0.0);
        Self {
            load,
            a: (4.0 * load * r / (std::f64::consts::PI * e_star)).sqrt(),
        }
    }

    /// The pressure at `s` from the centre, Pa.
    pub fn pressure(&self, s: f64) -> f64 {
        if self.a <= 0.0 || s.abs() >= self.a {
            return 0.0;
        }
        2.0 * self.load * (self.a * self.a - s * s).sqrt()
            / (std::f64::consts::PI * self.a * self.a)
    }

    /// The load per unit width from `-a` to `s`, N/m (0 below `-a`, `load` above `a`).
    pub fn cumulative(&self, s: f64) -> f64 {
        if self.a <= 0.0 {
            return if s >= 0.0 { self.load } else { 0.0 };
        }
        let s = s.clamp(-self.a, self.a);
        let a2 = self.a * self.a;
        self.load / (std::f64::consts::PI * a2)
            * (s * (a2 - s * s).max(0.0).sqrt() + a2 * (s / self.a).asin())
            + 0.5 * self.load
    }
}

/// One pass of the wheel over the track (module docs).
#[derive(Debug, Clone)]
pub struct TrackPass {
    sc: Scenario,
    ts: TrackScenario,
    opts: RunOptions,
    law: WearLaw,
    sliding: Sliding,
    patch: WearPatch,
    x0: f64,
    dx: f64,
    n: usize,
    force: Vec<(f64, f64)>,
    flat: Option<FlatPass>,
}

/// What a pass over the smooth rail gives the prediction ([`predicted_growth`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct FlatPass {
    /// Mean contact force, N.
    pub force_n: f64,
    /// The contact spring (the force over the rail's deflection under the axle less the
    /// axle's), N/m.
    pub contact_stiffness_n_m: f64,
    /// Mean worn depth of the inner grid per newton of mean force, m/N.
    pub depth_per_newton_m_n: f64,
    /// The wheel's rim radius in the pass (spun, as its Hertz patch used), m.
    pub rim_radius_m: f64,
}

impl TrackPass {
    /// The passes of the first run of the track scenario `sc` on a grid of spacing `dx` (m),
    /// wearing by `law` with `sliding` under `patch`.
    ///
    /// # Errors
    /// [`RunError::Input`]: not a track scenario with the wheel, a spacing not between the
    /// step's travel and a tenth of a bay, a bad wear law or sliding.
    pub fn new(
        sc: &Scenario,
        dx: f64,
        law: WearLaw,
        sliding: Sliding,
        patch: WearPatch,
        opts: RunOptions,
    ) -> Result<Self, RunError> {
        let input = |m: String| RunError::input(&sc.path, m);
        let run = sc.runs.first().ok_or_else(|| input("no run".into()))?;
        let ts =
            match &run.model {
                m if m
                    .get::<crate::scenario::TrackScenario>()
                    .is_some_and(|t| t.vehicle.model == VehicleModel::Wheel) =>
                {
                    m.get::<crate::scenario::TrackScenario>()
                        .cloned()
                        .expect("checked")
                }
                _ => return Err(input(
                    "a rail's growth study needs kind = \"track\" with vehicle.model = \"wheel\""
                        .into(),
                )),
            };
        law.check().map_err(input)?;
        match sliding {
            Sliding::Steady(sliding) => {
                if !(sliding.creepage.is_finite()
                    && sliding.creepage > 0.0
                    && sliding.creepage < 1.0)
                {
                    return Err(input(format!(
                        "growth.creepage = {}: must be in (0, 1) (the rim's slip over the rolling speed)",
                        sliding.creepage
                    )));
                }
                if !(sliding.traction_coefficient.is_finite()
                    && sliding.traction_coefficient >= 0.0)
                {
                    return Err(input(format!(
                        "growth.traction_coefficient = {}: must be finite and >= 0",
                        sliding.traction_coefficient
                    )));
                }
            }
            Sliding::Dynamic { .. } => {
                if run.friction.is_none_or(|law| !law.is_active()) || ts.vehicle.creepage == 0.0 {
                    return Err(input(format!(
                        "growth.sliding = \"dynamic\" wears the rail by the run's own friction: set contact.friction > 0 and vehicle.creepage (with vehicle.suspension_stiffness > 0 and time.gamma > 0, as scenarios/track-traction.toml); this scenario has contact.friction {} and vehicle.creepage = {}",
                        if run.friction.is_some_and(|law| law.is_active()) { "> 0" } else { "= 0" },
                        ts.vehicle.creepage
                    )));
                }
            }
        }
        let s = ts.spec.spacing;
        let travel_step = ts.vehicle.speed * run.params.h;
        if !(dx.is_finite() && dx > 0.0 && dx <= 0.1 * s) {
            return Err(input(format!(
                "growth.dx = {dx} m: must be > 0 and at most a tenth of a sleeper bay ({} m)",
                0.1 * s
            )));
        }
        if dx > ts.rim_passage() * ts.vehicle.speed {
            return Err(input(format!(
                "growth.dx = {dx} m: must be at most the rim's pitch ({:.3e} m), which the wear is laid over (the step's travel is {travel_step:.3e} m)",
                ts.rim_passage() * ts.vehicle.speed
            )));
        }
        let x0 = ts.start() + ts.settle_distance();
        let length = ts.travel() - ts.settle_distance();
        let samples = (length / dx).floor() + 1.0;
        if samples > MAX_SAMPLES as f64 {
            // (A spacing of 1 nm asked for 1.2e9 samples: the study ran out of time and
            // memory, deaf to its keys.)
            return Err(input(format!(
                "growth.dx = {dx} m: gives {samples:.3e} samples over the recorded {length:.4} m (at most {MAX_SAMPLES}): a longer spacing"
            )));
        }
        let n = samples as usize;
        Ok(Self {
            sc: sc.clone(),
            ts,
            opts,
            law,
            sliding,
            patch,
            x0,
            dx,
            n,
            force: Vec::new(),
            flat: None,
        })
    }

    /// The samples of the grid away from the faded ends (`FADE_BAYS` bays each side).
    pub fn inner(&self) -> std::ops::Range<usize> {
        let fade = (FADE_BAYS * self.ts.spec.spacing / self.dx).ceil() as usize;
        fade.min(self.n)..self.n.saturating_sub(fade).max(fade.min(self.n))
    }

    /// The last pass's contact force along the rail: `(x, F)` at every step from the grid's
    /// start (`x` the rail's abscissa under the axle's centre, its drift included, where the
    /// patch is centred, m; `F` the contact force, N).
    pub fn last_force(&self) -> &[(f64, f64)] {
        &self.force
    }

    /// The contact modulus `E*` of Hertz's patch (module docs), Pa.
    pub fn contact_modulus(&self) -> f64 {
        let wheel = &self.ts.vehicle.wheel;
        match wheel.plane {
            crate::material::PlaneModel::Strain => {
                wheel.material.young / (1.0 - wheel.material.poisson.powi(2))
            }
            crate::material::PlaneModel::Stress => wheel.material.young,
        }
    }

    /// Hertz's patch of the force `force` (N) on this wheel (module docs).
    pub fn patch_of(&self, force: f64) -> LinePatch {
        LinePatch::new(
            force,
            self.ts.vehicle.wheel.thickness,
            self.ts.vehicle.wheel_radius,
            self.contact_modulus(),
        )
    }

    /// The last pass over the smooth rail, if one was run.
    pub fn flat(&self) -> Option<FlatPass> {
        self.flat
    }

    /// The growth predicted from the receptances ([`predicted_growth`]) at `wavelengths`
    /// (m), with the figures of a pass over the smooth rail (run here if none was).
    ///
    /// # Errors
    /// [`RunError`]: the pass, or a singular dynamic stiffness.
    pub fn prediction(
        &mut self,
        wavelengths: &[f64],
        interrupt: &AtomicBool,
    ) -> Result<(FlatPass, Vec<PredictedGrowth>), RunError> {
        let track = self
            .ts
            .spec
            .build()
            .map_err(|e| RunError::input(&self.sc.path, e.to_string()))?;
        self.prediction_on(&track, wavelengths, interrupt)
    }

    /// [`TrackPass::prediction`] on the built `track`.
    fn prediction_on(
        &mut self,
        track: &crate::bodies::rail::Track,
        wavelengths: &[f64],
        interrupt: &AtomicBool,
    ) -> Result<(FlatPass, Vec<PredictedGrowth>), RunError> {
        let flat = match self.flat {
            Some(f) => f,
            None => {
                let smooth = SurfaceProfile {
                    x0: self.x0,
                    dx: self.dx,
                    z: vec![0.0; self.n],
                    periodic: false,
                };
                self.run_pass(&smooth, 0, interrupt)?;
                self.flat.ok_or_else(|| {
                    RunError::input(&self.sc.path, "the smooth rail's pass gave no figures")
                })?
            }
        };
        let err =
            |e: crate::bodies::rail::TrackError| RunError::input(&self.sc.path, e.to_string());
        // Hertz's patch on the rim radius the pass's patch used.
        let a = LinePatch::new(
            flat.force_n,
            self.ts.vehicle.wheel.thickness,
            flat.rim_radius_m,
            self.contact_modulus(),
        )
        .a;
        let pred = predicted_growth(
            track,
            (self.ts.vehicle.unsprung_mass, flat.contact_stiffness_n_m),
            self.speed(),
            a,
            flat.depth_per_newton_m_n,
            wavelengths,
        )
        .map_err(err)?;
        Ok((flat, pred))
    }

    /// The track scenario.
    pub fn track(&self) -> &TrackScenario {
        &self.ts
    }

    /// The profile the gap sees: `z` faded in and out over [`FADE_BAYS`] bays.
    fn gap_profile(&self, z: &[f64]) -> Result<Profile, RunError> {
        let fade = FADE_BAYS * self.ts.spec.spacing;
        let len = (self.n - 1) as f64 * self.dx;
        let w = |x: f64| -> f64 {
            let d = x.min(len - x);
            if d >= fade {
                1.0
            } else if d <= 0.0 {
                0.0
            } else {
                0.5 * (1.0 - (std::f64::consts::PI * d / fade).cos())
            }
        };
        let values = z
            .iter()
            .enumerate()
            .map(|(i, &z)| z * w(i as f64 * self.dx))
            .collect();
        Profile::sampled(self.x0, self.dx, values)
            .map_err(|e| RunError::input(&self.sc.path, format!("the rail's profile: {e}")))
    }
}

impl PassRunner for TrackPass {
    fn grid(&self) -> (f64, f64, usize, bool) {
        (self.x0, self.dx, self.n, false)
    }

    fn speed(&self) -> f64 {
        self.ts.vehicle.speed
    }

    /// The track carries no state from pass to pass: the reference is its ordinary pass 0.
    fn run_reference(
        &mut self,
        profile: &SurfaceProfile,
        interrupt: &AtomicBool,
    ) -> Result<PassResult, RunError> {
        self.run_pass(profile, 0, interrupt)
    }

    /// None: a pass depends on the rail's profile alone.
    fn carried_state(&self) -> Option<Vec<f64>> {
        None
    }

    /// The heights against the wheel's radius (the rail's profile enters the contact gap
    /// only: no mesh to move).
    fn check_profile(&self, z: &[f64]) -> Result<(), String> {
        crate::growth::check_profile_height(z, self.ts.vehicle.wheel_radius)
    }

    fn restore_state(&mut self, state: Option<&[f64]>) -> Result<(), String> {
        crate::growth::no_carried_state(state)
    }

    fn extra_outputs(
        &mut self,
        out: &std::path::Path,
        bands: &[(f64, f64)],
        plots: bool,
        interrupt: &AtomicBool,
    ) -> Result<Vec<std::path::PathBuf>, RunError> {
        let (lo, hi) = (self.dx.max(8e-3), (self.n as f64 * self.dx / 4.0).min(1.0));
        let m = 160;
        let lams: Vec<f64> = (0..m)
            .map(|i| lo * (hi / lo).powf(i as f64 / (m - 1) as f64))
            .collect();
        let path = self.sc.path.clone();
        let err = |e: crate::bodies::rail::TrackError| RunError::input(&path, e.to_string());
        let track = self.ts.spec.build().map_err(err)?;
        let (flat, pred) = match self.prediction_on(&track, &lams, interrupt) {
            // Stopped in the smooth rail's pass: no prediction (the command says interrupted).
            Err(_) if interrupt.load(std::sync::atomic::Ordering::Relaxed) => return Ok(Vec::new()),
            r => r?,
        };
        let r = crate::bodies::rail::receptance::receptance(
            &track,
            &crate::bodies::rail::receptance::log_frequencies(20.0, 3000.0, 200),
        )
        .map_err(err)?;
        let v = &self.ts.vehicle;
        let f = crate::bodies::rail::receptance::frequencies(
            &track,
            &r,
            &crate::bodies::rail::receptance::Wheel {
                unsprung_mass: v.unsprung_mass,
                load: v.axle_load,
                radius: v.wheel_radius,
            },
        )
        .map_err(err)?;
        let mut marks = Vec::new();
        if let Some(pp) = f.pinned_pinned_hz {
            marks.push((pp, "pinned-pinned".to_string()));
        }
        if let Some(p2) = f.p2_hz {
            marks.push((p2, "P2".to_string()));
        }
        let wheels = if v.wheelbase.is_some() { 2 } else { 1 };
        write_prediction(out, (&flat, &pred), bands, (v.speed, &marks, wheels), plots)
    }

    fn run_pass(
        &mut self,
        profile: &SurfaceProfile,
        _pass: usize,
        interrupt: &AtomicBool,
    ) -> Result<PassResult, RunError> {
        if profile.z.len() != self.n {
            return Err(RunError::input(
                &self.sc.path,
                format!(
                    "the rail's profile has {} samples, the grid {}",
                    profile.z.len(),
                    self.n
                ),
            ));
        }
        let run = &self.sc.runs[0];
        let gap = self.gap_profile(&profile.z)?;
        let (wot, mut sim, steps) =
            crate::kinds::track::rolling::passage(&self.sc, run, &self.ts, &self.opts, Some(gap))?;
        let mut trace = std::mem::take(&mut self.force);
        trace.clear();
        trace.reserve(steps + 1);
        let mut wearing = Wearing::new(self, &wot, run.params.h, trace);
        let clock = Instant::now();
        let stats =
            sim.run(interrupt, |s| wearing.step(s))
                .map_err(|source| RunError::Simulation {
                    run: run.label.clone(),
                    source,
                })?;
        let wall = clock.elapsed().as_secs_f64();
        let w = wearing;
        if stats.interrupted {
            // Stopped within a step (the contract): the study drops this pass whole, as the
            // wheel's; no figures of the smooth rail are kept from it.
            return Ok(PassResult {
                wear_depth: vec![0.0; self.n],
                plastic: vec![0.0; self.n],
                scalars: Vec::new(),
            });
        }
        self.force = w.trace;
        let m = w.count.max(1) as f64;
        let mean = w.f_sum / m;
        let std = (w.f2_sum / m - mean * mean).max(0.0).sqrt();
        let k_c = mean / (w.squeeze / m);
        if profile.z.iter().all(|&z| z == 0.0) {
            let inner = self.inner();
            let d = w.depth[inner.clone()].iter().sum::<f64>() / inner.len().max(1) as f64;
            self.flat = Some(FlatPass {
                force_n: mean,
                contact_stiffness_n_m: k_c,
                depth_per_newton_m_n: d / mean,
                rim_radius_m: wot.rim_radius,
            });
        }
        Ok(PassResult {
            plastic: vec![0.0; self.n],
            wear_depth: w.depth,
            scalars: vec![
                ("mean_force_n".into(), mean),
                ("std_force_n".into(), std),
                ("max_force_n".into(), w.f_max),
                ("min_force_n".into(), w.f_min),
                ("contact_stiffness_n_m".into(), k_c),
                ("worn_volume_m3".into(), w.volume),
                ("worn_volume_off_grid_m3".into(), w.lost),
                ("loop_s".into(), wall),
                ("wear_bookkeeping_s".into(), w.bookkeeping.as_secs_f64()),
            ]
            .into_iter()
            .chain(self.ts.vehicle.wheelbase.map_or_else(Vec::new, |_| {
                // The second wheel over the same grid (its own force and friction).
                let m2 = w.trailing_count.max(1) as f64;
                let mut v = vec![("trailing_mean_force_n".into(), w.trailing_f_sum / m2)];
                if let Some(f) = w.trailing_friction {
                    v.push((
                        "trailing_traction_ratio".into(),
                        f.traction / w.trailing_f_sum,
                    ));
                    v.push((
                        "trailing_sliding_share".into(),
                        f.sliding_force / w.trailing_f_sum,
                    ));
                }
                v
            }))
            .chain(w.friction.map_or_else(Vec::new, |f| {
                let xi_v = self.ts.vehicle.creepage * self.ts.vehicle.speed;
                vec![
                    // The rail's force on the wheel along the travel (module `sliding`).
                    ("mean_traction_n".into(), f.traction / m),
                    ("traction_ratio".into(), f.traction / w.f_sum),
                    ("frictional_power_w".into(), f.power / m),
                    ("creep_power_w".into(), f.traction / m * xi_v),
                    ("sliding_share".into(), f.sliding_force / w.f_sum),
                ]
            }))
            .collect(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hat_lays_its_area_exactly_and_centred() {
        let (x0, dx) = (2.0, 1e-3);
        let mut d = vec![0.0; 200];
        for &(x, b, a) in &[
            (2.05, 4e-3, 3e-9),
            (2.1234, 4.1e-3, 1e-9),
            (2.0015, 4e-3, 2e-9),
        ] {
            let before: f64 = d.iter().sum::<f64>() * dx;
            assert!(lay_hat(&mut d, (x0, dx), x, b, a));
            let after: f64 = d.iter().sum::<f64>() * dx;
            assert!(((after - before) / a - 1.0).abs() < 1e-12);
        }
        // Centred: the first hat's centroid is its centre.
        let mut e = vec![0.0; 200];
        lay_hat(&mut e, (x0, dx), 2.0504, 4e-3, 1.0);
        let c: f64 = e
            .iter()
            .enumerate()
            .map(|(i, &v)| (x0 + i as f64 * dx) * v)
            .sum::<f64>()
            / e.iter().sum::<f64>();
        assert!((c - 2.0504).abs() < 1e-9, "{c}");
        assert!(!lay_hat(&mut e, (x0, dx), 1.0, 4e-3, 1.0));
    }
}

/// The patch filter of Hertz's line contact at wavenumber `k` (rad/m) and half-width `a`:
/// the Fourier transform of its normalised pressure, `2 J1(k a) / (k a)`
/// (`(2 / pi) int_{-1}^{1} sqrt(1 - u^2) cos(k a u) du`, by 128-point Gauss-Chebyshev
/// of the second kind, exact for this integrand's polynomial part and converged to 1e-12
/// for `k a < 20`).
pub fn hertz_filter(k: f64, a: f64) -> f64 {
    let z = k * a;
    if z == 0.0 {
        return 1.0;
    }
    let n = 128;
    let mut s = 0.0;
    for i in 1..=n {
        let th = i as f64 * std::f64::consts::PI / (n + 1) as f64;
        let (u, w) = (th.cos(), th.sin().powi(2));
        s += w * (z * u).cos();
    }
    2.0 / (n + 1) as f64 * s
}

/// The growth of a harmonic profile predicted from the receptances (module docs of
/// [`crate::kinds::track::growth`]), at one wavelength.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PredictedGrowth {
    /// Wavelength, m.
    pub wavelength_m: f64,
    /// `V / lambda`, Hz.
    pub frequency_hz: f64,
    /// The wear per pass in phase with the profile, per unit of its amplitude (> 0: the
    /// crests wear more, the profile decays).
    pub in_phase: f64,
    /// The same in quadrature (the pattern's drift along the rail).
    pub quadrature: f64,
}

/// The linear prediction of the rail's roughness growth from frequency-domain receptances,
/// independent of the time-domain passes: a profile `r e^{i k x}` under the wheel at speed
/// `V` is a displacement input at `f = V / lambda`; seen through the patch filter `F(k a)`,
/// it changes the contact force by `dN = F r / alpha`, `alpha = alpha_R + 1 / k_c -
/// 1 / (m_u omega^2)` (the rail's receptance averaged over a bay, the contact spring, the
/// unsprung mass as a rigid body), and the wear, `s_w dN` per pass (`s_w` the depth per
/// newton of the law: `k gamma / (H w)` for Archard), is laid through the same filter:
/// `dz / r = s_w F^2 / alpha`. Its real part is [`PredictedGrowth::in_phase`].
///
/// # Errors
/// [`crate::bodies::rail::TrackError`] when a dynamic stiffness is singular.
pub fn predicted_growth(
    track: &crate::bodies::rail::Track,
    (unsprung_mass, contact_stiffness): (f64, f64),
    speed: f64,
    half_width: f64,
    depth_per_newton: f64,
    wavelengths: &[f64],
) -> Result<Vec<PredictedGrowth>, crate::bodies::rail::TrackError> {
    let freqs: Vec<f64> = wavelengths.iter().map(|l| speed / l).collect();
    let rail = crate::bodies::rail::receptance::bay_averaged(track, &freqs, 8)?;
    Ok(wavelengths
        .iter()
        .zip(&freqs)
        .zip(&rail)
        .map(|((&l, &f), &ar)| {
            let w = 2.0 * std::f64::consts::PI * f;
            let alpha =
                ar + faer::c64::new(1.0 / contact_stiffness - 1.0 / (unsprung_mass * w * w), 0.0);
            let filt = hertz_filter(2.0 * std::f64::consts::PI / l, half_width);
            let g = faer::c64::new(depth_per_newton * filt * filt, 0.0) / alpha;
            PredictedGrowth {
                wavelength_m: l,
                frequency_hz: f,
                in_phase: g.re,
                quadrature: g.im,
            }
        })
        .collect())
}

impl PredictedGrowth {
    /// The growth rate of the profile's amplitude, dB per 1e5 real passes (each real pass
    /// multiplies it by `1 - in_phase`).
    pub fn rate_db_per_1e5(&self) -> f64 {
        1e5 * 20.0 * (1.0 - self.in_phase).abs().max(f64::MIN_POSITIVE).log10()
    }
}

/// Writes `prediction.csv` and (with `plots`) `prediction.png` into `out`: the growth rate
/// predicted from the receptances against wavelength, the study's band rates (`measured`:
/// `(band centre wavelength m, dB per 1e5 real passes)`) beside it, and the track's
/// frequencies at the run's speed (`marks`: `(frequency Hz, name)`). With `wheels = 2` (a
/// bogie's pass) the flat pass's wear per newton is both wheels' over the first's force, so
/// the prediction is that of two wheels that do not interact: the study's departures from
/// it are the wheels' interaction through the rail, and the figure says so.
///
/// # Errors
/// The file that cannot be written.
pub fn write_prediction(
    out: &std::path::Path,
    (flat, pred): (&FlatPass, &[PredictedGrowth]),
    measured: &[(f64, f64)],
    (speed, marks, wheels): (f64, &[(f64, String)], usize),
    plots: bool,
) -> Result<Vec<std::path::PathBuf>, RunError> {
    let csv = out.join("prediction.csv");
    let mut text = format!(
        "# growth of the rail's roughness predicted from the track's receptance (bay-averaged), the contact spring {:.4e} N/m, the unsprung mass as a rigid body and Hertz's patch filter; wear {:.4e} m per N of contact force per pass; V = {:.3} m/s\n",
        flat.contact_stiffness_n_m, flat.depth_per_newton_m_n, speed
    );
    crate::output::csv::push_record(
        &mut text,
        [
            "wavelength_m",
            "frequency_Hz",
            "in_phase_per_pass",
            "quadrature_per_pass",
            "growth_dB_per_1e5_passes",
        ],
    );
    for p in pred {
        crate::output::csv::push_record(
            &mut text,
            [
                p.wavelength_m,
                p.frequency_hz,
                p.in_phase,
                p.quadrature,
                p.rate_db_per_1e5(),
            ]
            .map(|x| format!("{x:.6e}")),
        );
    }
    crate::output::files::write_atomic(&csv, text.as_bytes())
        .map_err(|e| RunError::output(&csv, e))?;
    let mut files = vec![csv];
    if plots {
        use softway_plot::{line_plot, Panel, Series, SeriesStyle};
        let mut p = Panel::new(
            format!(
                "Rail roughness growth at {:.0} km/h: passes against the receptance prediction",
                3.6 * speed
            ),
            "wavelength [mm]",
            "growth rate [dB per 1e5 real passes]",
        );
        p.x_log = true;
        p.series.push(Series::new(
            if wheels > 1 {
                "predicted from the receptance for wheels that do not interact (linear, frequency domain)"
            } else {
                "predicted from the receptance (linear, frequency domain)"
            },
            pred.iter().map(|q| 1e3 * q.wavelength_m).collect(),
            pred.iter().map(PredictedGrowth::rate_db_per_1e5).collect(),
            SeriesStyle::Line,
        ));
        let (lo, hi) = pred.iter().fold((f64::INFINITY, 0.0f64), |(a, b), q| {
            (a.min(q.wavelength_m), b.max(q.wavelength_m))
        });
        // The study's bands over the prediction's range (shorter ones are the patch's and
        // the mesh's, longer ones hold a few periods of the profile).
        let shown: Vec<&(f64, f64)> = measured
            .iter()
            .filter(|m| m.0 >= lo && m.0 <= hi && m.1.is_finite())
            .collect();
        if !shown.is_empty() {
            p.series.push(Series::new(
                "the passes (one-third-octave bands)",
                shown.iter().map(|m| 1e3 * m.0).collect(),
                shown.iter().map(|m| m.1).collect(),
                SeriesStyle::Markers,
            ));
        }
        p.hlines.push((0.0, String::new()));
        for (f, name) in marks {
            let l = speed / f;
            if l >= lo && l <= hi {
                p.vlines.push((1e3 * l, format!("{name} {f:.0} Hz")));
            }
        }
        p.note = "Growth > 0: the roughness at that wavelength deepens pass after pass. Frequency = V / wavelength.".into();
        if wheels > 1 {
            p.note.push_str(&format!(
                " A pass is {wheels} wheels' (a bogie's): the prediction is one wheel's receptance with the pass's wear, the wheels not interacting."
            ));
        }
        let png = out.join("prediction.png");
        line_plot(&png, &p, (1200, 700)).map_err(|e| RunError::output(&png, e))?;
        files.push(png);
    }
    Ok(files)
}
