//! The 3D wheel rolling on an elastic rail of its own material (`scenarios/rolling3d-rail.toml`,
//! `[rail]`): two bodies met through the facet search, the rail's frame translating under the
//! wheel, the wheel's refined zone relocating round its rim.
//!
//! What is checked against an answer the code does not compute:
//! - **Kalker's pair of one material.** Two elastic bodies of one material decouple the
//!   normal and tangential problems; the twin wheel on the rigid crown
//!   (`scenarios/rolling3d-kalker.toml`, `rolling.coupling = "uncoupled"`) poses that pair
//!   by another construction (a second copy of the wheel carries the tangential tractions,
//!   `G = 2 G_1`). On the same wheel mesh, the coefficient `C11 = dF / (G c^2 d xi)` of the
//!   wheel on the rail (`G = G_1`, `c` Hertz's at half the modulus) agrees with the twin's;
//! - **Hertz's contact of two elastic bodies**: the patch's measured semi-axes (its
//!   pressure's second moments) against Hertz's circle at the run's normal force and half the
//!   modulus of one body on a rigid base, and Hertz's approach within the flattening that
//!   the rail's frame pushes (the rest is the bodies' global give);
//! - **the relocations**: the zone relocates round the rim with the rail's nodes left where
//!   they are, and the normal force keeps steady through them;
//! - **the UIC60 rail**: the patch's semi-axes against Hertz's ellipse of the rim's radius
//!   and the head's 0.3 m crest;
//! - **the bar closed on itself** (`rail.periodic`, the bar's default): its columns shifted
//!   from one station's (each checked at set-up against a solved one) for a fraction of
//!   the solves, and the forces of the open bar with free ends far from the patch;
//! - **the ring rolled over again** (`rail.length_mm` shorter than the rolling): its labels
//!   shifted a station at a time are a symmetry of the ring, so a run whose patch starts a
//!   station further on (two shifts more, at other steps) has the same forces at every step
//!   to round-off;
//! - **spin**: the mirror, Kalker's antisymmetric coupling of the lateral force and the spin
//!   moment (`C23` read both ways) and the spin moment resisting the spin (`C33 > 0`);
//! - **bad input** refused on one line naming the key.

mod common;

use common::{assert_one_line_error, run_err, run_in_process, shipped};

fn num(v: &serde_json::Value, path: &str) -> f64 {
    v.pointer(path)
        .and_then(|x| x.as_f64())
        .unwrap_or_else(|| panic!("{path} missing from {v}"))
}

/// `C11` from the runs of `name` at `xi = +-5e-4` on the zone of `sectors`, and the summary
/// of the `+` run.
fn c11(name: &str, sectors: &str, extra: &[(&str, &str)]) -> (f64, serde_json::Value) {
    let mut sums = Vec::new();
    for xi in ["0.0005", "-0.0005"] {
        let mut keys = vec![("wheel.zone_sectors", sectors), ("rolling.creepage", xi)];
        keys.extend_from_slice(extra);
        let (path, text) = shipped(name, &keys);
        let (_dir, s) = run_in_process(&path, &text, &format!("{name}-{sectors}-{xi}"));
        sums.push(s);
    }
    let q = |s: &serde_json::Value| num(s, "/steady/creep_force_N");
    let scale = |s: &serde_json::Value| num(s, "/hertz3d/kalker_scale_N");
    let c = (q(&sums[0]) - q(&sums[1])) / (0.5 * (scale(&sums[0]) + scale(&sums[1])) * 1e-3);
    (c, sums.swap_remove(0))
}

