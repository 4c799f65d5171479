//! Defects the second hostile probe of the growth studies found (issue 47,
//! `validation/hostile_probe.py`), one test per class, each through the command users call:
//!
//! - a profile the body cannot carry (a roughness of 400 dB, a harmonic of 1 m, a
//!   checkpoint's profile scaled by 1e6) was refused as an inverted triangle of the mesh,
//!   naming no key; one below the rounding of the rim's coordinates (-400 dB) grew by
//!   +400,000 dB per 1e5 passes with exit 0;
//! - a harmonic longer than the rim (1 km) ran as the circumference without a word;
//! - `growth.passes_per_pass` = 1e-300 wrote rates of inf;
//! - a study from a smooth surface (`roughness = "none"`) wrote `-inf` and `NaN` cells and
//!   then failed on its spectrum figure, its folder half written;
//! - the rail's study: a spacing of 1 nm ran for ever, a spectrum its grid cannot make was
//!   refused naming no file and no key, an interrupted study exited 2 ("error: interrupted");
//! - a roughness CSV without a header lost its first point.

mod common;

use common::{assert_one_line_error, softway, TestDir};
use std::path::Path;
use std::time::{Duration, Instant};

fn scenario(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(name)
}

/// `softway grow scenarios/polygon.toml` (96 rim nodes, no reference pass, a short
/// settling) with `args` and `sets` into `out`: exit code and standard error.
fn grow(out: &Path, args: &[&str], sets: &[&str]) -> (i32, String) {
    let mut cmd = softway();
    cmd.arg("grow")
        .arg(scenario("polygon.toml"))
        .args(args)
        .args([
            "--threads",
            "1",
            "--set",
            "wheel.rim_nodes=96",
            "--set",
            "growth.reference=false",
            "--set",
            "rolling.settle_time=5e-4",
            "--out",
        ])
        .arg(out);
    for s in sets {
        cmd.args(["--set", s]);
    }
    let o = cmd.output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

const HARMONIC: &[&str] = &[
    "growth.roughness=\"harmonic\"",
    "growth.level=",
    "growth.min_wavelength=",
    "growth.max_wavelength=",
    "growth.seed=",
];

const SMOOTH: &[&str] = &[
    "growth.roughness=\"none\"",
    "growth.level=",
    "growth.min_wavelength=",
    "growth.max_wavelength=",
    "growth.seed=",
];

/// No cell of the folder's CSV tables is `NaN` or infinite.
fn assert_finite_tables(out: &Path) {
    for e in std::fs::read_dir(out).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "csv") {
            let t = std::fs::read_to_string(&p).unwrap();
            for (i, line) in t.lines().enumerate().skip(1) {
                for c in line.split(',') {
                    assert!(
                        c.is_empty() || c.parse::<f64>().is_ok_and(f64::is_finite),
                        "{} line {}: `{c}` in {line}",
                        p.display(),
                        i + 1
                    );
                }
            }
        }
    }
}

#[test]
fn a_roughness_the_rim_cannot_carry_is_refused_by_its_key() {
    let dir = TestDir::new("hostile-growth", "roughness");
    let with = |extra: &[&'static str]| -> Vec<&'static str> {
        HARMONIC.iter().chain(extra).copied().collect()
    };
    let cases: Vec<(Vec<&str>, &str)> = vec![
        // 400 dB re 1 um: 1e14 m (an inverted triangle of the mesh before).
        (vec!["growth.level=400"], "growth.level"),
        // -400 dB: 1e-26 m, below the rounding of a 0.1 m radius (grew +400,000 dB).
        (vec!["growth.level=-400"], "growth.level"),
        (
            with(&["growth.amplitude=1.0", "growth.wavelength=0.0785"]),
            "growth.amplitude",
        ),
        // 1 km on a rim of 0.628 m: was run as order 1 without a word.
        (
            with(&["growth.amplitude=1e-6", "growth.wavelength=1e3"]),
            "growth.wavelength",
        ),
        // 1e-300 of a real pass per simulated pass: rates of inf.
        (
            vec!["growth.passes_per_pass=1e-300"],
            "growth.passes_per_pass",
        ),
    ];
    for (k, (sets, key)) in cases.iter().enumerate() {
        let out = dir.join(format!("out{k}"));
        let (code, err) = grow(&out, &["--passes", "1"], sets);
        assert!(!err.contains("triangle"), "{sets:?}: {err}");
        assert_one_line_error(code, &err, &[key, "polygon.toml"]);
        assert!(!out.exists(), "{sets:?}: {} was written", out.display());
    }
}

/// A checkpoint's profile is input: one the rim cannot carry is refused naming its field,
/// and the folder's files stay as they were.
#[test]
fn a_checkpoint_profile_the_rim_cannot_carry_is_refused_naming_its_field() {
    let dir = TestDir::new("hostile-growth", "checkpoint");
    let out = dir.join("out");
    let (code, err) = grow(&out, &["--passes", "1"], &[]);
    assert_eq!(code, 0, "{err}");
    let ck = out.join("checkpoint.json");
    let mut s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&ck).unwrap()).unwrap();
    // Every height times 1e6 (the profile is kept as each float's bits).
    let z: Vec<serde_json::Value> = s["passes"][0]["z"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| (f64::from_bits(b.as_u64().unwrap()) * 1e6).to_bits().into())
        .collect();
    s["passes"][0]["z"] = z.into();
    let edited = serde_json::to_string(&s).unwrap();
    std::fs::write(&ck, &edited).unwrap();
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let (code, err) = grow(&out, &["--passes", "2", "--resume"], &[]);
    assert!(!err.contains("triangle"), "{err}");
    assert_one_line_error(code, &err, &["checkpoint.json", "`passes[0].z`", "radius"]);
    assert_eq!(std::fs::read_to_string(&ck).unwrap(), edited);
    assert_eq!(
        std::fs::read_to_string(out.join("summary.json")).unwrap(),
        summary
    );
}

