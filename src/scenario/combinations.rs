//! The combinations of model, integrator and contact treatment a scenario may ask for: one
//! table, [`check_combination`], that every run goes through (the top-level settings and
//! each `[[runs]]` entry alike).
//!
//! Allowed (every other combination is refused with the reason):
//!
//! | kind         | integrator                                            | contact `method`                                                   |
//! |--------------|-------------------------------------------------------|--------------------------------------------------------------------|
//! | `sdof`       | `space_time`                                          | any (the oscillator has no contact; the method is not used)        |
//! | `bar_impact`, `two_bars`, `wheel` | `space_time`                     | `soft_way*`, `exact`, `penalty`, `mass_redistribution`, `moreau_jean`, `subdivision` |
//! | `bar_impact`, `two_bars` | `newmark`, `newmark_dissipative`, `hht`, `generalized_alpha` | `exact`, `penalty`, `mass_redistribution`, `moreau_jean` |
//! | `wheel`      | `newmark_dissipative`, `hht`, `generalized_alpha`     | `exact`, `penalty`, `mass_redistribution`, `moreau_jean`           |
//! | `wheel`      | `newmark`                                             | `penalty`, `mass_redistribution`, `moreau_jean`                    |
//! | `bar_impact`, `two_bars` | `central_difference`                      | `exact`, `penalty`                                                 |
//! | `track`      | `space_time`, `newmark`, `newmark_dissipative`, `hht`, `generalized_alpha` | `exact` (the default), `soft_way_no_restore` (the rolling wheel; the moving load refuses `[contact]`) |
//!
//! `soft_way*` is `soft_way`, `soft_way_braking_restore`, `soft_way_momentum_restore` and
//! `soft_way_no_restore`. The rules
//! between an integrator and a treatment alone (the soft way and the subdivision are
//! space-time treatments; mass redistribution and Moreau-Jean need an implicit step) are the
//! engine's, [`crate::contact::Treatment::check`]; this table adds the model's: the
//! oscillator is the space-time scheme's (and has no contact: a `[contact]` table is refused
//! before this table), the wheel's explicit stable step (~1e-8 s) is refused, and so is the track's (its stiff
//! pads and short elements; the consistent mass), and so is exact
//! enforcement on the rolling wheel under an integrator that neither damps nor averages the
//! contact multipliers' period-2h mode ([`constraint_mode_factor`] above
//! [`MAX_CONSTRAINT_MODE_FACTOR`]: `newmark`, `hht` with `alpha_h` near 0,
//! `newmark_dissipative` with `gamma_n` near 1/2).
//!
//! **Why the trapezoidal rule and exact contact fail on the rolling wheel.** Exact enforcement
//! holds the gaps at the displacement level (index-3 constraints). The average-acceleration
//! Newmark has no numerical dissipation (`rho_inf = 1`), so the multipliers' period-2h mode
//! (the contact force alternating from step to step: 3856, 2191, 10200, ... N right after the
//! first contact) is never damped, and the active set, which changes at every node passing
//! (3,438 a second on the paper's wheel), keeps feeding it: on
//! `scenarios/wheel-paper-mesh.toml` (1 turn, h = 2 us) the energy grows from 327 J to 2.1e10 J
//! and the mean force is 55 MN. The bar's single impact changes its active set twice and stays
//! sane (`scenarios/compare-bar.toml`), so there it is allowed. Measured on that wheel (mean
//! force, max force; the soft way: 674.9 kN, 735 kN): `newmark_dissipative` 0.6, `hht` -0.1,
//! `generalized_alpha` 0.8 or 1.0 give 674.9 kN within 0.01%; `gamma_n` = 0.501 and
//! `alpha_h` = -0.001 blow up (1.5 MN, 1.3 MN mean, energy x2400 and x2900); `gamma_n` = 0.502
//! keeps the mean but doubles the max (1.34 MN); `gamma_n` = 0.505 and `alpha_h` = -0.003
//! are sane (674.9, 675.0 kN). Penalty, mass redistribution and Moreau-Jean under `newmark`
//! are sane too (648.9, 674.9, 672.9 kN).
//!
//! The model's rows are its kind's ([`crate::scenario::kind::Spec::combination`]). To allow a
//! combination, delete (or narrow) the arm of its kind that refuses it and update the table
//! above; the test `allowed_set_is_the_documented_table` in this
//! file holds the same table and must change with it.

