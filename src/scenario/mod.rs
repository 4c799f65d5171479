//! Scenario files (TOML), read in three stages (parse, then validate, then build: ripgrep's
//! low-level / high-level arguments split):
//!
//! 1. **Parse** (`raw.rs`, private): the text into structs that mirror the file. Unknown keys
//!    and wrong types are refused here, by the TOML parser, with the file, the line and the
//!    key.
//! 2. **Validate** (`validate.rs`, private, behind [`Scenario::from_file`] and
//!    [`Scenario::from_str`]): types, ranges and defaults of every value, and the
//!    combinations of model, integrator and contact treatment, refused in one table:
//!    [`combinations::check_combination`]; every key is used or refused (a table the kind
//!    does not read, a setting the run's integrator, treatment or model does not use, a
//!    top-level setting no run uses, a second run of a wheel: `validate/usage.rs`). The
//!    result is a [`Scenario<RunSpec>`]: plain
//!    data, nothing assembled, no mesh read. A run whose step is set by `cfl` keeps it as
//!    [`TimeStep::Cfl`].
//! 3. **Build** ([`crate::build`]): what needs a model. [`crate::build::resolve`] turns each
//!    [`RunSpec`] into a [`Run`] with its step `h` (assembling the contact bar to find the
//!    central difference's stable step when `cfl` is given, and warning about an explicit
//!    step or penalty beyond stability); the jobs ([`crate::run`](mod@crate::run)) take the built
//!    [`Scenario`] (= `Scenario<Run>`). Wheel meshes are read later still, by
//!    [`crate::kinds::wheel::run::build`].
//!
//! Errors name the file, the key and what is allowed, on one line ([`ScenarioError`]).
//!
//! ```toml
//! name = "bar-impact"          # output folder name (default: the file's stem)
//! kind = "bar_impact"          # "sdof" | "bar_impact" | "two_bars" | "wheel" | "track"
//!
//! [time]
//! alpha = 0.8                  # Eq. (8), in (0, 1]; default 0.8
//! gamma = 0.0                  # Eq. (24), in [0, 1]; default 0
//! h = 0.01                     # time step, s (> 0)
//! t_end = 5.0                  # end time, s (> 0)
//! integrator = "space_time"   # bars: also "newmark", "newmark_dissipative" (gamma_n),
//!                              # "hht" (alpha_h), "generalized_alpha" (rho_inf),
//!                              # "central_difference" (lumped mass; cfl sets h)
//!
//! [bar]                        # for kind = "bar_impact"
//! length = 1.0                 # m
//! ea = 1.0                     # axial stiffness EA, N
//! rho_a = 1.0                  # mass per length rho A, kg/m
//! speed = 1.0                  # initial speed towards the wall, m/s
//! gap = 0.5                    # distance from the head to the wall, m
//! elements = 8
//! mass = "consistent"          # or "lumped"
//! damping = 0.0                # eta_z per unit length (Eq. 22), N s/m^2
//!
//! [contact]
//! method = "soft_way"          # "soft_way" | "soft_way_braking_restore" |
//!                              # "soft_way_no_restore" | "soft_way_momentum_restore" |
//!                              # "exact" | "penalty" (penalty,
//!                              # N/m) | "mass_redistribution" | "moreau_jean"
//!                              # (restitution) | "subdivision" (see crate::contact)
//! friction = 0.3               # Coulomb coefficient mu, >= 0 (default 0: frictionless);
//!                              # 2D models only (the wheel), refused for bars
//!
//! [material]                   # kind = "wheel": young, poisson, density, and plasticity
//! model = "j2"                 # "elastic" (default) | "j2" (von Mises, crate::plasticity)
//! yield_stress = 500e6         # Pa (j2)
//! hardening = "isotropic"      # "none" (default) | "isotropic" (hardening_modulus, Pa;
//!                              # voce_q Pa, voce_b) | "kinematic" (Prager: hardening_modulus)
//!                              # | "armstrong_frederick" (af_c Pa, af_gamma)
//! plastic_tolerance = 1e-8     # the step's residual relative to the internal force
//! geometry = "large"           # "small" (default, linear) | "large" (crate::finite: the
//!                              # geometrically nonlinear force; elastic only)
//! law = "neo_hookean"          # large: "saint_venant_kirchhoff" (default) | "neo_hookean"
//! geometry_tolerance = 1e-6    # large: the step's residual relative to the internal force
//!
//! [block]                      # kind = "wheel" only: an elastic block as the base
//! young = 2.05e11              # Pa (default: the wheel's material)
//! poisson = 0.3
//! density = 7830.0             # kg/m^3
//! depth = 0.05                 # m, clamped at the bottom (default: half the radius)
//! dx = 2e-3                    # m, the top columns' width (default: the rim's pitch)
//! grading = 1.2                # the rows' growth from the top down, in [1, 2]
//! margin = 0.05                # m of block before and after the travel (default: depth)
//! reach = 8e-3                 # m, the contact search's reach (default: four columns)
//!
//! [track]                      # kind = "track" (crate::bodies::rail): a parameter set and overrides
//! set = "uic60"                # the named set (default)
//! pad_stiffness = 200e6        # any of: theory ("timoshenko" | "euler_bernoulli"), young,
//!                              # shear_modulus, shear_coefficient, area, inertia, density,
//!                              # pad_stiffness, pad_damping, sleeper_mass, ballast_stiffness,
//!                              # ballast_damping, spacing, bays, elements_per_bay, ends
//!                              # ("absorbing" | "free"), end_bays, end_damping, head_radius,
//!                              # poisson
//!
//! [vehicle]                    # kind = "track": one wheel
//! unsprung_mass = 800.0        # kg per wheel
//! axle_load = 100e3            # N per wheel
//! wheel_radius = 0.46          # m
//! speed = 30.0                 # m/s (required)
//! travel_bays = 6              # bays the load crosses, centred on the middle
//!
//! [receptance]                 # kind = "track": `softway receptance`
//! f_min = 20.0                 # Hz
//! f_max = 3000.0               # Hz
//! points = 400                 # log-spaced
//!
//! [[runs]]                     # optional: several runs of one scenario (a wheel: one)
//! label = "h = 0.4"
//! h = 0.4                      # any of h, alpha, gamma, elements, method, ...: the run's
//!                              # own beats the top level's; one no run uses is refused
//! ```

