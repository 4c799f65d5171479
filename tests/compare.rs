//! `softway compare` on the shipped bar comparison: one row per combination, the soft way
//! without penetration and with its energy kept, exact enforcement penetrating.

use std::process::Command;

#[test]
fn compare_bar_writes_one_row_per_combination() {
    let dir = std::env::temp_dir().join(format!("softway-compare-{}", std::process::id()));
    let o = Command::new(env!("CARGO_BIN_EXE_softway"))
        .args([
            "compare",
            concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/compare-bar.toml"),
            "--out",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(dir.join("compare.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 6);
    let col = |name: &str| {
        csv.lines()
            .next()
            .unwrap()
            .split(',')
            .position(|c| c == name)
            .unwrap()
    };
    let (pen, en, contact) = (
        col("max_penetration_m"),
        col("energy_change"),
        col("contact"),
    );
    for r in &rows {
        let p: f64 = r[pen].parse().unwrap();
        let e: f64 = r[en].parse().unwrap();
        match r[contact] {
            "soft_way" => assert!(p < 1e-9 && e.abs() < 0.02, "{r:?}"),
            "exact" => assert!(
                p > 1e-4,
                "exact enforcement should show its arrival penetration: {r:?}"
            ),
            _ => {}
        }
    }
    assert!(dir.join("compare_force.png").exists() && dir.join("compare_energy.png").exists());
}
