//! Stage 2, validate: the parsed file ([`super::raw`]) into a [`Scenario<RunSpec>`]: every
//! value's type, range and default, and the combination of model, integrator and contact
//! treatment of every run through the one table
//! [`check_combination`](super::combinations::check_combination). Plain data out:
//! nothing is assembled and no file other than the scenario is read (a `cfl` stays a
//! [`TimeStep::Cfl`] for [`crate::build`]).

use super::kind::{KindInput, Model, Registry};
use super::raw::{RawContact, RawRun, RawScenario, RawTime};
use super::{Contact, RunSpec, Scenario, ScenarioError, TimeStep};
use crate::contact::{FrictionLaw, Restore, Treatment};

mod run;
mod usage;

/// Default hub radius of `support = "hub"`, as a fraction of the wheel's radius (1 cm for
/// the paper's 10 cm wheel).
pub const DEFAULT_HUB_FRACTION: f64 = 0.1;
use crate::time::classic::ClassicParams;
use crate::time::sdof::analyse;
use crate::time::SpaceTimeParams;
use crate::time::{ClassicKind, Coriolis, Integrator};
use std::path::Path;

/// Validates a parsed scenario of `text` with the kinds of `kinds`; `path` names it in
/// errors and anchors relative mesh paths; `positions`: whether a parse error of a kind's
/// table names its line (not for a `--set` override's).
///
/// # Errors
/// [`ScenarioError::Invalid`] or [`ScenarioError::Missing`], naming the key.
pub(super) fn validate(
    raw: RawScenario,
    (text, path): (&str, &Path),
    kinds: &Registry,
    positions: bool,
) -> Result<Scenario<RunSpec>, ScenarioError> {
    let cx = Ctx { path, positions };
    let RawScenario {
        name,
        kind,
        description,
        time,
        contact,
        runs: raw_runs,
        output,
        sweep,
        growth,
        wear,
        keys,
    } = raw;
    let growth = crate::growth::config::validate(growth, wear, path)?;
    let name = scenario_name(&cx, name, path)?;
    let time = time.unwrap_or_default();
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
    let Some(the_kind) = kinds.get(&kind) else {
        return Err(cx.invalid(
            "kind",
            format!("\"{kind}\""),
            &format!("allowed: {}", kinds.names()),
        ));
    };
    let every_run_explicit = every_run_explicit(time.integrator.as_ref(), &raw_runs);
    usage::check_tables(&cx, the_kind, kinds, &keys, None)?;
    let model = the_kind.model(&KindInput {
        cx: &cx,
        text,
        every_run_explicit,
    })?;
    let given_end = match time.t_end {
        Some(t) => Some(cx.positive("time.t_end", t)?),
        None => None,
    };
    usage::check_tables(&cx, the_kind, kinds, &keys, Some(&model))?;
    let t_end = model.end_time(&cx, given_end)?;
    model.check_scenario(&cx, raw_runs.len(), contact.is_some())?;
    let base = Base {
        alpha,
        gamma,
        h,
        t_end,
        model,
        time,
        contact: contact.unwrap_or_default(),
    };
    let raw_runs = if raw_runs.is_empty() {
        vec![RawRun::default()]
    } else {
        raw_runs
    };
    // The top-level settings given that runs may override: (name, key, value); a bar's
    // `elements` under its table.
    let mut top_model = base.model.clone();
    let elements = top_model.elements_mut().map(|(t, e)| (t, *e));
    let top: Vec<(&str, String, String)> = usage::SETTINGS
        .iter()
        .filter_map(|&(name, table, _)| {
            let given = elements.filter(|e| e.1 > 0).map(|e| e.1 as i64);
            let value = usage::top_value(&base.time, &base.contact, given, name)?;
            let table = match (table, elements) {
                ("", Some((t, _))) => t,
                _ => table,
            };
            Some((name, format!("{table}.{name}"), value))
        })
        .collect();
    let mut runs = Vec::with_capacity(raw_runs.len());
    let mut uses = Vec::with_capacity(raw_runs.len());
    let mut warnings = Vec::new();
    for (i, r) in raw_runs.iter().enumerate() {
        let (run, used) = run::run_spec(&cx, i, r, &base, &top)?;
        warnings.extend(stability_warning(&run, raw_runs.len()));
        runs.push(run);
        uses.push(used);
    }
    usage::check_top_used(&cx, &top, &uses)?;
    let out = output.unwrap_or_default();
    let history_stride = cx.count(
        "output.history_stride",
        out.history_stride.unwrap_or(1),
        1_000_000_000,
    )?;
    let (sweep, sweep_ladder, sweep_ladder_with) = sweep_tables(&cx, sweep)?;
    Ok(Scenario {
        name,
        description: description.unwrap_or_default(),
        path: path.to_path_buf(),
        runs,
        history_stride,
        plots: out.plots.unwrap_or(true),
        warnings,
        sweep,
        sweep_ladder,
        sweep_ladder_with,
        source_sha256: String::new(),
        source_text: String::new(),
        overrides: Vec::new(),
        growth,
    })
}