use crate::contact::{FrictionLaw, Treatment};
use crate::time::Integrator;
use crate::time::SpaceTimeParams;
use std::path::{Path, PathBuf};

pub mod combinations;
pub mod error;
pub mod kind;
pub mod overrides;
pub(crate) mod raw;
mod validate;

pub use error::ScenarioError;
pub use kind::Model;
pub use validate::{Ctx, DEFAULT_HUB_FRACTION};

pub use overrides::Override;
pub use raw::set_key;

/// A one-degree-of-freedom oscillator `m x'' + k x = 0`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Sdof {
    /// Mass, kg.
    pub mass: f64,
    /// Stiffness, N/m.
    pub stiffness: f64,
    /// Initial displacement, m.
    pub x0: f64,
    /// Initial velocity, m/s.
    pub v0: f64,
}

/// Where the wheel's mesh comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshSource {
    /// The hexagonal-pattern disk of `n` rings (12: the paper's 469 nodes, 864 triangles).
    Rings(usize),
    /// The disk graded towards a rim of `rim_nodes` nodes, without low-order rotational
    /// symmetry ([`crate::mesh::generators::disk_graded`]).
    Graded {
        /// Nodes on the rim.
        rim_nodes: usize,
        /// Ratio of successive radial spacings from the rim inwards, in [1, 2].
        grading: f64,
        /// The depth of the band under the rim meshed with the rim's symmetry, m (`None`:
        /// the graded disk to the rim; [`crate::mesh::generators::disk_symmetric_rim`]).
        band: Option<f64>,
    },
    /// A Gmsh `.msh` file (4.1, ASCII or binary), centred at the axle.
    Gmsh(PathBuf),
    /// The hub's annulus refined in a zone of the rim that moves with the contact
    /// ([`crate::mesh::zone`]).
    Zone(crate::mesh::zone::ZoneOptions),
}

