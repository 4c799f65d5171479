//! `kind = "rolling3d"`: the 3D wheel rolling in its own frame on the rigid base, with the
//! longitudinal, lateral and spin creepages of [`crate::contact::RotatingBase`]
//! ([`crate::bodies::rolling3d::RollingSlice`]: the paper's rotating frame, §4, in 3D), the
//! friction law of `[contact]` on every rim node, the soft way (or the exact treatment).
//!
//! Its tables (every key has a default):
//!
//! ```toml
//! [wheel]
//! radius_m = 0.1
//! bore_m = 0.04               # held there
//! thickness_m = 0.01          # along the axle
//! mesh = [12, 192, 1]         # rings, sectors and layers of hexahedra
//! young_GPa = 205.0
//! poisson = 0.3
//! density = 7830.0            # kg/m^3
//! lumped = false
//! cyclic_columns = true       # the contact's columns turned from one sector's
//! # zone_sectors = 3072       # a refined zone that follows the contact (Fig. 4b in 3D):
//! #                           # the rim's pitch in the zone as a count round the rim,
//! #                           # mesh's sectors times 1, 2, 4, ...
//! # zone_deg = 30.0           # the zone's width, degrees
//! # zone_growth = 1.2         # the rings graded from the rim, the first as thick as the
//! #                           # zone's pitch (mesh's rings set the outer cells' size)
//! # zone_depth_mm = 4.0       # and refined in depth: a ring at depth d at most
//! #                           # s_f (1 + (d / l)^2) thick (s_f the zone's pitch)
//! # zone_axial_mm = 3.0       # and across the width: layers as wide as the zone's pitch
//! #                           # within this half-width of the mid-plane, growing by
//! #                           # zone_growth outward (mesh's layers set the outer size)
//! [rolling]
//! omega = 300.0               # rad/s (or speed_km_h = 3.6 omega radius_m)
//! # speed_km_h = 108.0        # the rim's speed, km/h, in place of omega
//! flattening_mm = 1.0         # the base pressed into the rim
//! settle_ms = 3.0             # the flattening's ramp (or settle_mm, the distance the rim
//! #                           # rolls in it: the same ramp at every speed)
//! # step_mm = 0.075           # the distance the rim rolls in a step, in place of time.h
//! #                           # (time.h = step_mm / speed): the same steps at every speed
//! creepage = 0.0              # longitudinal xi (> 0: the wheel drives)
//! lateral_creepage = 0.0      # eta
//! spin_creepage = 0.0         # phi, 1/m
//! # crown_radius_m = 0.1      # the base's crown across the rolling direction (a rail
//! #                           # head's): the patch is Hertz's ellipse, centred on the
//! #                           # wheel's mid-plane (none: a plane)
//! turns = 0.5                 # the run's length (or time.t_end)
//! # coupling = "uncoupled"    # Kalker's pair of one material: a twin wheel carries the
//! #                           # tangential tractions (twice the unknowns; default
//! #                           # "coupled": the elastic wheel on its rigid base)
//! # reference_curve = "ref.csv" # another code's creep curve to draw and measure the
//! #                           # run against (relative to the scenario's folder;
//! #                           # crate::analysis::reference_curve)
//! # [rail]                    # an elastic rail of the wheel's material in place of the
//! #                           # rigid base (crate::bodies::rolling3d::rail): a bar with
//! #                           # the base's crown whose frame moves under the wheel, its
//! #                           # foot held; coupled only (its spin creepage: the
//! #                           # rail's material turning under its mesh, a rigid slip)
//! # profile = "bar"           # or "uic60": the 60E1 section (its own height and width;
//! #                           # rolling.crown_radius_m defaults to its crest's 0.3 m)
//! # inclination = 0.0         # the UIC60 rail's, tan of the angle (1:40 = 0.025)
//! # height_mm = 20.0          # crest to foot (default: the wheel's thickness or a fifth
//! #                           # of its radius, the larger)
//! # width_mm = 10.0           # across (default: the wheel's thickness)
//! # pitch_mm = 1.6            # cells along the rail, and across and in depth near the
//! #                           # crest (default: the rim's pitch, the zone's with a zone)
//! # fine_half_width_mm = 3.5  # the fine cells across (default: wheel.zone_axial_mm, or
//! #                           # about the crown's Hertz semi-axis, or the whole width)
//! # fine_depth_mm = 2.0       # and in depth (default: wheel.zone_depth_mm, or as across)
//! # growth = 1.4              # beyond them (default: wheel.zone_growth, or 1.3)
//! # margin_mm = 28.0          # rail ahead of the patch at the start and behind it at the
//! #                           # end (default: the height or 8 fine half-widths, the
//! #                           # larger); the rail is as long as the run's rolling and two
//! #                           # margins
//! # periodic = true           # the bar's ends joined: a ring of equal stations, no free
//! #                           # end, its contact columns shifted from one station's
//! #                           # (default for the bar; false: free ends, each column
//! #                           # solved; the UIC60 rail's graded margins are open)
//! # length_mm = 80.0          # a closed rail's length (at least two margins and two
//! #                           # pitches; default: the run's rolling and two margins):
//! #                           # shorter, the ring is rolled over again, its labels
//! #                           # shifted a station at a time to keep its seam ahead
//! ```
//!
//! `[time]` gives the step (`time.h`, required) and the space-time scheme's `alpha` and
//! `gamma`; `[contact]` the treatment (`soft_way`, its variants, or `exact`) and the
//! friction law (`friction`, `friction_kinetic`, `friction_velocity`; none: frictionless).
//! What a run writes: [`run`].