/// The scenario's `name` (the output folder's), or its file's stem.
fn scenario_name(cx: &Ctx, name: Option<String>, path: &Path) -> Result<String, ScenarioError> {
    Ok(match name {
        Some(n)
            if !n.trim().is_empty()
                && !n.contains(['/', '\\', '\0'])
                && n != "."
                && n != ".."
                && n.len() <= crate::output::staging::NAME_MAX =>
        {
            n
        }
        Some(n) => {
            return Err(cx.invalid(
                "name",
                format!("\"{}\"", n.escape_debug()),
                &format!("must be a non-empty name of at most {} bytes (this one: {}) without slashes or NUL, not \".\" or \"..\" (it names the output folder out/<name>)", crate::output::staging::NAME_MAX, n.len()),
            ))
        }
        None => path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scenario".into()),
    })
}

/// Whether every run runs the explicit central difference (the top-level `integrator`,
/// or each `[[runs]]` entry's).
fn every_run_explicit(integrator: Option<&String>, raw_runs: &[RawRun]) -> bool {
    let explicit = |i: Option<&String>| i.is_some_and(|i| i == "central_difference");
    let top = explicit(integrator);
    if raw_runs.is_empty() {
        top
    } else {
        raw_runs
            .iter()
            .all(|r| r.integrator.as_ref().map_or(top, |i| explicit(Some(i))))
    }
}

/// A sweep's or a ladder's key and its values (TOML literals).
type KeyValues = (String, Vec<String>);

/// `[sweep]`: its key and values, its ladder's, and the keys set with each rung.
type SweepTables = (Option<KeyValues>, Option<KeyValues>, Vec<KeyValues>);

/// The scenario's `[sweep]`: its key and values, the refinement ladder it runs on, and the
/// keys set with each rung (`ladder.with`).
fn sweep_tables(
    cx: &Ctx,
    sweep: Option<crate::scenario::raw::RawSweep>,
) -> Result<SweepTables, ScenarioError> {
    Ok(match sweep {
        Some(sw) if sw.values.is_empty() => {
            return Err(cx.invalid("sweep.values", "[]", "give at least one value"));
        }
        Some(sw) => {
            let mut with = Vec::new();
            let ladder = match sw.ladder {
                Some(l) if l.key == sw.key => {
                    return Err(cx.invalid(
                        "sweep.ladder.key",
                        &l.key,
                        "a key other than sweep.key (the ladder runs every value of sweep.key on each rung)",
                    ));
                }
                Some(l) => {
                    let values: Vec<String> = l.values.iter().map(|v| v.to_string()).collect();
                    super::overrides::ladder_rungs(&values, 2).map_err(|why| {
                        cx.invalid(
                            "sweep.ladder.values",
                            format!("[{}]", values.join(", ")),
                            &why,
                        )
                    })?;
                    for (k, v) in l.with.iter().flatten() {
                        let name = format!("sweep.ladder.with.\"{k}\"");
                        if *k == sw.key || *k == l.key || !k.contains('.') {
                            return Err(cx.invalid(
                                &name,
                                v,
                                "a dotted key of the scenario other than sweep.key and sweep.ladder.key, set with each rung",
                            ));
                        }
                        match v.as_array() {
                            Some(vs) if vs.len() == values.len() => {
                                with.push((k.clone(), vs.iter().map(|v| v.to_string()).collect()))
                            }
                            _ => {
                                return Err(cx.invalid(
                                    &name,
                                    v,
                                    &format!(
                                    "a list of one value a rung: {} values, as sweep.ladder.values",
                                    values.len()
                                ),
                                ))
                            }
                        }
                    }
                    Some((l.key, values))
                }
                None => None,
            };
            (
                Some((sw.key, sw.values.iter().map(|v| v.to_string()).collect())),
                ladder,
                with,
            )
        }
        None => (None, None, Vec::new()),
    })
}

