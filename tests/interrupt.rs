//! Ctrl-C (SIGINT) stops a long run at the next step and still writes valid results.

use std::process::Command;
use std::time::Duration;

#[test]
fn sigint_stops_the_wheel_run_and_keeps_its_results() {
    let dir = std::env::temp_dir().join(format!("softway-int-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut child = Command::new(env!("CARGO_BIN_EXE_softway"))
        .args([
            "run",
            concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/wheel.toml"),
            "--quiet",
            "--out",
        ])
        .arg(&dir)
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    let ok = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap()
        .success();
    assert!(ok);
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "exit status {status:?}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["interrupted"], true);
    let steps = s["steps"].as_u64().unwrap();
    assert!(steps > 0 && steps < 54_860, "steps {steps}");
    // history.csv holds complete rows only, up to the last step.
    let h = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    let rows: Vec<&str> = h.lines().collect();
    assert!(rows.len() > 2);
    let n_cols = rows[0].split(',').count();
    assert!(rows.iter().all(|r| r.split(',').count() == n_cols));
    assert!(!dir.join("history.csv.part").exists());
}
