//! The commands a researcher reaches for: `run --set`, the wheel's load as a force and its
//! speed in km/h, multi-key sweeps, and the scenario's copy in every output folder.

mod common;

use common::{assert_one_line_error, cli, fresh_dir, scenario, BAR};
use softway::scenario::{Override, Scenario};
use std::path::{Path, PathBuf};

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

fn args(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

/// Checks the folder's copy of the scenario: its header names the file and each `--set`,
/// and the text below it is the text as run (its SHA-256 is the summary's, when there is
/// one) and runs as a scenario again.
fn assert_scenario_copy(dir: &Path, sets: &[&str]) {
    let copy = std::fs::read_to_string(dir.join("scenario.toml"))
        .unwrap_or_else(|e| panic!("{}: no scenario.toml: {e}", dir.display()));
    assert!(copy.starts_with("# softway "), "{copy}");
    for s in sets {
        assert!(copy.contains(&format!("# --set {s}\n")), "{s} in {copy}");
    }
    let sc = Scenario::from_str(&copy, &dir.join("scenario.toml")).unwrap();
    if dir.join("summary.json").exists() {
        let s = summary(dir);
        if let Some(sha) = s["scenario_sha256"].as_str() {
            let body = copy.split_once(".\n\n").unwrap().1;
            assert_eq!(softway::scenario::sha256_hex(body.as_bytes()), sha);
            assert!(!sc.runs.is_empty());
        }
    }
}

/// `run --set` changes the run as the same key in the file does (the bar's mesh), the
/// folder keeps the text as run, and that copy reproduces the run's summary.
#[test]
fn run_set_changes_the_run_as_the_file_would() {
    let p = scenario("set-bar", BAR);
    let out = fresh_dir("cmd", "set-bar").join("out");
    let o = cli(args(&[
        "run",
        p.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
        "--set",
        "bar.elements=16",
        "--set",
        "time.h=0.05",
    ]));
    assert_eq!(o.code, 0, "{}", o.stderr);
    let from_file = scenario(
        "set-bar-file",
        &BAR.replace("elements = 8", "elements = 16")
            .replace("h = 0.1", "h = 0.05"),
    );
    let out_file = fresh_dir("cmd", "set-bar-file").join("out");
    let o = cli(args(&[
        "run",
        from_file.to_str().unwrap(),
        "--out",
        out_file.to_str().unwrap(),
        "--quiet",
    ]));
    assert_eq!(o.code, 0, "{}", o.stderr);
    let (a, b) = (summary(&out), summary(&out_file));
    assert_eq!(a["runs"][0]["steps"], b["runs"][0]["steps"]);
    assert_eq!(
        a["runs"][0]["peak_contact_force"],
        b["runs"][0]["peak_contact_force"]
    );
    assert_scenario_copy(&out, &["bar.elements=16", "time.h=0.05"]);
    // The copy runs again to the same history.
    let again = fresh_dir("cmd", "set-bar-again").join("out");
    let o = cli(args(&[
        "run",
        out.join("scenario.toml").to_str().unwrap(),
        "--out",
        again.to_str().unwrap(),
        "--quiet",
    ]));
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert_eq!(
        std::fs::read(out.join("history.csv")).unwrap(),
        std::fs::read(again.join("history.csv")).unwrap()
    );
}

/// An unknown key or a wrong type given by `--set` is refused with the message the same
/// key gets in the file, naming the `--set` instead of a line; a value out of range names
/// the key; nothing is written.
#[test]
fn run_set_is_validated_exactly_like_the_file() {
    let tail = |e: &str| e.rsplit_once(": ").map(|x| x.1.to_string()).unwrap();
    for (set, line) in [
        ("bar.lenght=2", "lenght = 2"),
        ("bar.elements=\"eight\"", "elements = \"eight\""),
    ] {
        let in_file = scenario(
            "set-bad-file",
            &BAR.replace("gap = 0.5", &format!("gap = 0.5\n{line}"))
                .replace(
                    "elements = 8\n",
                    if line.starts_with("elements") {
                        ""
                    } else {
                        "elements = 8\n"
                    },
                ),
        );
        let o = cli(args(&["run", in_file.to_str().unwrap(), "--quiet"]));
        assert_eq!(o.code, 2, "{}", o.stderr);
        let p = scenario("set-bad", BAR);
        let out = p.with_extension("out");
        let o2 = cli(args(&[
            "run",
            p.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--set",
            set,
        ]));
        assert_one_line_error(
            o2.code,
            &o2.stderr,
            &["set-bad.toml", &format!("--set {set}: ")],
        );
        assert!(!o2.stderr.contains("line "), "{}", o2.stderr);
        assert_eq!(
            tail(&o.stderr),
            tail(&o2.stderr),
            "file: {}\nset: {}",
            o.stderr,
            o2.stderr
        );
        assert!(!out.exists());
    }
    let p = scenario("set-range", BAR);
    let o = cli(args(&[
        "run",
        p.to_str().unwrap(),
        "--quiet",
        "--set",
        "bar.length=-1",
    ]));
    assert_one_line_error(o.code, &o.stderr, &["set-range.toml", "bar.length", "> 0"]);
    let o = cli(args(&[
        "run",
        p.to_str().unwrap(),
        "--quiet",
        "--set",
        "bar.length",
    ]));
    assert_one_line_error(o.code, &o.stderr, &["--set bar.length", "KEY=VALUE"]);
}

/// The wheel of `wheel.toml` (one turn) text with the overrides written into it.
fn wheel_with(sets: &[&str]) -> Scenario<softway::scenario::RunSpec> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/wheel.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let sets: Vec<Override> = sets.iter().map(|s| Override::parse(s).unwrap()).collect();
    softway::scenario::overrides::read_with(
        &text,
        &path,
        &sets,
        &softway::kinds::Registry::builtin(),
    )
    .unwrap()
    .0
}

