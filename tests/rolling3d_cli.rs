//! `kind = "rolling3d"` through the command line (`scenarios/rolling3d.toml`): the 3D wheel
//! rolling on its base as a user runs it (`softway run`, `softway sweep`).
//!
//! What is checked against an answer the code does not compute:
//! - **full slip** at 20 % creepage, 30 degrees off the rolling direction: Coulomb's cone
//!   makes the creep forces' resultant `mu N` (within 1 %), the longitudinal force drives
//!   the wheel (`Q > 0` for `xi > 0`, the sign a wheel turning faster than it rolls must
//!   get) and the lateral force opposes the lateral slip;
//! - **the mirror**: `eta -> -eta` reverses `Q_y` and the spin moment and keeps `N` and `Q`
//!   (to 1e-6);
//! - **the summary against the history**: the steady figures are the means of
//!   `history.csv`'s rows over the last half of the rolling;
//! - **bad input** refused on one line naming the key, nothing written (the refined
//!   zone's keys and the crown among them).
//!
//! The library's `tests/rolling3d.rs` checks the normal force against the 2D wheel.

mod common;

use common::{assert_one_line_error, cli, fresh_dir, run_err};
use std::path::Path;

const MU: f64 = 0.3;

/// Runs the shipped scenario with `sets` into `out`; returns its summary.
fn run(out: &Path, sets: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "run".to_string(),
        "scenarios/rolling3d.toml".into(),
        "--out".into(),
        out.display().to_string(),
        "--force".into(),
        "--quiet".into(),
    ];
    for s in sets {
        args.push("--set".into());
        args.push(s.to_string());
    }
    let o = cli(&args);
    assert_eq!(o.code, 0, "{}", o.stderr);
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

fn num(v: &serde_json::Value, path: &str) -> f64 {
    v.pointer(path)
        .and_then(|x| x.as_f64())
        .unwrap_or_else(|| panic!("{path} missing from {v}"))
}

#[test]
fn full_slip_and_the_mirror_through_the_command_line() {
    let dir = fresh_dir("rolling3d", "full-slip");
    let c = 0.2_f64;
    let angle = 30_f64.to_radians();
    let (xi, eta) = (c * angle.cos(), c * angle.sin());
    let set_xi = format!("rolling.creepage={xi}");
    let mut summaries = Vec::new();
    for (k, e) in [eta, -eta].into_iter().enumerate() {
        let set_eta = format!("rolling.lateral_creepage={e}");
        let out = dir.join(format!("run{k}"));
        let s = run(&out, &[&set_xi, &set_eta, "rolling.turns=0.4"]);
        // The summary's steady figures are the history's last half of the rolling.
        let text = std::fs::read_to_string(out.join("history.csv")).unwrap();
        let mut lines = text.lines();
        let head: Vec<&str> = lines.next().unwrap().split(',').collect();
        let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
        let (ct, cn, cq) = (col("t_s"), col("normal_force_N"), col("creep_force_N"));
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').skip(1).map(|x| x.parse().unwrap()).collect())
            .map(|r: Vec<f64>| {
                let mut full = vec![0.0];
                full.extend(r);
                full
            })
            .filter(|r| r[ct] >= num(&s, "/steady/from_s"))
            .collect();
        let half = &rows[rows.len() / 2..];
        let mean = |c: usize| half.iter().map(|r| r[c]).sum::<f64>() / half.len() as f64;
        let (n, q) = (
            num(&s, "/steady/normal_force_N"),
            num(&s, "/steady/creep_force_N"),
        );
        assert!((mean(cn) / n - 1.0).abs() < 1e-9, "{} {n}", mean(cn));
        assert!((mean(cq) / q - 1.0).abs() < 1e-9, "{} {q}", mean(cq));
        summaries.push(s);
    }
    let s = &summaries[0];
    let (n, q, qy) = (
        num(s, "/steady/normal_force_N"),
        num(s, "/steady/creep_force_N"),
        num(s, "/steady/lateral_force_N"),
    );
    let ratio = q.hypot(qy) / (MU * n);
    println!(
        "full slip at ({xi:.4}, {eta:.4}): N = {n:.1} N, Q = {q:.1} N, Q_y = {qy:.1} N, |F|/(mu N) = {ratio:.5}, M_z = {:.4} N m",
        num(s, "/steady/spin_moment_N_m")
    );
    assert!(n > 1e5, "{n}");
    assert!((ratio - 1.0).abs() < 0.01, "{ratio}");
    assert!(q > 0.0 && qy < 0.0, "Q = {q}, Q_y = {qy}");
    assert_eq!(s["steady"]["reached"], true, "{s}");
    let b = &summaries[1];
    for (key, sign) in [
        ("/steady/normal_force_N", 1.0),
        ("/steady/creep_force_N", 1.0),
        ("/steady/lateral_force_N", -1.0),
    ] {
        let (x, y) = (num(s, key), num(b, key));
        assert!((sign * y / x - 1.0).abs() < 1e-6, "{key}: {x} against {y}");
    }
    let (m1, m2) = (
        num(s, "/steady/spin_moment_N_m"),
        num(b, "/steady/spin_moment_N_m"),
    );
    assert!((m1 + m2).abs() <= 1e-6 * m1.abs().max(1e-3), "{m1} {m2}");
    // The traction figures the sweep's creep curve reads.
    assert!((num(s, "/traction/traction_ratio") - q / (MU * n)).abs() < 1e-12);
    assert!(num(s, "/traction/hertz_half_width") > 0.0);
}

