//! Scenario files (TOML): parsed into raw structs (unknown keys rejected), then validated into
//! a [`Scenario`] whose every value has been checked, with errors that name the file, the
//! key and what is allowed (ripgrep's low-level / high-level arguments split).
//!
//! ```toml
//! name = "bar-impact"          # output folder name (default: the file's stem)
//! kind = "bar_impact"          # "sdof" | "bar_impact" | "two_bars" | "wheel"
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
//!                              # "soft_way_no_restore" | "exact"; bars: also "penalty"
//!                              # (penalty, N/m), "mass_redistribution", "moreau_jean"
//!                              # (restitution), "subdivision" (see crate::lab)
//!
//! [[runs]]                     # optional: several runs of one scenario
//! label = "h = 0.4"
//! h = 0.4                      # any of h, alpha, gamma, elements, method
//! ```

use crate::contact::ContactMethod;
use crate::lab::{ClassicKind, Integrator, Treatment};
use crate::problems::{BarImpact, TwoBars};
use crate::time::classic::ClassicParams;
use crate::time::sdof::analyse;
use crate::time::SpaceTimeParams;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// A scenario error: the file, the key at fault and what is allowed.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    /// The file cannot be read.
    #[error("{path}: cannot read the scenario: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// TOML syntax or schema error (unknown key, wrong type).
    #[error("{path}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// The parser's message, with line and column.
        message: String,
    },
    /// A value out of its allowed range.
    #[error("{path}: `{key}` = {value}: {allowed}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// Dotted key, e.g. `bar.length` or `runs[2].h`.
        key: String,
        /// The value found.
        value: String,
        /// What is allowed.
        allowed: String,
    },
    /// A required key is missing.
    #[error("{path}: missing `{key}`: {why}")]
    Missing {
        /// The file.
        path: PathBuf,
        /// Dotted key.
        key: String,
        /// What it is for.
        why: String,
    },
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScenario {
    name: Option<String>,
    kind: String,
    description: Option<String>,
    time: Option<RawTime>,
    bar: Option<RawBar>,
    two_bars: Option<RawBar>,
    sdof: Option<RawSdof>,
    wheel: Option<RawWheel>,
    material: Option<RawMaterial>,
    rolling: Option<RawRolling>,
    contact: Option<RawContact>,
    #[serde(default)]
    runs: Vec<RawRun>,
    output: Option<RawOutput>,
    sweep: Option<RawSweep>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSweep {
    key: String,
    values: Vec<toml::Value>,
}

#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawTime {
    alpha: Option<f64>,
    gamma: Option<f64>,
    h: Option<f64>,
    t_end: Option<f64>,

    integrator: Option<String>,
    rho_inf: Option<f64>,
    alpha_h: Option<f64>,
    gamma_n: Option<f64>,
    cfl: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBar {
    length: f64,
    ea: f64,
    rho_a: f64,
    speed: f64,
    gap: f64,
    elements: i64,
    mass: Option<String>,
    damping: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSdof {
    mass: f64,
    stiffness: f64,
    x0: Option<f64>,
    v0: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawWheel {
    radius: f64,
    thickness: f64,
    rings: Option<i64>,
    mesh: Option<String>,
    plane: Option<String>,
    mass: Option<String>,
    support: Option<String>,
    hub_radius: Option<f64>,
    damping: Option<f64>,
    stress_stiffening: Option<bool>,
    rotating_frame: Option<bool>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMaterial {
    young: f64,
    poisson: f64,
    density: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRolling {
    omega: f64,
    flattening: f64,
    settle_time: f64,
    turns: f64,
    settle_gamma: Option<f64>,
    fields_per_turn: Option<i64>,
}

#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawContact {
    method: Option<String>,
    penalty: Option<f64>,
    restitution: Option<f64>,
}

#[derive(Debug, Deserialize, Default, Clone)]
#[serde(deny_unknown_fields)]
struct RawRun {
    label: Option<String>,
    h: Option<f64>,
    alpha: Option<f64>,
    gamma: Option<f64>,
    elements: Option<i64>,
    method: Option<String>,
    penalty: Option<f64>,
    restitution: Option<f64>,
    integrator: Option<String>,
    rho_inf: Option<f64>,
    alpha_h: Option<f64>,
    gamma_n: Option<f64>,
    cfl: Option<f64>,
}

#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawOutput {
    history_stride: Option<i64>,
    plots: Option<bool>,
}

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
    /// A Gmsh `.msh` file (4.1, ASCII or binary), centred at the axle.
    Gmsh(PathBuf),
}

/// The rolling wheel scenario (paper §4).
#[derive(Debug, Clone, PartialEq)]
pub struct WheelScenario {
    /// The physical data.
    pub spec: crate::wheel::WheelSpec,
    /// The mesh.
    pub mesh: MeshSource,
    /// Turns rolled after settling.
    pub turns: f64,
    /// `gamma` during settling (default: the run's gamma).
    pub settle_gamma: Option<f64>,
    /// Velocity-field snapshots over the last turn (Fig. 17), default 8.
    pub fields_per_turn: usize,
}

impl WheelScenario {
    /// Settling time plus the turns, s.
    pub fn duration(&self) -> f64 {
        self.spec.flattening.settle_time + self.turns * 2.0 * std::f64::consts::PI / self.spec.omega
    }
}

/// The physical model of a scenario.
#[derive(Debug, Clone, PartialEq)]
pub enum Model {
    /// One degree of freedom.
    Sdof(Sdof),
    /// Elastic bar against a rigid wall.
    BarImpact(BarImpact),
    /// Two elastic bars colliding (node-to-node contact).
    TwoBars(TwoBars),
    /// The elastic wheel rolling on a rigid base.
    Wheel(Box<WheelScenario>),
}

/// One run of a scenario (the scenario may list several).
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// Label (plots, CSV).
    pub label: String,
    /// The scheme.
    pub params: SpaceTimeParams,
    /// The model, with this run's overrides.
    pub model: Model,
    /// Contact method of the driver (the wheel; for bars see `contact`).
    pub method: ContactMethod,
    /// The time integrator.
    pub integrator: Integrator,
    /// The contact treatment.
    pub contact: Contact,
    /// End time, s.
    pub t_end: f64,
}

/// The contact treatment of a run: the soft way family in the driver
/// ([`crate::simulation`]), or a treatment of the laboratory ([`crate::lab`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Contact {
    /// Run by [`crate::simulation::Simulation`].
    Driver(ContactMethod),
    /// Run by [`crate::lab::Lab`].
    Lab(Treatment),
}

