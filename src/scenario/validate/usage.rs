//! Every key of a scenario is used or refused: a table the kind does not read, a
//! run's own setting its integrator, treatment or model does not use, and a top-level setting
//! ([`SETTINGS`]) that no run uses (each run overrides it, or none runs the integrator or the
//! treatment it belongs to) are refused with one line naming the file, the key and what it
//! applies to. So a `sweep --set` of a key that every `[[runs]]` entry overrides is refused
//! for the same reason as the file that sets it.

use super::super::kind::{Kind, Model, Registry};
use super::super::raw::{RawContact, RawRun, RawTime};
use super::super::{Contact, ScenarioError, TimeStep};
use super::Ctx;
use crate::contact::Treatment;
use crate::time::{ClassicKind, Integrator};

/// Refuses a top-level table of `keys` (the file's top-level keys) that `kind` does not
/// read while another kind of `kinds` does: `[contact]` once the model is known (`model`,
/// which says why it has no contact), the others before.
///
/// # Errors
/// [`ScenarioError::Invalid`] naming the table and the kinds that read it.
pub(super) fn check_tables(
    cx: &Ctx,
    kind: &dyn Kind,
    kinds: &Registry,
    keys: &[String],
    model: Option<&Model>,
) -> Result<(), ScenarioError> {
    let reads = kind.tables();
    for table in keys {
        let table = table.as_str();
        if (table == "contact") != model.is_some() {
            continue;
        }
        if super::super::raw::COMMON.contains(&table) && table != "contact" {
            continue;
        }
        if reads.contains(&table) {
            continue;
        }
        let readers: Vec<String> = kinds
            .kinds()
            .filter(|k| k.tables().contains(&table))
            .map(|k| format!("kind = \"{}\"", k.name()))
            .collect();
        let why = match model.and_then(|m| m.no_contact()) {
            Some(why) if table == "contact" => format!(" ({why})"),
            _ => String::new(),
        };
        return Err(cx.invalid(
            table,
            "(a table)",
            &format!(
                "read by {} only, not by kind = \"{}\"{why}: remove [{table}] (this kind reads [{}])",
                readers.join(", "),
                kind.name(),
                reads.join("], [")
            ),
        ));
    }
    Ok(())
}

/// The settings a `[[runs]]` entry may override, with their top-level table and what they
/// are.
pub(super) const SETTINGS: [(&str, &str, &str); 13] = [
    ("h", "time", "the time step"),
    (
        "cfl",
        "time",
        "the central difference's step as a fraction of its stable step",
    ),
    ("alpha", "time", "alpha of the space-time scheme (Eq. 8)"),
    ("gamma", "time", "gamma of the space-time scheme (Eq. 24)"),
    ("integrator", "time", "the time integrator"),
    (
        "rho_inf",
        "time",
        "the spectral radius of integrator = \"generalized_alpha\"",
    ),
    ("alpha_h", "time", "alpha of integrator = \"hht\""),
    (
        "gamma_n",
        "time",
        "gamma of integrator = \"newmark_dissipative\"",
    ),
    (
        "coriolis",
        "time",
        "the space-time scheme's treatment of a rotating wheel's Coriolis term",
    ),
    ("method", "contact", "the contact treatment"),
    (
        "penalty",
        "contact",
        "the stiffness of method = \"penalty\"",
    ),
    (
        "restitution",
        "contact",
        "the restitution of method = \"moreau_jean\"",
    ),
    ("elements", "", "the bar's number of elements"),
];

