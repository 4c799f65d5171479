//! Stage 3 of reading a scenario, build: what needs a model. The validated
//! [`Scenario<RunSpec>`] ([`crate::scenario`], plain data) becomes the [`Scenario`] of
//! [`Run`]s that the jobs ([`crate::run`]) take, each with its time step `h` resolved:
//!
//! - `cfl` (central difference): `h = cfl * 2 / omega_max`, with `omega_max` the largest
//!   natural circular frequency of the lumped contact bar, found by assembling it (and a
//!   penalty spring on the contact node, if any); see [`crate::time::classic::stable_step`].
//! - a fixed `h` with the central difference: a warning when it exceeds `2 / omega_max`.
//! - a penalty with the central difference: a warning when `h sqrt(k / m) >= 2` on the
//!   contact node of lumped mass `m`.
//!
//! The wheel's mesh is read later, by the wheel job ([`crate::run::wheel::build`]).

use crate::problems::BarImpact;
use crate::scenario::{Contact, Model, Run, RunSpec, Scenario, ScenarioError, TimeStep};
use crate::time::SpaceTimeParams;

/// Builds a validated scenario: every run's step resolved, the warnings of the build added
/// to those of the validation.
///
/// # Errors
/// [`ScenarioError::Invalid`] naming the `cfl` key when the model has no finite stable step
/// (not a bar; the validation refuses `cfl` there already).
pub fn resolve(sc: &Scenario<RunSpec>) -> Result<Scenario, ScenarioError> {
    let mut warnings = sc.warnings.clone();
    let mut runs = Vec::with_capacity(sc.runs.len());
    for (i, spec) in sc.runs.iter().enumerate() {
        let h = resolve_time_step(sc, i, &mut warnings)?;
        runs.push(Run {
            label: spec.label_or_default(sc.runs.len(), h),
            params: SpaceTimeParams {
                alpha: spec.alpha,
                gamma: spec.gamma,
                h,
            },
            model: spec.model.clone(),
            integrator: spec.integrator,
            contact: spec.contact,
            friction: spec.friction,
            t_end: spec.t_end,
        });
    }
    Ok(Scenario {
        name: sc.name.clone(),
        description: sc.description.clone(),
        path: sc.path.clone(),
        runs,
        history_stride: sc.history_stride,
        plots: sc.plots,
        warnings,
        sweep: sc.sweep.clone(),
    })
}

/// The step `h` (s) of run `i` of `sc`: the fixed step, or `cfl * 2 / omega_max` of the
/// central difference; pushes the warnings of an explicit run beyond stability.
///
/// # Errors
/// [`ScenarioError::Invalid`] naming the `cfl` key when the stable step is not finite.
pub fn resolve_time_step(
    sc: &Scenario<RunSpec>,
    i: usize,
    warnings: &mut Vec<String>,
) -> Result<f64, ScenarioError> {
    let run = &sc.runs[i];
    let explicit = run.integrator.is_explicit();
    let penalty = match run.contact {
        Contact::Penalty { stiffness } => Some(stiffness),
        _ => None,
    };
    let h = match &run.step {
        TimeStep::Cfl { cfl, key } => {
            let hc = explicit_stable_step(&run.model, penalty);
            if !(hc.is_finite() && hc > 0.0) {
                return Err(ScenarioError::Invalid {
                    path: sc.path.clone(),
                    key: key.clone(),
                    value: cfl.to_string(),
                    allowed: format!(
                        "the stable step of this model is {hc}: cfl needs a bar (bar_impact, two_bars)"
                    ),
                });
            }
            cfl * hc
        }
        &TimeStep::Fixed(h) => {
            if explicit {
                let hc = explicit_stable_step(&run.model, penalty);
                if h > hc {
                    let with = if penalty.is_some() {
                        " with the penalty spring"
                    } else {
                        ""
                    };
                    warnings.push(format!(
                        "run {i}: h = {h} exceeds the central difference's stable step{with}, {hc:.4e} s (2/omega_max): expect a blow-up (or set cfl)"
                    ));
                }
            }
            h
        }
    };
    if let (Some(stiffness), true) = (penalty, explicit) {
        let m = explicit_contact_mass(&run.model);
        if h * (stiffness / m).sqrt() >= 2.0 {
            warnings.push(format!(
                "run {i}: penalty {stiffness:e} N/m on a node of {m:.3e} kg with the central difference: h sqrt(k/m) = {:.2} >= 2, the explicit penalty is unstable (keep k below {:.3e} N/m)",
                h * (stiffness / m).sqrt(),
                4.0 * m / (h * h)
            ));
        }
    }
    Ok(h)
}

/// The bar carrying the contact node: the bar itself, or bar A of two bars.
fn contact_bar(model: &Model) -> Option<BarImpact> {
    match model {
        Model::BarImpact(b) => Some(*b),
        Model::TwoBars(b) => Some(b.bar_a()),
        _ => None,
    }
}