#[test]
fn bad_input_is_refused_by_its_key() {
    let base = std::fs::read_to_string("scenarios/rolling3d.toml").unwrap();
    let with = |from: &str, to: &str| {
        assert!(base.contains(from), "{from}");
        base.replacen(from, to, 1)
    };
    for (name, text, key) in [
        (
            "mesh",
            with("mesh = [12, 192, 1]", "mesh = [0, 192, 1]"),
            "wheel.mesh",
        ),
        (
            "bore",
            with("bore_m = 0.04", "bore_m = 0.2"),
            "wheel.bore_m",
        ),
        (
            "turns",
            with("h = 1e-5", "h = 1e-5\nt_end = 0.01"),
            "time.t_end",
        ),
        (
            "integrator",
            with("h = 1e-5", "h = 1e-5\nintegrator = \"newmark\""),
            "time.integrator",
        ),
        (
            "creepage",
            with("creepage = 0.005", "creepage = 2.0"),
            "rolling.creepage",
        ),
        (
            "key",
            with("omega = 300.0", "omega = 300.0\nspeed = 3.0"),
            "speed",
        ),
        (
            "zone-sectors",
            with("poisson = 0.3", "poisson = 0.3\nzone_sectors = 1000"),
            "wheel.zone_sectors",
        ),
        (
            "zone-alone",
            with("poisson = 0.3", "poisson = 0.3\nzone_deg = 20.0"),
            "wheel.zone_deg",
        ),
        (
            "zone-wide",
            with(
                "poisson = 0.3",
                "poisson = 0.3\nzone_sectors = 768\nzone_deg = 170.0",
            ),
            "wheel.zone_deg",
        ),
        (
            "zone-cyclic",
            with(
                "poisson = 0.3",
                "poisson = 0.3\nzone_sectors = 768\ncyclic_columns = true",
            ),
            "wheel.cyclic_columns",
        ),
        (
            "axial-alone",
            with("poisson = 0.3", "poisson = 0.3\nzone_axial_mm = 2.0"),
            "wheel.zone_axial_mm",
        ),
        (
            "axial-wide",
            with(
                "poisson = 0.3",
                "poisson = 0.3\nzone_sectors = 768\nzone_axial_mm = 5.0",
            ),
            "wheel.zone_axial_mm",
        ),
        (
            "crown",
            with(
                "creepage = 0.005",
                "creepage = 0.005\ncrown_radius_m = 0.002",
            ),
            "rolling.crown_radius_m",
        ),
        (
            "coupling",
            with("creepage = 0.005", "creepage = 0.005\ncoupling = \"half\""),
            "rolling.coupling",
        ),
        (
            "coupling-frictionless",
            with(
                "creepage = 0.005",
                "creepage = 0.005\ncoupling = \"uncoupled\"",
            )
            .replacen("friction = 0.3", "friction = 0.0", 1),
            "rolling.coupling",
        ),
    ] {
        let (code, err) = run_err(&format!("rolling3d-{name}"), &text);
        assert_one_line_error(code, &err, &[key]);
    }
}