/// The rolling wheel scenario (paper §4).
#[derive(Debug, Clone, PartialEq)]
pub struct WheelScenario {
    /// The physical data.
    pub spec: crate::bodies::wheel::WheelSpec,
    /// The mesh.
    pub mesh: MeshSource,
    /// Turns rolled after settling.
    pub turns: f64,
    /// `gamma` during settling (default: the run's gamma).
    pub settle_gamma: Option<f64>,
    /// Velocity-field snapshots over the last turn (Fig. 17), default 8.
    pub fields_per_turn: usize,
    /// An elastic block as the base instead of the rigid line (`[block]`;
    /// [`crate::bodies::block`]).
    pub block: Option<crate::bodies::block::BlockSpec>,
    /// The wheel's load, N (`wheel.load`; for the wheel's thickness, the unit of the contact
    /// force in `summary.json`): the alternative to `rolling.flattening`. Then
    /// `spec.flattening.depth` is not known until the model is built:
    /// [`crate::kinds::wheel::run::build`] sets it to the flattening at which a static contact solve
    /// of the spinning wheel carries this load ([`crate::kinds::wheel::run::load`]); until then it
    /// is NaN.
    pub load: Option<f64>,
    /// The wheel's J2 elastic-plastic material (`material.model = "j2"`,
    /// [`crate::plasticity`]); `None`: elastic.
    pub plastic: Option<Plastic>,
    /// The wheel in large deformation (`material.geometry = "large"`,
    /// [`crate::kinds::wheel::large`]); `None`: linear in the geometry.
    pub large: Option<crate::kinds::wheel::large::Large>,
}

/// The wheel's plasticity (`[material]` with `model = "j2"`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Plastic {
    /// The material (its elastic constants are the wheel's).
    pub material: crate::plasticity::J2Material,
    /// The iteration's tolerance: the residual relative to the internal force
    /// (`material.plastic_tolerance`, default [`crate::model::DEFAULT_TOL`]).
    pub tolerance: f64,
}

impl WheelScenario {
    /// The space-time scheme's `gamma` over the run: `settle_gamma` while settling, then
    /// the run's `gamma` (empty: the run's throughout).
    pub fn gamma_schedule(&self, gamma: f64) -> Vec<(f64, f64)> {
        let t_settle = self.spec.flattening.settle_time;
        match self.settle_gamma {
            Some(g) if t_settle > 0.0 => vec![(0.0, g), (t_settle, gamma)],
            _ => vec![],
        }
    }

    /// Settling time plus the turns, s.
    pub fn duration(&self) -> f64 {
        self.spec.flattening.settle_time + self.turns * 2.0 * std::f64::consts::PI / self.spec.omega
    }
}

/// The vehicle of a track scenario (`[vehicle]`): one wheel, its share of the axle's
/// unsprung mass and load, and its passage.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Vehicle {
    /// What rolls along the rail (`vehicle.model`, default the wheel).
    pub model: VehicleModel,
    /// Unsprung mass per wheel, the wheel's own included, kg (default 800).
    #[serde(rename = "unsprung_mass_kg")]
    pub unsprung_mass: f64,
    /// Static load per wheel from the sprung mass, N (default 100e3).
    #[serde(rename = "axle_load_N")]
    pub axle_load: f64,
    /// Wheel radius, m (default 0.46).
    #[serde(rename = "wheel_radius_m")]
    pub wheel_radius: f64,
    /// Speed, m/s (`vehicle.speed`, or `vehicle.speed_km_h`).
    #[serde(rename = "speed_m_s")]
    pub speed: f64,
    /// Bays of the recorded passage, centred on the track's middle (default 6 for the moving
    /// load, 20 for the wheel).
    pub travel_bays: usize,
    /// Bays the wheel rolls before the recorded passage while its load is applied (over the
    /// first half of them) and settles (default 4; the wheel only).
    pub settle_bays: usize,
    /// The primary suspension's stiffness (isotropic, about the axle's nominal position),
    /// N/m (default 0: the axle load is a constant force).
    #[serde(rename = "suspension_stiffness_N_m")]
    pub suspension_stiffness: f64,
    /// The primary suspension's damping, N s/m (default 0).
    #[serde(rename = "suspension_damping_N_s_m")]
    pub suspension_damping: f64,
    /// Gravity, m/s^2 (default 9.81).
    #[serde(rename = "gravity_m_s2")]
    pub gravity: f64,
    /// Longitudinal creepage, dimensionless (default 0; the wheel only): the wheel turns at
    /// `omega = V (1 + xi) / R_s`, `R_s` the spun, unloaded rim's radius; positive:
    /// traction, the wheel turning faster than it rolls ([`crate::bodies::rail::rolling`]).
    pub creepage: f64,
    /// A second wheel `wheelbase` behind the first on the same rail (`vehicle.wheelbase`, m;
    /// the wheel only; `None`: one wheel): the same wheel, unsprung mass, load and
    /// suspension ([`crate::bodies::rail::rolling`], Two wheels). The passage runs on until
    /// the second wheel has crossed the recorded bays too.
    #[serde(rename = "wheelbase_m", skip_serializing_if = "Option::is_none")]
    pub wheelbase: Option<f64>,
    /// The wheel's mesh and material (the wheel only).
    pub wheel: TrackWheel,
}

