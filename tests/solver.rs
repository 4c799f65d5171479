//! The reference solver at run time (`--solver faer`): faer's own sparse factorizations and
//! solves in place of softway's tuned ones, on the same runs. The answers agree to rounding
//! (the factors are other orderings' and other kernels' sums, so not to the bit), the
//! summary says which solver ran, and a solver the command line does not know is refused.

mod common;

use softway::linalg::Backend;
use softway::run::RunOptions;
use softway::scenario::Scenario;

/// The run of the scenario text with each solver; the summaries.
fn both(text: &str) -> (serde_json::Value, serde_json::Value) {
    let sc = Scenario::from_str(text, std::path::Path::new("solver.toml")).unwrap();
    let sc = softway::build::resolve(&sc).unwrap();
    let run = |solver| {
        let opts = RunOptions {
            solver,
            ..RunOptions::default()
        };
        softway::run(&sc, &opts).unwrap().summary
    };
    (run(Backend::Softway), run(Backend::Faer))
}

fn close(a: f64, b: f64, rel: f64, what: &str) {
    assert!(
        (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-300),
        "{what}: {a} (softway) against {b} (faer)"
    );
}

/// The paper's wheel (a quarter turn of `scenarios/wheel.toml`: the symmetric, Cholesky
/// step matrix of its rotating frame with the Coriolis term extrapolated, or the LU of the
/// implicit one) and the bar against the wall (an LU): the contact forces and energies of
/// both solvers agree to 1e-9.
#[test]
fn faers_factorizations_give_the_same_answers_to_rounding() {
    let (_, wheel) = common::shipped("wheel", &[("rolling.turns", "0.25")]);
    let (a, b) = both(&wheel);
    assert!(a.get("solver").is_none(), "the default says nothing");
    assert_eq!(b["solver"], "faer");
    for key in [
        "mean_contact_force",
        "max_contact_force",
        "energy_after_settling",
        "energy_final",
    ] {
        let x = a[key].as_f64().unwrap_or_else(|| panic!("{key} in {a}"));
        close(x, b[key].as_f64().unwrap(), 1e-9, key);
    }
    assert_eq!(a["brakings"], b["brakings"], "the same contact history");
    let (a, b) = both(common::BAR);
    let (x, y) = (&a["runs"][0], &b["runs"][0]);
    for key in ["contact_duration", "mean_contact_force", "rebound_velocity"] {
        close(
            x[key].as_f64().unwrap(),
            y[key].as_f64().unwrap(),
            1e-9,
            key,
        );
    }
}

/// `--solver` on the command line: an unknown name is refused with what is allowed, and
/// nothing is written.
#[test]
fn an_unknown_solver_is_refused() {
    let sc = common::scenario("solver-unknown", common::BAR);
    let out = sc.with_file_name("out");
    let o = common::cli([
        "run",
        sc.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--solver",
        "mumps",
    ]);
    assert_eq!(o.code, 2, "{}", o.stderr);
    let e = &o.stderr;
    assert!(e.contains("mumps") && e.contains("\"faer\""), "{e}");
    assert!(!out.exists());
}
