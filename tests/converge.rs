//! `softway converge` through the CLI: on the one-degree-of-freedom scheme, whose period
//! error is second order in `h` (Eqs. 9-10), the observed order of the measured period is 2
//! and its Richardson limit is the exact period; a ladder too short to give an order is
//! refused before anything runs.

use std::process::Command;

const SDOF: &str = r#"
name = "sdof1"
kind = "sdof"
[time]
alpha = 0.8
gamma = 0.0
h = 0.05
t_end = 10.0
[sdof]
mass = 1.0
stiffness = 39.47841760435743
x0 = 1.0
v0 = 0.0
"#;

fn dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("softway-converge-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn the_period_converges_at_second_order_to_the_exact_period() {
    let d = dir("sdof");
    let sc = d.join("sdof.toml");
    std::fs::write(&sc, SDOF).unwrap();
    let out = d.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_softway"))
        .args(["converge", sc.to_str().unwrap(), "--set"])
        .arg("time.h=0.08,0.04,0.02,0.01")
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("converge.csv")).unwrap();
    let head: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert_eq!(
        head,
        [
            "figure",
            "time.h_s=0.08",
            "time.h_s=0.04",
            "time.h_s=0.02",
            "time.h_s=0.01",
            "order@0.02",
            "order@0.01",
            "extrapolated"
        ]
    );
    let row: Vec<&str> = csv
        .lines()
        .find(|l| l.starts_with("period_measured_s,"))
        .unwrap()
        .split(',')
        .collect();
    let p: f64 = row[6].parse().unwrap();
    let limit: f64 = row[7].parse().unwrap();
    assert!((p - 2.0).abs() < 0.05, "observed order {p}");
    assert!((limit - 1.0).abs() < 1e-4, "extrapolated period {limit}");
    assert!(out.join("converge.png").exists() && out.join("converge.md").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_short_ladder_or_several_runs_are_refused_before_anything_runs() {
    let d = dir("short");
    let sc = d.join("sdof.toml");
    std::fs::write(&sc, SDOF).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_softway"))
        .args(["converge", sc.to_str().unwrap(), "--set", "time.h=0.1,0.05"])
        .arg("--out")
        .arg(d.join("out"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        err.contains("time.h") && err.contains("three rungs"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(!d.join("out").exists(), "nothing written");
    // A scenario of several runs is refused before anything runs.
    let o = Command::new(env!("CARGO_BIN_EXE_softway"))
        .args([
            "converge",
            concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/sdof.toml"),
            "--set",
            "time.h=0.1,0.05,0.025",
        ])
        .arg("--out")
        .arg(d.join("multi"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("[[runs]]"), "{err}");
    assert!(!d.join("multi").exists(), "nothing written");
    // Ladders whose order would mean nothing: not monotone, or not a constant ratio.
    for (ladder, must) in [
        ("time.h=0.1,0.025,0.05", "increase (or decrease)"),
        ("time.h=0.1,0.09,0.001", "constant ratio"),
        ("time.h=0.1,0.1,0.1", "increase (or decrease)"),
    ] {
        let out = d.join("bad-ladder");
        let o = Command::new(env!("CARGO_BIN_EXE_softway"))
            .args(["converge", sc.to_str().unwrap(), "--set", ladder])
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{ladder}: {err}");
        assert!(
            err.contains(must) && err.lines().count() == 1,
            "{ladder}: {err}"
        );
        assert!(!out.exists(), "nothing written for {ladder}");
    }
    let _ = std::fs::remove_dir_all(&d);
}
