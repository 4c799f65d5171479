//! `softway sweep --shard I/N` + `softway gather` against `softway sweep`: the same table
//! (but for the wall-clock column) and the same plot, byte for byte, whatever the order the
//! shards are given in; shards of different sweeps, a missing or a repeated shard are
//! refused on one line.

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

/// A table less its `wall_time_s` column (the only one that measures the machine).
fn without_wall_time(p: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(p).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let wall = head.iter().position(|c| *c == "wall_time_s").unwrap();
    std::iter::once(head.join(","))
        .chain(lines.map(|l| {
            let mut cells: Vec<&str> = l.split(',').collect();
            cells.remove(wall);
            cells.join(",")
        }))
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
