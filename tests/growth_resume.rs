//! A plastic wheel's growth study through the entry point `softway grow` calls
//! ([`softway::run::grow::grow`], which boxes its pass runner) and through the binary
//! itself: the plastic state checkpointed and restored on `--resume`, and the reference
//! pass leaving it as it was (issue 47: a wrapper around the boxed runner forwarded
//! `run_pass` but not `run_reference`, `carried_state` nor `restore_state`, so a resumed
//! study went on from an unstrained wheel and pass 1 started from the reference pass's
//! plastic flow).
//!
//! The scenario is `scenarios/polygon-plastic.toml` made small (96 rim nodes, h = 1e-5 s,
//! a settling of 1.5 ms, no plots), written into a folder of the test's own: the load
//! (p0/k = 5.2, above the shakedown limit) flows in every pass.

mod common;

use softway::growth::{StudyState, CHECKPOINT};
use softway::run::grow::{grow, GrowOptions};
use softway::run::{Cancel, Par};
use std::path::{Path, PathBuf};

/// `scenarios/polygon-plastic.toml`, coarsened, with `growth.reference` as given, written
/// as `<dir>/polygon-plastic-small.toml`.
fn small_scenario(dir: &Path, reference: bool) -> PathBuf {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/polygon-plastic.toml");
    let mut text = std::fs::read_to_string(path).unwrap();
    let edits = [
        ("rim_nodes = 288", "rim_nodes = 96".to_string()),
        ("h = 2.5e-6", "h = 1e-5".to_string()),
        ("settle_time = 2e-3", "settle_time = 1.5e-3".to_string()),
        ("passes = 8", "passes = 2".to_string()),
        ("reference = true", format!("reference = {reference}")),
    ];
    for (from, to) in edits {
        assert_eq!(
            text.matches(from).count(),
            1,
            "`{from}` in the shipped scenario"
        );
        text = text.replacen(from, &to, 1);
    }
    text.push_str("\n[output]\nplots = false\n");
    let p = dir.join("polygon-plastic-small.toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// Runs the study of the scenario file `file` into `out` for `passes` passes as
/// `softway grow` does (read, built, [`grow`]); returns the checkpoint it leaves.
fn study(file: &Path, out: &Path, passes: usize, resume: bool) -> StudyState {
    let sc = softway::scenario::Scenario::from_file(file).unwrap();
    let sc = softway::build::resolve(&sc).unwrap();
    let opts = GrowOptions {
        passes: Some(passes),
        resume,
        plots: false,
        par: Par::Seq,
    };
    let r = grow(&sc, out, &opts, &Cancel::new(), |_| {}).unwrap();
    assert!(!r.interrupted);
    StudyState::read(&out.join(CHECKPOINT)).unwrap()
}

/// A pass scalar by name, from the checkpoint.
fn scalar(s: &StudyState, pass: usize, name: &str) -> f64 {
    let p = &s.passes[pass];
    let i = p.scalar_names.iter().position(|n| n == name).unwrap();
    p.scalar_values.0[i]
}

const EQ: &str = "max_equivalent_plastic_strain";

/// A column of `passes.csv` by name, one value per pass.
fn passes_csv(out: &Path, column: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(out.join("passes.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let i = header.iter().position(|h| *h == column).unwrap();
    lines
        .map(|l| l.split(',').nth(i).unwrap().parse().unwrap())
        .collect()
}

/// Two passes in one go and one pass then `resume` to two give the same plastic state and
/// the same profiles, bit for bit: the plastic state is checkpointed and restored.
#[test]
fn plastic_study_through_grow_resumes_with_its_plastic_state() {
    let dir = common::fresh_dir("growth-resume", "lib");
    let file = small_scenario(&dir, false);
    let whole = study(&file, &dir.join("whole"), 2, false);
    let split = dir.join("split");
    let first = study(&file, &split, 1, false);
    let resumed = study(&file, &split, 2, true);
    let (e0, e1, r1) = (
        scalar(&whole, 0, EQ),
        scalar(&whole, 1, EQ),
        scalar(&resumed, 1, EQ),
    );
    eprintln!("max equivalent plastic strain: pass 1 {e0:.6e}; pass 2 uninterrupted {e1:.6e}, resumed {r1:.6e}");
    assert!(e0 > 0.0, "the scenario yields in pass 1: {e0:e}");
    assert!(e1 > e0, "and again in pass 2 (ratcheting): {e0:e} {e1:e}");
    assert_eq!(
        e1.to_bits(),
        r1.to_bits(),
        "pass 2 resumed {r1:e} against uninterrupted {e1:e}"
    );
    assert!(
        first.runner.is_some(),
        "a plastic study checkpoints its plastic state"
    );
    assert_eq!(whole.runner, resumed.runner);
    assert_eq!(whole.passes.len(), resumed.passes.len());
    for (p, q) in whole.passes.iter().zip(&resumed.passes) {
        assert_eq!(p.z, q.z);
        assert_eq!(p.wear, q.wear);
        assert_eq!(p.scalar_names, q.scalar_names);
        // Every scalar of the physics, bit for bit (not the timings, `*_s`).
        for (k, name) in p.scalar_names.iter().enumerate() {
            if !name.ends_with("_s") {
                let (a, b) = (p.scalar_values.0[k], q.scalar_values.0[k]);
                assert_eq!(a.to_bits(), b.to_bits(), "{name}: {a:e} against {b:e}");
            }
        }
    }
    assert_eq!(passes_csv(&dir.join("whole"), EQ), passes_csv(&split, EQ));
    let _ = std::fs::remove_dir_all(dir);
}

/// The reference pass (`growth.reference = true`) runs on the smooth rim and leaves the
/// plastic state as it was: pass 1 starts from the virgin wheel and flows exactly as in a
/// study without a reference pass (the same initial profile, the same state), and the
/// state it leaves is the same.
#[test]
fn reference_pass_through_grow_leaves_the_plastic_state() {
    let dir = common::fresh_dir("growth-resume", "reference");
    let with = study(&small_scenario(&dir, true), &dir.join("with"), 1, false);
    let without_dir = dir.join("without");
    std::fs::create_dir_all(&without_dir).unwrap();
    let without = study(
        &small_scenario(&without_dir, false),
        &without_dir.join("out"),
        1,
        false,
    );
    assert!(with.reference.is_some() && without.reference.is_none());
    let (a, b) = (scalar(&with, 0, EQ), scalar(&without, 0, EQ));
    eprintln!("max equivalent plastic strain after pass 1: with a reference pass {a:.6e}, without {b:.6e}");
    assert!(b > 0.0, "the scenario yields in pass 1: {b:e}");
    assert_eq!(
        a.to_bits(),
        b.to_bits(),
        "with a reference pass {a:e}, without {b:e}"
    );
    assert_eq!(with.runner, without.runner);
    let _ = std::fs::remove_dir_all(dir);
}

/// The binary: `softway grow FILE --passes 1`, then `--passes 2 --resume` into the same
/// folder, gives the files of `--passes 2` in one go (the shipped scenario's reference
/// pass included).
#[test]
fn plastic_study_through_the_binary_resumes_with_its_plastic_state() {
    let dir = common::fresh_dir("growth-resume", "cli");
    let file = small_scenario(&dir, true);
    let grow = |out: &Path, passes: &str, resume: bool| {
        let mut args = vec![
            "grow".into(),
            file.clone().into_os_string(),
            "--out".into(),
            out.as_os_str().to_owned(),
            "--passes".into(),
            passes.into(),
            "--threads".into(),
            "1".into(),
        ];
        if resume {
            args.push("--resume".into());
        }
        let o = common::cli(&args);
        assert_eq!(o.code, 0, "{}\n{}", o.stdout, o.stderr);
    };
    let (whole, split) = (dir.join("whole"), dir.join("split"));
    grow(&whole, "2", false);
    grow(&split, "1", false);
    let after_one = passes_csv(&split, EQ);
    grow(&split, "2", true);
    let (w, s) = (passes_csv(&whole, EQ), passes_csv(&split, EQ));
    eprintln!("passes.csv max_equivalent_plastic_strain: uninterrupted {w:?}, resumed {s:?}");
    assert_eq!(after_one.len(), 1);
    assert!(after_one[0] > 0.0, "the scenario yields in pass 1");
    assert_eq!(w.len(), 2);
    assert_eq!(w, s, "uninterrupted {w:?}, resumed {s:?}");
    let (cw, cs) = (
        StudyState::read(&whole.join(CHECKPOINT)).unwrap(),
        StudyState::read(&split.join(CHECKPOINT)).unwrap(),
    );
    assert!(cw.runner.is_some(), "the plastic state is checkpointed");
    assert_eq!(cw.runner, cs.runner);
    assert_eq!(cw.current(), cs.current());
    let _ = std::fs::remove_dir_all(dir);
}
