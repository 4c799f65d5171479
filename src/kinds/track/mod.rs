//! `kind = "track"`: a rail on its pads and sleepers (a UIC60 or UIC54 set), with a
//! constant load or the elastic wheel with its unsprung mass moving along it. Its tables:
//! `[track]`, `[vehicle]`, `[receptance]`, `[irregularity]`, `[contact]` (its `validate` module);
//! its runs: the moving load's and the rolling wheel's in `run`.

use crate::contact::{FrictionLaw, Restore, Treatment};
use crate::growth::config::{GrowthSurface, SlidingModel};
use crate::growth::GrowOptions;
use crate::growth::{GrowthConfig, GrowthError, PassRunner};
use crate::kinds::track::growth::{RailSliding, Sliding, TrackPass, WearPatch};
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::run::results::Results;
use crate::scenario::combinations::{Culprit, Family, Refusal};
use crate::scenario::kind::{Kind, KindInput, Model, RunView, Size, Spec};
use crate::scenario::raw::{RawIrregularity, RawReceptance, RawTrack, RawVehicle};
use crate::scenario::{Ctx, Run, Scenario, ScenarioError, TrackScenario, VehicleModel};
use crate::time::Integrator;
use std::path::Path;

pub mod growth;
pub(crate) mod moving;
pub mod polygon;
pub(crate) mod rolling;
pub(crate) mod validate;

/// The kind `track`.
pub struct TrackKind;

#[derive(serde::Deserialize)]
struct Tables {
    track: Option<RawTrack>,
    vehicle: Option<RawVehicle>,
    receptance: Option<RawReceptance>,
    irregularity: Option<RawIrregularity>,
}

impl Kind for TrackKind {
    fn name(&self) -> &'static str {
        "track"
    }

    fn studies(&self) -> &'static [&'static str] {
        &["receptance"]
    }

    fn tables(&self) -> &'static [&'static str] {
        &["track", "vehicle", "receptance", "irregularity", "contact"]
    }

    fn model(&self, input: &KindInput) -> Result<Model, ScenarioError> {
        let t = input.tables::<Tables>()?;
        Ok(Model::new(validate::track_model(
            input.cx,
            t.track,
            t.vehicle,
            (t.receptance, t.irregularity),
        )?))
    }
}

/// Why the moving load has no contact.
const MOVING_LOAD: &str =
    "vehicle.model = \"moving_load\" has no contact (a constant load moves along the rail)";

impl TrackScenario {
    /// Whether the wheel rolls along the rail (else a constant load moves).
    fn rolls(&self) -> bool {
        self.vehicle.model == VehicleModel::Wheel
    }
}

impl Spec for TrackScenario {
    crate::spec_plumbing!("track");

    fn dim(&self) -> usize {
        2
    }

    fn end_time(&self, cx: &Ctx, given: Option<f64>) -> Result<f64, ScenarioError> {
        if let Some(t) = given {
            return Err(cx.invalid(
                "time.t_end",
                t,
                "a track run lasts vehicle.travel_bays bays at vehicle.speed: remove time.t_end",
            ));
        }
        Ok(self.duration())
    }

    fn check_scenario(&self, cx: &Ctx, _: usize, contact_given: bool) -> Result<(), ScenarioError> {
        if contact_given && !self.rolls() {
            return Err(cx.invalid(
                "contact",
                "(given)",
                "vehicle.model = \"moving_load\" has no contact (a constant load moves along the rail): remove [contact]",
            ));
        }
        Ok(())
    }