use crate::analysis::reference_curve::ReferenceCurve;
use crate::bodies::rolling3d::{RailProfile, SliceSpec, SliceZone};
use crate::bodies::wheel::Coupling;
use crate::contact::obstacle::Flattening;
use crate::contact::Treatment;
use crate::material::Elastic;
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::run::results::Results;
use crate::scenario::combinations::Refusal;
use crate::scenario::kind::{Culprit, FreeStep, Kind, KindInput, Model, Size, Spec};
use crate::scenario::{Ctx, Run, Scenario, ScenarioError};
use crate::time::Integrator;
use std::f64::consts::PI;
use std::path::Path;

mod rail;
pub mod run;

/// The run's length in turns when neither `rolling.turns` nor `time.t_end` is given.
pub const DEFAULT_TURNS: f64 = 0.5;

/// Entries of the LU factor of a slice of `dofs` unknowns (nested dissection; the implicit
/// Coriolis term makes the step's matrix unsymmetric), an upper estimate for the cost
/// check: `12 n^{4/3}`. Measured (`softway matrix`): 9.4 `n^{4/3}` at 14,976 unknowns
/// (12 x 192 x 1), 10.3 at 86,400 (24 x 384 x 2), 6.7 at 225,792 (48 x 768 x 1); the
/// generic 3D bound's 24 ([`crate::build::factor_entries_3d`]) put the last at 22 GB
/// against its measured 4.1 GB peak.
pub fn factor_entries(dofs: f64) -> f64 {
    12.0 * dofs.powf(4.0 / 3.0)
}

/// The kind `rolling3d`.
pub struct Rolling3dKind;

/// `[wheel]` as written.
#[derive(serde::Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawWheel {
    radius_m: Option<f64>,
    bore_m: Option<f64>,
    thickness_m: Option<f64>,
    mesh: Option<Vec<i64>>,
    #[serde(rename = "young_GPa")]
    young_gpa: Option<f64>,
    poisson: Option<f64>,
    density: Option<f64>,
    lumped: Option<bool>,
    cyclic_columns: Option<bool>,
    zone_sectors: Option<i64>,
    zone_deg: Option<f64>,
    zone_growth: Option<f64>,
    zone_depth_mm: Option<f64>,
    zone_axial_mm: Option<f64>,
}

