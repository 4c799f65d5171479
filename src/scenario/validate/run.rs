//! A run's validation: one `[[runs]]` entry (or the top-level settings alone) over the
//! scenario's [`Base`], stage by stage: its time, model, contact treatment, integrator,
//! their combination, friction, the wheel's refusals, the step and the use of every setting
//! ([`super::usage`]).

use super::super::combinations::{check_combination, Culprit};
use super::super::kind::{Model, RunView};
use super::super::raw::RawRun;
use super::super::{Contact, RunSpec, ScenarioError, TimeStep};
use super::usage::{run_uses, RunConfig, Use};
use super::{friction_law, Base, Ctx};
use crate::contact::FrictionLaw;
use crate::time::Integrator;

/// Run `i` (`[[runs]]` entry `r`, or the top-level settings alone): its overrides over
/// `base`, each setting checked under the key it came from (`runs[i].x` or `table.x`), with
/// how it uses each top-level setting of `top` ([`super::usage`]; a setting of its own
/// that it does not use is refused).
pub(super) fn run_spec(
    cx: &Ctx,
    i: usize,
    r: &RawRun,
    base: &Base,
    top: &[(&str, String, String)],
) -> Result<(RunSpec, Vec<Use>), ScenarioError> {
    let keys = RunKeys(i);
    // The label is a column of history.csv and a line of the plots' legends: one line.
    if let Some(l) = r.label.as_deref().filter(|l| l.contains(char::is_control)) {
        return Err(cx.invalid(
            &keys.key("label"),
            format!("{l:?}"),
            "a run's label is one line of text: no line break, tab or other control character",
        ));
    }
    let (alpha, gamma) = run_time(cx, &keys, r, base)?;
    let mut model = run_model(cx, &keys, r, base)?;
    if let Some(why) = model.no_contact() {
        let quoted = |m: &Option<String>| m.as_ref().map(|m| format!("\"{m}\""));
        for (k, given) in [
            ("method", quoted(&r.method)),
            ("penalty", r.penalty.map(|p| p.to_string())),
            ("restitution", r.restitution.map(|e| e.to_string())),
        ] {
            if let Some(value) = given {
                return Err(cx.invalid(&keys.key(k), value, why));
            }
        }
    }
    let (method_key, method_name, run_contact) = run_contact(cx, &keys, r, base, &model)?;
    let (integ_key, integ_name, integrator) = run_integrator(cx, &keys, r, base, (alpha, gamma))?;
    let (step, step_key) = run_step(cx, &keys, r, base, &model, &integrator)?;
    let uses = run_uses(
        cx,
        i,
        r,
        &RunConfig {
            model: &model,
            integrator: (&integrator, &integ_name),
            contact: (&run_contact, &method_name),
            step: (&step, &step_key),
        },
        top,
    )?;
    // The one table of allowed combinations (super::combinations).
    check_combination(&model, &integrator, &run_contact).map_err(|refusal| {
        let (k, v) = match refusal.culprit {
            Culprit::Integrator => (&integ_key, &integ_name),
            Culprit::Contact => (&method_key, &method_name),
        };
        cx.invalid(k, format!("\"{v}\""), &refusal.why)
    })?;
    let friction = run_friction(cx, base, &model, &run_contact)?;
    let gamma_key = if r.gamma.is_some() {
        keys.key("gamma")
    } else {
        "time.gamma".to_string()
    };
    model.check_run(
        cx,
        &RunView {
            index: i,
            integrator: (&integrator, &integ_name),
            contact: &run_contact,
            friction,
            alpha_gamma: (alpha, gamma),
            gamma_key,
        },
    )?;
    // The central difference runs explicit: a lumped mass, the step from cfl if given.
    if integrator.is_explicit() {
        model.spec_mut().make_explicit();
    }
    let spec = RunSpec {
        label: r.label.clone(),
        alpha,
        gamma,
        step,
        model,
        integrator,
        contact: run_contact,
        friction,
        t_end: base.t_end,
        step_key: step_key.clone(),
    };
    Ok((spec, uses))
}