/// The value of setting `name` in a `[[runs]]` entry, as written (`None`: not given).
fn run_value(r: &RawRun, name: &str) -> Option<String> {
    let f = |v: Option<f64>| v.map(|x| x.to_string());
    let s = |v: &Option<String>| v.as_ref().map(|x| format!("\"{x}\""));
    match name {
        "h" => f(r.h),
        "cfl" => f(r.cfl),
        "alpha" => f(r.alpha),
        "gamma" => f(r.gamma),
        "integrator" => s(&r.integrator),
        "rho_inf" => f(r.rho_inf),
        "alpha_h" => f(r.alpha_h),
        "gamma_n" => f(r.gamma_n),
        "coriolis" => s(&r.coriolis),
        "method" => s(&r.method),
        "penalty" => f(r.penalty),
        "restitution" => f(r.restitution),
        "elements" => r.elements.map(|e| e.to_string()),
        _ => None,
    }
}

/// The value of setting `name` at the top level (`[time]`, `[contact]`, the bar's table),
/// as written (`None`: not given).
pub(super) fn top_value(
    time: &RawTime,
    contact: &RawContact,
    elements: Option<i64>,
    name: &str,
) -> Option<String> {
    let f = |v: Option<f64>| v.map(|x| x.to_string());
    let s = |v: &Option<String>| v.as_ref().map(|x| format!("\"{x}\""));
    match name {
        "h" => f(time.h),
        "cfl" => f(time.cfl),
        "alpha" => f(time.alpha),
        "gamma" => f(time.gamma),
        "integrator" => s(&time.integrator),
        "rho_inf" => f(time.rho_inf),
        "alpha_h" => f(time.alpha_h),
        "gamma_n" => f(time.gamma_n),
        "coriolis" => s(&time.coriolis),
        "method" => s(&contact.method),
        "penalty" => f(contact.penalty),
        "restitution" => f(contact.restitution),
        "elements" => elements.map(|e| e.to_string()),
        _ => None,
    }
}

/// How one run uses a top-level setting.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Use {
    /// The run takes its value.
    Used,
    /// The run sets its own.
    Overridden,
    /// The run does not use the setting at all: why.
    NotUsed(String),
}

/// A run's configuration, as far as the use of its settings goes.
pub(super) struct RunConfig<'a> {
    /// The model.
    pub model: &'a Model,
    /// The integrator and its name as written (or the default's).
    pub integrator: (&'a Integrator, &'a str),
    /// The treatment and its name as written (or the default's).
    pub contact: (&'a Contact, &'a str),
    /// The step, and the key it came from (`time.h`, `runs[i].cfl`, ...).
    pub step: (&'a TimeStep, &'a str),
}

impl RunConfig<'_> {
    /// Why this run does not use the setting `name` wherever it is written (`None`: it
    /// does). `h` and `cfl` are the step's: [`Self::step_use`].
    fn unused(&self, name: &str) -> Option<String> {
        let (integ, integ_name) = self.integrator;
        let (contact, method_name) = self.contact;
        let by_integ = || format!("not used by integrator = \"{integ_name}\"");
        let classic =
            |k: ClassicKind| matches!(integ, Integrator::Classic { kind, .. } if *kind == k);
        match name {
            "alpha" | "gamma" if !integ.is_space_time() => Some(by_integ()),
            "rho_inf" if !classic(ClassicKind::GeneralizedAlpha) => Some(by_integ()),
            "alpha_h" if !classic(ClassicKind::Hht) => Some(by_integ()),
            "gamma_n" if !classic(ClassicKind::NewmarkDissipative) => Some(by_integ()),
            "cfl" if !integ.is_explicit() => Some(format!(
                "cfl sets the step of integrator = \"central_difference\" only, {}",
                by_integ()
            )),
            "coriolis" if !integ.is_space_time() => Some(by_integ()),
            "coriolis" => self.model.coriolis(),
            "method" | "penalty" | "restitution" if self.model.no_contact().is_some() => {
                self.model.no_contact().map(String::from)
            }
            "penalty" if !matches!(contact, Treatment::Penalty { .. }) => {
                Some(format!("not used by method = \"{method_name}\""))
            }
            "restitution" if !matches!(contact, Treatment::MoreauJean { .. }) => {
                Some(format!("not used by method = \"{method_name}\""))
            }
            _ => None,
        }
    }

    /// Whether the step setting `key` (`time.h`, `runs[i].cfl`, ...) is the one this run's
    /// step comes from.
    fn step_use(&self, key: &str, name: &str) -> Option<String> {
        if name == "cfl" {
            if let Some(why) = self.unused("cfl") {
                return Some(why);
            }
        }
        let (_, from) = self.step;
        (from != key).then(|| format!("the step is set by {from}"))
    }

    /// Why this run does not use its own setting `name` (`None`: it does).
    fn own_unused(&self, i: usize, name: &str) -> Option<String> {
        match name {
            "h" | "cfl" => self.step_use(&format!("runs[{i}].{name}"), name),
            _ => self.unused(name),
        }
    }
}