/// What every run starts from: the top-level settings, validated on their own.
struct Base {
    alpha: f64,
    gamma: f64,
    /// `time.h`, s, if given.
    h: Option<f64>,
    t_end: f64,
    model: Model,
    /// `[time]` as written (integrator and its parameters, `cfl`).
    time: RawTime,
    /// `[contact]` as written.
    contact: RawContact,
}

/// The warning for a space-time run whose `(alpha, gamma)` is only conditionally stable
/// (the one-degree-of-freedom analysis of [`crate::time::sdof`], no model needed).
fn stability_warning(run: &RunSpec, runs: usize) -> Option<String> {
    // A cfl step belongs to the central difference, never to the space-time scheme.
    let TimeStep::Fixed(h) = run.step else {
        return None;
    };
    if !matches!(run.integrator, Integrator::SpaceTime { .. }) {
        return None;
    }
    let (alpha, gamma) = (run.alpha, run.gamma);
    let lim = analyse(alpha, gamma, 1).stability_limit_omega_h?;
    Some(format!(
        "{}: (alpha = {alpha}, gamma = {gamma}) is only conditionally stable: omega h must stay below {lim:.4} (see `softway stability --alpha {alpha} --gamma {gamma}`)",
        run.label_or_default(runs, h)
    ))
}

/// A number as written by `Display` (`1e-300` as 300 digits) in exponent form when that is
/// shorter; anything else as it is.
fn compact_number(text: String) -> String {
    match text.parse::<f64>() {
        Ok(v) if text.len() > 12 && v.is_finite() => {
            let e = format!("{v:e}");
            if e.len() < text.len() {
                e
            } else {
                text
            }
        }
        _ => text,
    }
}

