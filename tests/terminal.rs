//! The terminal: what `softway run`, `sweep`, `converge` and `compare` print fits 100
//! columns, in readable units; the default output folders (a `--set` run never replaces the
//! scenario's own folder; `sweep` of a scenario named `...-sweep` does not double the word).
//! (The progress bar's time left is tested in `src/output/terminal.rs`.)

mod common;

use common::{fresh_dir, softway};
use std::path::{Path, PathBuf};

const WIDTH: usize = 100;

fn shipped(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(format!("{name}.toml"))
}

/// Runs `softway ARGS` in `cwd`; its standard output (asserting exit 0).
fn stdout_of(cwd: &Path, args: &[&str]) -> String {
    let o = softway().current_dir(cwd).args(args).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "{args:?}: {out}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    out
}

/// Every line of `text` within [`WIDTH`] characters, the paths of the files written aside
/// (a path is as long as the folder the user names).
fn assert_fits(what: &str, text: &str) {
    let mut files = false;
    for line in text.lines() {
        if line.trim_end() == "wrote:" {
            files = true;
            continue;
        }
        if files && line.starts_with("    ") {
            continue;
        }
        assert!(
            line.chars().count() <= WIDTH,
            "{what}: a line of {} characters:\n{line}\n\n{text}",
            line.chars().count()
        );
    }
}

/// The shipped wheel shortened to one turn on a coarse rim (about a second).
const QUICK: [&str; 4] = ["--set", "rolling.turns=1", "--set", "wheel.rim_nodes=72"];

/// `softway run` of the wheel: the report fits 100 columns and gives its forces in kN and its
/// lengths in mm; given `--set` values (and no `--out`) it writes into a folder of its own
/// that names them, and the scenario's own `out/wheel/` is left as the plain run wrote it.
#[test]
fn a_run_report_fits_and_a_set_run_keeps_the_plain_runs_folder() {
    let cwd = fresh_dir("terminal", "run");
    let wheel = shipped("wheel");
    let w = wheel.to_str().unwrap();
    // The plain run into out/wheel (shortened by a copy of the file: a plain run has no --set).
    let text = std::fs::read_to_string(&wheel)
        .unwrap()
        .replace("turns = 5", "turns = 1")
        .replace("rim_nodes = 288", "rim_nodes = 72");
    let copy = cwd.join("wheel.toml");
    std::fs::write(&copy, text).unwrap();
    let plain = stdout_of(&cwd, &["run", copy.to_str().unwrap(), "--quiet"]);
    assert_fits("run", &plain);
    assert!(
        plain.contains(" kN") && plain.contains("flattening 1.000 mm"),
        "{plain}"
    );
    let history = cwd.join("out/wheel/history.csv");
    let before = std::fs::read(&history).unwrap();
    // The one-off change: its own folder, `out/wheel,<key>=<value>,...`.
    let mut args = vec!["run", w, "--quiet"];
    args.extend(QUICK);
    args.extend(["--set", "rolling.omega=250"]);
    let set = stdout_of(&cwd, &args);
    assert_fits("run --set", &set);
    let own = cwd.join("out/wheel,rolling.turns=1,wheel.rim_nodes=72,rolling.omega=250");
    assert!(own.join("summary.json").is_file(), "{set}");
    assert_eq!(
        std::fs::read(&history).unwrap(),
        before,
        "out/wheel/ was replaced"
    );
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(own.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["omega"], 250.0);
    // The report's mean force is the summary's, in kN to four digits.
    let mean = s["mean_contact_force"].as_f64().unwrap();
    let shown = format!("mean {:.1} kN", mean / 1e3);
    assert!(set.contains(&shown), "{shown} not in:\n{set}");
}

/// `softway sweep scenarios/wheel-sweep.toml` writes `out/wheel-sweep/` (not
/// `out/wheel-sweep-sweep/`), and its table fits 100 columns: the swept key is repeated in
/// every block of columns, the forces are in kN.
#[test]
fn a_sweep_of_wheel_sweep_writes_out_wheel_sweep_and_its_table_fits() {
    let cwd = fresh_dir("terminal", "sweep");
    let ws = shipped("wheel-sweep");
    let mut args = vec![
        "sweep",
        ws.to_str().unwrap(),
        "--set",
        "rolling.omega=250,300",
    ];
    args.extend(QUICK);
    let out = stdout_of(&cwd, &args);
    assert_fits("sweep", &out);
    assert!(cwd.join("out/wheel-sweep/sweep.csv").is_file(), "{out}");
    assert!(!cwd.join("out/wheel-sweep-sweep").exists());
    // The table: more than one block, each headed by the swept keys; forces in kN.
    let heads = out
        .lines()
        .filter(|l| l.starts_with("rolling.omega_rad_s"))
        .count();
    assert!(heads >= 2, "{out}");
    assert!(out.contains("mean_contact_force_kN"), "{out}");
    // Every figure of the CSV is in the printed table, by its column's name.
    let csv = std::fs::read_to_string(cwd.join("out/wheel-sweep/sweep.csv")).unwrap();
    for name in csv.lines().next().unwrap().split(',') {
        let stem = name
            .trim_end_matches("_N")
            .trim_end_matches("_s")
            .trim_end_matches("_m");
        assert!(
            out.contains(stem),
            "{stem} of sweep.csv not printed:\n{out}"
        );
    }
}

/// `softway converge` names its folder `out/<name>-converge` and prints a table within 100
/// columns; `softway compare`'s table of 18 columns is printed in blocks within 100.
#[test]
fn converge_and_compare_tables_fit() {
    let cwd = fresh_dir("terminal", "converge");
    let text = std::fs::read_to_string(shipped("wheel"))
        .unwrap()
        .replace("turns = 5", "turns = 1");
    let p = cwd.join("ladder.toml");
    std::fs::write(&p, text).unwrap();
    let out = stdout_of(
        &cwd,
        &[
            "converge",
            p.to_str().unwrap(),
            "--set",
            "wheel.rim_nodes=72,144,288",
        ],
    );
    assert_fits("converge", &out);
    assert!(cwd.join("out/wheel-converge/converge.csv").is_file());
    assert!(out.contains("mean_contact_force_kN"), "{out}");
    let cmp = stdout_of(
        &cwd,
        &[
            "compare",
            shipped("compare-bar").to_str().unwrap(),
            "--out",
            "cmp",
        ],
    );
    assert_fits("compare", &cmp);
    // Every run's label is printed once in every block, and every column of compare.md
    // appears (by the stem of its name).
    let md = std::fs::read_to_string(cwd.join("cmp/compare.md")).unwrap();
    let header: Vec<&str> = md
        .lines()
        .next()
        .unwrap()
        .split('|')
        .map(str::trim)
        .collect();
    for name in header.iter().filter(|h| !h.is_empty()) {
        let stem = name.trim_end_matches("_s").trim_end_matches("_m");
        assert!(cmp.contains(stem), "{stem} not printed:\n{cmp}");
    }
    let blocks = cmp.lines().filter(|l| l.starts_with("run ")).count();
    let label = "space-time, soft way, h 0.05";
    assert_eq!(cmp.matches(label).count(), blocks, "{cmp}");
}
