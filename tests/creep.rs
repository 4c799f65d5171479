//! Creep forces a railway engineer can quote (issue 35): the coupled creep curve of a steel
//! roller on a rigid plane (`scenarios/creep-curve-coupled.toml`: plane strain, R = 0.1 m,
//! a = 1 mm, mu = 0.3) on the moving zone refined in depth (`wheel.zone_depth`).
//!
//! Frictionless and static (the quasi-static steady state of a roller at 5 m/s): the
//! surface's shortening across the patch against Flamant's, Bentall and Johnson's mu -> 0
//! free-rolling creepage, and what is left of its difference (the roller's curvature, of
//! order a / R). Rolling with friction (4 ms after settling, the creep force's start-up
//! transient extrapolated: `traction.traction_ratio_steady`, checked against a run four
//! times as long): the coupled free-rolling creepage on the ladder of zone pitches, run as
//! `softway sweep` with `[sweep] ladder` runs it, against an independent half-space answer
//! with the pressure solved with the traction (`validation/halfspace_creep_coupled.py`).
//!
//! Measured: the shipped scenario's sweep gives free-rolling creepages of 0.5623 / 0.5911 /
//! 0.6046 mu a / R on the undeformed radius at 4,608 / 9,216 / 18,432 in the zone (observed
//! order 1.10, Richardson limit 0.6164); with three creepages per rung (the parabola
//! through 1, 1.5 and 2 e-3 on each) 0.5607 / 0.5906 / 0.6041, order 1.15, limit 0.6151.
//! The half-space's 0.6276 less the wheel's own smooth strain at the contact (0.0096) is
//! 0.6180: the limit is 0.46 % below it, the shipped mesh 1.8 % short of the limit. The test
//! runs the ladder's two coarser rungs and takes its order as known ([`LADDER_ORDER`]); the
//! full ladder is the shipped sweep, about 8 minutes on two cores. The zone's chequerboard
//! of diagonals matters here: with one diagonal in every cell the same ladder gave 0.529 /
//! 0.578 / 0.5995 (8 ms, the mean), and the mirrored diagonal 0.606 / 0.599 (the other
//! direction of rolling).

mod common;

use softway::build::resolve;
use softway::kinds::wheel::run::load::static_solution;
use softway::scenario::Scenario;

/// The flattening of the shipped scenario's load (17,695 N: a = 1 mm), m (from its static
/// solve on the shipped mesh; the tests read the force it gives).
const FLATTENING: f64 = 2.48e-5;

/// The shipped scenario's wheel with `keys` set, pressed to [`FLATTENING`] (its
/// `wheel.load` replaced by the flattening: one static solve), and `zone_depth` removed when
/// `depth` is false.
fn wheel(keys: &[(&str, &str)], depth: bool) -> softway::wheel::WheelModel {
    wheel_at(keys, depth, FLATTENING)
}

/// [`wheel`] pressed to the flattening `d`, m.
fn wheel_at(keys: &[(&str, &str)], depth: bool, d: f64) -> softway::wheel::WheelModel {
    let (path, text) = common::shipped("creep-curve-coupled", keys);
    let mut text: String = text
        .lines()
        .filter(|l| !l.starts_with("load =") && (depth || !l.starts_with("zone_depth =")))
        .map(|l| format!("{l}\n"))
        .collect();
    text = softway::scenario::set_key(&text, "rolling.flattening", &d.to_string()).unwrap();
    let sc = resolve(&Scenario::from_str(&text, &path).unwrap()).unwrap();
    let Some(ws) = sc.runs[0].model.get::<softway::scenario::WheelScenario>() else {
        panic!("a wheel")
    };
    softway::kinds::wheel::run::build(ws, &sc.path).unwrap()
}

/// The rim nodes of the static contact pressed to `d`, along the base from the contact's
/// centre (below the axle): `(s, u_t, u_r, F_n)` sorted by `s`, with `s` and `u_t` counted
/// counter-clockwise round the rim, and the total force.
fn static_rim(wm: &softway::wheel::WheelModel, d: f64) -> (Vec<[f64; 4]>, f64) {
    let sol = static_solution(wm, d).unwrap();
    let r = wm.spec.radius;
    let force = |n: usize| sol.active.iter().find(|a| a.0 == n).map_or(0.0, |a| a.1);
    let mut rows: Vec<[f64; 4]> = wm
        .rim
        .iter()
        .map(|&n| {
            let p = wm.mesh.point(n);
            let th = p[1].atan2(p[0]);
            let (u, v) = (sol.u[2 * n], sol.u[2 * n + 1]);
            let ut = -th.sin() * u + th.cos() * v;
            let ur = th.cos() * u + th.sin() * v;
            let mut a = th + std::f64::consts::FRAC_PI_2;
            if a > std::f64::consts::PI {
                a -= 2.0 * std::f64::consts::PI;
            }
            [r * a, ut, ur, force(n)]
        })
        .filter(|row| row[0].abs() < 0.02)
        .collect();
    rows.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let total = sol.active.iter().map(|a| a.1).sum();
    (rows, total)
}