/// `[rolling]` as written.
#[derive(serde::Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawRolling {
    omega: Option<f64>,
    speed_km_h: Option<f64>,
    flattening_mm: Option<f64>,
    settle_ms: Option<f64>,
    settle_mm: Option<f64>,
    step_mm: Option<f64>,
    creepage: Option<f64>,
    lateral_creepage: Option<f64>,
    spin_creepage: Option<f64>,
    crown_radius_m: Option<f64>,
    turns: Option<f64>,
    reference_curve: Option<String>,
    coupling: Option<String>,
}

/// `[rail]` as written.
#[derive(serde::Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawRail {
    profile: Option<String>,
    inclination: Option<f64>,
    height_mm: Option<f64>,
    width_mm: Option<f64>,
    pitch_mm: Option<f64>,
    fine_half_width_mm: Option<f64>,
    fine_depth_mm: Option<f64>,
    growth: Option<f64>,
    margin_mm: Option<f64>,
    periodic: Option<bool>,
    length_mm: Option<f64>,
}

#[derive(serde::Deserialize)]
struct Tables {
    wheel: Option<RawWheel>,
    rolling: Option<RawRolling>,
    rail: Option<RawRail>,
}

/// The validated 3D rolling: the slice to build and the run's length.
#[derive(Debug, Clone, PartialEq)]
pub struct Rolling3dScenario {
    /// The wheel, its mesh, spin, flattening and creepages.
    pub slice: SliceSpec,
    /// `rolling.turns` when given.
    pub turns: Option<f64>,
    /// `wheel.cyclic_columns`: the contact's columns turned from one sector's (the rim
    /// repeats round the axle; [`crate::contact::cyclic`]) instead of each solved.
    pub cyclic_columns: bool,
    /// `rolling.reference_curve`: another code's creep curve the run and a creep sweep are
    /// measured against ([`crate::analysis::reference_curve`]).
    pub reference: Option<ReferenceCurve>,
    /// `rolling.step_mm` in metres: the distance the rim (`omega wheel.radius_m`) rolls in
    /// a step, which sets the step `h = step / (omega radius)` in place of `time.h`.
    pub step_rolled: Option<f64>,
}

impl Rolling3dScenario {
    /// The slice of a run of `t_end` s: an elastic rail long enough for the rolling
    /// ([`crate::bodies::rolling3d::RailBlock::rolled`]: the rim's travel with its creepages, and 1 % more).
    pub fn slice_for(&self, t_end: f64) -> SliceSpec {
        let mut slice = self.slice;
        if let Some(rail) = slice.rail.as_mut() {
            let [xi, eta, _] = slice.creepages;
            rail.rolled = 1.01 * slice.omega * slice.radius * (1.0 + xi.abs() + eta.abs()) * t_end;
        }
        slice
    }

    /// The wheel's turn, s.
    pub fn period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.slice.omega
    }

    /// The end of the flattening's ramp and of a settling as long again, s: the steady
    /// rolling's figures are taken after it ([`run`]).
    pub fn settled(&self) -> f64 {
        2.0 * self.slice.flattening.settle_time
    }

    /// Nodes of the model: the annulus's, twice over with an uncoupled twin.
    pub fn nodes(&self) -> usize {
        let [nr, nt, nz] = self.stations();
        let copies = match self.slice.coupling {
            Coupling::Coupled => 1,
            Coupling::Uncoupled => 2,
        };
        copies * (nr + 1) * nt * (nz + 1)
    }

    /// Rings, stations round the rim and layers of the mesh: `wheel.mesh`'s, or with a
    /// refined zone its graded rings and stations ([`crate::mesh::zone3d`]; `wheel.mesh`'s
    /// when the zone cannot be built, which the run then reports).
    pub fn stations(&self) -> [usize; 3] {
        let s = &self.slice;
        s.zone_options()
            .and_then(|o| crate::mesh::zone3d::annulus_zone_counts(&o).ok())
            .map_or(s.counts, |(stations, rings, layers)| {
                [rings, stations, layers]
            })
    }
}