/// A study from a smooth surface (and a band or order the initial profile does not hold)
/// has no level and no rate there: empty cells, not `-inf` and `NaN`, and the study ends
/// with exit 0 and its summary.
#[test]
fn a_study_from_a_smooth_surface_writes_empty_cells_not_nan() {
    let dir = TestDir::new("hostile-growth", "smooth");
    let out = dir.join("smooth");
    let (code, err) = grow(&out, &["--passes", "1"], SMOOTH);
    assert_eq!(code, 0, "{err}");
    assert_finite_tables(&out);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["passes"], 1, "{s}");
    assert_eq!(s["rms_initial_m"], 0.0, "{s}");
    // One order of a harmonic (a negative amplitude: the phase turned): the other bands
    // and orders hold nothing.
    let out = dir.join("harmonic");
    let sets: Vec<&str> = HARMONIC
        .iter()
        .copied()
        .chain(["growth.amplitude=-1e-6", "growth.wavelength=0.0785"])
        .collect();
    let (code, err) = grow(&out, &["--passes", "1"], &sets);
    assert_eq!(code, 0, "{err}");
    assert_finite_tables(&out);
    let orders = std::fs::read_to_string(out.join("orders.csv")).unwrap();
    // Order 8 (0.628 m / 0.0785 m) holds the harmonic and has a rate; order 3 has none.
    let rate = |order: &str| -> String {
        let row = orders
            .lines()
            .find(|l| l.split(',').next() == Some(order))
            .unwrap();
        row.split(',').nth_back(1).unwrap().to_string()
    };
    assert!(
        rate("8").parse::<f64>().is_ok_and(f64::is_finite),
        "{orders}"
    );
    assert_eq!(rate("3"), "", "{orders}");
}

/// A roughness CSV without a header keeps its first row (it was always dropped as one);
/// with a header, the same profile.
#[test]
fn a_roughness_csv_without_a_header_keeps_its_first_row() {
    let dir = TestDir::new("hostile-growth", "csv");
    // A bump at x = 0 only, on the rim's own samples (96 on 0.6283 m).
    let dx = 2.0 * std::f64::consts::PI * 0.1 / 96.0;
    let rows: String = (0..96)
        .map(|i| format!("{},{}\n", i as f64 * dx, if i == 0 { 2e-6 } else { 0.0 }))
        .collect();
    for (name, text) in [
        ("bare", rows.clone()),
        ("header", format!("x_m,z_m\n{rows}")),
    ] {
        let csv = dir.join(format!("{name}.csv"));
        std::fs::write(&csv, &text).unwrap();
        let out = dir.join(name);
        let file = format!("growth.file=\"{}\"", csv.display());
        let sets: Vec<&str> = [
            "growth.roughness=\"csv\"",
            "growth.level=",
            "growth.min_wavelength=",
            "growth.max_wavelength=",
            "growth.seed=",
            &file,
        ]
        .to_vec();
        let (code, err) = grow(&out, &["--passes", "1"], &sets);
        assert_eq!(code, 0, "{name}: {err}");
        let profile = std::fs::read_to_string(out.join("profile.csv")).unwrap();
        let z0: f64 = profile
            .lines()
            .nth(1)
            .unwrap()
            .split(',')
            .nth(1)
            .unwrap()
            .parse()
            .unwrap();
        assert!(
            (z0 - 2e-6).abs() < 1e-12,
            "{name}: z_initial at x = 0 is {z0}"
        );
    }
}

