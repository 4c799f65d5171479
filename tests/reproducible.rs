//! Reproducibility: the same input gives bit-identical `summary.json` and `history.csv`
//! run after run and in a sweep with `--jobs 1` or `--jobs 2`; the summary records the
//! softway version and the SHA-256 of the scenario text. The machine's measurements
//! (`wall_time_s`, `time_per_step_us`, `peak_rss_mib` and its `peak_rss_scope`) are the only
//! fields allowed to differ: they are left out of the comparison by name (the scope is
//! checked: `run` with `--jobs 1`, `process` with `--jobs 2`).

mod common;

use common::{cli, TestDir, BAR};
use std::path::Path;

/// The measurements of the machine, not of the model: wall-clock times and the peak
/// memory (which depends on what ran before in the same process and on the allocator), and
/// whose peak it is (a run's own with `--jobs 1`, the process's with runs at once).
const WALL_CLOCK_FIELDS: [&str; 4] = [
    "\"wall_time_s\"",
    "\"time_per_step_us\"",
    "\"peak_rss_mib\"",
    "\"peak_rss_scope\"",
];

/// The file's bytes less the lines of the wall-clock fields (one field a line).
fn without_wall_clock(p: &Path) -> Vec<u8> {
    let text = std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let kept: Vec<&str> = text
        .lines()
        .filter(|l| {
            !WALL_CLOCK_FIELDS
                .iter()
                .any(|f| l.trim_start().starts_with(f))
        })
        .collect();
    assert!(kept.len() > 10, "{}", p.display());
    kept.join("\n").into_bytes()
}

fn assert_same_results(a: &Path, b: &Path) {
    assert_eq!(
        without_wall_clock(&a.join("summary.json")),
        without_wall_clock(&b.join("summary.json")),
        "{} vs {}",
        a.display(),
        b.display()
    );
    let (ha, hb) = (
        std::fs::read(a.join("history.csv")).unwrap(),
        std::fs::read(b.join("history.csv")).unwrap(),
    );
    assert!(ha.len() > 100);
    assert!(
        ha == hb,
        "history.csv differs: {} vs {}",
        a.display(),
        b.display()
    );
}

/// A small wheel (3 rings, 37 nodes) pressed 2 mm, rolling a twentieth of a turn, held by a
/// hub on its first ring (pinned at its centre, its 18-node rim rocks its free rigid rotation
/// past a quarter of the flattening within a millisecond, which stops the run).
fn small_wheel() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/wheel-paper-mesh.toml"
    ))
    .unwrap()
    .replace("rings = 12", "rings = 3")
    .replace(
        "support = \"centre\"",
        "hub_radius = 0.0334\nsupport = \"hub\"\n#",
    )
    // 18 rim nodes need 1.5 mm for the base's chord to span a pitch (refused below).
    .replace("flattening = 1e-3", "flattening = 2e-3")
    .replace("turns = 5", "turns = 0.05")
    .replace("settle_time = 5e-3", "settle_time = 2e-4")
    .replace("h = 2e-6", "h = 1e-5")
    .replace("history_stride = 5", "history_stride = 1\nplots = false")
}

#[test]
fn sweeps_with_one_and_two_jobs_give_bit_identical_results() {
    for (name, text, set, values) in [
        (
            "bar",
            BAR.to_string(),
            "bar.speed=1,2,3",
            ["bar.speed=1", "bar.speed=2", "bar.speed=3"],
        ),
        (
            "wheel",
            small_wheel(),
            "rolling.omega=300,350,400",
            [
                "rolling.omega=300",
                "rolling.omega=350",
                "rolling.omega=400",
            ],
        ),
    ] {
        let dir = TestDir::new("repro", name);
        let sc = dir.join(format!("{name}.toml"));
        std::fs::write(&sc, &text).unwrap();
        for jobs in ["1", "2"] {
            let out = dir.join(format!("jobs{jobs}"));
            let o = cli([
                "sweep".as_ref(),
                sc.as_os_str(),
                "--set".as_ref(),
                set.as_ref(),
                "--jobs".as_ref(),
                jobs.as_ref(),
                "--out".as_ref(),
                out.as_os_str(),
            ]);
            assert_eq!(o.code, 0, "{}", o.stderr);
        }
        for v in values {
            assert_same_results(&dir.join("jobs1").join(v), &dir.join("jobs2").join(v));
            // What the two differ in, by design: whose peak memory each summary holds.
            for (jobs, scope) in [("jobs1", "run"), ("jobs2", "process")] {
                let text =
                    std::fs::read_to_string(dir.join(jobs).join(v).join("summary.json")).unwrap();
                if text.contains("\"peak_rss_mib\"") {
                    assert!(
                        text.contains(&format!("\"peak_rss_scope\": \"{scope}\"")),
                        "{jobs}/{v}: not {scope}"
                    );
                }
            }
        }
        // The points differ from each other (the comparison can fail).
        assert_ne!(
            without_wall_clock(&dir.join("jobs1").join(values[0]).join("summary.json")),
            without_wall_clock(&dir.join("jobs1").join(values[1]).join("summary.json"))
        );
    }
}

#[test]
fn a_run_repeated_gives_bit_identical_results_and_records_its_provenance() {
    let dir = TestDir::new("repro", "repeat");
    let sc = dir.join("wheel.toml");
    let text = small_wheel();
    std::fs::write(&sc, &text).unwrap();
    for k in ["a", "b"] {
        let o = cli([
            "run".as_ref(),
            sc.as_os_str(),
            "--quiet".as_ref(),
            "--out".as_ref(),
            dir.join(k).as_os_str(),
        ]);
        assert_eq!(o.code, 0, "{}", o.stderr);
    }
    assert_same_results(&dir.join("a"), &dir.join("b"));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("a/summary.json")).unwrap())
            .unwrap();
    assert_eq!(s["softway_version"], env!("CARGO_PKG_VERSION"));
    let hash = s["scenario_sha256"].as_str().unwrap();
    assert_eq!(hash, softway::scenario::sha256_hex(text.as_bytes()));
    assert_eq!(hash.len(), 64);
}