/// Linear interpolation of column `c` at `s`.
fn at(rows: &[[f64; 4]], c: usize, s: f64) -> f64 {
    let k = rows.partition_point(|r| r[0] < s).clamp(1, rows.len() - 1);
    let (a, b) = (rows[k - 1], rows[k]);
    a[c] + (b[c] - a[c]) * (s - a[0]) / (b[0] - a[0])
}

/// The hoop strain `du_t/ds + u_r/R` at the rim nodes (centred differences).
fn hoop(rows: &[[f64; 4]], r: f64) -> Vec<f64> {
    (0..rows.len())
        .map(|k| {
            let (a, b) = (rows[k.saturating_sub(1)], rows[(k + 1).min(rows.len() - 1)]);
            (b[1] - a[1]) / (b[0] - a[0]) + rows[k][2] / r
        })
        .collect()
}

/// The arc's shortening `int_{-x}^{x} (du_t/ds + u_r/R) ds` (trapezoids on the nodes).
fn shortening(rows: &[[f64; 4]], r: f64, x: f64) -> f64 {
    let mut sum = at(rows, 1, x) - at(rows, 1, -x);
    let mut prev = (-x, at(rows, 2, -x));
    for row in rows.iter().filter(|row| row[0] > -x && row[0] < x) {
        sum += 0.5 * (prev.1 + row[2]) * (row[0] - prev.0) / r;
        prev = (row[0], row[2]);
    }
    sum + 0.5 * (prev.1 + at(rows, 2, x)) * (x - prev.0) / r
}