#[test]
fn the_wheel_on_an_elastic_rail_of_its_material_is_kalkers_pair() {
    let (c_rail, rail) = c11("rolling3d-rail", "192", &[]);
    let (c_twin, twin) = c11("rolling3d-kalker", "192", &[("rolling.turns", "0.12")]);
    eprintln!("C11: rail {c_rail:.4}, twin {c_twin:.4}");
    // Two constructions of one continuum problem on the same wheel mesh.
    assert!(
        (c_rail / c_twin - 1.0).abs() < 0.05,
        "C11 on the rail {c_rail} against the twin's {c_twin}"
    );
    // Full adhesion: the creep force drives the wheel at xi > 0.
    assert!(num(&rail, "/steady/creep_force_N") > 0.0);
    // G_1 on the rail, 2 G_1 for the twin on its rigid base.
    let g = |s: &serde_json::Value| num(s, "/hertz3d/combined_shear_modulus_Pa");
    assert!((g(&twin) / g(&rail) - 2.0).abs() < 1e-12);
    // Hertz's circle of two elastic bodies at the run's normal force.
    let c = num(&rail, "/hertz3d/c_m");
    for key in [
        "/hertz3d/measured_a_rolling_m",
        "/hertz3d/measured_b_lateral_m",
    ] {
        let m = num(&rail, key);
        assert!((m / c - 1.0).abs() < 0.15, "{key} {m} against Hertz's {c}");
    }
    let approach = num(&rail, "/hertz3d/approach_m");
    assert!(
        approach > 0.8 * 7e-5 && approach < 7e-5,
        "Hertz's approach {approach} against the flattening 7e-5 m"
    );
    // The rail halves the modulus: at the same flattening the normal force falls (it
    // would halve with the approach all Hertz's).
    let ratio = num(&rail, "/steady/normal_force_N") / num(&twin, "/steady/normal_force_N");
    assert!(
        ratio > 0.5 && ratio < 0.65,
        "N on the rail / N on the rigid crown {ratio}"
    );
    // The zone relocated round the rim (7.5 degrees a relocation at 192 sectors),
    // the rail's nodes left where they are, and the normal force kept steady.
    assert!(
        num(&rail, "/counters/relocations") >= 3.0,
        "{}",
        rail["counters"]
    );
    let [a, b] = [
        "/steady/window_changes/normal_relative",
        "/steady/window_changes/traction_ratio",
    ]
    .map(|k| num(&rail, k));
    assert!(a < 0.01 && b < 1e-3, "window changes {a} {b}");
}

/// The wheel on the UIC60 rail (`scenarios/rolling3d-uic60.toml`, shortened): Hertz's
/// ellipse of the rim's radius along and the head's 0.3 m crest across, at half the
/// modulus, against the patch's measured semi-axes; the creep force drives the wheel within
/// Coulomb's bound.
#[test]
fn the_wheel_on_a_uic60_rail_has_hertzs_ellipse_of_the_heads_crest() {
    let (path, text) = shipped(
        "rolling3d-uic60",
        &[("rolling.settle_ms", "0.5"), ("rolling.turns", "0.06")],
    );
    let (_dir, s) = run_in_process(&path, &text, "rail-uic60");
    let (a, b) = (
        num(&s, "/hertz3d/a_rolling_m"),
        num(&s, "/hertz3d/b_lateral_m"),
    );
    // Hertz's ellipse of R_x = 0.1 m and R_y = 0.3 m: b / a about 2.
    assert!(b / a > 1.9 && b / a < 2.2, "Hertz's b/a {}", b / a);
    let (ma, mb) = (
        num(&s, "/hertz3d/measured_a_rolling_m"),
        num(&s, "/hertz3d/measured_b_lateral_m"),
    );
    eprintln!("a {ma:e} against {a:e}, b {mb:e} against {b:e}");
    assert!((ma / a - 1.0).abs() < 0.12, "a {ma} against Hertz's {a}");
    assert!((mb / b - 1.0).abs() < 0.12, "b {mb} against Hertz's {b}");
    let (n, q) = (
        num(&s, "/steady/normal_force_N"),
        num(&s, "/steady/creep_force_N"),
    );
    assert!(
        q > 0.0 && q < 0.3 * n * (1.0 + 1e-9),
        "Q {q} N against mu N {}",
        0.3 * n
    );
    assert!(
        s["rail"]["cells"][1].as_u64().unwrap() > 100,
        "{}",
        s["rail"]
    );
}

/// The bar closed on itself against the bar with free ends, on the coarse rung: the rail's
/// columns shifted from one station's (the set-up checked one against a solved column),
/// the forces the same where the ends are far from the patch.
#[test]
fn a_closed_rail_shifts_its_columns_and_keeps_the_open_rails_forces() {
    let mut sums = Vec::new();
    for periodic in ["true", "false"] {
        let (path, text) = shipped(
            "rolling3d-rail",
            &[("wheel.zone_sectors", "192"), ("rail.periodic", periodic)],
        );
        let (_dir, s) = run_in_process(&path, &text, &format!("rail-closed-{periodic}"));
        sums.push(s);
    }
    let (closed, open) = (&sums[0], &sums[1]);
    assert_eq!(closed["rail"]["closed"], true);
    assert_eq!(open["rail"]["closed"], false);
    // One station fewer: its nodes merged into the first's.
    assert!(num(closed, "/dofs") < num(open, "/dofs"));
    let solves = |s: &serde_json::Value| num(s, "/counters/column_solves");
    let shifted = closed["counters"]["columns_turned"].as_f64().unwrap_or(0.0);
    eprintln!(
        "columns solved: closed {} (and {shifted} shifted), open {}",
        solves(closed),
        solves(open)
    );
    assert!(shifted > solves(closed), "{}", closed["counters"]);
    assert!(solves(closed) < 0.35 * solves(open));
    for (key, tol) in [
        ("/steady/normal_force_N", 2e-3),
        ("/steady/creep_force_N", 1e-2),
    ] {
        let (c, o) = (num(closed, key), num(open, key));
        assert!((c / o - 1.0).abs() < tol, "{key}: closed {c}, open {o}");
    }
}