/// What rolls along the rail in a track scenario.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum VehicleModel {
    /// The elastic wheel in its rotating frame on its moving hub ([`crate::bodies::rail::rolling`]).
    Wheel,
    /// A constant force moving at the speed ([`crate::bodies::rail::moving`]).
    MovingLoad,
}

/// The rolling wheel of a track scenario (`vehicle.wheel_*` keys): a graded disk on a hub.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct TrackWheel {
    /// Rim nodes (default 720).
    pub rim_nodes: usize,
    /// Thickness (the line contact's width), m (default 0.02).
    #[serde(rename = "thickness_m")]
    pub thickness: f64,
    /// Hub radius, m (default 0.1).
    #[serde(rename = "hub_radius_m")]
    pub hub_radius: f64,
    /// The disk mesh's radial grading (default 1.3).
    pub grading: f64,
    /// The depth of the band under the rim meshed with the rim's rotational symmetry, m
    /// (`vehicle.wheel_rim_band`; `None`: the graded disk to the rim;
    /// [`crate::mesh::generators::disk_symmetric_rim`]).
    #[serde(rename = "rim_band_m")]
    pub rim_band: Option<f64>,
    /// Plane strain (default) or plane stress.
    pub plane: crate::material::PlaneModel,
    /// Steel: E = 210 GPa, nu = the track's Poisson's ratio, rho = 7850 kg/m^3.
    pub material: crate::material::Elastic,
}

/// The rail's irregularity in a track scenario (`[irregularity]`), over the rail's abscissa
/// measured from where the axle starts.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case", tag = "type")]
pub enum Irregularity {
    /// `amplitude sin(2 pi x / wavelength)`, faded in over `fade` wavelengths.
    Harmonic {
        /// m.
        #[serde(rename = "amplitude_m")]
        amplitude: f64,
        /// m.
        #[serde(rename = "wavelength_m")]
        wavelength: f64,
        /// Wavelengths.
        fade: f64,
    },
    /// Measured `(x, r)` points from a CSV file (`x_m,r_m`).
    Measured {
        /// The file.
        file: PathBuf,
        /// The points, m.
        #[serde(skip)]
        points: Vec<(f64, f64)>,
    },
    /// Random, from one-third-octave band levels `(wavelength m, dB re 1 um)`.
    Spectrum {
        /// The bands.
        bands: Vec<(f64, f64)>,
        /// Harmonics a band.
        per_band: usize,
        /// The phases' seed.
        seed: u64,
    },
}

impl Irregularity {
    /// The profile over the rail's abscissae `[from, to]` (m), shifted so that its `x = 0`
    /// is the rail's `from`.
    ///
    /// # Errors
    /// [`crate::contact::profile::ProfileError`].
    pub fn profile(
        &self,
        (from, to): (f64, f64),
    ) -> Result<crate::contact::profile::Profile, crate::contact::profile::ProfileError> {
        use crate::contact::profile::Profile;
        match self {
            Irregularity::Harmonic {
                amplitude,
                wavelength,
                fade,
            } => Profile::harmonic(*amplitude, *wavelength, (from, to), *fade),
            Irregularity::Measured { points, .. } => {
                let shifted: Vec<(f64, f64)> = points.iter().map(|&(x, r)| (x + from, r)).collect();
                Profile::from_points(&shifted)
            }
            Irregularity::Spectrum {
                bands,
                per_band,
                seed,
            } => Profile::from_spectrum(bands, *per_band, (from, to), *seed),
        }
    }
}

