//! Results in memory ([`softway::run`]) against the command line's files: the history's
//! columns are `history.csv` (every number the file's text through the same `{:e}`
//! formatting, and parsed back bit for bit), the per-node contact rows are
//! `contact_nodes.csv`, the summary is `summary.json` but for the wall-clock fields, and
//! [`softway::Results::save`] writes the same bytes as `softway run` (which streams its
//! tables during the run instead of holding them).

mod common;

use common::{run_ok, scenario, shipped, TestDir};
use softway::run::Columns;
use softway::run::RunOptions;
use softway::scenario::Scenario;
use std::path::Path;

/// Fields that measure the machine, not the run.
const WALL_CLOCK: [&str; 4] = [
    "wall_time_s",
    "time_per_step_us",
    "peak_rss_mib",
    "peak_rss_scope",
];

/// A `summary.json` text without the lines of the wall-clock fields (compared as text:
/// parsing JSON numbers back is not exact in serde_json's default build).
fn without_wall_clock(text: &str) -> String {
    text.lines()
        .filter(|l| !WALL_CLOCK.iter().any(|k| l.contains(&format!("\"{k}\":"))))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Asserts that `table` holds exactly the rows of the CSV file `path`: the same header, the
/// same key text, every number formatted as the file's text and parsed back to the same
/// bits. Returns the rows compared.
fn assert_table_is_file(table: &Columns, path: &Path) -> usize {
    // An independent RFC 4180 parser (the `csv` crate): quoted keys read back whole.
    let mut r = csv::Reader::from_path(path).unwrap();
    assert_eq!(r.headers().unwrap(), table.header());
    let key = table.key();
    let mut n = 0;
    for (i, row) in r.records().enumerate() {
        let row = row.unwrap();
        let mut cells = row.iter();
        if let Some(k) = key {
            assert_eq!(
                cells.next().unwrap(),
                k.text(i),
                "{}: row {i}",
                path.display()
            );
        }
        for c in table.columns() {
            let cell = cells.next().unwrap();
            let v = c.values[i];
            assert_eq!(
                format!("{v:e}"),
                cell,
                "{}: {} row {i}",
                path.display(),
                c.name
            );
            let back: f64 = cell.parse().unwrap();
            assert!(
                back.to_bits() == v.to_bits() || (back.is_nan() && v.is_nan()),
                "{}: {} row {i}",
                path.display(),
                c.name
            );
        }
        assert!(cells.next().is_none(), "{}: row {i} longer", path.display());
        n += 1;
    }
    assert_eq!(n, table.len(), "{}: rows", path.display());
    n
}

/// Asserts that the folders `a` and `b` hold the same files with the same bytes
/// (`summary.json`: the same JSON but for the wall-clock fields). Returns the files.
fn assert_same_files(a: &Path, b: &Path) -> Vec<String> {
    let names = |d: &Path| {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            // The command line's mark of a folder it wrote (`output::staging`).
            .filter(|n| n != softway::cli::MARKER)
            // The command line's copy of the scenario as run (`Results` holds no text).
            .filter(|n| n != softway::run::SCENARIO_COPY)
            .collect();
        v.sort();
        v
    };
    let files = names(a);
    assert_eq!(files, names(b));
    for f in &files {
        let (x, y) = (
            std::fs::read(a.join(f)).unwrap(),
            std::fs::read(b.join(f)).unwrap(),
        );
        if f == "summary.json" {
            let text = |s: &[u8]| without_wall_clock(std::str::from_utf8(s).unwrap());
            assert_eq!(text(&x), text(&y));
        } else {
            assert!(
                x == y,
                "{f} differs between {} and {}",
                a.display(),
                b.display()
            );
        }
    }
    files
}

/// Runs the scenario `text` (read as the file `path`) in memory and through the command
/// line; checks the tables and the summary against the files and that `save` writes the
/// command line's files. Returns the results.
fn run_both(name: &str, path: &Path, text: &str) -> softway::Results {
    let sc = softway::build::resolve(&Scenario::from_str(text, path).unwrap()).unwrap();
    let r = softway::run(&sc, &RunOptions::default()).unwrap();
    assert!(!r.interrupted);
    assert!(r.history.streamed_to().is_none());
    let p = scenario(name, text);
    let (out, _) = run_ok(&p);
    let file = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let memory = serde_json::to_string_pretty(&r.summary).unwrap() + "\n";
    assert_eq!(without_wall_clock(&memory), without_wall_clock(&file));
    // The wall clock is in the file (its lines are left out of the comparison).
    assert!(file.contains("\"wall_time_s\":"));
    assert!(assert_table_is_file(&r.history, &out.join("history.csv")) > 10);
    if let Some(nodes) = &r.contact_nodes {
        assert!(assert_table_is_file(nodes, &out.join("contact_nodes.csv")) > 10);
    }
    if let Some(t) = &r.traction_history {
        assert!(assert_table_is_file(t, &out.join("traction_history.csv")) > 10);
    }
    if let Some(t) = &r.rim_profile {
        assert!(assert_table_is_file(t, &out.join("j2_rim_profile.csv")) > 10);
    }
    let saved = TestDir::new("results", name);
    let files = r.save(&saved).unwrap();
    assert_eq!(files.len(), assert_same_files(&out, &saved).len());
    let _ = std::fs::remove_dir_all(p.parent().unwrap());
    r
}

/// The bar of Fig. 8 at three steps: one history of three runs keyed by their labels; the
/// units go with the columns; the run of h = 0.01 has 501 rows (t = 0..5 s) and its times
/// are the step grid.
#[test]
fn the_bar_in_memory_is_the_command_lines_files() {
    let (path, text) = shipped("bar-impact", &[]);
    let r = run_both("bar", &path, &text);
    assert_eq!(r.kind, "bar_impact");
    let key = r.history.key().unwrap();
    assert_eq!(key.name, "run");
    assert_eq!(key.labels, ["h = 0.01", "h = 0.1", "h = 0.4"]);
    let units: Vec<&str> = r
        .history
        .columns()
        .iter()
        .map(|c| c.unit.as_str())
        .collect();
    assert_eq!(units, ["s", "m", "m/s", "N", "J", "J", "J", "1", "m"]);
    let t = r.history.column("t_s").unwrap();
    let first: Vec<usize> = (0..r.history.len())
        .filter(|&i| key.codes[i] == 0)
        .collect();
    assert_eq!(first.len(), 501);
    for (k, &i) in first.iter().enumerate() {
        assert!(
            (t[i] - k as f64 * 0.01).abs() < 1e-9,
            "row {i}: t = {}",
            t[i]
        );
    }
    assert_eq!(r.summary["runs"].as_array().unwrap().len(), 3);
    assert!(r.fields.frames.is_empty() && r.contact_nodes.is_none());
}

/// The paper's wheel on a coarse mesh (6 rings) for one turn, with two velocity
/// snapshots: history, contact nodes, rim profile, fields and figures as the command line
/// writes them. The fields are the VTU files' (one turn average on the cells, two
/// snapshots on the points); the contact rows' nodes are rim nodes.
#[test]
fn a_short_wheel_in_memory_is_the_command_lines_files() {
    let (path, text) = shipped(
        "wheel-paper-mesh",
        &[
            ("wheel.rings", "6"),
            ("rolling.turns", "1"),
            ("rolling.fields_per_turn", "2"),
        ],
    );
    let r = run_both("wheel", &path, &text);
    assert_eq!(r.kind, "wheel");
    let mesh = r.fields.mesh.as_ref().unwrap();
    let frames: Vec<&str> = r.fields.frames.iter().map(|f| f.file.as_str()).collect();
    assert_eq!(
        frames,
        [
            "j2_turn_average.vtu",
            "velocity_000.vtu",
            "velocity_001.vtu"
        ]
    );
    let avg = &r.fields.frames[0];
    assert_eq!(avg.cell_data[0].values.len(), mesh.cells.len());
    let snap = &r.fields.frames[2];
    assert_eq!(snap.point_data[0].values.len(), mesh.n_dofs());
    assert!(snap.time.unwrap() > r.fields.frames[1].time.unwrap());
    let nodes = r.contact_nodes.as_ref().unwrap();
    let key = nodes.key().unwrap();
    let rim_radius: f64 = 0.1;
    for label in &key.labels {
        let p = mesh.point(label.parse::<usize>().unwrap());
        assert!((p[0].hypot(p[1]) / rim_radius - 1.0).abs() < 1e-9);
    }
    // The summary's mean force is the mean of the history's force over the rolling rows
    // only when every step is a row; here it is a check of order of magnitude and sign.
    let f = r.history.column("contact_force_N").unwrap();
    let mean = r.summary["mean_contact_force"].as_f64().unwrap();
    let tail = &f[f.len() / 2..];
    let tail_mean = tail.iter().sum::<f64>() / tail.len() as f64;
    assert!(
        (tail_mean / mean - 1.0).abs() < 0.05,
        "{tail_mean} vs {mean}"
    );
}

/// The same wheel with Coulomb friction and a driving creepage: the traction history and
/// `contact_nodes.csv`'s tangential columns come from memory as the command line streams
/// them, and `save` writes the traction profile and figures as it does.
#[test]
fn a_short_wheel_with_friction_in_memory_is_the_command_lines_files() {
    let (path, text) = shipped(
        "wheel-paper-mesh",
        &[
            ("wheel.rings", "6"),
            ("rolling.turns", "1"),
            ("rolling.fields_per_turn", "1"),
            ("rolling.creepage", "0.005"),
            ("contact.friction", "0.3"),
            // Held by a hub on the first ring: the creep force's torque would spin the
            // pinned disk's free rigid rotation up, which stops the run.
            ("wheel.support", "\"hub\""),
            ("wheel.hub_radius", "0.017"),
        ],
    );
    let r = run_both("traction", &path, &text);
    let nodes = r.contact_nodes.as_ref().unwrap();
    assert_eq!(nodes.header().last(), Some(&"sliding"));
    let t = r.traction_history.as_ref().unwrap();
    assert_eq!(t.len(), r.history.len());
    assert!(r.summary["traction"]["traction"]
        .as_f64()
        .unwrap()
        .is_finite());
}

/// Run labels holding a comma and a double quote (as `scenarios/compare-bar.toml`'s do) are
/// quoted in `history.csv` (RFC 4180): read back by an independent CSV parser, every row of
/// the file has exactly the header's width and its `run` column reads back the run's label.
/// The memory table and `save` agree with the streamed file (`run_both`).
#[test]
fn labels_with_commas_and_quotes_read_back_from_history_csv() {
    let labels = ["h = 0.1, soft way", "the \"soft\" way, h = 0.4"];
    let (path, text) = shipped("bar-impact", &[]);
    let text = text
        .replace("label = \"h = 0.1\"", "label = \"h = 0.1, soft way\"")
        .replace("label = \"h = 0.4\"", "label = 'the \"soft\" way, h = 0.4'");
    let r = run_both("labels", &path, &text);
    let key = r.history.key().unwrap();
    assert_eq!(key.labels, ["h = 0.01", labels[0], labels[1]]);
    // The file of `save` (the same bytes as the command line's, `run_both`).
    let dir = TestDir::new("results", "labels-file");
    r.save(&dir).unwrap();
    let mut rd = csv::ReaderBuilder::new()
        .flexible(true)
        .from_path(dir.join("history.csv"))
        .unwrap();
    let head = rd.headers().unwrap().clone();
    assert_eq!(head.get(0), Some("run"));
    let mut seen = std::collections::BTreeMap::new();
    for (i, row) in rd.records().enumerate() {
        let row = row.unwrap();
        assert_eq!(row.len(), head.len(), "row {i}: {row:?}");
        *seen.entry(row[0].to_string()).or_insert(0usize) += 1;
    }
    // Every run's rows under its own label: 501 at h = 0.01 and 51 at h = 0.1 (t = 0..5 s),
    // as many as the table in memory holds at h = 0.4.
    let held = |c: u32| key.codes.iter().filter(|&&k| k == c).count();
    assert_eq!(seen.get("h = 0.01"), Some(&501), "{seen:?}");
    assert_eq!(seen.get(labels[0]), Some(&51), "{seen:?}");
    assert_eq!(seen.get(labels[1]), Some(&held(2)), "{seen:?}");
    assert_eq!(seen.len(), 3, "{seen:?}");
}