impl Kind for Rolling3dKind {
    fn name(&self) -> &'static str {
        "rolling3d"
    }

    fn tables(&self) -> &'static [&'static str] {
        &["wheel", "rolling", "rail", "contact"]
    }

    fn model(&self, input: &KindInput) -> Result<Model, ScenarioError> {
        let cx = input.cx;
        let t = input.tables::<Tables>()?;
        let w = t.wheel.unwrap_or_default();
        let r = t.rolling.unwrap_or_default();
        let radius = cx.within("wheel.radius_m", w.radius_m.unwrap_or(0.1), 0.01, 2.0)?;
        let bore = w.bore_m.unwrap_or(0.4 * radius);
        if !(bore.is_finite() && bore > 0.0 && bore < 0.95 * radius) {
            return Err(cx.invalid(
                "wheel.bore_m",
                bore,
                &format!("must be > 0 and below 0.95 wheel.radius_m = {radius}"),
            ));
        }
        let thickness = cx.within(
            "wheel.thickness_m",
            w.thickness_m.unwrap_or(0.1 * radius),
            1e-4,
            radius,
        )?;
        let mesh = w.mesh.clone().unwrap_or_else(|| vec![12, 192, 1]);
        let counts = match mesh[..] {
            [a, b, c] if a >= 1 && b >= 8 && c >= 1 && a <= 512 && b <= 8192 && c <= 64 => {
                [a as usize, b as usize, c as usize]
            }
            _ => {
                return Err(cx.invalid(
                    "wheel.mesh",
                    format!("{mesh:?}"),
                    "[rings, sectors, layers] of hexahedra: rings within [1, 512], sectors within [8, 8192], layers within [1, 64]",
                ))
            }
        };
        let young = cx.within("wheel.young_GPa", w.young_gpa.unwrap_or(205.0), 1e-3, 1e4)?;
        let poisson = cx.within("wheel.poisson", w.poisson.unwrap_or(0.3), 0.0, 0.49)?;
        let density = cx.within("wheel.density", w.density.unwrap_or(7830.0), 1.0, 1e5)?;
        let omega = match (r.omega, r.speed_km_h) {
            (Some(_), Some(v)) => {
                return Err(cx.invalid(
                    "rolling.speed_km_h",
                    v,
                    "given with rolling.omega: give one of them (speed_km_h = 3.6 omega wheel.radius_m)",
                ))
            }
            (None, Some(v)) => {
                cx.within("rolling.speed_km_h", v, 1e-3, 1e4)? / 3.6 / radius
            }
            (omega, None) => cx.within("rolling.omega", omega.unwrap_or(300.0), 1e-3, 1e5)?,
        };
        let speed = omega * radius;
        let depth = cx.within(
            "rolling.flattening_mm",
            r.flattening_mm.unwrap_or(1.0),
            0.0,
            100.0 * radius,
        )?;
        let settle = match (r.settle_ms, r.settle_mm) {
            (Some(_), Some(l)) => {
                return Err(cx.invalid(
                    "rolling.settle_mm",
                    l,
                    "given with rolling.settle_ms: give one of them (settle_mm = settle_ms times the rim's speed in m/s)",
                ))
            }
            (None, Some(l)) => cx.within("rolling.settle_mm", l, 0.0, 1e6)? / speed,
            (ms, None) => cx.within("rolling.settle_ms", ms.unwrap_or(3.0), 0.0, 1e4)?,
        };
        let step_rolled = r
            .step_mm
            .map(|l| cx.within("rolling.step_mm", l, 1e-6, 1e3))
            .transpose()?
            .map(|l| 1e-3 * l);
        let creep =
            |key: &str, v: Option<f64>, lim: f64| cx.within(key, v.unwrap_or(0.0), -lim, lim);
        let xi = creep("rolling.creepage", r.creepage, 1.0)?;
        let eta = creep("rolling.lateral_creepage", r.lateral_creepage, 1.0)?;
        let phi = creep("rolling.spin_creepage", r.spin_creepage, 1e3)?;
        let coupling = match r.coupling.as_deref() {
            None | Some("coupled") => Coupling::Coupled,
            Some("uncoupled") => Coupling::Uncoupled,
            Some(other) => {
                return Err(cx.invalid(
                    "rolling.coupling",
                    format!("\"{other}\""),
                    "\"coupled\" (the elastic wheel on its rigid base) or \"uncoupled\" (Kalker's pair of one material: a twin wheel carries the tangential tractions)",
                ))
            }
        };
        // The patch's half-length along the rim, about Hertz's `sqrt(R delta)` (the zone's
        // check below).
        let patch_half = (radius * 1e-3 * depth).sqrt();
        let zone = match (
            w.zone_sectors,
            w.zone_deg,
            w.zone_growth,
            w.zone_depth_mm.or(w.zone_axial_mm),
        ) {
            (None, None, None, None) => None,
            (None, ..) => {
                return Err(cx.invalid(
                    if w.zone_deg.is_some() {
                        "wheel.zone_deg"
                    } else if w.zone_growth.is_some() {
                        "wheel.zone_growth"
                    } else if w.zone_depth_mm.is_some() {
                        "wheel.zone_depth_mm"
                    } else {
                        "wheel.zone_axial_mm"
                    },
                    "given",
                    "a key of the moving refined zone: give wheel.zone_sectors too",
                ))
            }
            (Some(z), deg, growth, _) => {
                let depth = w.zone_depth_mm;
                let nt = counts[1];
                let ratio = usize::try_from(z).unwrap_or(0) / nt;
                if z < nt as i64 || z > 1 << 20 || z % nt as i64 != 0 || !ratio.is_power_of_two() {
                    return Err(cx.invalid(
                        "wheel.zone_sectors",
                        z,
                        &format!("the rim's pitch in the zone as a count round the rim: wheel.mesh's sectors ({nt}) times 1, 2, 4, ... (at most 1048576)"),
                    ));
                }
                let deg = cx.within("wheel.zone_deg", deg.unwrap_or(30.0), 0.01, 170.0)?;
                // The zone relocates by one of the mesh's sectors when the patch has moved
                // that far: the patch must stay inside it until then, half a sector off its
                // centre and its own half-length on (else a coarse rim node enters the patch).
                let least = (PI / nt as f64 + patch_half / radius).to_degrees() * 2.0;
                if deg < least {
                    return Err(cx.invalid(
                        "wheel.zone_deg",
                        deg,
                        &format!("at least {least:.1}: the zone relocates by one of wheel.mesh's {nt} sectors ({:.1} degrees) as the patch moves, so it must hold the patch (about {:.1} mm long at this flattening) half a sector off its centre; widen the zone, or give wheel.mesh more sectors", 360.0 / nt as f64, 2e3 * patch_half),
                    ));
                }
                let growth = cx.within("wheel.zone_growth", growth.unwrap_or(1.2), 1.01, 2.0)?;
                let depth = depth
                    .map(|l| cx.within("wheel.zone_depth_mm", l, 1e-3, 1e3 * radius))
                    .transpose()?;
                if w.cyclic_columns == Some(true) {
                    return Err(cx.invalid(
                        "wheel.cyclic_columns",
                        true,
                        "a rim with a refined zone does not repeat round the axle: remove wheel.cyclic_columns (the patch stays under the base in the zone's frame, on the same nodes)",
                    ));
                }
                let axial = w
                    .zone_axial_mm
                    .map(|l| cx.within("wheel.zone_axial_mm", l, 1e-3, 0.5e3 * thickness))
                    .transpose()?;
                Some(SliceZone {
                    sectors: z as usize,
                    width: deg.to_radians(),
                    growth: Some(growth),
                    depth: depth.map(|l| 1e-3 * l),
                    axial: axial.map(|l| 1e-3 * l),
                })
            }
        };
        let crown = r
            .crown_radius_m
            .map(|c| cx.within("rolling.crown_radius_m", c, 0.5 * thickness, 1e3))
            .transpose()?;
        let turns = r
            .turns
            .map(|v| cx.within("rolling.turns", v, 1e-3, 1e3))
            .transpose()?;
        let reference = r
            .reference_curve
            .as_deref()
            .map(|f| {
                let path = cx.path().parent().unwrap_or(Path::new(".")).join(f);
                ReferenceCurve::load(&path).map_err(|why| {
                    cx.invalid(
                        "rolling.reference_curve",
                        format!("\"{f}\""),
                        &format!("a CSV of the columns creepage_mu_a_R and traction_ratio, relative to the scenario's folder: {why}"),
                    )
                })
            })
            .transpose()?;
        let rail = t
            .rail
            .map(|rail| {
                let sectors = zone.map_or(counts[1], |z| z.sectors);
                rail::rail_block(
                    cx,
                    &rail,
                    &w,
                    &r,
                    (radius, thickness, sectors),
                    (depth, crown, zone),
                )
            })
            .transpose()?;
        // The UIC60 head's crest radius sets Hertz's ellipse of the summary.
        let crown = crown.or(rail
            .filter(|b| matches!(b.profile, RailProfile::Uic60 { .. }))
            .map(|_| 0.3));
        let scenario = Rolling3dScenario {
            slice: SliceSpec {
                radius,
                bore,
                thickness,
                counts,
                material: Elastic {
                    young: 1e9 * young,
                    poisson,
                    density,
                },
                lumped: w.lumped.unwrap_or(false),
                omega,
                flattening: Flattening {
                    depth: 1e-3 * depth,
                    settle_time: 1e-3 * settle,
                },
                creepages: [xi, eta, phi],
                zone,
                crown,
                coupling,
                rail,
            },
            turns,
            cyclic_columns: w.cyclic_columns.unwrap_or(zone.is_none() && rail.is_none()),
            reference,
            step_rolled,
        };
        if let (Some(o), Some(z)) = (scenario.slice.zone_options(), zone) {
            crate::mesh::zone3d::annulus_zone_counts(&o).map_err(|e| {
                let (key, value) = match (&e, w.zone_axial_mm) {
                    (crate::mesh::generators::MeshError::OutOfRange { name, .. }, Some(l))
                        if name.starts_with("zone_axial") =>
                    {
                        ("wheel.zone_axial_mm", l)
                    }
                    _ => ("wheel.zone_deg", z.width.to_degrees()),
                };
                cx.invalid(key, value, &format!("the zone cannot be built: {e}"))
            })?;
        }
        Ok(Model::new(scenario))
    }
}

