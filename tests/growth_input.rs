//! Growth input refused by its own key, before anything is written: what the study's grid
//! cannot carry out (a smoothing window or a cutoff longer than the profile, a harmonic
//! shorter than two samples) and a wheel rolling part of a turn. Each case went on before:
//! `growth.smoothing = 1e300` hung for ever (a window of `usize::MAX` samples), a harmonic
//! shorter than two samples was aliased silently, `rolling.turns = 0.5` wore half the rim
//! and reported a +10,000 dB polygon.

mod common;

use common::{assert_one_line_error, softway, TestDir};
use std::path::Path;
use std::time::{Duration, Instant};

/// `softway grow scenarios/polygon.toml` (coarse: 96 rim nodes) with `sets`, into `out`,
/// one pass: exit code and standard error, with the time it took.
fn grow(out: &Path, sets: &[&str]) -> (i32, String, Duration) {
    grow_with(out, &["--passes", "1"], sets)
}

/// [`grow`] with the command's own arguments `args` (`--passes N`, `--resume`).
fn grow_with(out: &Path, args: &[&str], sets: &[&str]) -> (i32, String, Duration) {
    let polygon = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/polygon.toml");
    let mut cmd = softway();
    cmd.arg("grow")
        .arg(&polygon)
        .args(args)
        .args(["--set", "wheel.rim_nodes=96", "--out"])
        .arg(out);
    for s in sets {
        cmd.args(["--set", s]);
    }
    let start = Instant::now();
    let o = cmd.output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        start.elapsed(),
    )
}

#[test]
fn growth_keys_the_grid_cannot_carry_out_are_refused_by_name() {
    let dir = TestDir::new("growth-input", "grid");
    // The harmonic's keys instead of the random roughness's.
    let harmonic: &[&str] = &[
        "growth.roughness=\"harmonic\"",
        "growth.level=",
        "growth.min_wavelength=",
        "growth.max_wavelength=",
        "growth.seed=",
        "growth.amplitude=1e-6",
    ];
    // The rim: 96 nodes on a 0.1 m radius, dx = 6.54 mm, the profile 0.628 m long.
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["growth.smoothing=1e300"], "growth.smoothing"),
        (vec!["growth.smoothing=0.7"], "growth.smoothing"),
        (vec!["growth.cutoff=2.0"], "growth.cutoff"),
        (
            harmonic
                .iter()
                .copied()
                .chain(["growth.wavelength=1e-3"])
                .collect(),
            "growth.wavelength",
        ),
        (vec!["rolling.turns=0.5"], "rolling.turns"),
        (vec!["rolling.turns=1.5"], "rolling.turns"),
    ];
    for (k, (sets, key)) in cases.iter().enumerate() {
        let out = dir.join(format!("out{k}"));
        let (code, err, took) = grow(&out, sets);
        assert!(!err.contains("panicked"), "{sets:?}: {err}");
        assert_one_line_error(code, &err, &[key, "polygon.toml"]);
        assert!(!out.exists(), "{sets:?}: {} was written", out.display());
        // Refused at once, not after a pass (a pass here takes about half a second, the
        // 1e300 window hung).
        assert!(took < Duration::from_secs(20), "{sets:?}: {took:?}");
    }
    // The same harmonic two samples long and more is accepted and grows its one order.
    let out = dir.join("ok");
    let sets: Vec<&str> = harmonic
        .iter()
        .copied()
        .chain([
            "growth.wavelength=0.0785",
            "growth.reference=false",
            "rolling.settle_time=5e-4",
        ])
        .collect();
    let (code, err, _) = grow(&out, &sets);
    assert_eq!(code, 0, "{err}");
    assert!(out.join("checkpoint.json").exists());
}

/// A wear step that makes the profile not finite stops the study by its keys (exit 2), not
/// with NaN results and exit 0.
#[test]
fn a_wear_step_that_leaves_no_finite_profile_is_refused_by_its_keys() {
    let dir = TestDir::new("growth-input", "nan");
    let out = dir.join("out");
    let (code, err, _) = grow(
        &out,
        &[
            "wear.k_mass=1e300",
            "growth.reference=false",
            "rolling.settle_time=5e-4",
        ],
    );
    // (The wear law's depth is itself infinite there; a finite depth times a huge
    // growth.passes_per_pass is caught after the wear step, naming both keys.)
    assert_one_line_error(code, &err, &["wear.k_mass", "pass 0"]);
    // The checkpoint holds no pass of a non-finite profile.
    if let Ok(t) = std::fs::read_to_string(out.join("checkpoint.json")) {
        let s: serde_json::Value = serde_json::from_str(&t).unwrap();
        assert_eq!(s["passes"].as_array().map(Vec::len), Some(0), "{t}");
    }
}