/// The frequencies of `softway receptance` (`[receptance]`): `points` log-spaced from
/// `f_min` to `f_max`, Hz.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ReceptanceRange {
    /// Lowest frequency, Hz (default 20).
    #[serde(rename = "f_min_Hz")]
    pub f_min: f64,
    /// Highest frequency, Hz (default 3000).
    #[serde(rename = "f_max_Hz")]
    pub f_max: f64,
    /// Frequencies (default 400).
    pub points: usize,
}

/// The track scenario (`kind = "track"`): the track ([`crate::bodies::rail`]), the vehicle and the
/// receptance's frequencies.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackScenario {
    /// The parameter set named by `track.set`.
    pub set: String,
    /// The track: the set with the overrides of `[track]`.
    pub spec: crate::bodies::rail::TrackSpec,
    /// The vehicle.
    pub vehicle: Vehicle,
    /// The receptance's frequencies.
    pub receptance: ReceptanceRange,
    /// The rail's irregularity (`[irregularity]`; the wheel only).
    pub irregularity: Option<Irregularity>,
}

impl TrackScenario {
    /// Where the load starts: half its recorded travel before the middle sleeper, and the
    /// wheel its settling bays before that, m.
    pub fn start(&self) -> f64 {
        let s = self.spec.spacing;
        (self.spec.bays / 2) as f64 * s
            - 0.5 * self.vehicle.travel_bays as f64 * s
            - self.settle_distance()
    }

    /// The time a rim node of the wheel takes to pass the contact: the rim's pitch over the
    /// speed, s.
    pub fn rim_passage(&self) -> f64 {
        let w = &self.vehicle.wheel;
        2.0 * std::f64::consts::PI * self.vehicle.wheel_radius
            / w.rim_nodes as f64
            / self.vehicle.speed
    }

    /// The distance the wheel rolls before the recorded passage, m (0 for the moving load).
    pub fn settle_distance(&self) -> f64 {
        match self.vehicle.model {
            VehicleModel::Wheel => self.vehicle.settle_bays as f64 * self.spec.spacing,
            VehicleModel::MovingLoad => 0.0,
        }
    }

    /// The distance the load travels, settling included, m.
    pub fn travel(&self) -> f64 {
        self.vehicle.travel_bays as f64 * self.spec.spacing + self.settle_distance()
    }

    /// The distance the vehicle runs: [`TrackScenario::travel`], and with a second wheel
    /// the wheelbase more, so that the second wheel crosses the recorded bays too, m.
    pub fn run_distance(&self) -> f64 {
        self.travel() + self.vehicle.wheelbase.unwrap_or(0.0)
    }

    /// The passage's duration, s.
    pub fn duration(&self) -> f64 {
        self.run_distance() / self.vehicle.speed
    }
}

/// One run of a built scenario (the scenario may list several): what the jobs run.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// Label (plots, CSV).
    pub label: String,
    /// The scheme.
    pub params: SpaceTimeParams,
    /// The model, with this run's overrides.
    pub model: Model,
    /// The time integrator.
    pub integrator: Integrator,
    /// The contact treatment.
    pub contact: Contact,
    /// The friction law of the contact pairs (`contact.friction`, `friction_kinetic`,
    /// `friction_velocity`; `None`: frictionless).
    pub friction: Option<FrictionLaw>,
    /// End time, s.
    pub t_end: f64,
    /// The key the step comes from (`time.h`, `runs[1].h`, `time.cfl`, ...), for messages
    /// about the step.
    pub step_key: String,
}

/// The contact treatment of a run.
pub type Contact = Treatment;

