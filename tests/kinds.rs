//! A kind that exists only here: a mass hanging from a spring under gravity, released from
//! rest at the spring's free length (`m x'' + k x = -m g`). It is one module (its table, its
//! validated model, its run) and one registry line (`Registry::builtin().with(&Hanging)`),
//! and the generic layers take it as they take softway's own kinds: the parser (its table's
//! keys named with their line, the common tables, `[[runs]]`), the combination rules, the
//! step's checks, the build, the run, the summary's provenance and the saved folder.
//!
//! The physics is checked against the exact answer `x = -(m g / k) (1 - cos(omega t))`: the
//! space-time scheme with `alpha = 1/2, gamma = 0` (the trapezoidal rule) is second order.

use softway::kinds::{Kind, KindInput, Model, Registry, Size, Spec};
use softway::run::{Columns, Results, RunError, RunOptions};
use softway::scenario::{Ctx, Run, Scenario, ScenarioError};
use std::path::Path;

/// The kind `hanging_mass`.
struct Hanging;

/// `[hanging]` as written.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct RawHanging {
    mass: f64,
    stiffness: f64,
    gravity: Option<f64>,
}

/// The kind's tables.
#[derive(serde::Deserialize)]
struct Tables {
    hanging: Option<RawHanging>,
}

/// The validated model.
#[derive(Debug, Clone, PartialEq)]
struct HangingMass {
    mass: f64,
    stiffness: f64,
    gravity: f64,
}

impl HangingMass {
    fn omega(&self) -> f64 {
        (self.stiffness / self.mass).sqrt()
    }

    /// The static deflection `m g / k`, m.
    fn sag(&self) -> f64 {
        self.mass * self.gravity / self.stiffness
    }
}

impl Kind for Hanging {
    fn name(&self) -> &'static str {
        "hanging_mass"
    }

    fn tables(&self) -> &'static [&'static str] {
        &["hanging"]
    }

    fn model(&self, input: &KindInput) -> Result<Model, ScenarioError> {
        let cx = input.cx;
        let h = input
            .tables::<Tables>()?
            .hanging
            .ok_or_else(|| cx.missing("hanging", "kind = \"hanging_mass\" needs [hanging]"))?;
        Ok(Model::new(HangingMass {
            mass: cx.positive("hanging.mass", h.mass)?,
            stiffness: cx.positive("hanging.stiffness", h.stiffness)?,
            gravity: cx.finite("hanging.gravity", h.gravity.unwrap_or(9.81))?,
        }))
    }
}

impl Spec for HangingMass {
    softway::spec_plumbing!("hanging_mass");

    fn dim(&self) -> usize {
        1
    }

    fn end_time(&self, cx: &Ctx, given: Option<f64>) -> Result<f64, ScenarioError> {
        given.ok_or_else(|| cx.missing("time.t_end", "the end time, s"))
    }

    fn no_contact(&self) -> Option<&'static str> {
        Some("the hanging mass touches nothing")
    }

    fn size(&self, run: &Run, _: Option<usize>) -> Size {
        Size {
            dofs: 1.0,
            duration: run.t_end,
            contact_pairs: 0.0,
            key: None,
            factor_entries: None,
            kept_columns: 0.0,
        }
    }

    fn record(
        &self,
        sc: &Scenario,
        _stream: Option<&Path>,
        opts: &RunOptions,
    ) -> Result<Results, RunError> {
        let mut history = Columns::new(&[("t_s", "s"), ("x_m", "m"), ("x_exact_m", "m")]);
        let mut errors = Vec::new();
        let mut interrupted = false;
        for (i, run) in sc.runs.iter().enumerate() {
            let m = run.model.get::<HangingMass>().expect("a hanging mass");
            let (h, w) = (run.params.h, m.omega());
            let steps = (run.t_end / h).round() as usize;
            let (mut x, mut v, mut worst) = (0.0f64, 0.0f64, 0.0f64);
            for k in 0..=steps {
                let t = k as f64 * h;
                let exact = -m.sag() * (1.0 - (w * t).cos());
                worst = worst.max((x - exact).abs());
                history.push(i as u32, &[t, x, exact]);
                if k == steps || opts.cancel.is_cancelled() {
                    interrupted |= k < steps;
                    break;
                }
                let f = -m.mass * m.gravity;
                (x, v) = softway::time::sdof::step(m.mass, m.stiffness, f, run.params, x, v);
            }
            errors.push(serde_json::json!({"label": run.label, "h": h, "max_error_m": worst}));
        }
        let summary = serde_json::json!({"kind": "hanging_mass", "runs": errors});
        Ok(Results::of_kind(
            sc,
            summary,
            history,
            vec![format!("{} runs", sc.runs.len())],
            interrupted,
        ))
    }
}