impl Spec for Rolling3dScenario {
    crate::spec_plumbing!("rolling3d");

    fn dim(&self) -> usize {
        3
    }

    fn end_time(&self, cx: &Ctx, given: Option<f64>) -> Result<f64, ScenarioError> {
        match (given, self.turns) {
            (Some(t), Some(_)) => Err(cx.invalid(
                "time.t_end",
                t,
                "rolling.turns sets the run's length: give one of the two",
            )),
            (Some(t), None) => Ok(t),
            (None, turns) => Ok(turns.unwrap_or(DEFAULT_TURNS) * self.period()),
        }
    }

    fn coriolis(&self) -> Option<String> {
        None
    }

    fn default_step(&self) -> Option<f64> {
        self.step_rolled
            .map(|l| l / (self.slice.omega * self.slice.radius))
    }

    fn check_step(&self, cx: &Ctx, key: &str, h: f64) -> Result<(), ScenarioError> {
        match self.default_step() {
            Some(own) if (h - own).abs() > 1e-12 * own => Err(cx.invalid(
                key,
                h,
                &format!(
                    "rolling.step_mm sets the step (h = {own:.4e} s at this speed): give one of the two"
                ),
            )),
            _ => Ok(()),
        }
    }

    fn check_scenario(
        &self,
        cx: &Ctx,
        runs: usize,
        _contact_given: bool,
    ) -> Result<(), ScenarioError> {
        if runs > 1 {
            return Err(cx.invalid(
                "runs",
                runs,
                "kind = \"rolling3d\" takes one run: compare settings with `softway sweep`",
            ));
        }
        Ok(())
    }