/// The wide wheel on a crowned base (`rolling.crown_radius_m`, the zone graded across the
/// width by `wheel.zone_axial_mm`), a coarse first rung: 10,416 unknowns, the patch about 1.5
/// zone pitches in semi-axis. The patch is Hertz's circle of the wheel's and the crown's
/// equal radii: its semi-axes from the nodal forces' second moments within 10 % of Hertz's
/// at the steady normal force (measured +7.6 % along the rolling, +5.2 % across), its
/// aspect within 5 % of 1 (measured 0.977); the mirror `eta -> -eta` reverses the lateral
/// force and the spin moment and keeps the rest (measured to 1e-13): the layers are graded
/// symmetrically about the crown's crest and every node's forces are taken on its own
/// normal.
#[test]
fn a_crowned_base_gives_hertz_circle_and_the_mirror() {
    let dir = fresh_dir("rolling3d", "crown");
    let common = [
        "wheel.thickness_m=0.02",
        "wheel.mesh=[4,48,2]",
        "wheel.cyclic_columns=false",
        "wheel.zone_sectors=192",
        "wheel.zone_deg=24",
        "wheel.zone_axial_mm=4",
        "wheel.zone_depth_mm=4",
        "wheel.zone_growth=1.4",
        "rolling.crown_radius_m=0.1",
        "rolling.flattening_mm=0.3",
        "rolling.settle_ms=1",
        "rolling.turns=0.2",
        "rolling.creepage=0",
        "time.h=2e-5",
        "time.coriolis=extrapolated",
    ];
    let runs: Vec<serde_json::Value> = ["0.002", "-0.002"]
        .iter()
        .enumerate()
        .map(|(k, eta)| {
            let set = format!("rolling.lateral_creepage={eta}");
            let mut sets: Vec<&str> = common.to_vec();
            sets.push(&set);
            run(&dir.join(format!("run{k}")), &sets)
        })
        .collect();
    let s = &runs[0];
    let (a, b) = (
        num(s, "/hertz3d/a_rolling_m"),
        num(s, "/hertz3d/b_lateral_m"),
    );
    let (ma, mb) = (
        num(s, "/hertz3d/measured_a_rolling_m"),
        num(s, "/hertz3d/measured_b_lateral_m"),
    );
    println!(
        "crowned base: N = {:.1} kN; Hertz a = {:.3} mm, b = {:.3} mm; measured {:.3} mm ({:+.1} %), {:.3} mm ({:+.1} %)",
        1e-3 * num(s, "/steady/normal_force_N"),
        1e3 * a,
        1e3 * b,
        1e3 * ma,
        100.0 * (ma / a - 1.0),
        1e3 * mb,
        100.0 * (mb / b - 1.0)
    );
    assert!((a / b - 1.0).abs() < 1e-3, "{a} {b}");
    assert!((ma / a - 1.0).abs() < 0.1, "{ma} against {a}");
    assert!((mb / b - 1.0).abs() < 0.1, "{mb} against {b}");
    assert!((mb / ma - 1.0).abs() < 0.05, "{mb} / {ma}");
    let m = &runs[1];
    for (key, sign) in [
        ("/steady/normal_force_N", 1.0),
        ("/steady/creep_force_N", 1.0),
        ("/steady/lateral_force_N", -1.0),
        ("/steady/spin_moment_N_m", -1.0),
    ] {
        let (x, y) = (num(s, key), num(m, key));
        assert!((sign * y / x - 1.0).abs() < 1e-9, "{key}: {x} against {y}");
    }
    assert!(num(s, "/steady/lateral_force_N") < 0.0, "{s}");
}

