//! `softway sweep --shard I/N` + `softway gather` against `softway sweep`: the same table
//! (but for the wall-clock column) and the same plot, byte for byte, whatever the order the
//! shards are given in, for a sweep of one key and for grids of several (product and zip);
//! shards of different sweeps, a missing or a repeated shard are refused on one line.

mod common;

use common::{cli, TestDir};
use std::path::Path;

/// The paper's wheel on a small disk (6 rings), one turn: about a second a speed.
fn small_wheel(dir: &Path) -> std::path::PathBuf {
    let (_, mut text) = common::shipped(
        "wheel-paper-mesh",
        &[("wheel.rings", "6"), ("rolling.turns", "1")],
    );
    text.push('\n');
    let p = dir.join("wheel.toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// The fields of a CSV line (a field in quotes may hold commas; `""` is a quote).
fn csv_fields(line: &str) -> Vec<String> {
    let (mut fields, mut cur, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => fields.push(std::mem::take(&mut cur)),
            _ => cur.push(c),
        }
    }
    fields.push(cur);
    fields
}

/// A table less its wall-clock columns (named `wall_time...`: the only ones that measure
/// the machine), the columns found by name, a row per line.
fn without_wall_time(p: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(p).unwrap();
    let rows: Vec<Vec<String>> = text.lines().map(csv_fields).collect();
    let keep: Vec<usize> = (0..rows[0].len())
        .filter(|&i| !rows[0][i].starts_with("wall_time"))
        .collect();
    assert!(
        keep.len() < rows[0].len(),
        "no wall-clock column: {:?}",
        rows[0]
    );
    rows.iter()
        .map(|r| keep.iter().map(|&i| r[i].clone()).collect())
        .collect()
}

#[test]
fn two_shards_gathered_equal_the_sweep() {
    let dir = TestDir::new("shard", "equal");
    let sc = small_wheel(&dir);
    let sc = sc.to_str().unwrap();
    let set = "rolling.omega=250.0,300.0,350.0,400.0";
    let d = |s: &str| dir.join(s).to_str().unwrap().to_string();
    let whole = cli([
        "sweep",
        sc,
        "--set",
        set,
        "--out",
        &d("whole"),
        "--jobs",
        "2",
    ]);
    assert_eq!(whole.code, 0, "{}", whole.stderr);
    for i in 1..=2 {
        let o = cli([
            "sweep",
            sc,
            "--set",
            set,
            "--shard",
            &format!("{i}/2"),
            "--out",
            &d(&format!("s{i}")),
            "--jobs",
            "1",
        ]);
        assert_eq!(o.code, 0, "{}", o.stderr);
    }
    // Shard 1 holds the 1st and 3rd values, shard 2 the others.
    assert!(dir.join("s1/rolling.omega=250.0/summary.json").is_file());
    assert!(dir.join("s1/rolling.omega=350.0/summary.json").is_file());
    assert!(!dir.join("s1/rolling.omega=300.0").exists());
    assert!(dir.join("s2/rolling.omega=400.0/summary.json").is_file());
    // Given in either order.
    let g = cli(["gather", &d("s2"), &d("s1"), "--out", &d("gathered")]);
    assert_eq!(g.code, 0, "{}", g.stderr);
    let (a, b) = (dir.join("whole"), dir.join("gathered"));
    let table = without_wall_time(&a.join("sweep.csv"));
    assert_eq!(table.len(), 5, "{table:?}");
    assert_eq!(table, without_wall_time(&b.join("sweep.csv")));
    let png = std::fs::read(a.join("sweep.png")).unwrap();
    assert!(png.len() > 10_000);
    assert_eq!(png, std::fs::read(b.join("sweep.png")).unwrap());

    // Refused: a shard missing, a shard twice, shards of another sweep.
    let missing = cli(["gather", &d("s1"), "--out", &d("g2")]);
    assert_eq!(missing.code, 2);
    assert!(missing.stderr.contains("shard 2/2"), "{}", missing.stderr);
    let twice = cli(["gather", &d("s1"), &d("s1"), "--out", &d("g3")]);
    assert_eq!(twice.code, 2);
    assert!(
        twice.stderr.contains("give each shard once"),
        "{}",
        twice.stderr
    );
    let other = cli([
        "sweep",
        sc,
        "--set",
        "rolling.omega=250.0,300.0,350.0,410.0",
        "--shard",
        "2/2",
        "--out",
        &d("other"),
    ]);
    assert_eq!(other.code, 0, "{}", other.stderr);
    let mixed = cli(["gather", &d("s1"), &d("other"), "--out", &d("g4")]);
    assert_eq!(mixed.code, 2);
    assert!(
        mixed.stderr.contains("values not the same"),
        "{}",
        mixed.stderr
    );
    for g in ["g2", "g3", "g4"] {
        assert!(!dir.join(g).exists(), "{g} written after an error");
    }
    for e in [&missing, &twice, &mixed] {
        assert_eq!(e.stderr.trim().lines().count(), 1, "{}", e.stderr);
    }
}

#[test]
fn a_bad_shard_is_refused_on_one_line() {
    let dir = TestDir::new("shard", "bad");
    let sc = small_wheel(&dir);
    for bad in ["0/2", "3/2", "2", "a/b"] {
        let o = cli([
            "sweep",
            sc.to_str().unwrap(),
            "--set",
            "rolling.omega=250.0,300.0",
            "--shard",
            bad,
            "--out",
            dir.join("x").to_str().unwrap(),
        ]);
        assert_eq!(o.code, 2, "{bad}");
        assert!(o.stderr.contains("expected I/N"), "{bad}: {}", o.stderr);
        assert!(!dir.join("x").exists());
    }
}

/// Runs `softway sweep` over `sets` (each `--set KEY=V1,...`) with `extra` arguments whole,
/// then in `shards` slices, gathers the slices given in reverse order, and returns the
/// whole sweep's and the gathered folders.
fn whole_and_gathered(
    dir: &Path,
    sc: &str,
    sets: &[&str],
    extra: &[&str],
    shards: usize,
) -> (std::path::PathBuf, std::path::PathBuf) {
    let d = |s: &str| dir.join(s).to_str().unwrap().to_string();
    let mut base: Vec<String> = vec!["sweep".into(), sc.into()];
    for s in sets {
        base.extend(["--set".to_string(), s.to_string()]);
    }
    base.extend(extra.iter().map(|s| s.to_string()));
    let whole =
        cli(base
            .iter()
            .cloned()
            .chain(["--out".into(), d("whole"), "--jobs".into(), "2".into()]));
    assert_eq!(whole.code, 0, "{}", whole.stderr);
    let mut dirs = Vec::new();
    for i in 1..=shards {
        let out = d(&format!("s{i}"));
        let o = cli(base.iter().cloned().chain([
            "--shard".into(),
            format!("{i}/{shards}"),
            "--out".into(),
            out.clone(),
            "--jobs".into(),
            "1".into(),
        ]));
        assert_eq!(o.code, 0, "{}", o.stderr);
        dirs.push(out);
    }
    dirs.reverse();
    let g = cli(["gather".to_string()]
        .into_iter()
        .chain(dirs)
        .chain(["--out".into(), d("gathered")]));
    assert_eq!(g.code, 0, "{}", g.stderr);
    (dir.join("whole"), dir.join("gathered"))
}

/// A 2 x 2 product grid (two speeds x two flattenings) in 3 slices: the points dealt in the
/// grid's order (the first key outermost) and gathered into the whole sweep's table.
#[test]
fn a_product_grid_in_three_shards_gathers_into_the_sweep() {
    let dir = TestDir::new("shard", "grid");
    let sc = small_wheel(&dir);
    let (a, b) = whole_and_gathered(
        &dir,
        sc.to_str().unwrap(),
        &[
            "rolling.omega=250.0,350.0",
            "rolling.flattening=0.8e-3,1e-3",
        ],
        &[],
        3,
    );
    // Slice 1 holds points 0 and 3, slice 2 point 1, slice 3 point 2.
    let has = |s: &str, p: &str| dir.join(s).join(p).join("summary.json").is_file();
    assert!(has("s1", "rolling.omega=250.0,rolling.flattening=0.8e-3"));
    assert!(has("s1", "rolling.omega=350.0,rolling.flattening=1e-3"));
    assert!(has("s2", "rolling.omega=250.0,rolling.flattening=1e-3"));
    assert!(has("s3", "rolling.omega=350.0,rolling.flattening=0.8e-3"));
    assert!(!dir
        .join("s2/rolling.omega=350.0,rolling.flattening=1e-3")
        .exists());
    let table = without_wall_time(&a.join("sweep.csv"));
    assert_eq!(table.len(), 5, "{table:?}");
    assert_eq!(
        &table[0][..2],
        ["rolling.omega_rad_s", "rolling.flattening_m"]
    );
    // The rows in the grid's order: the speed outermost.
    let first_two: Vec<&str> = table[1..].iter().map(|r| r[0].as_str()).collect();
    assert_eq!(first_two, ["250.0", "250.0", "350.0", "350.0"]);
    assert_eq!(table, without_wall_time(&b.join("sweep.csv")));
    // Two keys vary: no Fig. 15 for either.
    assert!(!a.join("sweep.png").exists() && !b.join("sweep.png").exists());
    // A slice of another grid mode is refused.
    let d = |s: &str| dir.join(s).to_str().unwrap().to_string();
    let zip = cli([
        "sweep",
        sc.to_str().unwrap(),
        "--set",
        "rolling.omega=250.0,350.0",
        "--set",
        "rolling.flattening=0.8e-3,1e-3",
        "--grid",
        "zip",
        "--shard",
        "2/3",
        "--out",
        &d("zip2"),
    ]);
    assert_eq!(zip.code, 0, "{}", zip.stderr);
    let mixed = cli(["gather", &d("s1"), &d("zip2"), &d("s3"), "--out", &d("g")]);
    assert_eq!(mixed.code, 2);
    assert!(
        mixed.stderr.contains("grid not the same"),
        "{}",
        mixed.stderr
    );
    assert_eq!(mixed.stderr.trim().lines().count(), 1, "{}", mixed.stderr);
}

/// A zip grid of two keys, one of which varies, in 2 slices: the same table and the same
/// Fig. 15 plot, byte for byte.
#[test]
fn a_zip_grid_in_shards_gives_the_same_plot() {
    let dir = TestDir::new("shard", "zip");
    let sc = small_wheel(&dir);
    let (a, b) = whole_and_gathered(
        &dir,
        sc.to_str().unwrap(),
        &["rolling.omega=250.0,300.0,350.0", "rolling.turns=1,1,1"],
        &["--grid", "zip"],
        2,
    );
    let table = without_wall_time(&a.join("sweep.csv"));
    assert_eq!(table.len(), 4, "{table:?}");
    assert_eq!(table, without_wall_time(&b.join("sweep.csv")));
    let png = std::fs::read(a.join("sweep.png")).unwrap();
    assert!(png.len() > 10_000);
    assert_eq!(png, std::fs::read(b.join("sweep.png")).unwrap());
}

/// A manifest is input: an edited count of shards (`of`) beyond what `--shard` takes, or
/// zero, is refused on one line naming it, and nothing is written (an `of` of 1e18 aborted
/// on an allocation before); a large one that `--shard` takes lists the shards missing in
/// one short line.
#[test]
fn an_edited_manifest_count_is_refused_on_one_line() {
    let dir = TestDir::new("shard", "manifest");
    let sc = dir.join("bar.toml");
    std::fs::write(&sc, common::BAR).unwrap();
    let shard = dir.join("s1");
    let o = cli([
        "sweep",
        sc.to_str().unwrap(),
        "--set",
        "time.h=0.1,0.05",
        "--shard",
        "1/1",
        "--out",
        shard.to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let manifest = shard.join("shard.json");
    let good: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&manifest).unwrap()).unwrap();
    for of in [
        serde_json::json!(1_000_000_000_000_000_000u64),
        serde_json::json!(0),
    ] {
        let mut m = good.clone();
        m["of"] = of.clone();
        std::fs::write(&manifest, serde_json::to_string(&m).unwrap()).unwrap();
        let out = dir.join("gathered");
        let o = cli([
            "gather",
            shard.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.code, 2, "of = {of}: {}", o.stderr);
        assert!(
            o.stderr.contains("`of`") && o.stderr.lines().count() == 1,
            "{}",
            o.stderr
        );
        assert!(!out.exists());
    }
}

/// A point folder run again with other settings (issue 47: `softway run --set
/// rolling.omega=450 --out <shard>/rolling.omega=300` was gathered as the 300 rad/s row):
/// `gather` checks each point's as-run scenario against the manifest's point and refuses the
/// folder, naming it and the values it ran with.
#[test]
fn a_point_folder_run_again_with_other_settings_is_refused() {
    let dir = TestDir::new("shard", "rerun");
    let sc = dir.join("bar.toml");
    std::fs::write(&sc, common::BAR).unwrap();
    let shard = dir.join("s1");
    let o = cli([
        "sweep",
        sc.to_str().unwrap(),
        "--set",
        "time.h=0.1,0.05",
        "--shard",
        "1/1",
        "--out",
        shard.to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let gathered = dir.join("gathered");
    let g = cli([
        "gather",
        shard.to_str().unwrap(),
        "--out",
        gathered.to_str().unwrap(),
    ]);
    assert_eq!(g.code, 0, "{}", g.stderr);
    // The 0.1 s point's folder run again at 0.05 s.
    let point = shard.join("time.h=0.1");
    let o = cli([
        "run",
        sc.to_str().unwrap(),
        "--set",
        "time.h=0.05",
        "--quiet",
        "--force",
        "--out",
        point.to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let again = dir.join("again");
    let g = cli([
        "gather",
        shard.to_str().unwrap(),
        "--out",
        again.to_str().unwrap(),
    ]);
    assert_eq!(g.code, 2, "{}", g.stderr);
    assert_eq!(g.stderr.trim().lines().count(), 1, "{}", g.stderr);
    for m in ["time.h=0.1", "not the sweep's point", "--set time.h=0.05"] {
        assert!(g.stderr.contains(m), "`{m}` missing from {}", g.stderr);
    }
    assert!(!again.exists(), "written after an error");
    // An edited copy of the sweep's scenario in the shard folder is refused too.
    let copy = shard.join("scenario.toml");
    let text = std::fs::read_to_string(&copy).unwrap();
    std::fs::write(&copy, text.replace("ea = ", "ea =  ")).unwrap();
    let g = cli([
        "gather",
        shard.to_str().unwrap(),
        "--out",
        again.to_str().unwrap(),
    ]);
    assert_eq!(g.code, 2, "{}", g.stderr);
    assert!(
        g.stderr
            .contains("not the scenario of the shard's manifest"),
        "{}",
        g.stderr
    );
}