/// The stable step `2 / omega_max` (s) of the central difference on the contact bar
/// (lumped), with a penalty spring `k` (N/m) on the contact dof when given (for two bars
/// `2 k`: the spring between two equal facing nodes acts on their relative motion at twice
/// the rate); infinite for a model without a contact bar.
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn bar(integrator_and_step: &str, contact: &str) -> String {
        format!(
            r#"
kind = "bar_impact"
[time]
h = 0.1
t_end = 4.0
{integrator_and_step}
[bar]
length = 2.0
ea = 3.0
rho_a = 0.5
speed = 1.0
gap = 0.5
elements = 10
mass = "lumped"
[contact]
{contact}
"#
        )
    }

    fn validated(text: &str) -> Scenario<RunSpec> {
        Scenario::from_str(text, Path::new("b.toml")).unwrap()
    }

    /// The uniform free-free lumped bar of `N` elements of length `dx`: `omega_k =
    /// (2 c / dx) sin(k pi / (2 N))`, `k = 0..N`, so `omega_max = 2 c / dx` (k = N, the
    /// nodes alternating) and `h = cfl * 2 / omega_max = cfl * dx / c`.
    #[test]
    fn cfl_gives_the_analytic_step_of_the_lumped_bar() {
        let (length, ea, rho_a, n) = (2.0_f64, 3.0_f64, 0.5_f64, 10.0_f64);
        let c = (ea / rho_a).sqrt();
        let dx = length / n;
        let omega_max = 2.0 * c / dx;
        for cfl in [0.9, 0.5, 1.0] {
            let sc = validated(&bar(
                &format!("integrator = \"central_difference\"\ncfl = {cfl}"),
                "method = \"exact\"",
            ));
            let built = resolve(&sc).unwrap();
            let h = built.runs[0].params.h;
            let exact = cfl * 2.0 / omega_max;
            assert!(
                ((h - exact) / exact).abs() < 1e-9,
                "cfl {cfl}: h = {h:e}, analytic {exact:e}"
            );
            assert!(built.warnings.is_empty(), "{:?}", built.warnings);
        }
    }

    /// Two bars: the step of bar A alone (the contact bar), here with the same data.
    #[test]
    fn two_bars_take_the_step_of_bar_a() {
        let text = bar(
            "integrator = \"central_difference\"\ncfl = 0.8",
            "method = \"exact\"",
        )
        .replace("kind = \"bar_impact\"", "kind = \"two_bars\"")
        .replace("[bar]", "[two_bars]");
        let h = resolve(&validated(&text)).unwrap().runs[0].params.h;
        let b = match &validated(&text).runs[0].model {
            Model::TwoBars(b) => b.bar_a(),
            _ => unreachable!(),
        };
        let exact = 0.8 * (b.length / b.elements as f64) / b.wave_speed();
        assert!(((h - exact) / exact).abs() < 1e-9, "{h:e} vs {exact:e}");
    }

    /// A penalty spring on the contact node raises `omega_max`: a smaller step; one end
    /// spring `k` on the lumped end mass `m = rho A dx / 2` bounds `omega_max^2` by
    /// Gershgorin, `(2 EA / dx + k) / m`.
    #[test]
    fn cfl_with_a_penalty_spring_shrinks_the_step_within_gershgorin() {
        let free = resolve(&validated(&bar(
            "integrator = \"central_difference\"\ncfl = 1.0",
            "method = \"exact\"",
        )))
        .unwrap()
        .runs[0]
            .params
            .h;
        let k = 400.0;
        let sc = validated(&bar(
            "integrator = \"central_difference\"\ncfl = 1.0",
            &format!("method = \"penalty\"\npenalty = {k}"),
        ));
        let built = resolve(&sc).unwrap();
        let h = built.runs[0].params.h;
        let (ea, rho_a, dx) = (3.0_f64, 0.5_f64, 0.2_f64);
        let m = rho_a * dx / 2.0;
        let gershgorin = 2.0 / ((2.0 * ea / dx + k) / m).sqrt();
        assert!(
            h < free && h >= gershgorin * (1.0 - 1e-12),
            "{h} {free} {gershgorin}"
        );
        // cfl = 1 with the spring included: h sqrt(k/m) < 2, no penalty warning.
        assert!(built.warnings.is_empty(), "{:?}", built.warnings);
    }

    #[test]
    fn a_fixed_explicit_step_beyond_stability_warns_at_build_only() {
        // dx / c = 0.2 / sqrt(6) = 0.0816 s < h = 0.1 s.
        let sc = validated(&bar(
            "integrator = \"central_difference\"",
            "method = \"exact\"",
        ));
        assert!(
            sc.warnings.is_empty(),
            "validation warned: {:?}",
            sc.warnings
        );
        let built = resolve(&sc).unwrap();
        assert_eq!(built.runs[0].params.h, 0.1);
        assert_eq!(built.warnings.len(), 1, "{:?}", built.warnings);
        assert!(
            built.warnings[0].contains("stable step"),
            "{:?}",
            built.warnings
        );
    }

    #[test]
    fn labels_default_to_the_resolved_step() {
        let text = bar("integrator = \"central_difference\"", "method = \"exact\"")
            + "[[runs]]\ncfl = 0.5\n[[runs]]\nh = 0.01\nlabel = \"given\"\n";
        let built = resolve(&validated(&text)).unwrap();
        let h0 = built.runs[0].params.h;
        assert_eq!(built.runs[0].label, format!("h = {h0}"));
        assert_eq!(built.runs[1].label, "given");
    }
}