/// The reference curve of another code (`rolling.reference_curve`,
/// `validation/halfspace3d/rolling3d_reference.csv`: the coupled half-space answer) through
/// `softway sweep` of the shipped 3D creep scenario on two coarse rungs: each run's summary
/// carries the reference's traction ratio at the run's creepage (on the undeformed radius, in
/// `mu a / R`), and the ladder's table gives the reference's creepages at `Q/(mu N)` = -0.5 /
/// 0 / +0.5. Both are checked against the file read here and interpolated linearly (the
/// sweep's roots use a parabola through three of the curve's points: within 4e-3 of the
/// line's on this curve, measured 2.6e-3 at +0.5), the creepage's unit against Hertz's semi-axis and the radius in the
/// summary. A reference file that is not a curve is refused by its key.
#[test]
fn a_creep_sweep_is_measured_against_the_reference_curve() {
    let text = std::fs::read_to_string("validation/halfspace3d/rolling3d_reference.csv").unwrap();
    let pts: Vec<(f64, f64)> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("creepage"))
        .map(|l| {
            let mut c = l.split(',').map(|v| v.parse::<f64>().unwrap());
            (c.next().unwrap(), c.next().unwrap())
        })
        .collect();
    let at = |x: f64| {
        let k = pts
            .windows(2)
            .position(|w| w[0].0 <= x && x <= w[1].0)
            .unwrap();
        let ((x0, y0), (x1, y1)) = (pts[k], pts[k + 1]);
        y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    };
    let root = |y: f64| {
        let k = pts
            .windows(2)
            .position(|w| (w[0].1 - y) * (w[1].1 - y) <= 0.0)
            .unwrap();
        let ((x0, y0), (x1, y1)) = (pts[k], pts[k + 1]);
        x0 + (y - y0) * (x1 - x0) / (y1 - y0)
    };
    let out = fresh_dir("rolling3d", "creep-reference");
    let o = cli([
        "sweep",
        "scenarios/rolling3d-creep.toml",
        "--set",
        "rolling.creepage=0,0.003",
        "--set",
        "wheel.zone_sectors=192,384",
        "--set",
        "time.h=1e-5",
        "--out",
        out.to_str().unwrap(),
        "--force",
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let mut runs = 0;
    for e in std::fs::read_dir(&out).unwrap() {
        let f = e.unwrap().path().join("summary.json");
        if !f.exists() {
            continue;
        }
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&f).unwrap()).unwrap();
        let unit = num(&s, "/traction/friction") * num(&s, "/traction/hertz_half_width")
            / num(&s, "/traction/radius");
        let x = num(&s, "/traction/reference/creepage_of_run_mu_a_R");
        assert!(
            (x - num(&s, "/traction/creepage_undeformed") / unit).abs() < 1e-12,
            "{s}"
        );
        let y = num(&s, "/traction/reference/traction_ratio_at_run");
        assert!((y - at(x)).abs() < 1e-12, "{x}: {y} against {}", at(x));
        runs += 1;
    }
    assert_eq!(runs, 4);
    let csv = std::fs::read_to_string(out.join("creep_ladder.csv")).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = head.iter().position(|c| *c == "reference_mu_a_R").unwrap();
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        let target: f64 = cells[0].parse().unwrap();
        let r: f64 = cells[col].parse().unwrap();
        assert!(
            (r - root(target)).abs() < 4e-3,
            "{target}: {r} against {}",
            root(target)
        );
    }
    let md = std::fs::read_to_string(out.join("creep_ladder.md")).unwrap();
    assert!(md.contains("reference (rolling3d_reference.csv)"), "{md}");
    // The slope at free rolling: on two points a rung the interpolant is their line, so
    // the slope is the chord's, in mu a / R; as Kalker's C, times N R / (a G c^2).
    let pts_csv = std::fs::read_to_string(out.join("creep_curve.csv")).unwrap();
    let rows: Vec<Vec<f64>> = pts_csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
        .collect();
    let slope_line = md
        .lines()
        .find(|l| l.starts_with("| slope |"))
        .unwrap_or_else(|| panic!("{md}"));
    let cells: Vec<&str> = slope_line.split('|').map(str::trim).collect();
    for (k, rung) in [192.0, 384.0].iter().enumerate() {
        let c: Vec<&Vec<f64>> = rows.iter().filter(|r| r[0] == *rung).collect();
        let chord = (c[1][4] - c[0][4]) / (c[1][3] - c[0][3]);
        let got: f64 = cells[2 + k].parse().unwrap();
        assert!(
            (got - chord).abs() < 2e-4 * chord.abs() + 1e-4,
            "{rung}: {got} against {chord}"
        );
    }
    let c_line = md.lines().find(|l| l.starts_with("| C |")).unwrap();
    let c_finest: f64 = c_line
        .split('|')
        .map(str::trim)
        .nth(3)
        .unwrap()
        .parse()
        .unwrap();
    assert!(c_finest > 0.0 && c_finest.is_finite(), "{c_line}");
    assert!(out.join("creep_curve.png").exists());

    let base = std::fs::read_to_string("scenarios/rolling3d-creep.toml").unwrap();
    for (name, file, why) in [
        ("missing", "no-such-file.csv", "could not be read"),
        (
            "not-a-curve",
            "rolling3d-reference-not-a-curve.toml",
            "no column creepage_mu_a_R",
        ),
    ] {
        let text = base.replacen(
            "reference_curve = \"../validation/halfspace3d/rolling3d_reference.csv\"",
            &format!("reference_curve = \"{file}\""),
            1,
        );
        let (code, err) = run_err(&format!("rolling3d-reference-{name}"), &text);
        assert_one_line_error(code, &err, &["rolling.reference_curve", why]);
    }
}