/// The time step of a validated run.
#[derive(Debug, Clone, PartialEq)]
pub enum TimeStep {
    /// A fixed step `h`, s (`time.h` or `runs[i].h`).
    Fixed(f64),
    /// The central difference's step as a fraction of its stable step:
    /// `h = cfl * 2 / omega_max`, with `omega_max` of the lumped contact bar (penalty spring
    /// included). Resolved by [`crate::build::resolve`].
    Cfl {
        /// The fraction, in (0, 1].
        cfl: f64,
        /// Where it was set: `time.cfl` or `runs[i].cfl`.
        key: String,
    },
}

/// One validated run, before the build step: every setting checked, the step possibly
/// still a `cfl` fraction ([`TimeStep`]).
#[derive(Debug, Clone, PartialEq)]
pub struct RunSpec {
    /// The `label` given, if any (default: [`RunSpec::label_or_default`]).
    pub label: Option<String>,
    /// `alpha` of the space-time scheme, Eq. (8), in (0, 1].
    pub alpha: f64,
    /// `gamma` of the space-time scheme, Eq. (24), in [0, 1].
    pub gamma: f64,
    /// The time step.
    pub step: TimeStep,
    /// The model, with this run's overrides (`elements`; lumped mass for the central
    /// difference).
    pub model: Model,
    /// The time integrator.
    pub integrator: Integrator,
    /// The contact treatment.
    pub contact: Contact,
    /// The friction law (`contact.friction` >= 0 and the falling law's keys; `None`:
    /// frictionless).
    pub friction: Option<FrictionLaw>,
    /// End time, s.
    pub t_end: f64,
    /// The key the step comes from (`time.h`, `runs[1].h`, `time.cfl`, ...), for messages
    /// about the step.
    pub step_key: String,
}

impl RunSpec {
    /// The label: the one given, else `run` for the only run of a scenario, else
    /// `h = <h>` with the run's step `h` (s).
    pub fn label_or_default(&self, runs: usize, h: f64) -> String {
        self.label.clone().unwrap_or_else(|| {
            if runs == 1 {
                "run".into()
            } else {
                format!("h = {h}")
            }
        })
    }
}

/// A scenario: validated (`Scenario<RunSpec>`, from [`Scenario::from_file`]) or built
/// (`Scenario<Run>`, the default parameter, from [`crate::build::resolve`]; what the jobs
/// run).
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario<R = Run> {
    /// Name (default output folder `out/<name>`).
    pub name: String,
    /// Free text.
    pub description: String,
    /// The file it came from.
    pub path: PathBuf,
    /// The runs (at least one).
    pub runs: Vec<R>,
    /// Write every `history_stride`-th step to `history.csv` (default 1).
    pub history_stride: usize,
    /// Draw plots (default true).
    pub plots: bool,
    /// Warnings found while validating (e.g. a conditionally stable `(alpha, gamma)`) and,
    /// once built, while building (an explicit step beyond the stable step).
    pub warnings: Vec<String>,
    /// A default sweep for `softway sweep`: the dotted key and its values (TOML literals).
    pub sweep: Option<(String, Vec<String>)>,
    /// A refinement ladder the default sweep runs on (`[sweep] ladder = { key, values }`):
    /// every value of the sweep's key on every rung (the grid's product), as
    /// `softway sweep --set KEY=... --set RUNG_KEY=R1,R2,R3` does; a creepage sweep on a
    /// mesh ladder gives the creep curve with its Richardson limit
    /// ([`crate::run::sweep`]).
    pub sweep_ladder: Option<(String, Vec<String>)>,
    /// Keys set with each rung of the ladder (`[sweep] ladder.with`), one value a rung:
    /// what else a rung changes beside its key (a zone's pitch that needs another coarse
    /// mesh, e.g. `wheel.mesh`).
    pub sweep_ladder_with: Vec<(String, Vec<String>)>,
    /// SHA-256 of the scenario text as run (the file's bytes; a sweep's or a ladder's
    /// value set into it for that run), lowercase hex: recorded in `summary.json`.
    pub source_sha256: String,
    /// The scenario text as run (the file's, with the `--set` values or a sweep's point
    /// written into it): copied into every output folder as `scenario.toml`
    /// ([`Scenario::provenance_text`]).
    pub source_text: String,
    /// The command line's `--set KEY=VALUE` overrides written into the text, in order (a
    /// sweep's or a ladder's point among them).
    pub overrides: Vec<Override>,
    /// The growth study of `[growth]` and `[wear]` (`softway grow`; [`crate::growth`]).
    pub growth: Option<crate::growth::GrowthConfig>,
}