/// The mu -> 0 free-rolling creepage on the undeformed radius from the static patch: the
/// slip `omega R (xi + eps)` (eps the hoop strain) changes sign where the central part of the
/// patch carries half the load; `p` and `eps` linear between the nodes.
fn free_rolling_mu0(rows: &[[f64; 4]], r: f64) -> f64 {
    let eps = hoop(rows, r);
    // Pressure per node: force over the tributary length.
    let n = rows.len();
    let p: Vec<f64> = (0..n)
        .map(|k| {
            let (a, b) = (rows[k.saturating_sub(1)][0], rows[(k + 1).min(n - 1)][0]);
            rows[k][3] / (0.5 * (b - a))
        })
        .collect();
    let g = |xi: f64| {
        let mut sum = 0.0;
        for k in 0..n - 1 {
            let (s0, s1) = (rows[k][0], rows[k + 1][0]);
            let (f0, f1) = (xi + eps[k], xi + eps[k + 1]);
            let (p0, p1) = (p[k], p[k + 1]);
            let seg = |a: f64, b: f64, sign: f64| {
                // int of p over [a, b] (fractions of the segment), times sign.
                let pa = p0 + (p1 - p0) * a;
                let pb = p0 + (p1 - p0) * b;
                sign * 0.5 * (pa + pb) * (b - a) * (s1 - s0)
            };
            if f0 * f1 >= 0.0 {
                sum += seg(0.0, 1.0, (f0 + f1).signum());
            } else {
                let z = f0 / (f0 - f1);
                sum += seg(0.0, z, f0.signum()) + seg(z, 1.0, f1.signum());
            }
        }
        sum
    };
    let (mut lo, mut hi) = (-1e-2, 1e-2);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The shortening of the surface across the patch over Flamant's (the flat half-space's,
/// plane strain: `(1 - 2 nu)(1 + nu) P' / E` between any two points outside the patch), at
/// `x / a` = 1.5, 2, 2.5, 3, and the intercept at `x = 0` of the line through them: the
/// wheel's own smooth strain (its curvature, its clamped hub) adds `2 x eps_c` to the
/// half-space's constant; the intercept is the part from the pressure. Returns the ratios,
/// the intercept, the slope (per a) and `eps_c`.
fn shortening_over_flamant(
    wm: &softway::wheel::WheelModel,
    rows: &[[f64; 4]],
    total: f64,
) -> (Vec<f64>, f64, f64, f64) {
    let (e, nu, r) = (
        wm.spec.material.young,
        wm.spec.material.poisson,
        wm.spec.radius,
    );
    let flamant = -(1.0 - 2.0 * nu) * (1.0 + nu) * total / wm.spec.thickness / e;
    let a = softway::kinds::wheel::run::load::hertz_half_width(wm, total);
    let xs = [1.5, 2.0, 2.5, 3.0];
    let ys: Vec<f64> = xs
        .iter()
        .map(|&k| shortening(rows, r, k * a) / flamant)
        .collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    let slope = sxy / sxx;
    // The wheel's smooth strain: d(shortening)/dx = 2 eps_c (x in units of a).
    let eps_c = 0.5 * slope * flamant / a;
    (ys, my - slope * mx, slope, eps_c)
}

/// The mesh for creep studies removes the depth error: on the zone refined in depth
/// (`wheel.zone_depth`), frictionless, the surface's shortening across the patch from the
/// pressure is Flamant's within 1 % on the shipped mesh (18,432 rim nodes in the zone), and
/// converges on the ladder of zone pitches (2,304 / 4,608 / 9,216 / 18,432) from below, the
/// second difference less than half the first.
#[test]
fn the_depth_refined_zone_gives_flamants_surface_shortening() {
    let mut at_15 = Vec::new();
    for zone in ["2304", "4608", "9216", "18432"] {
        let wm = wheel(&[("wheel.zone_rim_nodes", zone)], true);
        let (rows, total) = static_rim(&wm, FLATTENING);
        let (ys, intercept, slope, _) = shortening_over_flamant(&wm, &rows, total);
        eprintln!(
            "zone {zone}: {} nodes; shortening / Flamant at 1.5, 2, 2.5, 3 a: {ys:.4?}; intercept {intercept:.4}, slope {slope:.4} per a",
            wm.mesh.n_nodes()
        );
        at_15.push(ys[0]);
        if zone == "18432" {
            assert!((intercept - 1.0).abs() < 0.01, "intercept {intercept}");
        }
    }
    let (d1, d2, d3) = (
        at_15[1] - at_15[0],
        at_15[2] - at_15[1],
        at_15[3] - at_15[2],
    );
    assert!(
        d1 > 0.0 && d2 > 0.0 && d2 < 0.5 * d1 && d3 > 0.0,
        "{at_15:?}"
    );
    // Without the refinement in depth the zone's elements at depth ~a are g a = 0.3 a:
    // the surface comes out short by several per cent whatever the pitch.
    let wm = wheel(&[("wheel.zone_rim_nodes", "9216")], false);
    let (rows, total) = static_rim(&wm, FLATTENING);
    let (ys, intercept, _, _) = shortening_over_flamant(&wm, &rows, total);
    eprintln!("zone 9216 without zone_depth: {ys:.4?}; intercept {intercept:.4}");
    assert!(intercept < 0.98, "{intercept}");
}

/// Bentall and Johnson's mu -> 0 limit of the free-rolling creepage of an elastic roller
/// on a rigid plane (Bentall and Johnson, Int. J. Mech. Sci. 9, 1967; Johnson, Contact
/// Mechanics, 1985, §8.2): with mu -> 0 the traction is `mu p` signed by the slip, which
/// the pressure alone sets; the slip `omega R (xi + eps)` (on the undeformed radius; `eps`
/// the surface's strain, `-(1 - 2 nu)(1 + nu) p / E` on the half-space) is backwards in the
/// middle of the patch, forwards at its edges, and `Q = 0` when the middle carries half the
/// load: `|x| < c` with `asin(c/a) + (c/a) sqrt(1 - c^2/a^2) = pi/4`, `c = 0.4040 a`, so
/// `xi_0 = beta (a / R) sqrt(1 - c^2/a^2) = 0.9148 beta a / R`, with Dundurs'
/// `beta = (1 - 2 nu) / (2 (1 - nu))` (0.2857 for steel, nu = 0.3): 0.2614 a / R.
///
/// Evaluated on the shipped mesh's frictionless steady state (quasi-static: 5 m/s against
/// 3,000 m/s waves), with the wheel's own smooth strain at the contact (its curvature, its
/// hub: the surface strain just outside the patch, where the half-space's is zero) taken off.
///
/// Measured: -1.57 % on the shipped mesh (18,432 rim nodes in the zone), -2.07 % on the
/// rung below (9,216); without taking the wheel's smooth strain off, -2.68 % and -3.25 %.
/// (With one diagonal in every cell, before the chequerboard, -1.67 % and -2.44 %.)
/// Asserted: within 2 % on the shipped mesh, 3 % on the rung below, and the error falling.
#[test]
fn bentall_johnson_free_rolling_creepage_as_mu_goes_to_zero() {
    let errors: Vec<f64> = ["9216", "18432"]
        .iter()
        .map(|zone| bentall_johnson_error(zone))
        .collect();
    assert!(errors[0].abs() < 0.03, "{errors:?}");
    assert!(errors[1].abs() < 0.02, "{errors:?}");
    assert!(errors[1].abs() < errors[0].abs(), "{errors:?}");
}

/// The wheel's own smooth strain at the contact (its curvature, its hub), which the
/// half-space does not have: from the slope of the frictionless surface shortening outside
/// the patch, `d(shortening)/dx = 2 eps_c` ([`shortening_over_flamant`]). A creepage on the
/// wheel is the half-space's less `eps_c`.
fn smooth_strain(wm: &softway::wheel::WheelModel) -> f64 {
    let (rows, total) = static_rim(wm, FLATTENING);
    shortening_over_flamant(wm, &rows, total).3
}

/// The relative error of the free-rolling creepage as mu -> 0 (the wheel's smooth strain
/// taken off) against Bentall and Johnson's on the zone of `zone` rim nodes.
fn bentall_johnson_error(zone: &str) -> f64 {
    bentall_johnson_error_at(&[("wheel.zone_rim_nodes", zone)], FLATTENING)
}

/// [`bentall_johnson_error`] of the wheel with `keys` set, pressed to `d`.
fn bentall_johnson_error_at(keys: &[(&str, &str)], d: f64) -> f64 {
    let wm = wheel_at(keys, true, d);
    let (rows, total) = static_rim(&wm, d);
    let (nu, r) = (wm.spec.material.poisson, wm.spec.radius);
    let a = softway::kinds::wheel::run::load::hertz_half_width(&wm, total);
    let beta = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu));
    let c = {
        let (mut lo, mut hi) = (0.0f64, std::f64::consts::FRAC_PI_2);
        for _ in 0..100 {
            let m = 0.5 * (lo + hi);
            if m + m.sin() * m.cos() > std::f64::consts::FRAC_PI_4 {
                hi = m;
            } else {
                lo = m;
            }
        }
        lo.sin()
    };
    let bj = beta * a / r * (1.0 - c * c).sqrt();
    let xi0 = free_rolling_mu0(&rows, r);
    // The same static solve gives the wheel's smooth strain ([`smooth_strain`]).
    let eps_c = shortening_over_flamant(&wm, &rows, total).3;
    eprintln!(
        "{keys:?}, d {d:e}: a/R {:.4}; c/a {c:.4}; Bentall-Johnson xi0 {bj:.5e} ({:.4} beta a/R); wheel {xi0:.5e} ({:+.2}%), its smooth strain {eps_c:.3e}, without it {:.5e} ({:+.2}%)",
        a / r,
        bj / (beta * a / r),
        100.0 * (xi0 / bj - 1.0),
        xi0 + eps_c,
        100.0 * ((xi0 + eps_c) / bj - 1.0)
    );
    assert!((c - 0.4040).abs() < 1e-3, "{c}");
    (xi0 + eps_c) / bj - 1.0
}