impl Contact {
    /// The name used in tables.
    pub fn name(&self) -> String {
        match self {
            Contact::Driver(m) => serde_json::to_value(m)
                .ok()
                .and_then(|v| v.as_str().map(String::from))
                .unwrap_or_default(),
            Contact::Lab(t) => t.name(),
        }
    }
}

/// A validated scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// Name (default output folder `out/<name>`).
    pub name: String,
    /// Free text.
    pub description: String,
    /// The file it came from.
    pub path: PathBuf,
    /// The runs (at least one).
    pub runs: Vec<Run>,
    /// Write every `history_stride`-th step to `history.csv` (default 1).
    pub history_stride: usize,
    /// Draw plots (default true).
    pub plots: bool,
    /// Warnings found while validating (e.g. a conditionally stable `(alpha, gamma)`).
    pub warnings: Vec<String>,
    /// A default sweep for `softway sweep`: the dotted key and its values (TOML literals).
    pub sweep: Option<(String, Vec<String>)>,
}

struct Ctx<'a> {
    path: &'a Path,
}

impl Ctx<'_> {
    fn invalid(&self, key: &str, value: impl std::fmt::Display, allowed: &str) -> ScenarioError {
        ScenarioError::Invalid {
            path: self.path.to_path_buf(),
            key: key.to_string(),
            value: value.to_string(),
            allowed: allowed.to_string(),
        }
    }
    fn missing(&self, key: &str, why: &str) -> ScenarioError {
        ScenarioError::Missing {
            path: self.path.to_path_buf(),
            key: key.to_string(),
            why: why.to_string(),
        }
    }
    fn positive(&self, key: &str, v: f64) -> Result<f64, ScenarioError> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.invalid(key, v, "must be a finite number > 0"))
        }
    }
    fn non_negative(&self, key: &str, v: f64) -> Result<f64, ScenarioError> {
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(self.invalid(key, v, "must be a finite number >= 0"))
        }
    }
    fn count(&self, key: &str, v: i64, max: i64) -> Result<usize, ScenarioError> {
        if v >= 1 && v <= max {
            Ok(v as usize)
        } else {
            Err(self.invalid(key, v, &format!("must be a whole number from 1 to {max}")))
        }
    }
    fn alpha(&self, key: &str, v: f64) -> Result<f64, ScenarioError> {
        if v.is_finite() && v > 0.0 && v <= 1.0 {
            Ok(v)
        } else {
            Err(self.invalid(key, v, "alpha must be in (0, 1] (Eq. 8)"))
        }
    }
    fn gamma(&self, key: &str, v: f64) -> Result<f64, ScenarioError> {
        if v.is_finite() && (0.0..=1.0).contains(&v) {
            Ok(v)
        } else {
            Err(self.invalid(key, v, "gamma must be in [0, 1] (Eq. 24)"))
        }
    }
    fn method(&self, key: &str, v: &str) -> Result<ContactMethod, ScenarioError> {
        match v {
            "soft_way" => Ok(ContactMethod::SoftWay),
            "soft_way_no_restore" => Ok(ContactMethod::SoftWayNoRestore),
            "soft_way_braking_restore" => Ok(ContactMethod::SoftWayBrakingRestore),
            "exact" => Ok(ContactMethod::Exact),
            _ => Err(self.invalid(
                key,
                format!("\"{v}\""),
                "allowed for the wheel: \"soft_way\", \"soft_way_braking_restore\", \"soft_way_no_restore\", \"exact\"",
            )),
        }
    }

    /// The contact treatment named `v` (key `key`), with its parameters.
    fn contact(
        &self,
        key: &str,
        v: &str,
        penalty: Option<(String, f64)>,
        restitution: Option<(String, f64)>,
    ) -> Result<Contact, ScenarioError> {
        let t = match v {
            "soft_way" | "soft_way_no_restore" | "soft_way_braking_restore" => {
                return Ok(Contact::Driver(self.method(key, v)?))
            }
            "exact" => Treatment::Exact,
            "penalty" => {
                let (k, s) = penalty.ok_or_else(|| {
                    self.missing(
                        "contact.penalty",
                        "method = \"penalty\" needs the penalty stiffness, N/m (or runs[].penalty)",
                    )
                })?;
                Treatment::Penalty {
                    stiffness: self.positive(&k, s)?,
                }
            }
            "mass_redistribution" => Treatment::MassRedistribution,
            "moreau_jean" => {
                let e = match restitution {
                    Some((k, e)) if !(0.0..=1.0).contains(&e) => {
                        return Err(self.invalid(&k, e, "the restitution must be in [0, 1]"))
                    }
                    Some((_, e)) => e,
                    None => 0.0,
                };
                Treatment::MoreauJean { restitution: e }
            }
            "subdivision" => Treatment::Subdivision,
            _ => {
                return Err(self.invalid(
                    key,
                    format!("\"{v}\""),
                    "allowed: \"soft_way\", \"soft_way_braking_restore\", \"soft_way_no_restore\", \"exact\", \"penalty\", \"mass_redistribution\", \"moreau_jean\", \"subdivision\"",
                ))
            }
        };
        Ok(Contact::Lab(t))
    }

    /// The integrator named `v` (key `key`) with `alpha`, `gamma` (space-time) and the
    /// optional parameters `(key, value)` of the classic ones.
    fn integrator(
        &self,
        key: &str,
        v: &str,
        (alpha, gamma): (f64, f64),
        rho_inf: Option<(String, f64)>,
        alpha_h: Option<(String, f64)>,
        gamma_n: Option<(String, f64)>,
    ) -> Result<Integrator, ScenarioError> {
        let unused = |p: &Option<(String, f64)>, what: &str| -> Result<(), ScenarioError> {
            match p {
                Some((k, x)) => {
                    Err(self.invalid(k, x, &format!("only used with integrator = \"{what}\"")))
                }
                None => Ok(()),
            }
        };
        let (kind, params) = match v {
            "space_time" => {
                unused(&rho_inf, "generalized_alpha")?;
                unused(&alpha_h, "hht")?;
                unused(&gamma_n, "newmark_dissipative")?;
                return Ok(Integrator::SpaceTime { alpha, gamma });
            }
            "newmark" => (ClassicKind::Newmark, ClassicParams::average_acceleration()),
            "newmark_dissipative" => {
                let g = match gamma_n.clone() {
                    Some((k, g)) if !(g.is_finite() && g > 0.5 && g <= 1.0) => {
                        return Err(self.invalid(&k, g, "gamma_n must be in (0.5, 1]"))
                    }
                    Some((_, g)) => g,
                    None => ClassicParams::DEFAULT_DISSIPATIVE_GAMMA,
                };
                (ClassicKind::NewmarkDissipative, ClassicParams::newmark_dissipative(g))
            }
            "hht" => {
                let (k, a) = alpha_h.clone().unwrap_or(("alpha_h".into(), ClassicParams::DEFAULT_ALPHA_H));
                let p = ClassicParams::hht(a).map_err(|_| self.invalid(&k, a, "alpha_h must be in [-1/3, 0]"))?;
                (ClassicKind::Hht, p)
            }
            "generalized_alpha" => {
                let (k, r) = rho_inf.clone().unwrap_or(("rho_inf".into(), ClassicParams::DEFAULT_RHO_INF));
                let p = ClassicParams::generalized_alpha(r)
                    .map_err(|_| self.invalid(&k, r, "rho_inf must be in [0, 1]"))?;
                (ClassicKind::GeneralizedAlpha, p)
            }
            "central_difference" => (ClassicKind::CentralDifference, ClassicParams::central_difference()),
            _ => {
                return Err(self.invalid(
                    key,
                    format!("\"{v}\""),
                    "allowed: \"space_time\", \"newmark\", \"newmark_dissipative\", \"hht\", \"generalized_alpha\", \"central_difference\"",
                ))
            }
        };
        if kind != ClassicKind::GeneralizedAlpha {
            unused(&rho_inf, "generalized_alpha")?;
        }
        if kind != ClassicKind::Hht {
            unused(&alpha_h, "hht")?;
        }
        if kind != ClassicKind::NewmarkDissipative {
            unused(&gamma_n, "newmark_dissipative")?;
        }
        Ok(Integrator::Classic { kind, params })
    }
}