/// A ring of 70 mm under 75 mm of rolling, its seam kept ahead of the patch by shifting its
/// labels a station at a time: the shift is the ring's symmetry, so starting the patch one
/// station further on (`rail.margin_mm` + one station: the shifts come at other steps, two
/// more of them) changes no force at any step beyond round-off.
#[test]
fn a_ring_rolled_over_again_shifts_its_labels_exactly() {
    let run = |margin: &str, tag: &str| {
        let (path, text) = shipped(
            "rolling3d-rail",
            &[
                ("wheel.zone_sectors", "192"),
                ("rail.length_mm", "70.0"),
                ("rail.margin_mm", margin),
            ],
        );
        let (dir, s) = run_in_process(&path, &text, tag);
        let history = std::fs::read_to_string(dir.join("history.csv")).unwrap();
        (s, history)
    };
    let (a, ha) = run("28.0", "ring-a");
    let stations = num(&a, "/rail/stations");
    let length = num(&a, "/rail/length_m");
    assert!((length - 0.07).abs() < 1e-12, "{length}");
    let (b, hb) = run(&format!("{}", 28.0 + 1e3 * length / stations), "ring-b");
    assert_eq!(a["rail"]["ring"], true);
    let shifts = |s: &serde_json::Value| num(s, "/counters/ring_shifts");
    assert!(shifts(&a) >= 15.0, "{}", a["counters"]);
    assert_eq!(shifts(&b), shifts(&a) + 2.0);
    let column = |h: &str, key: &str| -> Vec<f64> {
        let mut lines = h.lines();
        let head: Vec<&str> = lines.next().unwrap().split(',').collect();
        let k = head.iter().position(|c| *c == key).unwrap();
        lines
            .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
            .collect()
    };
    let peak = column(&ha, "normal_force_N")
        .iter()
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    for key in ["normal_force_N", "creep_force_N", "lateral_force_N"] {
        let (x, y) = (column(&ha, key), column(&hb, key));
        assert_eq!(x.len(), y.len());
        let worst = x
            .iter()
            .zip(&y)
            .fold(0.0_f64, |m, (p, q)| m.max((p - q).abs()));
        assert!(
            worst < 1e-9 * peak,
            "{key}: {worst:e} N apart (peak N {peak})"
        );
    }
}

/// The steady lateral force and spin moment of the wheel on the rail at the lateral
/// creepage `eta` and the spin `phi` (1/m), on the zone of `sectors`; and `G c^3`.
fn lateral(sectors: &str, eta: &str, phi: &str) -> (f64, f64, f64, serde_json::Value) {
    let (path, text) = shipped(
        "rolling3d-rail",
        &[
            ("wheel.zone_sectors", sectors),
            ("rolling.creepage", "0"),
            ("rolling.lateral_creepage", eta),
            ("rolling.spin_creepage", phi),
        ],
    );
    let (_dir, s) = run_in_process(&path, &text, &format!("rail-lateral-{sectors}-{eta}-{phi}"));
    let gc3 = num(&s, "/hertz3d/kalker_scale_N") * num(&s, "/hertz3d/c_m");
    (
        num(&s, "/steady/lateral_force_N"),
        num(&s, "/steady/spin_moment_N_m"),
        gc3,
        s,
    )
}