/// What is left of Bentall and Johnson's difference on the shipped mesh is the roller's
/// curvature, not the mesh: the half-space's answer is the limit `a / R -> 0`, and a
/// roller differs from it by terms of order `a / R`. Halving the zone's pitch again (36,864
/// rim nodes in the zone) moves the difference by less than 0.2 % (measured -1.58 % to
/// -1.45 %: converged in the pitch; `zone_depth` 4 and 8 mm give -1.55 %), while a quarter
/// of the load (a / R = 0.0049 against 0.0100, the zone's pitch halved with it: the same
/// rim pitches across the patch as the shipped mesh) about halves it: -0.89 % at 36,864 in
/// the zone (0.61 of -1.45 %), -0.75 % at 73,728 (0.52). The wheel's smooth strain that is
/// taken off scales the same way (1.1 % of Bentall and Johnson's value at a / R = 0.01,
/// 0.55 % at 0.0049).
#[test]
fn bentall_johnson_difference_is_the_rollers_curvature() {
    let shipped = bentall_johnson_error("18432");
    let finer = bentall_johnson_error("36864");
    // A quarter of the load: Hertz's a halves (d from the static solve: 6.8e-6 m).
    let small = bentall_johnson_error_at(
        &[
            ("wheel.zone_rim_nodes", "36864"),
            ("wheel.zone_depth", "1e-3"),
        ],
        6.8e-6,
    );
    let ratio = small / finer;
    eprintln!(
        "Bentall and Johnson: {:+.2}% / {:+.2}% at a/R = 0.01 (18,432 / 36,864 in the zone); {:+.2}% at a/R = 0.0049 (36,864): ratio {ratio:.2}",
        100.0 * shipped,
        100.0 * finer,
        100.0 * small
    );
    assert!((finer - shipped).abs() < 0.002, "{shipped} {finer}");
    assert!(ratio > 0.4 && ratio < 0.7, "{small} / {finer}");
}