impl Scenario {
    /// Reads and validates a scenario file.
    ///
    /// # Errors
    /// [`ScenarioError`] naming the file, the key and what is allowed.
    pub fn from_file(path: &Path) -> Result<Self, ScenarioError> {
        let text = std::fs::read_to_string(path).map_err(|source| ScenarioError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_str(&text, path)
    }

    /// Parses and validates scenario text; `path` names it in errors.
    ///
    /// # Errors
    /// [`ScenarioError`].
    pub fn from_str(text: &str, path: &Path) -> Result<Self, ScenarioError> {
        let raw: RawScenario = toml::from_str(text).map_err(|e| ScenarioError::Parse {
            path: path.to_path_buf(),
            message: e
                .to_string()
                .trim_end()
                .replace('\n', " ")
                .replace("  ", " "),
        })?;
        let cx = Ctx { path };
        let name = match raw.name {
            Some(n) if !n.trim().is_empty() && !n.contains(['/', '\\']) => n,
            Some(n) => {
                return Err(cx.invalid(
                    "name",
                    format!("\"{n}\""),
                    "must be a non-empty name without slashes",
                ))
            }
            None => path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "scenario".into()),
        };
        let time = raw.time.unwrap_or_default();
        let alpha = cx.alpha(
            "time.alpha",
            time.alpha.unwrap_or(SpaceTimeParams::DEFAULT_ALPHA),
        )?;
        let gamma = cx.gamma(
            "time.gamma",
            time.gamma.unwrap_or(SpaceTimeParams::DEFAULT_GAMMA),
        )?;
        let h = match time.h {
            Some(h) => Some(cx.positive("time.h", h)?),
            None => None,
        };
        let t_end = match (time.t_end, raw.kind.as_str()) {
            (Some(t), _) => cx.positive("time.t_end", t)?,
            (None, "wheel") => f64::NAN,
            (None, _) => return Err(cx.missing("time.t_end", "the end time of the run, s")),
        };
        let contact = raw.contact.unwrap_or_default();
        let model = match raw.kind.as_str() {
            "sdof" => {
                let s = raw
                    .sdof
                    .ok_or_else(|| cx.missing("sdof", "kind = \"sdof\" needs a [sdof] table"))?;
                Model::Sdof(Sdof {
                    mass: cx.positive("sdof.mass", s.mass)?,
                    stiffness: cx.positive("sdof.stiffness", s.stiffness)?,
                    x0: finite(&cx, "sdof.x0", s.x0.unwrap_or(1.0))?,
                    v0: finite(&cx, "sdof.v0", s.v0.unwrap_or(0.0))?,
                })
            }
            "bar_impact" => {
                let b = raw.bar.ok_or_else(|| {
                    cx.missing("bar", "kind = \"bar_impact\" needs a [bar] table")
                })?;
                let lumped = mass_kind(&cx, "bar.mass", b.mass.as_deref())?;
                Model::BarImpact(BarImpact {
                    length: cx.positive("bar.length", b.length)?,
                    ea: cx.positive("bar.ea", b.ea)?,
                    rho_a: cx.positive("bar.rho_a", b.rho_a)?,
                    speed: cx.positive("bar.speed", b.speed)?,
                    gap: cx.non_negative("bar.gap", b.gap)?,
                    elements: cx.count("bar.elements", b.elements, 1_000_000)?,
                    lumped,
                    damping: cx.non_negative("bar.damping", b.damping.unwrap_or(0.0))?,
                })
            }
            "two_bars" => {
                let b = raw.two_bars.ok_or_else(|| {
                    cx.missing("two_bars", "kind = \"two_bars\" needs a [two_bars] table")
                })?;
                if b.damping.is_some() {
                    return Err(cx.invalid(
                        "two_bars.damping",
                        b.damping.unwrap_or_default(),
                        "the two-bars case has no external damping",
                    ));
                }
                Model::TwoBars(TwoBars {
                    length: cx.positive("two_bars.length", b.length)?,
                    ea: cx.positive("two_bars.ea", b.ea)?,
                    rho_a: cx.positive("two_bars.rho_a", b.rho_a)?,
                    speed: cx.positive("two_bars.speed", b.speed)?,
                    gap: cx.non_negative("two_bars.gap", b.gap)?,
                    elements: cx.count("two_bars.elements", b.elements, 1_000_000)?,
                    lumped: mass_kind(&cx, "two_bars.mass", b.mass.as_deref())?,
                })
            }
            "wheel" => Model::Wheel(Box::new(wheel_model(
                &cx,
                raw.wheel,
                raw.material,
                raw.rolling,
            )?)),
            other => {
                return Err(cx.invalid(
                    "kind",
                    format!("\"{other}\""),
                    "allowed: \"sdof\", \"bar_impact\", \"two_bars\", \"wheel\"",
                ))
            }
        };
        let t_end = match &model {
            Model::Wheel(w) => {
                if time.t_end.is_some() {
                    return Err(cx.invalid(
                        "time.t_end",
                        t_end,
                        "a wheel run lasts rolling.settle_time + rolling.turns turns: remove time.t_end",
                    ));
                }
                w.duration()
            }
            _ => t_end,
        };
        let base_runs = if raw.runs.is_empty() {
            vec![RawRun::default()]
        } else {
            raw.runs
        };
        let mut runs = Vec::with_capacity(base_runs.len());
        let mut warnings = Vec::new();
        for (i, r) in base_runs.iter().enumerate() {
            let key = |k: &str| format!("runs[{i}].{k}");
            let alpha = match r.alpha {
                Some(a) => cx.alpha(&key("alpha"), a)?,
                None => alpha,
            };
            let gamma = match r.gamma {
                Some(g) => cx.gamma(&key("gamma"), g)?,
                None => gamma,
            };
            let h = match (r.h, h) {
                (Some(h), _) => cx.positive(&key("h"), h)?,
                (None, Some(h)) => h,
                (None, None) => return Err(cx.missing("time.h", "the time step, s (or runs[].h)")),
            };
            if h > t_end {
                return Err(cx.invalid(
                    &key("h"),
                    h,
                    &format!("the step must not exceed time.t_end = {t_end}"),
                ));
            }
            let mut model = model.clone();
            if let Some(e) = r.elements {
                match &mut model {
                    Model::BarImpact(b) => b.elements = cx.count(&key("elements"), e, 1_000_000)?,
                    Model::TwoBars(b) => b.elements = cx.count(&key("elements"), e, 1_000_000)?,
                    _ => {
                        return Err(cx.invalid(
                            &key("elements"),
                            e,
                            "only bar scenarios have elements",
                        ))
                    }
                }
            }
            // Each setting from the run, else from its table, with the key it came from.
            let pick = |run: Option<f64>, name: &str, table: &str, base: Option<f64>| {
                run.map(|x| (key(name), x))
                    .or(base.map(|x| (format!("{table}.{name}"), x)))
            };
            let (method_key, method_name) = match (&r.method, &contact.method) {
                (Some(m), _) => (key("method"), m.clone()),
                (None, Some(m)) => ("contact.method".to_string(), m.clone()),
                (None, None) => (
                    "contact.method".to_string(),
                    if matches!(model, Model::TwoBars(_)) {
                        "exact"
                    } else {
                        "soft_way"
                    }
                    .to_string(),
                ),
            };
            let run_contact = cx.contact(
                &method_key,
                &method_name,
                pick(r.penalty, "penalty", "contact", contact.penalty),
                pick(r.restitution, "restitution", "contact", contact.restitution),
            )?;
            let (integ_key, integ_name) = match (&r.integrator, &time.integrator) {
                (Some(m), _) => (key("integrator"), m.clone()),
                (None, Some(m)) => ("time.integrator".to_string(), m.clone()),
                (None, None) => ("time.integrator".to_string(), "space_time".to_string()),
            };
            let integrator = cx.integrator(
                &integ_key,
                &integ_name,
                (alpha, gamma),
                pick(r.rho_inf, "rho_inf", "time", time.rho_inf),
                pick(r.alpha_h, "alpha_h", "time", time.alpha_h),
                pick(r.gamma_n, "gamma_n", "time", time.gamma_n),
            )?;
            let space_time = matches!(integrator, Integrator::SpaceTime { .. });
            let method = match (&model, run_contact) {
                (Model::Wheel(_) | Model::Sdof(_), _) if !space_time => {
                    return Err(cx.invalid(
                        &integ_key,
                        format!("\"{integ_name}\""),
                        "only bar scenarios (bar_impact, two_bars) run the classic integrators; use \"space_time\"",
                    ))
                }
                (Model::Wheel(_), Contact::Lab(Treatment::Exact)) => ContactMethod::Exact,
                (Model::Wheel(_), Contact::Lab(_)) => {
                    return Err(cx.invalid(
                        &method_key,
                        format!("\"{method_name}\""),
                        "the wheel runs \"soft_way\", \"soft_way_braking_restore\", \"soft_way_no_restore\" or \"exact\"",
                    ))
                }
                (Model::TwoBars(_), Contact::Driver(_)) => {
                    return Err(cx.invalid(
                        &method_key,
                        format!("\"{method_name}\""),
                        "the soft way brakes a node against an obstacle; two_bars (node against node) runs \"exact\", \"penalty\", \"mass_redistribution\", \"moreau_jean\" or \"subdivision\"",
                    ))
                }
                (_, Contact::Driver(_)) if !space_time => {
                    return Err(cx.invalid(
                        &method_key,
                        format!("\"{method_name}\""),
                        &format!("the soft way is a treatment of the space-time scheme, not of {}; use integrator = \"space_time\"", integrator.name()),
                    ))
                }
                (_, Contact::Driver(m)) => m,
                (_, Contact::Lab(t)) => {
                    let refuse = match t {
                        Treatment::Subdivision if !space_time => Some("subdivision of the time step (the paper's Fig. 5) is a space-time treatment: use integrator = \"space_time\""),
                        Treatment::MassRedistribution if integrator.is_explicit() => Some("mass redistribution makes the contact nodes massless: the explicit central difference would divide by zero; use an implicit integrator"),
                        Treatment::MoreauJean { .. } if integrator.is_explicit() => Some("Moreau-Jean is a velocity-level implicit treatment; with the central difference the impulse acts one step late and the contact chatters: use an implicit integrator"),
                        _ => None,
                    };
                    if let Some(why) = refuse {
                        return Err(cx.invalid(&method_key, format!("\"{method_name}\""), why));
                    }
                    ContactMethod::Exact
                }
            };
            // The central difference runs explicit: lumped mass, step from cfl if given.
            let mut h = h;
            if integrator.is_explicit() {
                match &mut model {
                    Model::BarImpact(b) => b.lumped = true,
                    Model::TwoBars(b) => b.lumped = true,
                    _ => {}
                }
            }
            let pen = match run_contact {
                Contact::Lab(Treatment::Penalty { stiffness }) => Some(stiffness),
                _ => None,
            };
            if let Some((k, c)) = pick(r.cfl, "cfl", "time", time.cfl) {
                if !integrator.is_explicit() {
                    return Err(cx.invalid(
                        &k,
                        c,
                        "cfl sets the step of integrator = \"central_difference\" only",
                    ));
                }
                if !(c.is_finite() && c > 0.0 && c <= 1.0) {
                    return Err(cx.invalid(&k, c, "cfl must be in (0, 1]: the step as a fraction of the stable step 2/omega_max (penalty spring included)"));
                }
                h = c * explicit_stable_step(&model, pen);
            } else if integrator.is_explicit() {
                let hc = explicit_stable_step(&model, pen);
                if h > hc {
                    let with = if pen.is_some() {
                        " with the penalty spring"
                    } else {
                        ""
                    };
                    warnings.push(format!(
                        "run {i}: h = {h} exceeds the central difference's stable step{with}, {hc:.4e} s (2/omega_max): expect a blow-up (or set cfl)"
                    ));
                }
            }
            if let (Some(stiffness), true) = (pen, integrator.is_explicit()) {
                let m = explicit_contact_mass(&model);
                if h * (stiffness / m).sqrt() >= 2.0 {
                    warnings.push(format!(
                        "run {i}: penalty {stiffness:e} N/m on a node of {m:.3e} kg with the central difference: h sqrt(k/m) = {:.2} >= 2, the explicit penalty is unstable (keep k below {:.3e} N/m)",
                        h * (stiffness / m).sqrt(),
                        4.0 * m / (h * h)
                    ));
                }
            }
            let label = r.label.clone().unwrap_or_else(|| {
                if base_runs.len() == 1 {
                    "run".into()
                } else {
                    format!("h = {h}")
                }
            });
            let rep = analyse(alpha, gamma, 1);
            if let (true, Some(lim)) = (space_time, rep.stability_limit_omega_h) {
                let msg = format!(
                    "{label}: (alpha = {alpha}, gamma = {gamma}) is only conditionally stable: omega h must stay below {lim:.4} (see `softway stability --alpha {alpha} --gamma {gamma}`)"
                );
                warnings.push(msg);
            }
            runs.push(Run {
                label,
                params: SpaceTimeParams { alpha, gamma, h },
                model,
                method,
                integrator,
                contact: run_contact,
                t_end,
            });
        }
        let out = raw.output.unwrap_or_default();
        let history_stride = cx.count(
            "output.history_stride",
            out.history_stride.unwrap_or(1),
            1_000_000_000,
        )?;
        Ok(Self {
            name,
            description: raw.description.unwrap_or_default(),
            path: path.to_path_buf(),
            runs,
            history_stride,
            plots: out.plots.unwrap_or(true),
            warnings,
            sweep: match raw.sweep {
                Some(sw) if sw.values.is_empty() => {
                    return Err(cx.invalid("sweep.values", "[]", "give at least one value"));
                }
                Some(sw) => Some((sw.key, sw.values.iter().map(|v| v.to_string()).collect())),
                None => None,
            },
        })
    }
}

