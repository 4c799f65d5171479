//! Stage 2, validate: the parsed file ([`super::raw`]) into a [`Scenario<RunSpec>`]: every
//! value's type, range and default, and the combination of model, integrator and contact
//! treatment of every run through the one table [`check_combination`]. Plain data out:
//! nothing is assembled and no file other than the scenario is read (a `cfl` stays a
//! [`TimeStep::Cfl`] for [`crate::build`]).

use super::combinations::{check_combination, Culprit, ModelKind};
use super::raw::{
    RawBar, RawBlock, RawContact, RawMaterial, RawRolling, RawRun, RawScenario, RawSdof, RawTime,
    RawWheel,
};
use super::{
    Contact, MeshSource, Model, RunSpec, Scenario, ScenarioError, Sdof, TimeStep, WheelScenario,
};
use crate::contact::{FrictionLaw, Restore, Treatment};
use crate::wheel::{ContactSurface, Coupling};

/// Default hub radius of `support = "hub"`, as a fraction of the wheel's radius (1 cm for
/// the paper's 10 cm wheel).
pub const DEFAULT_HUB_FRACTION: f64 = 0.1;
use crate::problems::{BarImpact, TwoBars};
use crate::time::classic::ClassicParams;
use crate::time::sdof::analyse;
use crate::time::SpaceTimeParams;
use crate::time::{ClassicKind, Coriolis, Integrator};
use std::path::Path;