    fn no_contact(&self) -> Option<&'static str> {
        (!self.rolls()).then_some(MOVING_LOAD)
    }

    fn default_method(&self) -> &'static str {
        "exact"
    }

    fn combination(
        &self,
        integrator: &Integrator,
        contact: &Treatment,
    ) -> Option<Result<(), Refusal>> {
        let refuse = |culprit, why: &str| {
            Some(Err(Refusal {
                culprit,
                why: why.into(),
            }))
        };
        if Family::of(integrator) == Family::Explicit {
            return refuse(
                Culprit::Integrator,
                "the track's explicit step is bounded by its stiff pads and short rail elements (consistent mass); use \"space_time\", \"newmark\", \"newmark_dissipative\", \"hht\" or \"generalized_alpha\"",
            );
        }
        if !matches!(
            contact,
            Treatment::Exact
                | Treatment::SoftWay {
                    restore: Restore::Nothing
                }
        ) {
            return refuse(
                Culprit::Contact,
                "the wheel on the track rolls with \"exact\" (the default) or \"soft_way_no_restore\": the soft way's momentum back, given at each release of a rim node re-braked inside the loaded patch, misses the static load by 1-2% and blows up at three steps a rim node (tests/rolling.rs); the other treatments are not checked on it",
            );
        }
        Some(Ok(()))
    }

    /// Friction on the wheel's contact with the rail needs the axle held along the track by
    /// the suspension ([`crate::bodies::rail::rolling`], Friction and creepage).
    fn check_friction(&self, cx: &Ctx, law: FrictionLaw) -> Result<(), ScenarioError> {
        if law.is_active() && !self.rolls() {
            return Err(cx.invalid(
                "contact.friction",
                law.static_mu,
                "vehicle.model = \"moving_load\" has no contact: remove the key or set it to 0",
            ));
        }
        if law.is_active() && self.vehicle.suspension_stiffness <= 0.0 {
            return Err(cx.invalid(
                "contact.friction",
                law.static_mu,
                "friction on the track needs vehicle.suspension_stiffness > 0 (N/m): only the suspension holds the axle along the track, a traction force would accelerate it for ever",
            ));
        }
        Ok(())
    }

    /// The wheel on the track with friction under the space-time scheme without numerical
    /// dissipation: loaded rim nodes stick for steps in full slip, and the creep force falls
    /// short of mu P, more so on finer rims (the book, docs/src/track.md).
    fn check_run(&self, cx: &Ctx, run: &RunView) -> Result<(), ScenarioError> {
        // A creepage transmits a force only through friction (as on the rigid base): refused
        // here, so that a sweep refuses it before any point runs.
        if self.vehicle.creepage != 0.0 && run.friction.is_none_or(|law| !law.is_active()) {
            return Err(cx.invalid(
                "vehicle.creepage",
                self.vehicle.creepage,
                "a creepage transmits a force only through friction: set contact.friction > 0 (with vehicle.suspension_stiffness > 0 and time.gamma > 0, as scenarios/track-traction.toml) or remove vehicle.creepage",
            ));
        }
        let (alpha, gamma) = run.alpha_gamma;
        if let Some(law) = run.friction {
            if law.is_active() && run.integrator.1 == "space_time" && gamma == 0.0 && alpha < 1.0 {
                return Err(cx.invalid(
                    &run.gamma_key,
                    gamma,
                    "friction on the track needs time.gamma > 0 (0.2, as scenarios/track-traction.toml) or time.alpha = 1: with gamma = 0 loaded rim nodes stick for steps in full slip and the creep force falls short of mu P (by 21% on 1440 rim nodes at 40 m/s)",
                ));
            }
        }
        Ok(())
    }

    fn default_step(&self) -> Option<f64> {
        self.rolls().then(|| self.rim_passage() / 3.0)
    }

    fn check_step(&self, cx: &Ctx, key: &str, h: f64) -> Result<(), ScenarioError> {
        let pass = self.rim_passage();
        if self.rolls() && h > 0.5 * pass {
            return Err(cx.invalid(
                key,
                h,
                &format!(
                    "a rim node passes the contact in {pass:.3e} s (the rim's pitch over the speed, vehicle.wheel_rim_nodes and vehicle.speed): the step must be at most half that, {:.3e} s (without time.h: a third)",
                    0.5 * pass
                ),
            ));
        }
        Ok(())
    }

    fn size(&self, _: &Run, _: Option<usize>) -> Size {
        let s = &self.spec;
        let mut dofs = 2.0 * (s.bays * s.elements_per_bay + 1) as f64 + (s.bays + 1) as f64;
        let mut pairs = 2.0;
        let mut key = "track.bays";
        if self.rolls() {
            let r = self.vehicle.wheel.rim_nodes as f64;
            let wheel = 2.0 * 1.2 * r * r.ln() + 2.0;
            // The key that sets the size: the wheel's rim when its dofs (or the contact
            // rows' dense blocks, 16 rows^2 bytes) outweigh the rail's.
            if wheel > dofs || 16.0 * r * r > 4096.0 * dofs {
                key = "vehicle.wheel_rim_nodes";
            }
            dofs += wheel;
            pairs = r;
        }
        Size {
            dofs,
            duration: self.duration(),
            contact_pairs: pairs,
            key: Some(key),
            factor_entries: None,
            kept_columns: 0.0,
        }
    }

    fn study(&self, command: &str) -> Option<&dyn crate::scenario::kind::Study> {
        (command == "receptance")
            .then_some(&moving::TrackReceptance as &dyn crate::scenario::kind::Study)
    }

    fn growth_runner(
        &self,
        sc: &Scenario,
        config: &GrowthConfig,
        opts: &GrowOptions,
    ) -> Result<Box<dyn PassRunner>, GrowthError> {
        let need = |key: &str, v: Option<f64>, what: &str| {
            v.ok_or_else(|| {
                GrowthError::Run(RunError::input(
                    &sc.path,
                    format!("growth.{key} is missing: {what}"),
                ))
            })
        };
        let r = &config.rail;
        let density = config.wear_density.unwrap_or(7850.0);
        if r.surface == Some(GrowthSurface::Wheel) {
            // The rail's keys have no meaning for the wheel's rim (one sample per rim
            // node, the run's own friction).
            let misplaced = [
                ("growth.dx", r.dx.is_some()),
                ("growth.creepage", r.creepage.is_some()),
                (
                    "growth.traction_coefficient",
                    r.traction_coefficient.is_some(),
                ),
                ("growth.patch", r.patch.is_some()),
                (
                    "growth.sliding = \"steady\"",
                    r.sliding == Some(SlidingModel::Steady),
                ),
            ];
            if let Some(key) = misplaced.iter().find_map(|&(k, given)| given.then_some(k)) {
                return Err(GrowthError::Run(RunError::input(
                    &sc.path,
                    format!("{key} is the rail's: with growth.surface = \"wheel\" the profile is one sample per rim node and the wear the run's own friction (contact.friction, vehicle.creepage); remove it"),
                )));
            }
            let pass = crate::kinds::track::polygon::WheelTrackPass::new(
                sc,
                config.wear,
                density,
                RunOptions {
                    progress: false,
                    par: Some(opts.par),
                    ..RunOptions::default()
                },
            )?;
            return Ok(Box::new(pass));
        }
        let sliding = match r.sliding.unwrap_or(SlidingModel::Steady) {
            SlidingModel::Steady => Sliding::Steady(RailSliding {
                creepage: need("creepage", r.creepage, "the rim's steady slip over the rolling speed (or growth.sliding = \"dynamic\": the run's own friction; e.g. 0.005)")?,
                traction_coefficient: need("traction_coefficient", r.traction_coefficient, "T / N of the steady creep force (e.g. 0.3)")?,
                density,
            }),
            SlidingModel::Dynamic => {
                if let Some(key) = [
                    ("growth.creepage", r.creepage.is_some()),
                    ("growth.traction_coefficient", r.traction_coefficient.is_some()),
                ]
                .into_iter()
                .find_map(|(k, given)| given.then_some(k))
                {
                    return Err(GrowthError::Run(RunError::input(
                        &sc.path,
                        format!("{key} is the steady model's: with growth.sliding = \"dynamic\" the creepage is vehicle.creepage and the traction the run's own friction (contact.friction); remove {key}"),
                    )));
                }
                Sliding::Dynamic { density }
            }
        };
        let pass = TrackPass::new(
            sc,
            r.dx.unwrap_or(1e-3),
            config.wear,
            sliding,
            r.patch.unwrap_or(WearPatch::Hertz),
            RunOptions {
                progress: false,
                par: Some(opts.par),
                ..RunOptions::default()
            },
        )?;
        Ok(Box::new(pass))
    }

    fn record(
        &self,
        sc: &Scenario,
        stream: Option<&Path>,
        opts: &RunOptions,
    ) -> Result<Results, RunError> {
        if self.rolls() {
            crate::kinds::track::rolling::record(sc, stream, opts)
        } else {
            crate::kinds::track::moving::record(sc, stream, opts)
        }
    }
}
