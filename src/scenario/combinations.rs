//! The combinations of model, integrator and contact treatment a scenario may ask for: one
//! table, [`check_combination`], that every run goes through (the top-level settings and
//! each `[[runs]]` entry alike).
//!
//! Allowed today (every other combination is refused with the reason):
//!
//! | kind         | integrator                                            | contact `method`                                                   |
//! |--------------|-------------------------------------------------------|--------------------------------------------------------------------|
//! | `sdof`       | `space_time`                                          | any (the oscillator has no contact; the method is not used)        |
//! | `bar_impact` | `space_time`                                          | `soft_way*`, `exact`, `penalty`, `mass_redistribution`, `moreau_jean`, `subdivision` |
//! | `bar_impact` | `newmark`, `newmark_dissipative`, `hht`, `generalized_alpha` | `exact`, `penalty`, `mass_redistribution`, `moreau_jean`     |
//! | `bar_impact` | `central_difference`                                  | `exact`, `penalty`                                                 |
//! | `two_bars`   | `space_time`                                          | `exact`, `penalty`, `mass_redistribution`, `moreau_jean`, `subdivision` |
//! | `two_bars`   | `newmark`, `newmark_dissipative`, `hht`, `generalized_alpha` | `exact`, `penalty`, `mass_redistribution`, `moreau_jean`     |
//! | `two_bars`   | `central_difference`                                  | `exact`, `penalty`                                                 |
//! | `wheel`      | `space_time`                                          | `soft_way*`, `exact`                                               |
//!
//! `soft_way*` is `soft_way`, `soft_way_braking_restore` and `soft_way_no_restore`.
//!
//! To allow a combination, delete (or narrow) the arm of [`check_combination`] that refuses
//! it and update the table above; the test `allowed_set_is_the_documented_table` in this
//! file holds the same table and must change with it.

use crate::lab::{ClassicKind, Integrator, Treatment};

use super::{Contact, Model};

/// The kind of model, as `kind` names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelKind {
    /// `sdof`.
    Sdof,
    /// `bar_impact`.
    BarImpact,
    /// `two_bars`.
    TwoBars,
    /// `wheel`.
    Wheel,
}

impl ModelKind {
    /// The kind of a model.
    pub fn of(model: &Model) -> Self {
        match model {
            Model::Sdof(_) => ModelKind::Sdof,
            Model::BarImpact(_) => ModelKind::BarImpact,
            Model::TwoBars(_) => ModelKind::TwoBars,
            Model::Wheel(_) => ModelKind::Wheel,
        }
    }
}

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

/// Which setting a refusal is about: the error names that key.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Culprit {
    /// `time.integrator` (or `runs[i].integrator`).
    Integrator,
    /// `contact.method` (or `runs[i].method`).
    Contact,
}

/// A combination refused: the key at fault and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Refusal {
    /// The key the error names.
    pub culprit: Culprit,
    /// Why, and what to use instead.
    pub why: String,
}

fn refuse(culprit: Culprit, why: impl Into<String>) -> Result<(), Refusal> {
    Err(Refusal {
        culprit,
        why: why.into(),
    })
}