/// Refuses the settings of run `i` (`[[runs]]` entry `r`) that it does not use, and tells
/// how it uses each top-level setting given (`top`: the name, its key, its value).
///
/// # Errors
/// [`ScenarioError::Invalid`] naming `runs[i].<name>`, its value and why it is not used.
pub(super) fn run_uses(
    cx: &Ctx,
    i: usize,
    r: &RawRun,
    config: &RunConfig,
    top: &[(&str, String, String)],
) -> Result<Vec<Use>, ScenarioError> {
    for (name, _, what) in SETTINGS {
        let Some(value) = run_value(r, name) else {
            continue;
        };
        if let Some(why) = config.own_unused(i, name) {
            return Err(cx.invalid(
                &format!("runs[{i}].{name}"),
                value,
                &format!("{what}, {why}: remove it"),
            ));
        }
    }
    let own_step = r.h.is_some() || r.cfl.is_some();
    Ok(top
        .iter()
        .map(|(name, key, _)| {
            let own = match *name {
                "h" | "cfl" => own_step,
                n => run_value(r, n).is_some(),
            };
            let why = match *name {
                "h" | "cfl" => config.step_use(key, name),
                n => config.unused(n),
            };
            match why {
                // A run whose integrator does not use cfl: not used, whatever it overrides.
                Some(w) if *name == "cfl" && !config.integrator.0.is_explicit() => Use::NotUsed(w),
                _ if own => Use::Overridden,
                Some(w) => Use::NotUsed(w),
                None => Use::Used,
            }
        })
        .collect())
}

/// Refuses a top-level setting (`top[k]`: the name, its key, its value) that no run uses
/// (`uses[run][k]`).
///
/// # Errors
/// [`ScenarioError::Invalid`] naming the key, its value, what it is and why no run uses it.
pub(super) fn check_top_used(
    cx: &Ctx,
    top: &[(&str, String, String)],
    uses: &[Vec<Use>],
) -> Result<(), ScenarioError> {
    for (k, (name, key, value)) in top.iter().enumerate() {
        let of_runs: Vec<&Use> = uses.iter().filter_map(|u| u.get(k)).collect();
        if of_runs.iter().any(|u| **u == Use::Used) {
            continue;
        }
        let what = SETTINGS.iter().find(|s| s.0 == *name).map_or("", |s| s.2);
        let mut reasons: Vec<String> = Vec::new();
        for u in &of_runs {
            if let Use::NotUsed(w) = u {
                if !reasons.contains(w) {
                    reasons.push(w.clone());
                }
            }
        }
        let overridden = of_runs.iter().filter(|u| ***u == Use::Overridden).count();
        let why = match (reasons.is_empty(), overridden) {
            (true, _) => format!("every [[runs]] entry sets its own {name}"),
            (false, 0) => reasons.join("; "),
            (false, _) => format!(
                "{}; the other runs set their own {name}",
                reasons.join("; ")
            ),
        };
        return Err(cx.invalid(
            key,
            value,
            &format!("{what}, used by no run ({why}): remove it"),
        ));
    }
    Ok(())
}