use crate::time::classic::ClassicParams;
use crate::time::{ClassicKind, Integrator};

use super::kind::Model;
use super::Contact;

/// The factor by which a classic integrator carries the period-2h mode of displacement-level
/// contact multipliers from one step to the next: its high-frequency spectral radius
/// `rho_inf` times `|1 - 2 alpha_f|`, the weight of that mode in the step's force (the
/// constraint forces act at the level `1 - alpha_f` of the step, so a mid-step level,
/// `alpha_f = 1/2`, averages the alternating mode out). 1 for the trapezoidal rule
/// (`newmark`, `hht` with `alpha_h = 0`); `newmark_dissipative` 0.6: 0.82; `hht` -0.1: 0.65;
/// `generalized_alpha` 0.8: 0.09 (`rho (1 - rho) / (1 + rho)`, at most 0.17).
pub fn constraint_mode_factor(params: ClassicParams) -> f64 {
    crate::time::classic::rho_inf(params) * (1.0 - 2.0 * params.alpha_f).abs()
}

/// The largest [`constraint_mode_factor`] allowed with exact enforcement on the rolling
/// wheel: the mode must lose at least 0.5% a step (module docs: 0.996 and 0.998 blew up or
/// doubled the peak force on the paper's wheel, 0.99 and below were sane).
pub const MAX_CONSTRAINT_MODE_FACTOR: f64 = 0.995;

/// The family of a time integrator, as far as the combinations care.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// The space-time scheme (`space_time`).
    SpaceTime,
    /// An implicit member of the generalized-alpha family (`newmark`,
    /// `newmark_dissipative`, `hht`, `generalized_alpha`).
    Implicit,
    /// The explicit central difference (`central_difference`).
    Explicit,
}

impl Family {
    /// The family of an integrator.
    pub fn of(integrator: &Integrator) -> Self {
        match integrator {
            Integrator::SpaceTime { .. } => Family::SpaceTime,
            Integrator::Classic {
                kind: ClassicKind::CentralDifference,
                ..
            } => Family::Explicit,
            Integrator::Classic { .. } => Family::Implicit,
        }
    }
}

pub use super::kind::{Culprit, Refusal};