/// Braking may only push, also when several pairs brake at once: a brake whose impulse
/// comes out tensile is taken off, and the interval is solved again until no brake pulls
/// (taking one brake off changes the others' impulses). With one pass, the creep scenario's
/// middle rung (50,184 unknowns, 3 zone pitches a semi-axis) at `h = 1e-5` (2.7 steps to a
/// rim node's passage) ended step 208 with a brake pulling 0.61 N, and the divergence guard
/// stopped the run. It now runs to its end, brakes on the way, and reaches its steady
/// state.
#[test]
fn brakes_taken_together_never_pull() {
    let dir = fresh_dir("rolling3d", "brakes");
    let o = cli([
        "run",
        "scenarios/rolling3d-creep.toml",
        "--set",
        "time.h=1e-5",
        "--out",
        dir.to_str().unwrap(),
        "--force",
        "--quiet",
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert!(num(&s, "/counters/brakings") > 0.0, "{s}");
    assert_eq!(s.pointer("/steady/reached"), Some(&serde_json::json!(true)));
}

/// Reads a run's `summary.json` in `dir`.
fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// The creep forces at speed (`scenarios/rolling3d-speed.toml`, `softway sweep` over
/// `rolling.speed_km_h`). Rolled in the same steps of distance (`rolling.step_mm`,
/// `settle_mm`), the rotating frame's inertial terms (the mass's, the Coriolis term, the
/// spin's softening and prestress) all grow as `rho V^2`, against the stiffness `E`: what
/// speed changes depends on `rho V^2 / E` alone. Checked on a coarse rung with the wheel's
/// modulus divided by 100 (300 km/h is then the real wheel's 3,000 km/h, `V / c_s` = 0.26):
/// - **the similarity**: `E / 4` at 150 km/h gives the forces of `E` at 300 km/h, `N` a
///   quarter and `Q / (mu N)` the same (to 1e-12: the same discrete problem scaled by
///   powers of two, so the same contact decisions), which fails if a term or a key does
///   not scale as the physics does (a tolerance in absolute units, a ramp in time);
/// - **inertia is there**: 300 km/h raises `N` by more than a percent over 5 km/h at the
///   same flattening (measured +2.7 %; the spun rim's stress stiffening and the mass);
/// - `speed_effect.csv` gives each change as the summaries' difference.
#[test]
fn inertia_scales_as_rho_v_squared() {
    let out = fresh_dir("rolling3d", "speed");
    let coarse = [
        "--set",
        "wheel.zone_sectors=192",
        "--set",
        "rolling.step_mm=0.6",
        "--set",
        "rolling.turns=0.12",
    ];
    let mut args = vec![
        "sweep",
        "scenarios/rolling3d-speed.toml",
        "--set",
        "wheel.young_GPa=2.05",
        "--set",
        "rolling.speed_km_h=5,300",
        "--out",
        out.to_str().unwrap(),
        "--force",
    ];
    args.extend(coarse);
    let o = cli(&args);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let point = |v: &str| {
        let tag = format!("rolling.speed_km_h={v},");
        let dir = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().path())
            .find(|p| p.is_dir() && p.to_string_lossy().contains(&tag))
            .unwrap_or_else(|| panic!("no point {tag} in {}", out.display()));
        summary(&dir)
    };
    let (s5, s300) = (point("5"), point("300"));
    let q = |s: &serde_json::Value| num(s, "/traction/traction_ratio_steady");
    let n = |s: &serde_json::Value| num(s, "/traction/normal");
    eprintln!(
        "E / 100: Q/(mu N) {:.5} / {:.5} and N {:.2} / {:.2} N at 5 / 300 km/h",
        q(&s5),
        q(&s300),
        n(&s5),
        n(&s300)
    );
    assert!(n(&s300) / n(&s5) - 1.0 > 1e-2, "{} {}", n(&s300), n(&s5));

    let similar = fresh_dir("rolling3d", "speed-similar");
    let mut args = vec![
        "run",
        "scenarios/rolling3d-speed.toml",
        "--set",
        "wheel.young_GPa=0.5125",
        "--set",
        "rolling.speed_km_h=150",
        "--out",
        similar.to_str().unwrap(),
        "--force",
        "--quiet",
    ];
    args.extend(coarse);
    let o = cli(&args);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let s = summary(&similar);
    for k in ["/steady/traction_ratio", "/traction/traction_ratio_steady"] {
        assert!(
            (num(&s, k) - num(&s300, k)).abs() < 1e-12,
            "{k}: {s} against {s300}"
        );
    }
    let rel = n(&s) / n(&s300);
    assert!((rel - 0.25).abs() < 1e-12, "{rel}");

    let csv = std::fs::read_to_string(out.join("speed_effect.csv")).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|c| *c == name).unwrap();
    let (vc, dc) = (col("speed_km_h"), col("traction_ratio_change"));
    let rows: Vec<(f64, f64)> = lines
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (c[vc].parse().unwrap(), c[dc].parse().unwrap())
        })
        .collect();
    assert_eq!(rows.len(), 2);
    for (v, d) in rows {
        let want = [(5.0, &s5), (300.0, &s300)]
            .iter()
            .find(|w| (w.0 - v).abs() < 1e-9)
            .map(|w| q(w.1) - q(&s5))
            .unwrap();
        assert!((d - want).abs() < 1e-12, "{v}: {d} against {want}");
    }
    assert!(out.join("speed_effect.md").exists() && out.join("speed_effect.png").exists());
}