impl<R> Scenario<R> {
    /// The copy of the scenario an output folder keeps (`scenario.toml`): a header of
    /// comments (the softway version, the git commit it was built from when built from a
    /// checkout, the file, the `--set` values), then the text as run, which
    /// `softway run scenario.toml` runs again (a relative `wheel.mesh` is relative to the
    /// original file's folder, named in the header).
    pub fn provenance_text(&self) -> String {
        use std::fmt::Write as _;
        let mut s = format!("# softway {}", env!("CARGO_PKG_VERSION"));
        if let Some(c) = crate::GIT_COMMIT {
            let _ = write!(s, " (git {c})");
        }
        let _ = write!(s, "\n# scenario: {}\n", self.path.display());
        for o in &self.overrides {
            let _ = writeln!(s, "# --set {}", o.to_arg());
        }
        let _ = writeln!(
            s,
            "# The text below is the scenario as run{} (SHA-256 {}, summary.json's scenario_sha256).\n",
            if self.overrides.is_empty() { "" } else { ", the --set values written into it" },
            self.source_sha256
        );
        s.push_str(&self.source_text);
        s
    }
}

impl Scenario<RunSpec> {
    /// Parses and validates scenario text whose kind is one of `kinds` (softway's own and
    /// any added with [`kind::Registry::with`]); `path` names it in errors.
    ///
    /// # Errors
    /// [`ScenarioError`].
    pub fn from_str_in(
        text: &str,
        path: &Path,
        kinds: &kind::Registry,
    ) -> Result<Self, ScenarioError> {
        let mut sc = validate::validate(raw::parse(text, path, kinds)?, (text, path), kinds, true)?;
        sc.source_sha256 = sha256_hex(text.as_bytes());
        sc.source_text = text.to_string();
        Ok(sc)
    }
}

/// The parser's message for scenario `text` (TOML syntax, a wrong type, an unknown key,
/// in the common tables or in its kind's), without the position; `None` when the parser
/// takes it.
pub(crate) fn parse_error(text: &str, kinds: &kind::Registry) -> Option<String> {
    let raw = match raw::parse_message(text, kinds) {
        Ok(raw) => raw,
        Err(m) => return Some(m),
    };
    match validate::validate(raw, (text, Path::new("")), kinds, false) {
        Err(ScenarioError::Parse { message, .. }) => Some(message),
        _ => None,
    }
}

/// Largest scenario file read, bytes (16 MiB; the shipped ones are a few kB).
pub const MAX_SCENARIO_BYTES: u64 = 16 << 20;