fn mass_kind(cx: &Ctx, key: &str, v: Option<&str>) -> Result<bool, ScenarioError> {
    match v.unwrap_or("consistent") {
        "consistent" => Ok(false),
        "lumped" => Ok(true),
        other => Err(cx.invalid(
            key,
            format!("\"{other}\""),
            "allowed: \"consistent\", \"lumped\"",
        )),
    }
}

/// The bar carrying the contact node: the bar itself, or bar A of two bars.
fn contact_bar(model: &Model) -> Option<BarImpact> {
    match model {
        Model::BarImpact(b) => Some(*b),
        Model::TwoBars(b) => Some(b.bar_a()),
        _ => None,
    }
}

/// The stable step `2 / omega_max` of the central difference on the contact bar (lumped),
/// with a penalty spring `k` (N/m) on the contact dof when given (for two bars `2 k`: the
/// spring between two equal facing nodes acts on their relative motion at twice the rate).
fn explicit_stable_step(model: &Model, penalty: Option<f64>) -> f64 {
    let Some(mut bar) = contact_bar(model) else {
        return f64::INFINITY;
    };
    bar.lumped = true;
    let k = penalty.unwrap_or(0.0)
        * if matches!(model, Model::TwoBars(_)) {
            2.0
        } else {
            1.0
        };
    let mut m = bar.model(&bar.mesh());
    let pattern = m.pattern().clone();
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let d = bar.elements;
    for p in cp[d]..cp[d + 1] {
        if ri[p] == d {
            m.k[p] += k;
        }
    }
    crate::time::classic::stable_step(&m, &[])
}