static HANGING: Hanging = Hanging;

fn registry() -> Registry {
    Registry::builtin().with(&HANGING)
}

const TEXT: &str = r#"
kind = "hanging_mass"
[hanging]
mass = 2.0
stiffness = 800.0
[time]
alpha = 0.5
gamma = 0.0
t_end = 0.5
[[runs]]
h = 4e-3
[[runs]]
h = 2e-3
[[runs]]
h = 1e-3
"#;

fn parse(text: &str) -> Result<Scenario<softway::scenario::RunSpec>, ScenarioError> {
    Scenario::from_str_in(text, Path::new("hanging.toml"), &registry())
}

/// The kind runs through the library's one entry point, and the answer converges to the
/// exact one at second order (three steps, each halving).
#[test]
fn a_kind_of_the_tests_runs_and_converges_at_second_order() {
    let sc = softway::build::resolve(&parse(TEXT).unwrap()).unwrap();
    assert_eq!(sc.runs.len(), 3);
    assert_eq!(sc.runs[0].model.kind(), "hanging_mass");
    let r = softway::run(&sc, &RunOptions::default()).unwrap();
    assert_eq!(r.kind, "hanging_mass");
    // The provenance every summary carries, stamped by the generic layer.
    assert!(r.summary["scenario_sha256"]
        .as_str()
        .is_some_and(|s| s.len() == 64));
    let e: Vec<f64> = (0..3)
        .map(|i| r.summary["runs"][i]["max_error_m"].as_f64().unwrap())
        .collect();
    let sag = 2.0 * 9.81 / 800.0;
    assert!(e[2] < 1e-2 * sag, "{e:?} against a sag of {sag} m");
    for w in e.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!((order - 2.0).abs() < 0.15, "observed order {order} ({e:?})");
    }
    assert_eq!(r.history.len(), 126 + 251 + 501);
    // Saved as every kind's results are: the summary and the history.
    let dir = std::env::temp_dir().join(format!("softway-kinds-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let files = r.save(&dir).unwrap();
    assert!(
        files.iter().any(|f| f.ends_with("summary.json")),
        "{files:?}"
    );
    let csv = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 126 + 251 + 501);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The generic layers check the kind's scenario as any other: its table's misspelt key with
/// its line, a missing key, another kind's table, a setting it has no use for, a step
/// longer than the run; softway's own registry does not know it.
#[test]
fn the_generic_checks_hold_for_a_kind_of_the_tests() {
    let e = parse(&TEXT.replace("stiffness = 800.0", "stifness = 800.0"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("stifness") && e.contains("line 5"), "{e}");
    let e = parse(&TEXT.replace("mass = 2.0", "mass = -2.0"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("`hanging.mass` = -2"), "{e}");
    let e = parse(&format!(
        "{TEXT}\n[wheel]\nradius = 0.1\nthickness = 0.01\n"
    ))
    .unwrap_err()
    .to_string();
    assert!(
        e.contains(
            "read by kind = \"wheel\", kind = \"press\", kind = \"rolling3d\" only, not by kind = \"hanging_mass\""
        ),
        "{e}"
    );
    let e = parse(&TEXT.replace("h = 1e-3", "h = 1e-3\nmethod = \"exact\""))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`runs[2].method`") && e.contains("touches nothing"),
        "{e}"
    );
    let e = parse(&TEXT.replace("h = 4e-3", "h = 4.0"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("`runs[0].h`") && e.contains("time.t_end"), "{e}");
    let e = parse(&TEXT.replace("t_end = 0.5\n", ""))
        .unwrap_err()
        .to_string();
    assert!(e.contains("`time.t_end`"), "{e}");
    let e = Scenario::from_str(TEXT, Path::new("hanging.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`kind` = \"hanging_mass\"") && e.contains("\"bar_impact\""),
        "{e}"
    );
}