/// Kalker's coefficients through `softway sweep` of `scenarios/rolling3d-kalker.toml` (the
/// pair of one material: `rolling.coupling = "uncoupled"`, a twin wheel carrying the
/// tangential tractions; full adhesion at `mu = 10`), on the coarse rung of the crowned test
/// (192 sectors at the zone's pitch, a = 5 mm: 1.5 pitches a semi-axis, 20,832 unknowns with
/// the twin), over five points of `(xi, eta)` taken together (`--grid zip`). Checked:
/// - **the mirror**: `eta -> -eta` keeps `N` and `Q` and reverses `Q_y` and `M_z` (to 1e-9),
///   the twin and its split pairs included;
/// - **the normal problem does not see the creepages**: `N` is the same at every point
///   within 1e-3 (the gap reads the wheel, the slip the twin);
/// - **linear in full adhesion**: the fit of the forces over the five points leaves less
///   than 1 % of their range (measured 6e-4), and `C_11` in `kalker.csv` is the two-point
///   slope `(Q(+xi) - Q(-xi)) / (2 xi G c^2)` computed here from the summaries (within
///   1 %);
/// - **Kalker's table at nu = 0.25, a/b = 1** (4.12, 3.67, 1.47) in `kalker.md`, and `C_11`
///   within 15 % of it on this rung (measured +10.7 %; the ladder of the book converges).
#[test]
fn kalker_coefficients_of_the_twin_wheel() {
    let out = fresh_dir("rolling3d", "kalker");
    let d = 5e-4;
    let pts = [(d, 0.0), (-d, 0.0), (0.0, d), (0.0, -d), (d, d)];
    let list = |f: &dyn Fn(&(f64, f64)) -> f64| {
        pts.iter()
            .map(|p| format!("{}", f(p)))
            .collect::<Vec<_>>()
            .join(",")
    };
    let xi = format!("rolling.creepage={}", list(&|p| p.0));
    let eta = format!("rolling.lateral_creepage={}", list(&|p| p.1));
    let mut args: Vec<String> = vec![
        "sweep".into(),
        "scenarios/rolling3d-kalker.toml".into(),
        "--grid".into(),
        "zip".into(),
        "--out".into(),
        out.display().to_string(),
        "--force".into(),
    ];
    for s in [
        "wheel.zone_sectors=192",
        "wheel.zone_deg=24",
        "wheel.zone_axial_mm=4",
        "wheel.zone_depth_mm=4",
        "rolling.flattening_mm=0.3",
        "rolling.turns=0.2",
        "time.h=2e-5",
        &xi,
        &eta,
    ] {
        args.push("--set".into());
        args.push(s.to_string());
    }
    let o = cli(&args);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let mut runs: Vec<serde_json::Value> = Vec::new();
    for entry in std::fs::read_dir(&out).unwrap() {
        let dir = entry.unwrap().path();
        if dir.join("summary.json").exists() {
            runs.push(summary(&dir));
        }
    }
    assert_eq!(runs.len(), pts.len());
    let at = |x: f64, e: f64| {
        runs.iter()
            .find(|s| num(s, "/creepages/longitudinal") == x && num(s, "/creepages/lateral") == e)
            .unwrap_or_else(|| panic!("no run at ({x}, {e})"))
    };
    for s in &runs {
        assert_eq!(s["coupling"], "uncoupled");
    }
    let (up, down) = (at(0.0, d), at(0.0, -d));
    for (key, sign) in [
        ("/steady/normal_force_N", 1.0),
        ("/steady/creep_force_N", 1.0),
        ("/steady/lateral_force_N", -1.0),
        ("/steady/spin_moment_N_m", -1.0),
    ] {
        let (x, y) = (num(up, key), num(down, key));
        assert!((sign * y / x - 1.0).abs() < 1e-9, "{key}: {x} against {y}");
    }
    let n0 = num(&runs[0], "/steady/normal_force_N");
    for s in &runs {
        let n = num(s, "/steady/normal_force_N");
        assert!((n / n0 - 1.0).abs() < 1e-3, "N = {n} against {n0}");
    }
    let (p, m) = (at(d, 0.0), at(-d, 0.0));
    let scale = num(p, "/hertz3d/combined_shear_modulus_Pa") * num(p, "/hertz3d/c_m").powi(2);
    let two_point =
        (num(p, "/steady/creep_force_N") - num(m, "/steady/creep_force_N")) / (2.0 * d * scale);
    let csv = std::fs::read_to_string(out.join("kalker.csv")).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<String>> = lines
        .map(|l| {
            // The coefficient's name may be quoted with a comma inside.
            let (name, rest) = if let Some(r) = l.strip_prefix('"') {
                let end = r.find('"').unwrap();
                (r[..end].to_string(), &r[end + 2..])
            } else {
                let end = l.find(',').unwrap();
                (l[..end].to_string(), &l[end + 1..])
            };
            std::iter::once(name)
                .chain(rest.split(',').map(str::to_string))
                .collect()
        })
        .collect();
    let c11 = rows.iter().find(|r| r[0] == "C11").unwrap();
    let v: f64 = c11[col("value")].parse().unwrap();
    let table: f64 = c11[col("kalker_table")].parse().unwrap();
    let residual: f64 = c11[col("fit_residual")].parse().unwrap();
    println!("twin wheel, coarse rung: C11 = {v:.4} (two points {two_point:.4}), table {table}");
    assert!(
        (v / two_point - 1.0).abs() < 0.01,
        "{v} against {two_point}"
    );
    assert!(residual < 0.01, "{residual}");
    assert!((table - 4.12).abs() < 1e-3, "{table}");
    assert!((v / table - 1.0).abs() < 0.15, "{v} against {table}");
    for k in ["C22", "C23 (M_z, eta)"] {
        let r = rows.iter().find(|r| r[0] == k).unwrap();
        let c: f64 = r[col("value")].parse().unwrap();
        assert!(c > 0.0, "{k} = {c}: Kalker's sign");
    }
    let md = std::fs::read_to_string(out.join("kalker.md")).unwrap();
    assert!(
        md.contains("| Kalker's table | | | 4.120 | 3.670 | 1.470 |"),
        "{md}"
    );
    assert!(!md.contains("Not the table's problem"), "{md}");
}