/// `wheel.load`: the flattening found for it carries the load in an independent static
/// contact solve of the built wheel (to 0.5%), and the rolling run's mean force stays at it;
/// the load and the flattening together are refused.
#[test]
fn wheel_load_is_carried_statically_and_in_rolling() {
    use softway::contact::obstacle::Obstacle;
    let load = 6.0e5;
    let sc = wheel_with(&[
        &format!("wheel.load={load:e}"),
        "rolling.flattening=",
        "rolling.turns=1",
    ]);
    let Some(ws) = sc.runs[0].model.get::<softway::scenario::WheelScenario>() else {
        panic!()
    };
    assert_eq!(ws.load, Some(load));
    let wm = softway::kinds::wheel::run::build(ws, &sc.path).unwrap();
    let d = wm.spec.flattening.depth;
    assert!(d > 0.0 && d < 1e-3, "{d}");
    // The static force at that flattening, solved here with the contact module directly.
    let mut base = wm.base();
    base.flattening.settle_time = 0.0;
    let hs = base.half_space(0.0, [0.0; 3]);
    let sol = softway::contact::statics::solve(
        wm.model.pattern(),
        &wm.model.k,
        &wm.fixed_dofs,
        &wm.load,
        &wm.mesh.reference_positions(),
        &wm.rim,
        hs,
    )
    .unwrap();
    let force: f64 = sol.active.iter().map(|a| a.1).sum();
    println!("load {load:e} N: flattening {d:.6e} m, static force {force:.6e} N");
    assert!((force / load - 1.0).abs() < 5e-3, "{force} against {load}");
    // Rolling: the mean contact force over a turn.
    let out = fresh_dir("cmd", "load-roll");
    let sc = softway::build::resolve(&sc).unwrap();
    softway::run::run_scenario(&sc, &out, &softway::RunOptions::default()).unwrap();
    let s = summary(&out);
    let mean = s["mean_contact_force"].as_f64().unwrap();
    println!("rolling mean {mean:.6e} N");
    assert!((mean / load - 1.0).abs() < 5e-3, "{mean} against {load}");
    assert_eq!(s["requested_load_n"].as_f64(), Some(load));
    assert_eq!(s["flattening_m"].as_f64(), Some(d));
    // Both at once: refused, naming the key.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/wheel.toml");
    let o = cli(args(&[
        "run",
        path.to_str().unwrap(),
        "--quiet",
        "--set",
        "wheel.load=6e5",
    ]));
    assert_one_line_error(
        o.code,
        &o.stderr,
        &["wheel.toml", "`wheel.load`", "rolling.flattening"],
    );
}

/// `rolling.speed_km_h` is the rim's speed: `omega = v / 3.6 / R`; with `rolling.omega` it is
/// refused.
#[test]
fn speed_in_km_h_sets_omega() {
    let sc = wheel_with(&["rolling.omega=", "rolling.speed_km_h=120"]);
    let Some(ws) = sc.runs[0].model.get::<softway::scenario::WheelScenario>() else {
        panic!()
    };
    assert!((ws.spec.omega - 120.0 / 3.6 / 0.1).abs() < 1e-12 * ws.spec.omega);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/wheel.toml");
    let o = cli(args(&[
        "run",
        path.to_str().unwrap(),
        "--quiet",
        "--set",
        "rolling.speed_km_h=120",
    ]));
    assert_one_line_error(o.code, &o.stderr, &["rolling.speed_km_h", "rolling.omega"]);
}