/// The keys of run `i`'s settings: `runs[i].x` for its own, `table.x` for its tables'.
struct RunKeys(usize);

impl RunKeys {
    /// The key `runs[i].k` of the run's own setting `k`.
    fn key(&self, k: &str) -> String {
        let i = self.0;
        format!("runs[{i}].{k}")
    }

    /// Each setting from the run, else from its table, with the key it came from.
    fn pick(
        &self,
        run: Option<f64>,
        name: &str,
        table: &str,
        base: Option<f64>,
    ) -> Option<(String, f64)> {
        run.map(|x| (self.key(name), x))
            .or(base.map(|x| (format!("{table}.{name}"), x)))
    }
}

/// The run's `(alpha, gamma)`: its own, else the top-level ones.
fn run_time(
    cx: &Ctx,
    keys: &RunKeys,
    r: &RawRun,
    base: &Base,
) -> Result<(f64, f64), ScenarioError> {
    let alpha = match r.alpha {
        Some(a) => cx.alpha(&keys.key("alpha"), a)?,
        None => base.alpha,
    };
    let gamma = match r.gamma {
        Some(g) => cx.gamma(&keys.key("gamma"), g)?,
        None => base.gamma,
    };
    Ok((alpha, gamma))
}

/// The run's model: the top-level one with the run's `elements` (bars only; given here or
/// in the bar's table).
fn run_model(cx: &Ctx, keys: &RunKeys, r: &RawRun, base: &Base) -> Result<Model, ScenarioError> {
    let mut model = base.model.clone();
    let Some((table, elements)) = model.spec_mut().elements_mut() else {
        if let Some(e) = r.elements {
            return Err(cx.invalid(&keys.key("elements"), e, "only bar scenarios have elements"));
        }
        return Ok(model);
    };
    if let Some(e) = r.elements {
        *elements = cx.count(&keys.key("elements"), e, 1_000_000)?;
    }
    if *elements == 0 {
        return Err(cx.missing(
            &format!("{table}.elements"),
            &format!("the bar's number of elements (or {})", keys.key("elements")),
        ));
    }
    Ok(model)
}

/// The run's contact treatment with the key and the name it came from (default: exact for
/// two bars, the soft way otherwise).
fn run_contact(
    cx: &Ctx,
    keys: &RunKeys,
    r: &RawRun,
    base: &Base,
    model: &Model,
) -> Result<(String, String, Contact), ScenarioError> {
    let contact = &base.contact;
    let (method_key, method_name) = match (&r.method, &contact.method) {
        (Some(m), _) => (keys.key("method"), m.clone()),
        (None, Some(m)) => ("contact.method".to_string(), m.clone()),
        (None, None) => (
            "contact.method".to_string(),
            model.default_method().to_string(),
        ),
    };
    let run_contact = cx.contact(
        &method_key,
        &method_name,
        keys.pick(r.penalty, "penalty", "contact", contact.penalty),
        keys.pick(r.restitution, "restitution", "contact", contact.restitution),
    )?;
    Ok((method_key, method_name, run_contact))
}

/// The run's integrator with the key and the name it came from (default: the space-time
/// scheme), its Coriolis treatment and the classic ones' parameters.
fn run_integrator(
    cx: &Ctx,
    keys: &RunKeys,
    r: &RawRun,
    base: &Base,
    alpha_gamma: (f64, f64),
) -> Result<(String, String, Integrator), ScenarioError> {
    let time = &base.time;
    let (integ_key, integ_name) = match (&r.integrator, &time.integrator) {
        (Some(m), _) => (keys.key("integrator"), m.clone()),
        (None, Some(m)) => ("time.integrator".to_string(), m.clone()),
        (None, None) => ("time.integrator".to_string(), "space_time".to_string()),
    };
    let coriolis = match (&r.coriolis, &time.coriolis) {
        (Some(c), _) => Some((keys.key("coriolis"), c.clone())),
        (None, Some(c)) => Some(("time.coriolis".to_string(), c.clone())),
        (None, None) => None,
    };
    let integrator = cx.integrator(
        &integ_key,
        &integ_name,
        alpha_gamma,
        coriolis,
        keys.pick(r.rho_inf, "rho_inf", "time", time.rho_inf),
        keys.pick(r.alpha_h, "alpha_h", "time", time.alpha_h),
        keys.pick(r.gamma_n, "gamma_n", "time", time.gamma_n),
    )?;
    Ok((integ_key, integ_name, integrator))
}