    fn combination(
        &self,
        integrator: &Integrator,
        contact: &Treatment,
    ) -> Option<Result<(), Refusal>> {
        if !matches!(integrator, Integrator::SpaceTime { .. }) {
            return Some(Err(Refusal {
                culprit: Culprit::Integrator,
                why: "the 3D rolling runs the space-time scheme (\"space_time\")".into(),
            }));
        }
        if !matches!(contact, Treatment::SoftWay { .. } | Treatment::Exact) {
            return Some(Err(Refusal {
                culprit: Culprit::Contact,
                why: "the 3D rolling runs \"soft_way\" (or its variants) or \"exact\"".into(),
            }));
        }
        Some(Ok(()))
    }

    fn size(&self, run: &Run, _: Option<usize>) -> Size {
        let [_, nt, nz] = self.stations();
        let rim = (nt * (nz + 1)) as f64;
        // An elastic rail: a block of its own in the matrix.
        let rail_dofs = self
            .slice_for(run.t_end)
            .rail
            .map_or(0.0, |b| 3.0 * b.nodes(b.rolled) as f64);
        Size {
            dofs: 3.0 * self.nodes() as f64 + rail_dofs,
            duration: run.t_end,
            contact_pairs: rim,
            // The patch and the band it sweeps lie on the zone's fine rim nodes: their three
            // dofs, and their twins' three.
            kept_columns: self
                .slice
                .zone_options()
                .and_then(|o| crate::mesh::zone3d::annulus_zone_fine_rim(&o).ok())
                .map_or(0.0, |(along, across)| {
                    let per_node = match self.slice.coupling {
                        Coupling::Coupled => 3.0,
                        Coupling::Uncoupled => 6.0,
                    };
                    per_node * (along * across) as f64
                }),
            key: Some("wheel.mesh"),
            // A twin is a second block of the matrix: twice one wheel's factor.
            factor_entries: Some(
                match self.slice.coupling {
                    Coupling::Coupled => factor_entries(3.0 * self.nodes() as f64),
                    Coupling::Uncoupled => 2.0 * factor_entries(1.5 * self.nodes() as f64),
                } + factor_entries(rail_dofs),
            ),
        }
    }

    fn free_step(&self, run: &Run, scenario: &Path) -> Option<Result<FreeStep, RunError>> {
        Some(
            crate::bodies::rolling3d::RollingSlice::new(&self.slice_for(run.t_end))
                .map(|slice| {
                    let p =
                        slice.problem_with((run.integrator, run.params.h, 1), run.contact, None);
                    let n = p.model.n();
                    FreeStep {
                        v0: (0..n).map(|i| 1e-3 * (i as f64).sin()).collect(),
                        fixed: p.dirichlet.iter().map(|d| d.0).collect(),
                        u0: p.u0,
                        f: vec![0.0; n],
                        model: p.model,
                    }
                })
                .map_err(|e| RunError::input(scenario, e.to_string())),
        )
    }

    fn record(
        &self,
        sc: &Scenario,
        stream: Option<&Path>,
        opts: &RunOptions,
    ) -> Result<Results, RunError> {
        run::record(sc, stream, opts)
    }
}