/// `softway sweep` of the falling-friction scenario over the zone's pitch (a coarse ladder,
/// a = 5 mm, 96 to 384 sectors) writes `slip_history.md`, `.csv` and `.png`, and each point's
/// figures hold against what the runs' histories and the rim's geometry say:
/// - **the ripple's frequency** is the rim pitch's passage through the patch, `omega sectors
///   / (2 pi)`, or a harmonic of it (within 3 %): the forces' ripple is the discrete rim's,
///   periodic at the passage;
/// - **it falls under refinement**, rung by rung;
/// - **`Q / (mu_s N)` and the ripple** are the mean and the RMS about it of `history.csv`'s
///   last half of the rolling, recomputed here (1e-9);
/// - the slip share lies in [0, 1] and `Q <= mu_s N`; the summary names the law and its
///   memory.
#[test]
fn falling_friction_refinement_sweep_writes_the_slip_history() {
    let out = fresh_dir("rolling3d", "falling-sweep");
    let mut args: Vec<String> = vec![
        "sweep".into(),
        "scenarios/rolling3d-falling.toml".into(),
        "--out".into(),
        out.display().to_string(),
        "--force".into(),
    ];
    for s in [
        "wheel.zone_sectors=96,192,384",
        "time.h=1e-5",
        "rolling.flattening_mm=0.3",
        "wheel.zone_deg=24",
        "wheel.zone_axial_mm=4",
        "wheel.zone_depth_mm=4",
        "rolling.turns=0.2",
    ] {
        args.push("--set".into());
        args.push(s.to_string());
    }
    let o = cli(&args);
    assert_eq!(o.code, 0, "{}", o.stderr);
    for f in ["slip_history.md", "slip_history.csv", "slip_history.png"] {
        assert!(out.join(f).exists(), "{f} missing");
    }
    let md = std::fs::read_to_string(out.join("slip_history.md")).unwrap();
    assert!(
        md.contains("the mesh at h = 10 us") && md.contains("mu_k = 0.2"),
        "{md}"
    );
    let csv = std::fs::read_to_string(out.join("slip_history.csv")).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 3);
    let mut ripples = Vec::new();
    for r in &rows {
        let sectors = r[col("zone_sectors")];
        let dir = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().path())
            .find(|d| {
                d.file_name()
                    .unwrap()
                    .to_string_lossy()
                    .starts_with(&format!("wheel.zone_sectors={sectors},"))
            })
            .unwrap();
        let s = summary(&dir);
        assert_eq!(num(&s, "/friction_law/kinetic"), 0.2);
        assert_eq!(num(&s, "/friction_law/stribeck_velocity_m_s"), 0.02);
        let passage = num(&s, "/omega_rad_s") * sectors / std::f64::consts::TAU;
        let peak = r[col("ripple_peak_hz")];
        let harmonic = (peak / passage).round();
        assert!(
            harmonic >= 1.0 && (peak / (harmonic * passage) - 1.0).abs() < 0.03,
            "{sectors}: {peak} Hz against {passage}"
        );
        let share = r[col("slip_share")];
        assert!((0.0..=1.0).contains(&share), "{share}");
        // The steady figures from the history's last half of the rolling.
        let text = std::fs::read_to_string(dir.join("history.csv")).unwrap();
        let mut hl = text.lines();
        let hh: Vec<&str> = hl.next().unwrap().split(',').collect();
        let hc = |name: &str| hh.iter().position(|h| *h == name).unwrap();
        let (ct, cr) = (hc("t_s"), hc("traction_ratio"));
        let (cq, cn) = (hc("creep_force_N"), hc("normal_force_N"));
        let from = num(&s, "/steady/from_s");
        let rows: Vec<Vec<f64>> = hl
            .map(|l| {
                l.split(',')
                    .map(|x| x.parse::<f64>().unwrap_or(f64::NAN))
                    .collect::<Vec<_>>()
            })
            .filter(|r| r[ct] >= from)
            .collect();
        let half = &rows[rows.len() / 2..];
        let avg = |c: usize| half.iter().map(|r| r[c]).sum::<f64>() / half.len() as f64;
        // Q/(mu_s N): the means' ratio; the ripple: the RMS of each step's ratio.
        let mean = avg(cq) / (0.3 * avg(cn));
        let m = avg(cr);
        let rms =
            (half.iter().map(|r| (r[cr] - m).powi(2)).sum::<f64>() / half.len() as f64).sqrt();
        let q = r[col("traction_ratio")];
        assert!((q - mean).abs() < 1e-6 * q, "{q} against {mean}");
        assert!(q > 0.0 && q <= 1.0, "{q}");
        let ripple = r[col("traction_ratio_ripple")];
        assert!((ripple / rms - 1.0).abs() < 1e-3, "{ripple} against {rms}");
        println!("{sectors} sectors: Q/(mu_s N) = {q:.4}, slip share {share:.3}, ripple {ripple:.2e} at {peak:.0} Hz (passage {passage:.0} Hz)");
        ripples.push(ripple);
    }
    assert!(ripples.windows(2).all(|w| w[1] < w[0]), "{ripples:?}");
    the_cost_study_holds_against_the_summaries(&out);
}

