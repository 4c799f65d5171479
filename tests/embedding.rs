//! Embedding: a run is a value of its caller's. Its threads are a parameter (`Par`) and its
//! helper thread belongs to the run; it follows the rayon pool it is called in; two runs at
//! once on two threads of a caller share nothing; its interruption is a token the caller
//! passes; its warnings come back in the report. Every arrangement gives the same bits.

mod common;

use common::TestDir;
use softway::run::{run_scenario, Cancel, Par, RunOptions, RunReport};
use softway::scenario::Scenario;

/// `wheel.toml` (3,432 dofs: its factor split in two parts, its right-hand side, contact
/// columns and energies formed in two halves) shortened to 250 steps: 100 of settling into
/// contact, then 0.02 turn rolling.
fn short_wheel() -> softway::scenario::Scenario {
    let (path, text) = common::shipped(
        "wheel",
        &[
            ("rolling.turns", "0.02"),
            ("rolling.settle_time", "2e-4"),
            ("output.history_stride", "1"),
            ("output.plots", "false"),
        ],
    );
    softway::build::resolve(&Scenario::from_str(&text, &path).unwrap()).unwrap()
}

/// Runs `sc` with `opts` into a fresh folder; the report and the bytes of `history.csv`.
fn history(sc: &Scenario, name: &str, opts: &RunOptions) -> (RunReport, Vec<u8>) {
    let dir = TestDir::new("embedding", name);
    let report = run_scenario(sc, &dir, opts).unwrap();
    (report, std::fs::read(dir.join("history.csv")).unwrap())
}

fn with_par(par: Option<Par>) -> RunOptions {
    RunOptions {
        par,
        ..RunOptions::default()
    }
}

/// One thread, two, three and four threads (the run's helpers), a run inside a caller's pool of two threads
/// (following it), and two runs at once on two threads of a caller's pool and on two
/// threads of the caller's own: the same history, byte for byte, every row of every step.
#[test]
fn runs_alone_in_a_callers_pool_and_side_by_side_give_the_same_bits() {
    let sc = short_wheel();
    let (report, seq) = history(&sc, "seq", &with_par(Some(Par::Seq)));
    assert!(!report.interrupted);
    // A header, then one row per step (steps 0..=250).
    let rows = seq.split(|&b| b == b'\n').filter(|l| !l.is_empty()).count();
    assert!(rows > 250, "{rows} rows");
    let (_, two) = history(&sc, "two", &with_par(Some(Par::threads(2))));
    assert!(two == seq, "two threads against one");
    // Three and four threads (the right-hand side in as many parts as the machine's free
    // cores allow; the team's own `for_each` is checked on four threads beyond the cores
    // in `linalg::team` and `linalg::rhs`).
    for n in [3, 4] {
        let (_, more) = history(
            &sc,
            &format!("threads-{n}"),
            &with_par(Some(Par::threads(n))),
        );
        assert!(more == seq, "{n} threads against one");
    }

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    assert_eq!(pool.install(|| with_par(None).par()), Par::threads(2));
    let (_, inside) = pool.install(|| history(&sc, "inside", &with_par(None)));
    assert!(inside == seq, "inside a caller's pool against one thread");

    let ((_, a), (_, b)) = pool.install(|| {
        rayon::join(
            || history(&sc, "pool-a", &with_par(None)),
            || history(&sc, "pool-b", &with_par(None)),
        )
    });
    assert!(a == seq && b == seq, "two runs at once in a caller's pool");

    let (a, b) = std::thread::scope(|s| {
        let a = s.spawn(|| history(&sc, "thread-a", &with_par(Some(Par::threads(2)))));
        let b = s.spawn(|| history(&sc, "thread-b", &with_par(Some(Par::threads(2)))));
        (a.join().unwrap().1, b.join().unwrap().1)
    });
    assert!(a == seq && b == seq, "two runs at once on two threads");
}

/// A token cancelled before the run stops it at its first step: the report says so, and the
/// history holds the initial state only; a clone cancels the original.
#[test]
fn a_cancelled_token_stops_the_run_and_it_reports_so() {
    let cancel = Cancel::new();
    assert!(!cancel.is_cancelled());
    let theirs = cancel.clone();
    assert!(!theirs.cancel(), "a fresh token was not cancelled");
    assert!(cancel.is_cancelled() && theirs.cancel());
    let opts = RunOptions {
        cancel,
        ..RunOptions::default()
    };
    let (report, bytes) = history(&short_wheel(), "cancelled", &opts);
    assert!(report.interrupted);
    let rows = bytes
        .split(|&b| b == b'\n')
        .filter(|l| !l.is_empty())
        .count();
    assert!(rows <= 3, "{rows} rows after a cancelled start");
}

/// The library prints no warning: a node-passing resonance (the paper's mesh at 510
/// rad/s, its node passing at 5844 Hz on its bounce of 5842 Hz; `tests/wheel.rs`) comes back
/// in the report, and a run off the resonance (300 rad/s) has none.
#[test]
fn warnings_come_back_in_the_report() {
    let warnings = |omega: &str| {
        let (path, text) = common::shipped(
            "wheel-paper-mesh",
            &[
                ("rolling.omega", omega),
                ("rolling.turns", "0.005"),
                ("rolling.settle_time", "2e-4"),
                ("output.plots", "false"),
            ],
        );
        let sc = softway::build::resolve(&Scenario::from_str(&text, &path).unwrap()).unwrap();
        let all = history(&sc, &format!("warn-{omega}"), &RunOptions::default())
            .0
            .warnings;
        // The paper's 72-node rim has 1.6 pitches across Hertz's patch: warned about at
        // every speed (`softway::kinds::wheel::run::load::coarse_rim_warning`).
        assert!(
            all.iter().any(|w| w.contains("the rim is coarse")),
            "{all:?}"
        );
        all.into_iter()
            .filter(|w| !w.contains("the rim is coarse"))
            .collect::<Vec<_>>()
    };
    let at = warnings("510.0");
    assert!(
        at.len() == 1 && at[0].contains("node passing") && at[0].contains("bounce"),
        "{at:?}"
    );
    assert!(warnings("300.0").is_empty());
}