/// Spin on the elastic rail (the rail's material turning under its mesh, a rigid slip):
/// - the mirror about the wheel's mid-plane: `phi -> -phi` reverses `Q_y` and `M_z` and
///   keeps `N`;
/// - Kalker's antisymmetric coupling, `dQ_y / dphi = -dM_z / deta`: the coefficient `C23`
///   read from the lateral force at a spin agrees with the one read from the spin moment at a
///   lateral creepage, two runs that share no creepage (measured 16 % apart on this coarse
///   zone of 0.75 pitches a semi-axis, 0.3 % on the 768-sector one; the half-space's two are
///   equal to every digit);
/// - the spin moment resists the spin: `C33 > 0`, within a factor 2 of the half-space's
///   1.192 on this coarse zone (`validation/halfspace3d/spin_coefficients.py`; measured
///   0.705, and 1.202 on the 1088-sector zone).
#[test]
fn spin_on_the_rail_couples_antisymmetrically_and_is_resisted() {
    let phi = 0.2;
    let (qy_p, mz_p, gc3, sp) = lateral("192", "0", "0.2");
    let (qy_m, mz_m, _, sm) = lateral("192", "0", "-0.2");
    let (_, mz_eta, gc3_eta, _) = lateral("192", "0.0005", "0");
    for (key, sign) in [
        ("/steady/normal_force_N", 1.0),
        ("/steady/lateral_force_N", -1.0),
        ("/steady/spin_moment_N_m", -1.0),
    ] {
        let (a, b) = (num(&sp, key), num(&sm, key));
        assert!(
            (a - sign * b).abs() < 1e-3 * a.abs().max(1e-6 * num(&sp, "/steady/normal_force_N")),
            "{key}: {a} at phi, {b} at -phi"
        );
    }
    let c23_phi = (qy_p - qy_m) / (2.0 * phi) / gc3;
    let c23_eta = -mz_eta / 5e-4 / gc3_eta;
    let c = num(&sp, "/hertz3d/c_m");
    let c33 = -(mz_p - mz_m) / (2.0 * phi) / (gc3 * c);
    eprintln!("C23 from Q_y at phi {c23_phi:.4}, from M_z at eta {c23_eta:.4}; C33 {c33:.4}");
    assert!(
        c23_phi > 0.0 && (c23_phi / c23_eta - 1.0).abs() < 0.25,
        "C23 {c23_phi} (Q_y, phi) against {c23_eta} (M_z, eta)"
    );
    assert!(c33 > 0.5 * 1.192 && c33 < 2.0 * 1.192, "C33 {c33}");
}

#[test]
fn a_rail_refuses_a_twin_and_a_bad_pitch_by_name() {
    let base = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/rolling3d-rail.toml"
    ))
    .unwrap();
    for (key, value, must) in [
        ("rolling.coupling", "\"uncoupled\"", "rolling.coupling"),
        ("rolling.spin_creepage", "5000.0", "rolling.spin_creepage"),
        ("rail.pitch_mm", "50.0", "rail.pitch_mm"),
        ("wheel.cyclic_columns", "true", "wheel.cyclic_columns"),
        ("rail.growth", "3.0", "rail.growth"),
        ("rail.profile", "\"uic61\"", "rail.profile"),
        ("rail.inclination", "0.025", "rail.inclination"),
        ("rail.margin_mm", "5.0", "rail.periodic"),
        ("rail.length_mm", "40.0", "rail.length_mm"),
    ] {
        let text = softway::scenario::set_key(&base, key, value).unwrap();
        let (code, err) = run_err(&format!("rail-bad-{key}"), &text);
        assert_one_line_error(code, &err, &[must]);
    }
    // A zone too narrow to hold the patch until it relocates by one of 34 coarse sectors
    // (10.6 degrees): a coarse rim node would enter the patch late in the run.
    let text = softway::scenario::set_key(&base, "wheel.zone_sectors", "544").unwrap();
    let text = softway::scenario::set_key(&text, "wheel.mesh", "[4, 34, 2]").unwrap();
    let (code, err) = run_err("rail-bad-zone-width", &text);
    assert_one_line_error(code, &err, &["wheel.zone_deg", "13.6"]);
    // The UIC60 section has its own height.
    let uic = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/rolling3d-uic60.toml"
    ))
    .unwrap();
    let text = softway::scenario::set_key(&uic, "rail.height_mm", "20.0").unwrap();
    let (code, err) = run_err("rail-bad-uic-height", &text);
    assert_one_line_error(code, &err, &["rail.height_mm", "UIC60"]);
    // A spin turns about the wheel's mid-plane, off an inclined rail's patch.
    let text = softway::scenario::set_key(&uic, "rail.inclination", "0.025").unwrap();
    let text = softway::scenario::set_key(&text, "rolling.spin_creepage", "0.2").unwrap();
    let (code, err) = run_err("rail-bad-uic-spin", &text);
    assert_one_line_error(code, &err, &["rolling.spin_creepage", "rail.inclination"]);
    // A length is a closed rail's.
    let text = softway::scenario::set_key(&base, "rail.periodic", "false").unwrap();
    let text = softway::scenario::set_key(&text, "rail.length_mm", "80.0").unwrap();
    let (code, err) = run_err("rail-bad-open-length", &text);
    assert_one_line_error(code, &err, &["rail.length_mm", "rail.periodic"]);
    // Its margins are graded: its stations are not equal, it cannot close on itself.
    let text = softway::scenario::set_key(&uic, "rail.periodic", "true").unwrap();
    let (code, err) = run_err("rail-bad-uic-periodic", &text);
    assert_one_line_error(code, &err, &["rail.periodic", "UIC60"]);
}