/// Validates a parsed scenario; `path` names it in errors and anchors relative mesh paths.
///
/// # Errors
/// [`ScenarioError::Invalid`] or [`ScenarioError::Missing`], naming the key.
pub(super) fn validate(raw: RawScenario, path: &Path) -> Result<Scenario<RunSpec>, ScenarioError> {
    let cx = Ctx { path };
    let RawScenario {
        name,
        kind,
        description,
        time,
        bar,
        two_bars,
        sdof,
        wheel,
        material,
        rolling,
        block,
        contact,
        runs: raw_runs,
        output,
        sweep,
    } = raw;
    let name = match name {
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
    let t_end = match (time.t_end, kind.as_str()) {
        (Some(t), _) => cx.positive("time.t_end", t)?,
        (None, "wheel") => f64::NAN,
        (None, _) => return Err(cx.missing("time.t_end", "the end time of the run, s")),
    };
    let mut model = model(
        &cx,
        &kind,
        (sdof, bar, two_bars),
        (wheel, material, rolling),
    )?;
    if let Some(b) = block {
        let Model::Wheel(w) = &mut model else {
            return Err(cx.invalid(
                "block",
                "(given)",
                "an elastic block is a base for kind = \"wheel\"",
            ));
        };
        w.block = Some(block_spec(&cx, b, &w.spec)?);
    }
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
    let mut runs = Vec::with_capacity(raw_runs.len());
    let mut warnings = Vec::new();
    for (i, r) in raw_runs.iter().enumerate() {
        let run = run_spec(&cx, i, r, &base)?;
        warnings.extend(stability_warning(&run, raw_runs.len()));
        runs.push(run);
    }
    let out = output.unwrap_or_default();
    let history_stride = cx.count(
        "output.history_stride",
        out.history_stride.unwrap_or(1),
        1_000_000_000,
    )?;
    let sweep = match sweep {
        Some(sw) if sw.values.is_empty() => {
            return Err(cx.invalid("sweep.values", "[]", "give at least one value"));
        }
        Some(sw) => Some((sw.key, sw.values.iter().map(|v| v.to_string()).collect())),
        None => None,
    };
    Ok(Scenario {
        name,
        description: description.unwrap_or_default(),
        path: path.to_path_buf(),
        runs,
        history_stride,
        plots: out.plots.unwrap_or(true),
        warnings,
        sweep,
        source_sha256: String::new(),
    })
}

/// The model of `kind` from its tables, each value checked under its key.
fn model(
    cx: &Ctx,
    kind: &str,
    (sdof, bar, two_bars): (Option<RawSdof>, Option<RawBar>, Option<RawBar>),
    (wheel, material, rolling): (Option<RawWheel>, Option<RawMaterial>, Option<RawRolling>),
) -> Result<Model, ScenarioError> {
    Ok(match kind {
        "sdof" => {
            let s =
                sdof.ok_or_else(|| cx.missing("sdof", "kind = \"sdof\" needs a [sdof] table"))?;
            Model::Sdof(Sdof {
                mass: cx.positive("sdof.mass", s.mass)?,
                stiffness: cx.positive("sdof.stiffness", s.stiffness)?,
                x0: finite(cx, "sdof.x0", s.x0.unwrap_or(1.0))?,
                v0: finite(cx, "sdof.v0", s.v0.unwrap_or(0.0))?,
            })
        }
        "bar_impact" => {
            let b =
                bar.ok_or_else(|| cx.missing("bar", "kind = \"bar_impact\" needs a [bar] table"))?;
            let lumped = mass_kind(cx, "bar.mass", b.mass.as_deref())?;
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
            let b = two_bars.ok_or_else(|| {
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
                lumped: mass_kind(cx, "two_bars.mass", b.mass.as_deref())?,
            })
        }
        "wheel" => Model::Wheel(Box::new(wheel_model(cx, wheel, material, rolling)?)),
        other => {
            return Err(cx.invalid(
                "kind",
                format!("\"{other}\""),
                "allowed: \"sdof\", \"bar_impact\", \"two_bars\", \"wheel\"",
            ))
        }
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

/// Run `i` (`[[runs]]` entry `r`, or the top-level settings alone): its overrides over
/// `base`, each setting checked under the key it came from (`runs[i].x` or `table.x`).
fn run_spec(cx: &Ctx, i: usize, r: &RawRun, base: &Base) -> Result<RunSpec, ScenarioError> {
    let key = |k: &str| format!("runs[{i}].{k}");
    let alpha = match r.alpha {
        Some(a) => cx.alpha(&key("alpha"), a)?,
        None => base.alpha,
    };
    let gamma = match r.gamma {
        Some(g) => cx.gamma(&key("gamma"), g)?,
        None => base.gamma,
    };
    let h = match (r.h, base.h) {
        (Some(h), _) => cx.positive(&key("h"), h)?,
        (None, Some(h)) => h,
        (None, None) => return Err(cx.missing("time.h", "the time step, s (or runs[].h)")),
    };
    if h > base.t_end {
        return Err(cx.invalid(
            &key("h"),
            h,
            &format!("the step must not exceed time.t_end = {}", base.t_end),
        ));
    }
    let mut model = base.model.clone();
    if let Some(e) = r.elements {
        match &mut model {
            Model::BarImpact(b) => b.elements = cx.count(&key("elements"), e, 1_000_000)?,
            Model::TwoBars(b) => b.elements = cx.count(&key("elements"), e, 1_000_000)?,
            _ => return Err(cx.invalid(&key("elements"), e, "only bar scenarios have elements")),
        }
    }
    // Each setting from the run, else from its table, with the key it came from.
    let pick = |run: Option<f64>, name: &str, table: &str, base: Option<f64>| {
        run.map(|x| (key(name), x))
            .or(base.map(|x| (format!("{table}.{name}"), x)))
    };
    let (time, contact) = (&base.time, &base.contact);
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
    let coriolis = match (&r.coriolis, &time.coriolis) {
        (Some(c), _) => Some((key("coriolis"), c.clone())),
        (None, Some(c)) => Some(("time.coriolis".to_string(), c.clone())),
        (None, None) => None,
    };
    let integrator = cx.integrator(
        &integ_key,
        &integ_name,
        (alpha, gamma),
        coriolis,
        pick(r.rho_inf, "rho_inf", "time", time.rho_inf),
        pick(r.alpha_h, "alpha_h", "time", time.alpha_h),
        pick(r.gamma_n, "gamma_n", "time", time.gamma_n),
    )?;
    // The one table of allowed combinations (super::combinations).
    check_combination(ModelKind::of(&model), &integrator, &run_contact).map_err(|refusal| {
        let (k, v) = match refusal.culprit {
            Culprit::Integrator => (&integ_key, &integ_name),
            Culprit::Contact => (&method_key, &method_name),
        };
        cx.invalid(k, format!("\"{v}\""), &refusal.why)
    })?;
    // Friction: finite coefficients >= 0 (the falling law: kinetic coefficient and Stribeck
    // velocity), on a 2D model (the wheel), with a treatment that carries it
    // (crate::contact::Treatment::check_friction).
    let friction = friction_law(cx, &base.contact)?;
    if let Some(law) = friction {
        let dim = if matches!(model, Model::Wheel(_)) {
            2
        } else {
            1
        };
        run_contact
            .check_friction(Some(law), dim)
            .map_err(|why| cx.invalid("contact.friction", law.static_mu, &why))?;
    }
    if let Model::Wheel(w) = &model {
        if let MeshSource::Zone(_) = w.mesh {
            let why = if friction.is_some_and(|law| law.is_active()) {
                Some("contact.friction: the traction outputs follow rim nodes, which a moving zone relabels (not yet)")
            } else if w.spec.coupling == Coupling::Uncoupled {
                Some("rolling.coupling = \"uncoupled\": its twin disk is not relabelled (not yet)")
            } else if w.spec.surface != ContactSurface::Nodes {
                Some("wheel.contact_surface = \"segments\": a moving zone relabels node pairs only")
            } else if !matches!(run_contact, Treatment::SoftWay { .. } | Treatment::Exact)
                || !integrator.is_space_time()
            {
                Some("a moving zone runs with the space-time scheme and the soft way or exact enforcement")
            } else {
                None
            };
            if let Some(why) = why {
                return Err(cx.invalid(
                    "wheel.zone_rim_nodes",
                    "(given)",
                    &format!("a moving refined zone does not work with {why}"),
                ));
            }
        }
        if w.spec.coupling == Coupling::Uncoupled {
            let why = if friction.is_none_or(|law| !law.is_active()) {
                Some("the uncoupled problem differs from the coupled one only through friction: set contact.friction > 0 (or remove rolling.coupling)")
            } else if w.spec.surface != ContactSurface::Nodes {
                Some("the uncoupled problem poses node pairs: remove wheel.contact_surface or set it to \"nodes\"")
            } else {
                None
            };
            if let Some(why) = why {
                return Err(cx.invalid("rolling.coupling", "\"uncoupled\"", why));
            }
        }
        if w.block.is_some() {
            let why = if friction.is_some_and(|law| law.is_active()) {
                Some("contact.friction: the block's tangential rows are searched but not yet verified; remove contact.friction")
            } else if w.spec.creepage != 0.0 {
                Some("rolling.creepage: the block runs under the wheel at the rim's speed; remove rolling.creepage")
            } else if w.spec.coupling == Coupling::Uncoupled {
                Some("rolling.coupling = \"uncoupled\": remove it")
            } else if w.spec.surface != ContactSurface::Nodes {
                Some("wheel.contact_surface = \"segments\": the rim's nodes are searched against the block's segments; remove it")
            } else if matches!(w.mesh, MeshSource::Zone(_)) {
                Some("a moving refined zone (wheel.zone_rim_nodes): remove it")
            } else {
                None
            };
            if let Some(why) = why {
                return Err(cx.invalid(
                    "block",
                    "(given)",
                    &format!("an elastic block does not work with {why}"),
                ));
            }
        }
        if w.spec.creepage != 0.0 && friction.is_none_or(|law| !law.is_active()) {
            return Err(cx.invalid(
                "rolling.creepage",
                w.spec.creepage,
                "a creepage transmits a force only through friction: set contact.friction > 0 \
                 (or remove rolling.creepage)",
            ));
        }
    }
    // The central difference runs explicit: lumped mass, step from cfl if given.
    if integrator.is_explicit() {
        match &mut model {
            Model::BarImpact(b) => b.lumped = true,
            Model::TwoBars(b) => b.lumped = true,
            _ => {}
        }
    }
    let step = match pick(r.cfl, "cfl", "time", time.cfl) {
        Some((k, c)) if !integrator.is_explicit() => {
            return Err(cx.invalid(
                &k,
                c,
                "cfl sets the step of integrator = \"central_difference\" only",
            ));
        }
        Some((k, c)) if !(c.is_finite() && c > 0.0 && c <= 1.0) => {
            return Err(cx.invalid(&k, c, "cfl must be in (0, 1]: the step as a fraction of the stable step 2/omega_max (penalty spring included)"));
        }
        Some((key, cfl)) => TimeStep::Cfl { cfl, key },
        None => TimeStep::Fixed(h),
    };
    Ok(RunSpec {
        label: r.label.clone(),
        alpha,
        gamma,
        step,
        model,
        integrator,
        contact: run_contact,
        friction,
        t_end: base.t_end,
    })
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

struct Ctx<'a> {
    path: &'a Path,
}

impl Ctx<'_> {
    fn invalid(&self, key: &str, value: impl std::fmt::Display, allowed: &str) -> ScenarioError {
        ScenarioError::Invalid {
            path: self.path.to_path_buf(),
            key: key.to_string(),
            value: one_line(&compact_number(value.to_string())),
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
    fn method(&self, key: &str, v: &str) -> Result<Treatment, ScenarioError> {
        let soft = |restore| Ok(Treatment::SoftWay { restore });
        match v {
            "soft_way" => soft(Restore::StoppingImpulse),
            "soft_way_no_restore" => soft(Restore::Nothing),
            "soft_way_braking_restore" => soft(Restore::BrakingReaction),
            "exact" => Ok(Treatment::Exact),
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
                    "allowed: \"soft_way\", \"soft_way_braking_restore\", \"soft_way_no_restore\", \"exact\", \"penalty\", \"mass_redistribution\", \"moreau_jean\", \"subdivision\"",
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
            _ if coriolis.is_some() => {
                let (k, c) = coriolis.unwrap_or_default();
                return Err(self.invalid(
                    &k,
                    format!("\"{c}\""),
                    "only used with integrator = \"space_time\"",
                ));
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

/// The friction law of `[contact]`: `friction` the static (Coulomb) coefficient,
/// `friction_kinetic` and `friction_velocity` the falling law's, `friction_viscosity` the
/// viscoplastic overstress, `tangential_stiffness` the stick's spring
/// ([`crate::contact::FrictionLaw`]).
fn friction_law(cx: &Ctx, c: &RawContact) -> Result<Option<FrictionLaw>, ScenarioError> {
    let Some(mu) = c.friction else {
        for (key, v) in [
            ("contact.friction_kinetic", c.friction_kinetic),
            ("contact.friction_velocity", c.friction_velocity),
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
    if let Some(eta) = c.friction_viscosity {
        law.viscosity = cx.non_negative("contact.friction_viscosity", eta)?;
    }
    if let Some(kt) = c.tangential_stiffness {
        law.tangential_stiffness = cx.positive("contact.tangential_stiffness", kt)?;
    }
    Ok(Some(law))
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
    let given = [
        ("wheel.rings", w.rings.is_some()),
        ("wheel.rim_nodes", w.rim_nodes.is_some()),
        ("wheel.mesh", w.mesh.is_some()),
    ];
    if given.iter().filter(|g| g.1).count() > 1 {
        let names: Vec<&str> = given.iter().filter(|g| g.1).map(|g| g.0).collect();
        return Err(cx.invalid(
            names[1],
            format!("given with {}", names[0]),
            "give one of wheel.rings, wheel.rim_nodes or wheel.mesh",
        ));
    }
    if w.grading.is_some() && w.rim_nodes.is_none() {
        return Err(cx.invalid(
            "wheel.grading",
            w.grading.unwrap_or_default(),
            "the grading of the disk of wheel.rim_nodes; give wheel.rim_nodes",
        ));
    }
    let mesh = match (w.rings, &w.mesh) {
        (None, None) if w.rim_nodes.is_some() => {
            let n = cx.count("wheel.rim_nodes", w.rim_nodes.unwrap_or(0), 100_000)?;
            if n < 12 {
                return Err(cx.invalid("wheel.rim_nodes", n, "at least 12 rim nodes"));
            }
            let grading = w
                .grading
                .unwrap_or(crate::mesh::generators::DiskOptions::DEFAULT_GRADING);
            if !(1.0..=2.0).contains(&grading) {
                return Err(cx.invalid("wheel.grading", grading, "in [1, 2]"));
            }
            MeshSource::Graded {
                rim_nodes: n,
                grading,
            }
        }
        (Some(n), _) => MeshSource::Rings(cx.count("wheel.rings", n, 400)?),
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
    // Default: a hub clamped over a tenth of the radius (the pinned centre is a point
    // support whose stiffness vanishes as the mesh is refined; `softway::wheel`).
    let support = match w.support.as_deref().unwrap_or("hub") {
        "centre" | "center" => {
            if let Some(hr) = w.hub_radius {
                return Err(cx.invalid(
                    "wheel.hub_radius",
                    hr,
                    "only with support = \"hub\" (the centre node is pinned)",
                ));
            }
            Support::CentrePinned
        }
        "hub" => {
            let hr = w.hub_radius.unwrap_or(DEFAULT_HUB_FRACTION * radius);
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
    let mesh = match (w.zone_rim_nodes, mesh) {
        (None, mesh) => {
            for (k, given) in [
                ("wheel.zone_width", w.zone_width.is_some()),
                ("wheel.zone_sectors", w.zone_sectors.is_some()),
            ] {
                if given {
                    return Err(cx.invalid(
                        k,
                        "(given)",
                        "a key of the moving refined zone: give wheel.zone_rim_nodes too",
                    ));
                }
            }
            mesh
        }
        (Some(z), MeshSource::Graded { rim_nodes, .. }) => {
            let Support::Hub { radius: hub_radius } = support else {
                return Err(cx.invalid(
                    "wheel.zone_rim_nodes",
                    z,
                    "the refined zone's mesh is the annulus on the hub: needs support = \"hub\"",
                ));
            };
            let sectors = cx.count("wheel.zone_sectors", w.zone_sectors.unwrap_or(72), 720)?;
            if sectors < 8 {
                return Err(cx.invalid("wheel.zone_sectors", sectors, "at least 8 sectors"));
            }
            let pow2 = |a: usize, b: usize| a % b == 0 && (a / b).is_power_of_two();
            if !pow2(rim_nodes, sectors) {
                return Err(cx.invalid(
                    "wheel.rim_nodes",
                    rim_nodes,
                    &format!("with a refined zone: wheel.zone_sectors = {sectors} times a power of two (e.g. {}, {})", sectors, 2 * sectors),
                ));
            }
            let zn = cx.count("wheel.zone_rim_nodes", z, 100_000)?;
            if !pow2(zn, rim_nodes) {
                return Err(cx.invalid(
                    "wheel.zone_rim_nodes",
                    zn,
                    &format!("wheel.rim_nodes = {rim_nodes} times 1, 2, 4, 8, ... (the rim's pitch in the zone; times 1: the same mesh family without a zone)"),
                ));
            }
            let width = w.zone_width.unwrap_or(30.0);
            let min = 2.0 * 360.0 / sectors as f64;
            if !(width.is_finite() && width >= min && width <= 180.0) {
                return Err(cx.invalid(
                    "wheel.zone_width",
                    width,
                    &format!("the zone's arc of the rim in degrees, from two sectors ({min}) to 180"),
                ));
            }
            MeshSource::Zone(crate::mesh::zone::ZoneOptions {
                radius,
                hub_radius,
                sectors,
                rim_nodes,
                zone_rim_nodes: zn,
                zone_width: width.to_radians(),
                grading: 0.3,
            })
        }
        (Some(z), _) => {
            return Err(cx.invalid(
                "wheel.zone_rim_nodes",
                z,
                "the refined zone is a generated mesh: give wheel.rim_nodes (the rim's pitch outside the zone), not wheel.rings or wheel.mesh",
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
    let creepage = r.creepage.unwrap_or(0.0);
    if !(creepage.is_finite() && creepage.abs() < 1.0) {
        return Err(cx.invalid(
            "rolling.creepage",
            creepage,
            "the creepage (omega rho - V)/(omega rho) must be a finite number between -1 and 1 \
             (railway creepages are below 0.01)",
        ));
    }
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
            creepage,
            coupling: match r.coupling.as_deref().unwrap_or("coupled") {
                "coupled" => Coupling::Coupled,
                "uncoupled" => Coupling::Uncoupled,
                o => {
                    return Err(cx.invalid(
                        "rolling.coupling",
                        format!("\"{o}\""),
                        "allowed: \"coupled\" (the elastic wheel on its rigid base), \"uncoupled\" (Carter's elastically similar bodies: a twin disk carries the tangential tractions)",
                    ))
                }
            },
            surface: match w.contact_surface.as_deref().unwrap_or("nodes") {
                "nodes" => ContactSurface::Nodes,
                "segments" => ContactSurface::Segments,
                o => {
                    return Err(cx.invalid(
                        "wheel.contact_surface",
                        format!("\"{o}\""),
                        "allowed: \"nodes\" (a gap per rim node), \"segments\" (mortar-weighted gaps on the rim's segments)",
                    ))
                }
            },
        },
        mesh,
        turns,
        settle_gamma,
        fields_per_turn: cx.count(
            "rolling.fields_per_turn",
            r.fields_per_turn.unwrap_or(8),
            1000,
        )?,
        block: None,
    })
}

/// The `[block]` table under a wheel of `spec`: the material (default the wheel's), the
/// depth (default half the wheel's radius), the top column width (default the rim's pitch),
/// the rows' growth (default 1.2), the margins before and after the travel (default the
/// depth: an end nearer than that softens the block under the patch) and the search's reach
/// (default four columns).
fn block_spec(
    cx: &Ctx,
    b: RawBlock,
    spec: &crate::wheel::WheelSpec,
) -> Result<crate::models::wheel_on_block::BlockSpec, ScenarioError> {
    use crate::material::Elastic;
    let mat = spec.material;
    let young = cx.positive("block.young", b.young.unwrap_or(mat.young))?;
    let density = cx.positive("block.density", b.density.unwrap_or(mat.density))?;
    let poisson = b.poisson.unwrap_or(mat.poisson);
    if !(poisson.is_finite() && poisson > -1.0 && poisson < 0.5) {
        return Err(cx.invalid(
            "block.poisson",
            poisson,
            "Poisson's ratio must be in (-1, 0.5)",
        ));
    }
    let grading = b.grading.unwrap_or(1.2);
    if !(1.0..=2.0).contains(&grading) {
        return Err(cx.invalid(
            "block.grading",
            grading,
            "the growth of the rows from the top down, in [1, 2]",
        ));
    }
    let opt = |key: &str, v: Option<f64>| v.map(|x| cx.positive(key, x)).transpose();
    let depth = cx.positive("block.depth", b.depth.unwrap_or(0.5 * spec.radius))?;
    if depth <= 2.0 * spec.flattening.depth {
        return Err(cx.invalid(
            "block.depth",
            depth,
            &format!(
                "the block must be deeper than twice rolling.flattening = {} m",
                spec.flattening.depth
            ),
        ));
    }
    Ok(crate::models::wheel_on_block::BlockSpec {
        material: Elastic {
            young,
            poisson,
            density,
        },
        depth,
        dx: opt("block.dx", b.dx)?,
        grading,
        margin: cx.positive("block.margin", b.margin.unwrap_or(depth))?,
        reach: opt("block.reach", b.reach)?,
    })
}