/// `softway grow scenarios/corrugation.toml` on a short track (30 bays, 2 recorded) with
/// `args` and `sets` into `out`.
fn grow_track(out: &Path, args: &[&str], sets: &[&str]) -> std::process::Command {
    let mut cmd = softway();
    cmd.arg("grow")
        .arg(scenario("corrugation.toml"))
        .args(args)
        .args(["--threads", "1"]);
    for s in [
        "growth.reference=false",
        "track.bays=30",
        "track.end_bays=8",
        "vehicle.travel_bays=2",
        "vehicle.wheel_rim_nodes=360",
    ]
    .iter()
    .chain(sets)
    {
        cmd.args(["--set", s]);
    }
    cmd.arg("--out").arg(out);
    cmd
}

#[test]
fn the_rail_grid_and_spectrum_are_refused_by_their_keys_at_once() {
    let dir = TestDir::new("hostile-growth", "rail");
    for (k, (set, key)) in [
        // 1.2e9 samples: ran for ever.
        ("growth.dx=1e-9", "growth.dx"),
        // The spectrum's sampling (2e7 samples) and stretch: refused naming neither.
        ("growth.min_wavelength=1e-6", "growth.min_wavelength"),
        ("growth.max_wavelength=100.0", "growth.max_wavelength"),
    ]
    .into_iter()
    .enumerate()
    {
        let out = dir.join(format!("out{k}"));
        let start = Instant::now();
        let o = grow_track(&out, &["--passes", "1"], &[set])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_one_line_error(
            o.status.code().unwrap_or(-1),
            &err,
            &[key, "corrugation.toml"],
        );
        assert!(
            start.elapsed() < Duration::from_secs(20),
            "{set}: {:?}",
            start.elapsed()
        );
        assert!(!out.exists(), "{set}: {} written", out.display());
    }
}

/// The rail's study stopped by SIGTERM during a pass ends as interrupted (exit 130, the
/// finished passes kept), not with "error: interrupted" (exit 2), and `--resume` finishes
/// it.
#[test]
fn an_interrupted_rail_study_ends_as_interrupted_and_resumes() {
    let dir = TestDir::new("hostile-growth", "rail-sigterm");
    let out = dir.join("out");
    let child = grow_track(&out, &["--passes", "3"], &[])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Wait for the first pass's checkpoint, then stop the second pass.
    let ck = out.join("checkpoint.json");
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(120) {
        let passes = std::fs::read_to_string(&ck)
            .ok()
            .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
            .and_then(|s| s["passes"].as_array().map(Vec::len));
        if passes.is_some_and(|n| n >= 1) {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(300));
    assert!(std::process::Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap()
        .success());
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("error"), "{err}");
    if o.status.code() == Some(0) {
        // The study finished before the signal (a fast machine): nothing to check.
        return;
    }
    assert_eq!(o.status.code(), Some(130), "{err}");
    let o = grow_track(&out, &["--passes", "3", "--resume"], &[])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        (s["passes"].as_u64(), &s["interrupted"]),
        (Some(3), &false.into()),
        "{s}"
    );
}

/// The mutation campaign's case 10076: a plastic wheel on a hub of 0.7 um (a point at the
/// centre) took over two minutes a growth pass in its plastic iterations, where the
/// estimate said seconds. A plastic wheel's hub below a thousandth of its radius is refused
/// by `wheel.hub_radius` before anything is written, by `grow` and by `run`; the shipped
/// plastic study's own hub (a tenth of the radius) runs.
#[test]
fn a_point_like_hub_under_a_plastic_wheel_is_refused_by_its_key() {
    let dir = TestDir::new("hostile-growth", "point-hub");
    let plastic = scenario("polygon-plastic.toml");
    for command in ["grow", "run"] {
        let out = dir.join(command);
        let o = softway()
            .arg(command)
            .arg(&plastic)
            .args(["--set", "wheel.hub_radius=7.1e-7", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_one_line_error(
            o.status.code().unwrap_or(-1),
            &err,
            &["wheel.hub_radius", "polygon-plastic.toml", "thousandth"],
        );
        assert!(!out.exists(), "{command}: {} was written", out.display());
    }
}