/// A checkpoint is input: a damaged or edited one is refused on `--resume` naming its
/// field, before anything is written (the folder's scenario copy stays the one it was run
/// with); a FIFO in its place is refused, not read for ever.
#[test]
fn a_damaged_checkpoint_is_refused_naming_its_field() {
    let dir = TestDir::new("growth-input", "checkpoint");
    let out = dir.join("out");
    let base: &[&str] = &["growth.reference=false", "rolling.settle_time=5e-4"];
    let (code, err, _) = grow(&out, base);
    assert_eq!(code, 0, "{err}");
    let ck = out.join("checkpoint.json");
    let good: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&ck).unwrap()).unwrap();
    let copy = std::fs::read_to_string(out.join("scenario.toml")).unwrap();
    let nan_bits = serde_json::json!(f64::NAN.to_bits());
    type Edit = Box<dyn Fn(&mut serde_json::Value)>;
    let cases: Vec<(Edit, &str)> = vec![
        (Box::new(|s| s["x0"] = serde_json::json!([])), "`x0`"),
        (Box::new(|s| s["dx"] = serde_json::json!([])), "`dx`"),
        (
            Box::new(|s| s["passes"][0]["uniform_loss"] = serde_json::json!([])),
            "`passes[0].uniform_loss`",
        ),
        (
            Box::new(|s| {
                let v = s["initial"].as_array().unwrap().clone();
                s["initial"] = serde_json::json!(v[..v.len() / 2]);
            }),
            "`initial`",
        ),
        (
            Box::new(|s| {
                let mut v = s["passes"][0]["z"].as_array().unwrap().clone();
                v.extend(v.clone());
                s["passes"][0]["z"] = serde_json::json!(v);
            }),
            "`passes[0].z`",
        ),
        (
            Box::new(move |s| s["passes"][0]["wear"][3] = nan_bits.clone()),
            "`passes[0].wear`[3]",
        ),
    ];
    for (k, (edit, field)) in cases.iter().enumerate() {
        let mut s = good.clone();
        edit(&mut s);
        std::fs::write(&ck, serde_json::to_string(&s).unwrap()).unwrap();
        let (code, err, _) = grow_with(&out, &["--passes", "2", "--resume"], base);
        assert!(!err.contains("panicked"), "case {k}: {err}");
        assert_one_line_error(code, &err, &["checkpoint.json", field]);
        assert_eq!(
            std::fs::read_to_string(out.join("scenario.toml")).unwrap(),
            copy,
            "case {k}: the scenario copy was overwritten"
        );
    }
    // A FIFO where the checkpoint was.
    std::fs::remove_file(&ck).unwrap();
    let made = std::process::Command::new("mkfifo").arg(&ck).status();
    if made.is_ok_and(|s| s.success()) {
        let (code, err, took) = grow_with(&out, &["--passes", "2", "--resume"], base);
        assert_one_line_error(code, &err, &["not a regular file"]);
        assert!(took < Duration::from_secs(20), "{took:?}");
    }
}

/// A study stopped before its first pass (here in its reference pass) has no checkpoint to
/// go on from: the message says to run it again, not to `--resume` (which it advised), and
/// the folder's marker says interrupted.
#[test]
fn a_study_stopped_before_a_pass_does_not_advise_resuming() {
    let dir = TestDir::new("growth-input", "early");
    let out = dir.join("out");
    let polygon = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/polygon.toml");
    let child = softway()
        .arg("grow")
        .arg(&polygon)
        .args(["--passes", "3", "--set", "wheel.rim_nodes=96", "--out"])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(150));
    assert!(std::process::Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap()
        .success());
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    if out.join("checkpoint.json").exists() {
        // The reference pass finished before the signal (a fast machine): resumable.
        assert!(err.contains("--resume"), "{err}");
    } else {
        assert!(
            err.contains("nothing to go on from") && !err.contains("go on with --resume"),
            "{err}"
        );
    }
    let marker = std::fs::read_to_string(out.join(".softway")).unwrap();
    assert!(marker.lines().any(|l| l == "interrupted"), "{marker}");
    // Issue 47: the summary says so too (it had no `interrupted` at all).
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["interrupted"], true, "{summary}");
    assert!(summary["passes"].as_u64().unwrap() < 3, "{summary}");
}

/// A study that reaches its passes says `"interrupted": false` in its summary.
#[test]
fn a_finished_study_says_it_was_not_interrupted() {
    let dir = TestDir::new("growth-input", "finished");
    let out = dir.join("out");
    let polygon = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/polygon.toml");
    let o = softway()
        .arg("grow")
        .arg(&polygon)
        .args(["--passes", "1", "--set", "wheel.rim_nodes=96", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["interrupted"], false, "{summary}");
    assert_eq!(summary["passes"], 1, "{summary}");
}
