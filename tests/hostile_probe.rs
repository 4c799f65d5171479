//! Defects of the second hostile probe (issue 47, `validation/hostile_probe.py`) outside
//! the growth studies, one test per class:
//!
//! - the vehicle's values beyond any railway vehicle's (a speed of 1e-6 km/h, a load of
//!   1e12 N, a wheel of 50 m) ran until the contact lost its rim nodes, or named another
//!   key;
//! - a block's margin of 1 km built a block of 3e5 columns for ever, and a `block.dx` of
//!   1 um one of millions of nodes (12 GB, deaf to SIGTERM): the estimate left the block out;
//! - a wheel's material whose spin stretch is absurd (`material.young` = 1e-300) was
//!   refused naming only `rolling.omega` and `wheel.radius`.

mod common;

use common::{assert_one_line_error, softway, TestDir};
use std::path::Path;
use std::time::{Duration, Instant};

/// `softway run scenarios/NAME` with `sets` into a fresh folder: the refusal must be one
/// line naming `must` and the scenario, at once, and write nothing.
fn refused(dir: &Path, k: usize, name: &str, sets: &[&str], must: &[&str]) {
    let out = dir.join(format!("out{k}"));
    let mut cmd = softway();
    cmd.arg("run")
        .arg(
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("scenarios")
                .join(name),
        )
        .args(["--quiet", "--threads", "1", "--out"])
        .arg(&out);
    for s in sets {
        cmd.args(["--set", s]);
    }
    let start = Instant::now();
    let o = cmd.output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    let mut must = must.to_vec();
    must.push(name);
    assert_one_line_error(o.status.code().unwrap_or(-1), &err, &must);
    assert!(!out.exists(), "{sets:?}: {} written", out.display());
    assert!(
        start.elapsed() < Duration::from_secs(20),
        "{sets:?}: {:?}",
        start.elapsed()
    );
}

#[test]
fn vehicle_values_beyond_any_railway_vehicles_are_refused_by_their_key() {
    let dir = TestDir::new("hostile-probe", "vehicle");
    for (k, (set, key)) in [
        ("vehicle.speed_km_h=1e-6", "vehicle.speed_km_h"),
        ("vehicle.axle_load=1e12", "vehicle.axle_load"),
        ("vehicle.wheel_radius=50.0", "vehicle.wheel_radius"),
        ("vehicle.unsprung_mass=1e9", "vehicle.unsprung_mass"),
    ]
    .into_iter()
    .enumerate()
    {
        refused(&dir, k, "track.toml", &[set], &[key, "railway vehicle"]);
    }
}

#[test]
fn a_block_margin_beyond_twenty_depths_is_refused() {
    let dir = TestDir::new("hostile-probe", "block");
    refused(
        &dir,
        0,
        "wheel-on-block.toml",
        &["block.margin=1e3"],
        &["block.margin", "block.depth"],
    );
}

#[test]
fn an_absurd_spin_stretch_names_the_material_too() {
    let dir = TestDir::new("hostile-probe", "spin");
    for (k, set) in ["material.young=1e-300", "material.density=1e300"]
        .into_iter()
        .enumerate()
    {
        refused(
            &dir,
            k,
            "wheel.toml",
            &[set, "wheel.rim_nodes=96", "rolling.turns=0.1"],
            &["rolling.omega", "material.density", "material.young"],
        );
    }
}

/// The block's nodes count in the run's cost: a `block.dx` of 1 um (millions of nodes,
/// 12 GB before the first step, deaf to SIGTERM) is refused up front by the estimate,
/// naming the key.
#[test]
fn a_block_beyond_the_machine_is_refused_by_its_cost() {
    let dir = TestDir::new("hostile-probe", "block-cost");
    refused(
        &dir,
        0,
        "wheel-on-block.toml",
        &["block.dx=1e-6", "wheel.rim_nodes=96", "rolling.turns=0.1"],
        &["block.dx"],
    );
}