/// `text` with its control characters (a line break in a TOML string) escaped, so that a
/// message stays on one line.
fn one_line(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_control() {
                c.escape_default().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// The checks of a scenario's values: each error names the file, the key, the value and
/// what is allowed.
pub struct Ctx<'a> {
    path: &'a Path,
    /// Whether a parse error names its line (not for a `--set` override's).
    positions: bool,
}

impl<'a> Ctx<'a> {
    /// The checks of the scenario file `path`.
    pub fn new(path: &'a Path) -> Self {
        Self {
            path,
            positions: true,
        }
    }

    /// The scenario file.
    pub fn path(&self) -> &Path {
        self.path
    }

    /// A kind's tables `T` from the scenario text ([`crate::scenario::kind::KindInput::tables`]).
    ///
    /// # Errors
    /// [`ScenarioError::Parse`].
    pub fn parse_tables<T: serde::de::DeserializeOwned>(
        &self,
        text: &str,
    ) -> Result<T, ScenarioError> {
        super::raw::parse_tables(text, self.positions).map_err(|message| ScenarioError::Parse {
            path: self.path.to_path_buf(),
            message,
        })
    }

    /// The refusal of `value` under `key`, with what is allowed.
    pub fn invalid(
        &self,
        key: &str,
        value: impl std::fmt::Display,
        allowed: &str,
    ) -> ScenarioError {
        ScenarioError::Invalid {
            path: self.path.to_path_buf(),
            key: key.to_string(),
            value: one_line(&compact_number(value.to_string())),
            allowed: allowed.to_string(),
        }
    }
    /// A finite number under `key`.
    ///
    /// # Errors
    /// [`ScenarioError::Invalid`].
    pub fn finite(&self, key: &str, v: f64) -> Result<f64, ScenarioError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.invalid(key, v, "must be a finite number"))
        }
    }

    /// The refusal of a missing `key`, with what it is for.
    pub fn missing(&self, key: &str, why: &str) -> ScenarioError {
        ScenarioError::Missing {
            path: self.path.to_path_buf(),
            key: key.to_string(),
            why: why.to_string(),
        }
    }
    /// See the module's checks.
    pub fn positive(&self, key: &str, v: f64) -> Result<f64, ScenarioError> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.invalid(key, v, "must be a finite number > 0"))
        }
    }
    /// See the module's checks.
    pub fn non_negative(&self, key: &str, v: f64) -> Result<f64, ScenarioError> {
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(self.invalid(key, v, "must be a finite number >= 0"))
        }
    }
    /// A finite number under `key` within `[lo, hi]`.
    ///
    /// # Errors
    /// [`ScenarioError::Invalid`] saying the range.
    pub fn within(&self, key: &str, v: f64, lo: f64, hi: f64) -> Result<f64, ScenarioError> {
        if v.is_finite() && v >= lo && v <= hi {
            Ok(v)
        } else {
            Err(self.invalid(key, v, &format!("must be within [{lo}, {hi}]")))
        }
    }
    /// See the module's checks.
    pub fn count(&self, key: &str, v: i64, max: i64) -> Result<usize, ScenarioError> {
        if v >= 1 && v <= max {
            Ok(v as usize)
        } else {
            Err(self.invalid(key, v, &format!("must be a whole number from 1 to {max}")))
        }
    }
    /// See the module's checks.
    pub fn alpha(&self, key: &str, v: f64) -> Result<f64, ScenarioError> {
        if v.is_finite() && v > 0.0 && v <= 1.0 {
            Ok(v)
        } else {
            Err(self.invalid(key, v, "alpha must be in (0, 1] (Eq. 8)"))
        }
    }
    /// See the module's checks.
    pub fn gamma(&self, key: &str, v: f64) -> Result<f64, ScenarioError> {
        if v.is_finite() && (0.0..=1.0).contains(&v) {
            Ok(v)
        } else {
            Err(self.invalid(key, v, "gamma must be in [0, 1] (Eq. 24)"))
        }
    }
    fn method(&self, key: &str, v: &str) -> Result<Treatment, ScenarioError> {
        let soft = |restore| Ok(Treatment::SoftWay { restore });
        match v {
            "soft_way" => soft(Restore::StoppingImpulse),
            "soft_way_no_restore" => soft(Restore::Nothing),
            "soft_way_braking_restore" => soft(Restore::BrakingReaction),
            "soft_way_momentum_restore" => soft(Restore::ApproachMomentum),
            "exact" => Ok(Treatment::Exact),
            _ => Err(self.invalid(
                key,
                format!("\"{v}\""),
                "allowed for the wheel: \"soft_way\", \"soft_way_braking_restore\", \"soft_way_momentum_restore\", \"soft_way_no_restore\", \"exact\"",
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
            "soft_way"
            | "soft_way_no_restore"
            | "soft_way_braking_restore"
            | "soft_way_momentum_restore" => {
                return self.method(key, v)
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
                    "allowed: \"soft_way\", \"soft_way_braking_restore\", \"soft_way_momentum_restore\", \"soft_way_no_restore\", \"exact\", \"penalty\", \"mass_redistribution\", \"moreau_jean\", \"subdivision\"",
                ))
            }
        };
        Ok(t)
    }

    /// The integrator named `v` (key `key`) with `alpha`, `gamma` (space-time) and the
    /// optional parameters `(key, value)` of the classic ones.
    #[allow(clippy::too_many_arguments)]
    fn integrator(
        &self,
        key: &str,
        v: &str,
        (alpha, gamma): (f64, f64),
        coriolis: Option<(String, String)>,
        rho_inf: Option<(String, f64)>,
        alpha_h: Option<(String, f64)>,
        gamma_n: Option<(String, f64)>,
    ) -> Result<Integrator, ScenarioError> {
        // A parameter of another integrator is refused by the use of the settings
        // (super::usage), not here.
        let (kind, params) = match v {
            "space_time" => {
                let coriolis = match coriolis {
                    None => Coriolis::Implicit,
                    Some((_, c)) if c == "implicit" => Coriolis::Implicit,
                    Some((_, c)) if c == "extrapolated" => Coriolis::Extrapolated,
                    Some((k, c)) => {
                        return Err(self.invalid(
                            &k,
                            format!("\"{c}\""),
                            "allowed: \"implicit\" (the Coriolis term in the step's matrix, the exact scheme), \"extrapolated\" (on the right-hand side, a Cholesky factor)",
                        ))
                    }
                };
                return Ok(Integrator::SpaceTime {
                    alpha,
                    gamma,
                    coriolis,
                });
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
        Ok(Integrator::Classic { kind, params })
    }
}

/// The friction law of `[contact]`: `friction` the static (Coulomb) coefficient,
/// `friction_kinetic` and `friction_velocity` the falling law's, `friction_viscosity` the
/// viscoplastic overstress, `tangential_stiffness` the stick's spring
/// ([`crate::contact::FrictionLaw`]).
fn friction_law(cx: &Ctx, c: &RawContact) -> Result<Option<FrictionLaw>, ScenarioError> {
    let Some(mu) = c.friction else {
        for (key, v) in [
            ("contact.friction_kinetic", c.friction_kinetic),
            ("contact.friction_velocity", c.friction_velocity),
            ("contact.friction_memory_um", c.friction_memory_um),
            ("contact.friction_viscosity", c.friction_viscosity),
            ("contact.tangential_stiffness", c.tangential_stiffness),
        ] {
            if let Some(v) = v {
                return Err(cx.invalid(
                    key,
                    v,
                    "needs contact.friction (the static coefficient) beside it",
                ));
            }
        }
        return Ok(None);
    };
    let static_mu = cx.non_negative("contact.friction", mu)?;
    let mut law =
        match (c.friction_kinetic, c.friction_velocity) {
            (None, None) => FrictionLaw::coulomb(static_mu),
            (Some(k), Some(v)) => FrictionLaw {
                static_mu,
                kinetic: cx.non_negative("contact.friction_kinetic", k)?,
                velocity: cx.positive("contact.friction_velocity", v)?,
                viscosity: 0.0,
                tangential_stiffness: 0.0,
                memory: 0.0,
            },
            (Some(k), None) => return Err(cx.invalid(
                "contact.friction_kinetic",
                k,
                "needs contact.friction_velocity (the Stribeck velocity v_s > 0, m/s) beside it",
            )),
            (None, Some(v)) => {
                return Err(cx.invalid(
                    "contact.friction_velocity",
                    v,
                    "needs contact.friction_kinetic (the coefficient at high slip speed) beside it",
                ))
            }
        };
    if let Some(l) = c.friction_memory_um {
        if c.friction_kinetic.is_none() {
            return Err(cx.invalid(
                "contact.friction_memory_um",
                l,
                "is the falling law's memory: give contact.friction_kinetic and contact.friction_velocity beside it",
            ));
        }
        law.memory = 1e-6 * cx.positive("contact.friction_memory_um", l)?;
    }
    if let Some(eta) = c.friction_viscosity {
        law.viscosity = cx.non_negative("contact.friction_viscosity", eta)?;
    }
    if let Some(kt) = c.tangential_stiffness {
        law.tangential_stiffness = cx.positive("contact.tangential_stiffness", kt)?;
    }
    if !law.is_active() {
        for (key, v) in [
            ("contact.friction_viscosity", c.friction_viscosity),
            ("contact.tangential_stiffness", c.tangential_stiffness),
        ] {
            if let Some(v) = v {
                return Err(cx.invalid(
                    key,
                    v,
                    "a key of the friction law, not used while contact.friction = 0 (frictionless): remove it",
                ));
            }
        }
    }
    Ok(Some(law))
}