/// The lumped mass of the contact node, kg.
fn explicit_contact_mass(model: &Model) -> f64 {
    contact_bar(model)
        .map(|b| b.rho_a * b.length / (2.0 * b.elements as f64))
        .unwrap_or(f64::INFINITY)
}

fn finite(cx: &Ctx, key: &str, v: f64) -> Result<f64, ScenarioError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(cx.invalid(key, v, "must be a finite number"))
    }
}

fn wheel_model(
    cx: &Ctx,
    w: Option<RawWheel>,
    m: Option<RawMaterial>,
    r: Option<RawRolling>,
) -> Result<WheelScenario, ScenarioError> {
    use crate::contact::obstacle::Flattening;
    use crate::material::{Elastic, PlaneModel};
    use crate::wheel::{Support, WheelSpec};
    let w = w.ok_or_else(|| cx.missing("wheel", "kind = \"wheel\" needs a [wheel] table"))?;
    let m = m.ok_or_else(|| {
        cx.missing(
            "material",
            "the wheel's [material] (young, poisson, density)",
        )
    })?;
    let r = r.ok_or_else(|| {
        cx.missing(
            "rolling",
            "[rolling] (omega, flattening, settle_time, turns)",
        )
    })?;
    let radius = cx.positive("wheel.radius", w.radius)?;
    let thickness = cx.positive("wheel.thickness", w.thickness)?;
    let young = cx.positive("material.young", m.young)?;
    if !(m.poisson.is_finite() && m.poisson > -1.0 && m.poisson < 0.5) {
        return Err(cx.invalid(
            "material.poisson",
            m.poisson,
            "Poisson's ratio must be in (-1, 0.5)",
        ));
    }
    let density = cx.positive("material.density", m.density)?;
    let mesh = match (w.rings, &w.mesh) {
        (Some(_), Some(_)) => {
            return Err(cx.invalid(
                "wheel.mesh",
                "given with wheel.rings",
                "give either wheel.rings or wheel.mesh, not both",
            ))
        }
        (Some(n), None) => MeshSource::Rings(cx.count("wheel.rings", n, 400)?),
        (None, Some(f)) => {
            let p = Path::new(f);
            let p = if p.is_relative() {
                cx.path.parent().unwrap_or(Path::new(".")).join(p)
            } else {
                p.to_path_buf()
            };
            MeshSource::Gmsh(p)
        }
        (None, None) => MeshSource::Rings(12),
    };
    let plane = match w.plane.as_deref().unwrap_or("stress") {
        "stress" => PlaneModel::Stress,
        "strain" => PlaneModel::Strain,
        o => {
            return Err(cx.invalid(
                "wheel.plane",
                format!("\"{o}\""),
                "allowed: \"stress\", \"strain\"",
            ))
        }
    };
    let lumped = match w.mass.as_deref().unwrap_or("consistent") {
        "consistent" => false,
        "lumped" => true,
        o => {
            return Err(cx.invalid(
                "wheel.mass",
                format!("\"{o}\""),
                "allowed: \"consistent\", \"lumped\"",
            ))
        }
    };
    let support = match w.support.as_deref().unwrap_or("centre") {
        "centre" | "center" => Support::CentrePinned,
        "hub" => {
            let hr = w.hub_radius.ok_or_else(|| {
                cx.missing(
                    "wheel.hub_radius",
                    "support = \"hub\" needs the hub radius, m",
                )
            })?;
            let hr = cx.positive("wheel.hub_radius", hr)?;
            if hr >= radius {
                return Err(cx.invalid(
                    "wheel.hub_radius",
                    hr,
                    &format!("must be smaller than wheel.radius = {radius}"),
                ));
            }
            Support::Hub { radius: hr }
        }
        o => {
            return Err(cx.invalid(
                "wheel.support",
                format!("\"{o}\""),
                "allowed: \"centre\", \"hub\"",
            ))
        }
    };
    let omega = r.omega;
    if !(omega.is_finite() && omega > 0.0) {
        return Err(cx.invalid(
            "rolling.omega",
            omega,
            "the wheel's angular speed must be a finite number > 0, rad/s",
        ));
    }
    let depth = cx.positive("rolling.flattening", r.flattening)?;
    if depth >= radius {
        return Err(cx.invalid(
            "rolling.flattening",
            depth,
            &format!("the flattening must be smaller than wheel.radius = {radius} m"),
        ));
    }
    let settle_time = cx.non_negative("rolling.settle_time", r.settle_time)?;
    let turns = cx.positive("rolling.turns", r.turns)?;
    let settle_gamma = match r.settle_gamma {
        Some(g) => Some(cx.gamma("rolling.settle_gamma", g)?),
        None => None,
    };
    Ok(WheelScenario {
        spec: WheelSpec {
            radius,
            thickness,
            material: Elastic {
                young,
                poisson: m.poisson,
                density,
            },
            plane,
            lumped,
            damping: cx.non_negative("wheel.damping", w.damping.unwrap_or(0.0))?,
            support,
            omega,
            flattening: Flattening { depth, settle_time },
            stress_stiffening: w.stress_stiffening.unwrap_or(true),
            rotating_frame: w.rotating_frame.unwrap_or(true),
        },
        mesh,
        turns,
        settle_gamma,
        fields_per_turn: cx.count(
            "rolling.fields_per_turn",
            r.fields_per_turn.unwrap_or(8),
            1000,
        )?,
    })
}

/// Sets a dotted key (e.g. `rolling.omega`) in TOML text to a value, for sweeps and
/// command-line overrides; the result is validated as usual.
///
/// # Errors
/// A message naming the key when the text is not TOML or the key cannot be set.
pub fn set_key(text: &str, key: &str, value: &str) -> Result<String, String> {
    let mut doc: toml::Table = toml::from_str(text).map_err(|e| e.to_string())?;
    let parsed: toml::Value = match toml::from_str::<toml::Table>(&format!("v = {value}")) {
        Ok(t) => t["v"].clone(),
        Err(_) => toml::Value::String(value.to_string()),
    };
    let parts: Vec<&str> = key.split('.').collect();
    let mut cur = &mut doc;
    for (i, part) in parts.iter().enumerate() {
        if i + 1 == parts.len() {
            cur.insert((*part).to_string(), parsed.clone());
        } else {
            cur = cur
                .entry((*part).to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()))
                .as_table_mut()
                .ok_or_else(|| format!("`{}` is not a table", parts[..=i].join(".")))?;
        }
    }
    toml::to_string(&doc).map_err(|e| e.to_string())
}