/// Whether a model runs with an integrator and a contact treatment: the model's kind's rows
/// ([`crate::scenario::kind::Spec::combination`]), else the treatment's own rule with the
/// integrator ([`crate::contact::Treatment::check`]).
///
/// # Errors
/// [`Refusal`] naming the setting at fault and what is allowed instead.
pub fn check_combination(
    model: &Model,
    integrator: &Integrator,
    contact: &Contact,
) -> Result<(), Refusal> {
    model.combination(integrator, contact).unwrap_or_else(|| {
        contact.check(integrator).map_err(|why| Refusal {
            culprit: Culprit::Contact,
            why,
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kinds, for the table's test.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    enum ModelKind {
        Sdof,
        BarImpact,
        TwoBars,
        Wheel,
        Track,
    }

    /// A model of `kind`, through the parser.
    fn model_of(kind: ModelKind) -> Model {
        let text = match kind {
            ModelKind::Track => "kind = \"track\"\n[vehicle]\nspeed = 30.0\n".to_string(),
            k => scenario_text(k, "exact"),
        };
        let sc = crate::scenario::Scenario::from_str(&text, std::path::Path::new("k.toml"))
            .unwrap_or_else(|e| panic!("{kind:?}: {e}"));
        sc.runs[0].model.clone()
    }

    fn check(kind: ModelKind, integrator: &Integrator, contact: &Contact) -> Result<(), Refusal> {
        check_combination(&model_of(kind), integrator, contact)
    }
    use crate::contact::{Restore, Treatment};
    use crate::time::classic::ClassicParams;

    fn integrators() -> Vec<(&'static str, Integrator)> {
        let classic = |kind, params| Integrator::Classic { kind, params };
        vec![
            (
                "space_time",
                Integrator::SpaceTime {
                    alpha: 0.8,
                    gamma: 0.0,
                    coriolis: crate::time::Coriolis::Implicit,
                },
            ),
            (
                "newmark",
                classic(ClassicKind::Newmark, ClassicParams::average_acceleration()),
            ),
            (
                "newmark_dissipative",
                classic(
                    ClassicKind::NewmarkDissipative,
                    ClassicParams::newmark_dissipative(0.6),
                ),
            ),
            (
                "hht",
                classic(ClassicKind::Hht, ClassicParams::hht(-0.1).unwrap()),
            ),
            (
                "generalized_alpha",
                classic(
                    ClassicKind::GeneralizedAlpha,
                    ClassicParams::generalized_alpha(0.5).unwrap(),
                ),
            ),
            (
                "central_difference",
                classic(
                    ClassicKind::CentralDifference,
                    ClassicParams::central_difference(),
                ),
            ),
        ]
    }

    fn contacts() -> Vec<(&'static str, Contact)> {
        vec![
            ("soft_way", Treatment::SOFT_WAY),
            (
                "soft_way_braking_restore",
                Treatment::SoftWay {
                    restore: Restore::BrakingReaction,
                },
            ),
            (
                "soft_way_no_restore",
                Treatment::SoftWay {
                    restore: Restore::Nothing,
                },
            ),
            (
                "soft_way_momentum_restore",
                Treatment::SoftWay {
                    restore: Restore::ApproachMomentum,
                },
            ),
            ("exact", Treatment::Exact),
            ("penalty", Treatment::Penalty { stiffness: 50.0 }),
            ("mass_redistribution", Treatment::MassRedistribution),
            ("moreau_jean", Treatment::MoreauJean { restitution: 0.0 }),
            ("subdivision", Treatment::Subdivision),
        ]
    }

    /// The table of the module docs, written out independently of the `match`.
    fn documented(kind: ModelKind, integrator: &str, contact: &str) -> bool {
        let soft = contact.starts_with("soft_way");
        let implicit = matches!(
            integrator,
            "newmark" | "newmark_dissipative" | "hht" | "generalized_alpha"
        );
        match (kind, integrator) {
            (ModelKind::Sdof, _) => integrator == "space_time",
            // The wheel on the track: exact, or the soft way without its momentum back.
            (ModelKind::Track, _) => {
                integrator != "central_difference"
                    && matches!(contact, "exact" | "soft_way_no_restore")
            }
            (_, "space_time") => true,
            // The trapezoidal rule with displacement-level contact on the rolling wheel.
            (ModelKind::Wheel, "newmark") if contact == "exact" => false,
            (_, _) if implicit => !soft && contact != "subdivision",
            (ModelKind::Wheel, "central_difference") => false,
            (_, "central_difference") => matches!(contact, "exact" | "penalty"),
            _ => unreachable!(),
        }
    }

    #[test]
    fn allowed_set_is_the_documented_table() {
        let kinds = [
            ModelKind::Sdof,
            ModelKind::BarImpact,
            ModelKind::TwoBars,
            ModelKind::Wheel,
            ModelKind::Track,
        ];
        let mut allowed = 0;
        for kind in kinds {
            for (iname, integ) in integrators() {
                for (cname, contact) in contacts() {
                    let got = check(kind, &integ, &contact);
                    assert_eq!(
                        got.is_ok(),
                        documented(kind, iname, cname),
                        "{kind:?} x {iname} x {cname}: {got:?}"
                    );
                    allowed += usize::from(got.is_ok());
                }
            }
        }
        // sdof 9, bar_impact and two_bars 9 + 4*4 + 2 each, wheel 9 + 4*4 - 1, track 5*2: 97.
        assert_eq!(allowed, 9 + 27 + 27 + 24 + 10);
    }

    /// A scenario of `kind` with `time.h` set and, for the models with contact, a
    /// `[contact]` table holding the `penalty` when `contact` is `"penalty"` (an unused key
    /// is refused).
    fn scenario_text(kind: ModelKind, contact: &str) -> String {
        let model = match kind {
            ModelKind::Sdof => "kind = \"sdof\"\n[sdof]\nmass = 1.0\nstiffness = 1.0\n",
            ModelKind::BarImpact | ModelKind::TwoBars => {
                "[bar]\nlength = 1.0\nea = 1.0\nrho_a = 1.0\nspeed = 1.0\ngap = 0.5\nelements = 8\n"
            }
            ModelKind::Track => unreachable!("the track refuses [contact]: not in this test"),
            ModelKind::Wheel => concat!(
                "kind = \"wheel\"\n",
                "[wheel]\nradius = 0.1\nthickness = 0.01\n",
                "[material]\nyoung = 2.05e11\npoisson = 0.3\ndensity = 7830.0\n",
                "[rolling]\nomega = 300.0\nflattening = 1e-3\nsettle_time = 5e-3\nturns = 1\n",
            ),
        };
        let model = match kind {
            ModelKind::BarImpact => format!("kind = \"bar_impact\"\n{model}"),
            ModelKind::TwoBars => {
                format!(
                    "kind = \"two_bars\"\n{}",
                    model.replace("[bar]", "[two_bars]")
                )
            }
            _ => model.to_string(),
        };
        let t_end = if kind == ModelKind::Wheel {
            ""
        } else {
            "t_end = 1.0\n"
        };
        let contact = match (kind, contact) {
            (ModelKind::Sdof, _) => "",
            (_, "penalty") => "[contact]\npenalty = 50.0\n",
            _ => "[contact]\n",
        };
        format!("{model}{contact}[time]\nh = 1e-6\n{t_end}")
    }

    /// Every (kind, integrator, contact) through the parser, set at the top level and in a
    /// `[[runs]]` entry: the documented ones parse, the others give one error naming the
    /// key at fault (`time.integrator` / `contact.method`, or `runs[0].integrator` /
    /// `runs[0].method`) and the value. The oscillator has no contact: its scenarios name
    /// no method (one naming one is refused for that, `tests/bad_input.rs`).
    #[test]
    fn every_path_goes_through_the_table() {
        use crate::scenario::Scenario;
        use std::path::Path;
        let kinds = [
            ModelKind::Sdof,
            ModelKind::BarImpact,
            ModelKind::TwoBars,
            ModelKind::Wheel,
        ];
        let path = Path::new("combo.toml");
        let (mut allowed, mut refused) = (0, 0);
        for kind in kinds {
            for (iname, _) in integrators() {
                for (cname, _) in contacts() {
                    let sdof = kind == ModelKind::Sdof;
                    if sdof && cname != "soft_way" {
                        continue;
                    }
                    let base = scenario_text(kind, cname);
                    let top = base
                        .replace("[time]\n", &format!("[time]\nintegrator = \"{iname}\"\n"))
                        .replace("[contact]\n", &format!("[contact]\nmethod = \"{cname}\"\n"));
                    let method = if sdof {
                        String::new()
                    } else {
                        format!("method = \"{cname}\"\n")
                    };
                    let run = format!("{base}[[runs]]\nintegrator = \"{iname}\"\n{method}");
                    let ok = documented(kind, iname, cname);
                    for (text, prefix) in [(top, None), (run, Some("runs[0]."))] {
                        let got = Scenario::from_str(&text, path);
                        let what = format!("{kind:?} x {iname} x {cname} ({prefix:?})");
                        if ok {
                            let sc = got.unwrap_or_else(|e| panic!("{what}: {e}"));
                            assert_eq!(sc.runs.len(), 1, "{what}");
                            allowed += 1;
                            continue;
                        }
                        let e = got.expect_err(&what).to_string();
                        let (field, value) = match kind {
                            ModelKind::Sdof if iname != "space_time" => ("integrator", iname),
                            ModelKind::Wheel
                                if iname == "central_difference"
                                    || (iname, cname) == ("newmark", "exact") =>
                            {
                                ("integrator", iname)
                            }
                            _ => ("method", cname),
                        };
                        let key = match prefix {
                            Some(p) => format!("`{p}{field}`"),
                            None if field == "integrator" => "`time.integrator`".into(),
                            None => "`contact.method`".into(),
                        };
                        let value = format!("\"{value}\"");
                        assert!(
                            e.starts_with("combo.toml: ") && e.contains(&key) && e.contains(&value),
                            "{what}: {e}"
                        );
                        assert_eq!(e.lines().count(), 1, "{what}: {e}");
                        refused += 1;
                    }
                }
            }
        }
        // Bars and wheel: 78 of 3 * 6 * 9 allowed; the oscillator: 1 of 6 integrators.
        assert_eq!((allowed, refused), (2 * (78 + 1), 2 * (3 * 6 * 9 - 78 + 5)));
    }

    /// The trapezoidal members (`newmark`, `hht` with `alpha_h = 0`, `newmark_dissipative`
    /// a hair above 1/2) are refused with exact contact on the wheel, naming the integrator,
    /// the mode and the alternatives; their damped members, the mid-step generalized-alpha
    /// (`rho_inf = 1`) and the bar's single impact are allowed.
    #[test]
    fn exact_contact_on_the_wheel_needs_a_damped_or_averaged_constraint_mode() {
        let classic = |kind, params| Integrator::Classic { kind, params };
        let refused = [
            classic(ClassicKind::Newmark, ClassicParams::average_acceleration()),
            classic(ClassicKind::Hht, ClassicParams::hht(0.0).unwrap()),
            classic(ClassicKind::Hht, ClassicParams::hht(-0.001).unwrap()),
            classic(
                ClassicKind::NewmarkDissipative,
                ClassicParams::newmark_dissipative(0.501),
            ),
        ];
        for integ in &refused {
            let r = check(ModelKind::Wheel, integ, &Treatment::Exact).unwrap_err();
            assert_eq!(r.culprit, Culprit::Integrator, "{integ:?}");
            assert!(
                r.why.contains("period-2h") && r.why.contains("newmark_dissipative"),
                "{}",
                r.why
            );
            for kind in [ModelKind::BarImpact, ModelKind::TwoBars] {
                check(kind, integ, &Treatment::Exact).unwrap();
            }
            check(ModelKind::Wheel, integ, &Treatment::MassRedistribution).unwrap();
        }
        let allowed = [
            classic(
                ClassicKind::NewmarkDissipative,
                ClassicParams::newmark_dissipative(0.505),
            ),
            classic(ClassicKind::Hht, ClassicParams::hht(-0.003).unwrap()),
            classic(
                ClassicKind::GeneralizedAlpha,
                ClassicParams::generalized_alpha(1.0).unwrap(),
            ),
            classic(
                ClassicKind::GeneralizedAlpha,
                ClassicParams::generalized_alpha(0.0).unwrap(),
            ),
        ];
        for integ in &allowed {
            check(ModelKind::Wheel, integ, &Treatment::Exact)
                .unwrap_or_else(|r| panic!("{integ:?}: {}", r.why));
        }
        let f = |p| constraint_mode_factor(p);
        assert!((f(ClassicParams::average_acceleration()) - 1.0).abs() < 1e-6);
        assert!((f(ClassicParams::newmark_dissipative(0.6)) - 0.818).abs() < 1e-3);
        assert!((f(ClassicParams::hht(-0.1).unwrap()) - 0.818 * 0.8).abs() < 1e-3);
        assert!(f(ClassicParams::generalized_alpha(1.0).unwrap()) < 1e-9);
    }

    #[test]
    fn refusals_blame_the_integrator_for_the_oscillator_and_the_explicit_wheel() {
        let newmark = &integrators()[1].1;
        for kind in [ModelKind::Sdof, ModelKind::Wheel] {
            // The central difference.
            let r = check(kind, &integrators()[5].1, &Treatment::Exact);
            assert_eq!(r.unwrap_err().culprit, Culprit::Integrator);
        }
        let r = check(ModelKind::BarImpact, newmark, &Treatment::SOFT_WAY);
        let r = r.unwrap_err();
        assert_eq!(r.culprit, Culprit::Contact);
        assert!(r.why.contains("not one of newmark"), "{}", r.why);
        let sdof = check(ModelKind::Sdof, newmark, &Treatment::Exact);
        assert_eq!(sdof.unwrap_err().culprit, Culprit::Integrator);
    }
}
