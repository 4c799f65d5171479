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

/// `softway grow scenarios/polygon.toml` (coarse: 96 rim nodes) with `sets`, into `out`:
/// exit code and standard error, with the time it took.
fn grow(out: &Path, sets: &[&str]) -> (i32, String, Duration) {
    let polygon = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/polygon.toml");
    let mut cmd = softway();
    cmd.arg("grow")
        .arg(&polygon)
        .args(["--passes", "1", "--set", "wheel.rim_nodes=96", "--out"])
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