/// The rolling after settling, ms: the shipped scenario's 4, the creep force's start-up
/// transient extrapolated out of the means over its last three quarters
/// (`traction.traction_ratio_steady`).
const ROLLING_MS: f64 = 4.0;

/// `rolling.turns` for `ms` of rolling at the shipped 50 rad/s.
fn turns(ms: f64) -> String {
    (ms * 1e-3 * 50.0 / (2.0 * std::f64::consts::PI)).to_string()
}

/// The start-up transient's extrapolation (`traction_ratio_steady`) after 4 ms of rolling
/// gives the creep force that a run four times as long reaches: on the ladder's first rung
/// at the braking side's creepage (`Q/(mu P)` about -0.5; the transient there starts at
/// +0.3), within 5e-4 in `Q/(mu P)` of the last half's mean after 16 ms, where the 4 ms
/// run's own mean is 0.015 away. Measured: -0.50378 (4 ms, extrapolated; decay 0.32 a
/// quarter), -0.50342 (16 ms, the mean; extrapolated -0.50347), -0.48853 (4 ms, the mean).
#[test]
fn the_start_up_transient_extrapolates_to_the_long_runs_creep_force() {
    let run = |ms: f64| {
        let (path, text) = common::shipped(
            "creep-curve-coupled",
            &[
                ("wheel.zone_rim_nodes", "4608"),
                ("rolling.creepage", "4e-4"),
                ("rolling.turns", &turns(ms)),
            ],
        );
        common::run_in_process(&path, &text, &format!("transient-{ms}")).1["traction"].clone()
    };
    let (short, long) = std::thread::scope(|s| {
        let a = s.spawn(|| run(ROLLING_MS));
        let b = s.spawn(|| run(16.0));
        (a.join().unwrap(), b.join().unwrap())
    });
    let f = |t: &serde_json::Value, k: &str| t[k].as_f64().unwrap();
    let (steady, mean_short, mean_long) = (
        f(&short, "traction_ratio_steady"),
        f(&short, "traction_ratio"),
        f(&long, "traction_ratio"),
    );
    let decay = f(&short, "transient_decay");
    eprintln!(
        "4 ms: steady {steady:.5} (mean {mean_short:.5}, decay {decay:.3} a quarter); 16 ms: mean {mean_long:.5}, steady {:.5}",
        f(&long, "traction_ratio_steady")
    );
    assert!((steady - mean_long).abs() < 5e-4, "{steady} vs {mean_long}");
    assert!(
        (mean_short - mean_long).abs() > 0.01,
        "{mean_short} vs {mean_long}"
    );
    assert!(decay > 0.0 && decay < 0.8, "{decay}");
}

/// The coupled free-rolling creepage, mu a / R, of the half-space with the pressure solved
/// with the traction (`validation/halfspace_creep_coupled.py`: 150 and 300 cells over 3 a
/// give 0.6273 and 0.6276). Holding the pressure at Hertz's instead (the Goodman
/// simplification, `validation/halfspace_creep.py`) gives 0.6183: the traction's pull on the
/// pressure moves free rolling by 1.5 %.
const HALF_SPACE_FREE_ROLLING: f64 = 0.6276;