/// A rolling 3D sweep's `cost.md`, `.csv` and `.png`, against its runs' summaries:
/// - **each run's `cost`** holds its invariants: the loop's step costs at least the free
///   solves it made (`step / free >= free solves a step`: the loop's time contains them),
///   a free step reads at least its factor (8 bytes an entry), a metre is `step / (V h)`;
/// - **the study's figures** are the summaries', and its floor is the free step's bytes
///   over the bandwidth the study measured and wrote (1e-9);
/// - the finer the zone, the more unknowns and the larger the factor.
fn the_cost_study_holds_against_the_summaries(out: &std::path::Path) {
    for f in ["cost.md", "cost.csv", "cost.png"] {
        assert!(out.join(f).exists(), "{f} missing");
    }
    let csv = std::fs::read_to_string(out.join("cost.csv")).unwrap();
    let mut lines = csv.lines();
    let head: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|h| h.trim_matches('"').to_string())
        .collect();
    let col = |name: &str| head.iter().position(|h| h == name).unwrap();
    let mut sizes = Vec::new();
    for line in lines {
        // The point's values (the first column, quoted) hold commas: the other cells are
        // read from the right.
        let mut cells: Vec<&str> = line.rsplitn(head.len(), ',').collect();
        cells.reverse();
        let get = |name: &str| cells[col(name)].trim_matches('"').parse::<f64>().unwrap();
        let dir = std::fs::read_dir(out)
            .unwrap()
            .map(|e| e.unwrap().path())
            .find(|d| {
                d.join("summary.json").exists() && summary(d)["dofs"].as_f64() == Some(get("dofs"))
            })
            .unwrap();
        let s = summary(&dir);
        let c = |k: &str| num(&s, &format!("/cost/{k}"));
        let step = c("step_s");
        let free = c("free_step_s");
        assert!(
            step / free >= c("free_solves_per_step") * (1.0 - 1e-12)
                && c("free_solves_per_step") >= 1.0,
            "{}: step {step} s against free {free} s and {} free solves a step",
            dir.display(),
            c("free_solves_per_step")
        );
        assert!(c("free_step_bytes") >= 8.0 * c("factor_nnz"));
        let metre = step / (num(&s, "/speed_m_s") * num(&s, "/h_s"));
        assert!((c("metre_s") / metre - 1.0).abs() < 1e-12);
        let floor_ms = 1e3 * c("free_step_bytes") / (1e9 * get("bandwidth_triad_GB_s"));
        assert!((get("floor_ms") / floor_ms - 1.0).abs() < 1e-9);
        assert!((get("step_ms") / (1e3 * step) - 1.0).abs() < 1e-9);
        assert!(
            (get("free_over_floor") - get("free_step_ms") / get("floor_ms")).abs()
                < 1e-9 * get("free_over_floor")
        );
        sizes.push((get("dofs"), c("factor_nnz")));
    }
    assert_eq!(sizes.len(), 3);
    sizes.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert!(
        sizes.windows(2).all(|w| w[1].0 > w[0].0 && w[1].1 > w[0].1),
        "{sizes:?}"
    );
    let md = std::fs::read_to_string(out.join("cost.md")).unwrap();
    assert!(md.contains("rolls a metre in"), "{md}");
}