/// The text of a scenario file: a regular file (not a folder, a device such as `/dev/zero`
/// or a pipe, which could be read forever) of at most [`MAX_SCENARIO_BYTES`], in UTF-8.
/// What [`Scenario::from_file`] reads, and the Python package's `Scenario(path)`.
///
/// # Errors
/// The file cannot be opened or read, or is not such a file (the message says which).
pub fn read_text(path: &Path) -> std::io::Result<String> {
    use std::io::Read as _;
    // Checked before opening too: opening a pipe with no writer waits for one forever.
    let before = std::fs::metadata(path)?;
    if !before.is_file() && !before.is_dir() {
        return Err(std::io::Error::other(
            "not a regular file (a device or a pipe); give a TOML file",
        ));
    }
    let file = std::fs::File::open(path)?;
    let meta = file.metadata()?;
    if meta.is_dir() {
        return Err(std::io::Error::other("is a directory, not a scenario file"));
    }
    if !meta.is_file() {
        return Err(std::io::Error::other(
            "not a regular file (a device or a pipe); give a TOML file",
        ));
    }
    let mut bytes = Vec::new();
    file.take(MAX_SCENARIO_BYTES + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > MAX_SCENARIO_BYTES {
        return Err(std::io::Error::other(format!(
            "larger than {} MiB: a scenario is a small TOML file",
            MAX_SCENARIO_BYTES >> 20
        )));
    }
    String::from_utf8(bytes).map_err(|e| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "not UTF-8 text (byte {} is not valid UTF-8); save the file as UTF-8",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

/// The SHA-256 digest of `bytes`, lowercase hex (64 characters).
pub fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::Digest as _;
    use std::fmt::Write as _;
    let digest = sha2::Sha256::digest(bytes);
    let mut s = String::with_capacity(64);
    for b in digest {
        let _ = write!(s, "{b:02x}");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    const BAR: &str = r#"
kind = "bar_impact"
[time]
t_end = 1.0
integrator = "central_difference"
cfl = 0.5
[bar]
length = 1.0
ea = 1.0
rho_a = 1.0
speed = 1.0
gap = 0.5
elements = 1000000
[contact]
method = "exact"
"#;

    /// Validation keeps `cfl` as it is: the step of a run is not known before the build
    /// stage assembles the bar. A million elements: building them (assembly and a power
    /// iteration of up to 1e5 sweeps) would take minutes, validating takes microseconds.
    /// The digest of FIPS 180-2's "abc" example, and the scenario's digest is that of its
    /// text.
    #[test]
    fn the_scenario_records_the_sha256_of_its_text() {
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        let sc = Scenario::from_str(BAR, Path::new("h.toml")).unwrap();
        assert_eq!(sc.source_sha256, sha256_hex(BAR.as_bytes()));
        let other = Scenario::from_str(&format!("{BAR}\n"), Path::new("h.toml")).unwrap();
        assert_ne!(other.source_sha256, sc.source_sha256);
    }

    #[test]
    fn parsing_a_cfl_scenario_builds_nothing() {
        let text = format!("{BAR}[[runs]]\n[[runs]]\ncfl = 0.25\n[[runs]]\nh = 0.05\n");
        let t0 = std::time::Instant::now();
        let sc = Scenario::from_str(&text, Path::new("big.toml")).unwrap();
        assert!(t0.elapsed().as_secs_f64() < 10.0, "{:?}", t0.elapsed());
        let steps: Vec<&TimeStep> = sc.runs.iter().map(|r| &r.step).collect();
        assert_eq!(
            steps,
            [
                &TimeStep::Cfl {
                    cfl: 0.5,
                    key: "time.cfl".into()
                },
                &TimeStep::Cfl {
                    cfl: 0.25,
                    key: "runs[1].cfl".into()
                },
                // A run's own step overrides the scenario's cfl, as every run setting does.
                &TimeStep::Fixed(0.05),
            ]
        );
        // The explicit integrator's lumped mass is a validated setting.
        assert!(sc.runs[0]
            .model
            .get::<crate::bodies::bar::BarImpact>()
            .is_some_and(|b| b.lumped && b.elements == 1_000_000));
        // Nothing built, so no stability warning yet (those come from crate::build).
        assert!(sc.warnings.is_empty(), "{:?}", sc.warnings);
        assert!(sc.runs.iter().all(|r| r.label.is_none()));
    }

    #[test]
    fn cfl_is_refused_at_validation_for_an_implicit_integrator_and_out_of_range() {
        let e = Scenario::from_str(
            &BAR.replace("central_difference", "newmark"),
            Path::new("impl.toml"),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("impl.toml: `time.cfl` = 0.5") && e.contains("central_difference"),
            "{e}"
        );
        let e = Scenario::from_str(&format!("{BAR}[[runs]]\ncfl = 1.5\n"), Path::new("r.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("r.toml: `runs[0].cfl` = 1.5") && e.contains("(0, 1]"),
            "{e}"
        );
    }

    #[test]
    fn unknown_keys_are_refused_at_parse_naming_the_file_and_the_key() {
        let e = Scenario::from_str(
            &BAR.replace("cfl = 0.5", "cfl = 0.5\ncfll = 1"),
            Path::new("typo.toml"),
        )
        .unwrap_err();
        assert!(matches!(e, ScenarioError::Parse { .. }), "{e:?}");
        let e = e.to_string();
        assert!(
            e.starts_with("typo.toml: ") && e.contains("cfll") && !e.contains('\n'),
            "{e}"
        );
    }
}