/// Whether a model kind runs with an integrator and a contact treatment: the list of
/// allowed combinations (module docs). One arm per refused case, in the order the checks are
/// made; everything that reaches the last arm is allowed.
///
/// # Errors
/// [`Refusal`] naming the setting at fault and what is allowed instead.
pub fn check_combination(
    kind: ModelKind,
    integrator: &Integrator,
    contact: &Contact,
) -> Result<(), Refusal> {
    use Culprit::{Contact as Method, Integrator as Integ};
    use Family::{Explicit, Implicit, SpaceTime};
    use ModelKind::{Sdof, TwoBars, Wheel};
    match (kind, Family::of(integrator), contact) {
        (Sdof | Wheel, Implicit | Explicit, _) => refuse(
            Integ,
            "only bar scenarios (bar_impact, two_bars) run the classic integrators; use \"space_time\"",
        ),
        (Wheel, SpaceTime, Contact::Lab(Treatment::Exact) | Contact::Driver(_)) => Ok(()),
        (Wheel, SpaceTime, Contact::Lab(_)) => refuse(
            Method,
            "the wheel runs \"soft_way\", \"soft_way_braking_restore\", \"soft_way_no_restore\" or \"exact\"",
        ),
        (TwoBars, _, Contact::Driver(_)) => refuse(
            Method,
            "the soft way brakes a node against an obstacle; two_bars (node against node) runs \"exact\", \"penalty\", \"mass_redistribution\", \"moreau_jean\" or \"subdivision\"",
        ),
        (_, Implicit | Explicit, Contact::Driver(_)) => refuse(
            Method,
            format!(
                "the soft way is a treatment of the space-time scheme, not of {}; use integrator = \"space_time\"",
                integrator.name()
            ),
        ),
        (_, Implicit | Explicit, Contact::Lab(Treatment::Subdivision)) => refuse(
            Method,
            "subdivision of the time step (the paper's Fig. 5) is a space-time treatment: use integrator = \"space_time\"",
        ),
        (_, Explicit, Contact::Lab(Treatment::MassRedistribution)) => refuse(
            Method,
            "mass redistribution makes the contact nodes massless: the explicit central difference would divide by zero; use an implicit integrator",
        ),
        (_, Explicit, Contact::Lab(Treatment::MoreauJean { .. })) => refuse(
            Method,
            "Moreau-Jean is a velocity-level implicit treatment; with the central difference the impulse acts one step late and the contact chatters: use an implicit integrator",
        ),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::ContactMethod;
    use crate::time::classic::ClassicParams;

    fn integrators() -> Vec<(&'static str, Integrator)> {
        let classic = |kind, params| Integrator::Classic { kind, params };
        vec![
            (
                "space_time",
                Integrator::SpaceTime {
                    alpha: 0.8,
                    gamma: 0.0,
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
            ("soft_way", Contact::Driver(ContactMethod::SoftWay)),
            (
                "soft_way_braking_restore",
                Contact::Driver(ContactMethod::SoftWayBrakingRestore),
            ),
            (
                "soft_way_no_restore",
                Contact::Driver(ContactMethod::SoftWayNoRestore),
            ),
            ("exact", Contact::Lab(Treatment::Exact)),
            (
                "penalty",
                Contact::Lab(Treatment::Penalty { stiffness: 50.0 }),
            ),
            (
                "mass_redistribution",
                Contact::Lab(Treatment::MassRedistribution),
            ),
            (
                "moreau_jean",
                Contact::Lab(Treatment::MoreauJean { restitution: 0.0 }),
            ),
            ("subdivision", Contact::Lab(Treatment::Subdivision)),
        ]
    }

    /// The table of the module docs, written out independently of the `match`.
    fn documented(kind: ModelKind, integrator: &str, contact: &str) -> bool {
        let soft = contact.starts_with("soft_way");
        let implicit = matches!(
            integrator,
            "newmark" | "newmark_dissipative" | "hht" | "generalized_alpha"
        );
        match kind {
            ModelKind::Sdof => integrator == "space_time",
            ModelKind::Wheel => integrator == "space_time" && (soft || contact == "exact"),
            ModelKind::BarImpact | ModelKind::TwoBars => {
                let obstacle = kind == ModelKind::BarImpact;
                match integrator {
                    "space_time" => obstacle || !soft,
                    _ if implicit => !soft && contact != "subdivision",
                    "central_difference" => matches!(contact, "exact" | "penalty"),
                    _ => unreachable!(),
                }
            }
        }
    }

    #[test]
    fn allowed_set_is_the_documented_table() {
        let kinds = [
            ModelKind::Sdof,
            ModelKind::BarImpact,
            ModelKind::TwoBars,
            ModelKind::Wheel,
        ];
        let mut allowed = 0;
        for kind in kinds {
            for (iname, integ) in integrators() {
                for (cname, contact) in contacts() {
                    let got = check_combination(kind, &integ, &contact);
                    assert_eq!(
                        got.is_ok(),
                        documented(kind, iname, cname),
                        "{kind:?} x {iname} x {cname}: {got:?}"
                    );
                    allowed += usize::from(got.is_ok());
                }
            }
        }
        // sdof 8, bar_impact 8 + 4*4 + 2, two_bars 5 + 4*4 + 2, wheel 4: 61.
        assert_eq!(allowed, 8 + 26 + 23 + 4);
    }

    /// A scenario of `kind` with `time.h` and `[contact] penalty` set (the penalty is
    /// needed by `method = "penalty"` and unused by the others).
    fn scenario_text(kind: ModelKind) -> String {
        let model = match kind {
            ModelKind::Sdof => "kind = \"sdof\"\n[sdof]\nmass = 1.0\nstiffness = 1.0\n",
            ModelKind::BarImpact | ModelKind::TwoBars => {
                "[bar]\nlength = 1.0\nea = 1.0\nrho_a = 1.0\nspeed = 1.0\ngap = 0.5\nelements = 8\n"
            }
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
        format!("{model}[contact]\npenalty = 50.0\n[time]\nh = 1e-6\n{t_end}")
    }

    /// Every (kind, integrator, contact) through the parser, set at the top level and in a
    /// `[[runs]]` entry: the documented ones parse, the others give one error naming the
    /// key at fault (`time.integrator` / `contact.method`, or `runs[0].integrator` /
    /// `runs[0].method`) and the value.
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
            let base = scenario_text(kind);
            for (iname, _) in integrators() {
                for (cname, _) in contacts() {
                    let top = base
                        .replace("[time]\n", &format!("[time]\nintegrator = \"{iname}\"\n"))
                        .replace("[contact]\n", &format!("[contact]\nmethod = \"{cname}\"\n"));
                    let run =
                        format!("{base}[[runs]]\nintegrator = \"{iname}\"\nmethod = \"{cname}\"\n");
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
                            ModelKind::Sdof | ModelKind::Wheel if iname != "space_time" => {
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
        assert_eq!((allowed, refused), (2 * 61, 2 * (4 * 6 * 8 - 61)));
    }

    #[test]
    fn refusals_blame_the_integrator_only_for_non_bars() {
        let newmark = &integrators()[1].1;
        for kind in [ModelKind::Sdof, ModelKind::Wheel] {
            let r = check_combination(kind, newmark, &Contact::Lab(Treatment::Exact));
            assert_eq!(r.unwrap_err().culprit, Culprit::Integrator);
        }
        let r = check_combination(
            ModelKind::BarImpact,
            newmark,
            &Contact::Driver(ContactMethod::SoftWay),
        );
        let r = r.unwrap_err();
        assert_eq!(r.culprit, Culprit::Contact);
        assert!(r.why.contains("not of newmark"), "{}", r.why);
    }
}
