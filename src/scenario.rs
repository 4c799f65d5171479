//! Scenario files (TOML): parsed into raw structs (unknown keys rejected), then validated into
//! a [`Scenario`] whose every value has been checked, with errors that name the file, the
//! key and what is allowed (ripgrep's low-level / high-level arguments split).
//!
//! ```toml
//! name = "bar-impact"          # output folder name (default: the file's stem)
//! kind = "bar_impact"          # "sdof" | "bar_impact" | "wheel"
//!
//! [time]
//! alpha = 0.8                  # Eq. (8), in (0, 1]; default 0.8
//! gamma = 0.0                  # Eq. (24), in [0, 1]; default 0
//! h = 0.01                     # time step, s (> 0)
//! t_end = 5.0                  # end time, s (> 0)
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
//!                              # "soft_way_no_restore" | "exact"
//!
//! [[runs]]                     # optional: several runs of one scenario
//! label = "h = 0.4"
//! h = 0.4                      # any of h, alpha, gamma, elements, method
//! ```

use crate::contact::ContactMethod;
use crate::problems::BarImpact;
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
    /// Contact method.
    pub method: ContactMethod,
    /// End time, s.
    pub t_end: f64,
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
                "allowed: \"soft_way\", \"soft_way_braking_restore\", \"soft_way_no_restore\", \"exact\"",
            )),
        }
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
        let method = cx.method(
            "contact.method",
            raw.contact
                .and_then(|c| c.method)
                .as_deref()
                .unwrap_or("soft_way"),
        )?;
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
                let lumped = match b.mass.as_deref().unwrap_or("consistent") {
                    "consistent" => false,
                    "lumped" => true,
                    other => {
                        return Err(cx.invalid(
                            "bar.mass",
                            format!("\"{other}\""),
                            "allowed: \"consistent\", \"lumped\"",
                        ))
                    }
                };
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
                    "allowed: \"sdof\", \"bar_impact\", \"wheel\"",
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
            let method = match &r.method {
                Some(m) => cx.method(&key("method"), m)?,
                None => method,
            };
            let mut model = model.clone();
            if let Some(e) = r.elements {
                match &mut model {
                    Model::BarImpact(b) => b.elements = cx.count(&key("elements"), e, 1_000_000)?,
                    _ => {
                        return Err(cx.invalid(
                            &key("elements"),
                            e,
                            "only bar scenarios have elements",
                        ))
                    }
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
            if let Some(lim) = rep.stability_limit_omega_h {
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