/// The free-rolling creepage of the shipped scenario's full ladder, `softway sweep
/// scenarios/creep-curve-coupled.toml` (4,608 / 9,216 / 18,432 in the zone: 0.5623 /
/// 0.5911 / 0.6046 mu a / R, observed order 1.10, Richardson limit 0.6164; the book's
/// Friction chapter): its observed order, which the test's two rungs take as known.
const LADDER_ORDER: f64 = 1.10;

/// The coupled free-rolling creepage converges on the ladder of the shipped family (the
/// zone's pitch halved: 4,608 / 9,216 rim nodes in the zone, the shipped 18,432's two
/// coarser rungs; the full ladder is the shipped scenario's sweep, whose numbers the book
/// reports), run as a user runs it: `softway sweep` over the creepages 0.001 / 0.0015 /
/// 0.002 (on `rho`) with the ladder's key (the library's sweep, side by side on the cores),
/// its `creep_ladder.csv` read at `Q/(mu P)` = 0. The finer rung is the larger and within 5
/// % of the reference, and the two rungs extrapolated at the full ladder's order
/// ([`LADDER_ORDER`]) land within 1 % of the half-space's ([`HALF_SPACE_FREE_ROLLING`]) less
/// the wheel's own smooth strain at the contact (its curvature and hub; the static solve's,
/// as in Bentall and Johnson's check), which a half-space does not have. Measured: 0.5607 /
/// 0.5906, extrapolated 0.6167 against 0.6173 (-0.10 %; the finer rung -4.33 %), in 172 s.
#[test]
fn coupled_free_rolling_creepage_converges_on_the_zone_ladder() {
    use softway::scenario::overrides::{grid, Grid};
    let (path, text) = common::shipped(
        "creep-curve-coupled",
        &[("rolling.turns", &turns(ROLLING_MS))],
    );
    let keys = [
        (
            "rolling.creepage".to_string(),
            vec!["0.001".into(), "0.0015".into(), "0.002".into()],
        ),
        (
            "wheel.zone_rim_nodes".to_string(),
            vec!["4608".into(), "9216".into()],
        ),
    ];
    let points = grid(&keys, Grid::Product).unwrap();
    let dir = common::TestDir::new("lib", "creep-ladder");
    let (done, _) =
        softway::run::sweep(&path, &text, &points, &dir, &softway::run::Cancel::new()).unwrap();
    let h = resolve(&Scenario::from_str(&text, &path).unwrap())
        .unwrap()
        .runs[0]
        .params
        .h;
    for p in &done {
        assert!(p.status.is_complete(), "{}: {}", p.label(), p.status);
        common::assert_dissipates(&p.summary["traction"], 50.0, h);
    }
    let csv = std::fs::read_to_string(dir.join("creep_ladder.csv")).unwrap();
    eprintln!("{csv}");
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let row: Vec<&str> = lines
        .find(|l| l.starts_with("0,"))
        .unwrap()
        .split(',')
        .collect();
    let col = |name: &str| -> f64 {
        let k = head.iter().position(|h| *h == name).unwrap();
        row[k].parse().unwrap()
    };
    let [x1, x2] = ["4608", "9216"].map(|z| col(&format!("mu_a_R@wheel.zone_rim_nodes={z}")));
    let limit = x2 + (x2 - x1) / (2f64.powf(LADDER_ORDER) - 1.0);
    // The unit: mu a / R with the finer rung's a, as the CSV's.
    let t = &done.last().unwrap().summary["traction"];
    let unit = 0.3 * t["hertz_half_width"].as_f64().unwrap() / 0.1;
    let eps_c = smooth_strain(&wheel(&[("wheel.zone_rim_nodes", "9216")], true));
    let reference = HALF_SPACE_FREE_ROLLING - eps_c / unit;
    eprintln!(
        "free rolling {x1:.4} / {x2:.4} mu a / R, extrapolated at order {LADDER_ORDER}: {limit:.4}; the half-space's {HALF_SPACE_FREE_ROLLING} less the wheel's smooth strain {:.4}: {reference:.4} ({:+.2}%); the finer rung {:+.2}% from it",
        eps_c / unit,
        100.0 * (limit / reference - 1.0),
        100.0 * (x2 / reference - 1.0)
    );
    assert!(x1 < x2 && x2 < reference, "{x1} {x2} -> {reference}");
    assert!((x2 / reference - 1.0).abs() < 0.05, "{x2} vs {reference}");
    assert!(
        (limit / reference - 1.0).abs() < 0.01,
        "{limit} vs {reference}"
    );
}