/// The run's friction law ([`friction_law`]), checked against the model's dimension and the
/// treatment ([`crate::contact::Treatment::check_friction`]).
fn run_friction(
    cx: &Ctx,
    base: &Base,
    model: &Model,
    run_contact: &Contact,
) -> Result<Option<FrictionLaw>, ScenarioError> {
    // Friction: finite coefficients >= 0 (the falling law: kinetic coefficient and Stribeck
    // velocity), the kind's own rules, a 2D model, a treatment that carries it
    // (crate::contact::Treatment::check_friction).
    let friction = friction_law(cx, &base.contact)?;
    if let Some(law) = friction {
        model.check_friction(cx, law)?;
        run_contact
            .check_friction(Some(law), model.dim())
            .map_err(|why| cx.invalid("contact.friction", law.static_mu, &why))?;
    }
    Ok(friction)
}

/// Why an implicit run's only step setting, a `cfl`, does not set its step.
const NOT_EXPLICIT: &str = "cfl sets the step of integrator = \"central_difference\" only, not of an implicit integrator: give time.h (or runs[].h) instead";

/// The run's step and the key it comes from: the run's own (`runs[i].cfl` for the central
/// difference, else `runs[i].h`) before the top-level one (`time.cfl` for the central
/// difference, else `time.h`); a fixed step no longer than the run. A `cfl` the integrator
/// does not use, or a step setting the chosen one overrides, is refused by
/// [`super::usage`].
fn run_step(
    cx: &Ctx,
    keys: &RunKeys,
    r: &RawRun,
    base: &Base,
    model: &Model,
    integrator: &Integrator,
) -> Result<(TimeStep, String), ScenarioError> {
    let explicit = integrator.is_explicit();
    let cfl = |key: String, c: f64| {
        if c.is_finite() && c > 0.0 && c <= 1.0 {
            Ok((
                TimeStep::Cfl {
                    cfl: c,
                    key: key.clone(),
                },
                key,
            ))
        } else {
            Err(cx.invalid(&key, c, "cfl must be in (0, 1]: the step as a fraction of the stable step 2/omega_max (penalty spring included)"))
        }
    };
    let (h, key) = match (r.cfl, r.h, base.time.cfl, base.h) {
        (Some(c), _, _, _) if explicit => return cfl(keys.key("cfl"), c),
        (_, Some(h), _, _) => (cx.positive(&keys.key("h"), h)?, keys.key("h")),
        (_, None, Some(c), _) if explicit => return cfl("time.cfl".to_string(), c),
        (_, None, _, Some(h)) => (h, "time.h".to_string()),
        (Some(c), None, _, None) => return Err(cx.invalid(&keys.key("cfl"), c, NOT_EXPLICIT)),
        (None, None, Some(c), None) => return Err(cx.invalid("time.cfl", c, NOT_EXPLICIT)),
        (None, None, None, None) if model.default_step().is_some() => (
            model.default_step().unwrap_or_default(),
            "time.h".to_string(),
        ),
        _ => {
            return Err(cx.missing(
                "time.h",
                "the time step, s (or runs[].h; time.cfl for the central difference)",
            ))
        }
    };
    model.check_step(cx, &key, h)?;
    if h > base.t_end {
        return Err(cx.invalid(&key, h, &model.end_phrase(base.t_end)));
    }
    Ok((TimeStep::Fixed(h), key))
}