/// A sweep over two keys: the product's four points and the zip's two, a folder and a row
/// each with a column per key (the step's with its unit, `time.h_s`), each folder's copy
/// holding its values; lists in `sweep.csv` as JSON. A zip broadcasts a key's single value
/// to every point.
#[test]
fn sweeps_over_several_keys() {
    let p = scenario("grid", BAR);
    for (grid, hs, n) in [
        ("product", "0.1,0.05", 4),
        ("zip", "0.1,0.05", 2),
        ("zip", "0.05", 2),
    ] {
        let out = fresh_dir("cmd", &format!("grid-{grid}-{}", hs.len())).join("out");
        let o = cli(args(&[
            "sweep",
            p.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--set",
            "bar.elements=8,16",
            "--set",
            &format!("time.h={hs}"),
            "--grid",
            grid,
        ]));
        assert_eq!(o.code, 0, "{}", o.stderr);
        let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
        let mut lines = csv.lines();
        assert!(
            lines.next().unwrap().starts_with("bar.elements,time.h_s,"),
            "{csv}"
        );
        let rows: Vec<&str> = lines.collect();
        assert_eq!(rows.len(), n, "{csv}");
        let mut dirs: Vec<PathBuf> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.is_dir())
            .collect();
        dirs.sort();
        assert_eq!(dirs.len(), n);
        for (row, (e, h)) in rows.iter().zip(if hs == "0.05" {
            vec![("8", "0.05"), ("16", "0.05")]
        } else if grid == "zip" {
            vec![("8", "0.1"), ("16", "0.05")]
        } else {
            vec![("8", "0.1"), ("8", "0.05"), ("16", "0.1"), ("16", "0.05")]
        }) {
            assert!(row.starts_with(&format!("{e},{h},")), "{row}");
            let d = out.join(format!("bar.elements={e},time.h={h}"));
            assert_scenario_copy(&d, &[&format!("bar.elements={e}"), &format!("time.h={h}")]);
            let s = summary(&d);
            let steps = s["runs"][0]["steps"].as_u64().unwrap();
            assert_eq!(steps, (1.0 / h.parse::<f64>().unwrap()).round() as u64);
        }
        assert_scenario_copy(&out, &[]);
    }
    let o = cli(args(&[
        "sweep",
        p.to_str().unwrap(),
        "--set",
        "bar.elements=8,16",
        "--set",
        "time.h=0.1,0.05,0.025",
        "--grid",
        "zip",
    ]));
    assert_one_line_error(o.code, &o.stderr, &["--grid zip", "same length"]);
}

/// A `[sweep]` ladder with a key set with each rung (`ladder.with`): every value of the
/// sweep's key on every rung, each rung with its own value of the linked key (three rungs
/// of `bar.elements`, each with its own step: 6 points, not the 18 of a product), as
/// `sweep.csv`'s rows and each run's steps say.
#[test]
fn a_ladder_sets_its_linked_keys_with_each_rung() {
    let p = scenario(
        "ladder_with",
        &format!(
            "{BAR}[sweep]\nkey = \"bar.speed\"\nvalues = [1.0, 2.0]\nladder = {{ key = \"bar.elements\", values = [8, 16, 32], with = {{ \"time.h\" = [0.1, 0.05, 0.025] }} }}\n"
        ),
    );
    let out = fresh_dir("cmd", "ladder-with").join("out");
    let o = cli(args(&[
        "sweep",
        p.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]));
    assert_eq!(o.code, 0, "{}", o.stderr);
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let mut lines = csv.lines();
    assert!(
        lines
            .next()
            .unwrap()
            .starts_with("bar.speed_m_s,bar.elements,time.h_s,"),
        "{csv}"
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 6, "{csv}");
    let mut i = 0;
    for v in ["1.0", "2.0"] {
        for (e, h) in [("8", "0.1"), ("16", "0.05"), ("32", "0.025")] {
            assert!(rows[i].starts_with(&format!("{v},{e},{h},")), "{}", rows[i]);
            let d = out.join(format!("bar.speed={v},bar.elements={e},time.h={h}"));
            let steps = summary(&d)["runs"][0]["steps"].as_u64().unwrap();
            assert_eq!(steps, (1.0 / h.parse::<f64>().unwrap()).round() as u64);
            i += 1;
        }
    }
}

/// Every command that writes a folder keeps the scenario's copy: compare and modes (with
/// `--set`), converge.
#[test]
fn every_output_folder_keeps_the_scenario() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    let out = fresh_dir("cmd", "copies");
    let o = cli(args(&[
        "compare",
        root.join("compare-bar.toml").to_str().unwrap(),
        "--out",
        out.join("compare").to_str().unwrap(),
        "--set",
        "bar.elements=20",
    ]));
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert_scenario_copy(&out.join("compare"), &["bar.elements=20"]);
    let o = cli(args(&[
        "modes",
        root.join("wheel.toml").to_str().unwrap(),
        "--out",
        out.join("modes").to_str().unwrap(),
        "--count",
        "4",
        "--set",
        "wheel.rim_nodes=",
        "--set",
        "wheel.rings=4",
    ]));
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(!o.stdout.contains("Hub {"), "{}", o.stdout);
    assert!(
        o.stdout.contains("a hub clamped within 0.01 m"),
        "{}",
        o.stdout
    );
    assert_scenario_copy(&out.join("modes"), &["wheel.rim_nodes=", "wheel.rings=4"]);
    let p = scenario("ladder", BAR);
    let o = cli(args(&[
        "converge",
        p.to_str().unwrap(),
        "--out",
        out.join("converge").to_str().unwrap(),
        "--set",
        "bar.elements=4,8,16",
    ]));
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert_scenario_copy(&out.join("converge"), &[]);
    assert_scenario_copy(
        &out.join("converge").join("bar.elements=8"),
        &["bar.elements=8"],
    );
}
