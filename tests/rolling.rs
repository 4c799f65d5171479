//! The wheel rolling on the track (issue 30): the elastic wheel in its rotating frame on a
//! moving hub with its unsprung mass, loaded through the axle, on the UIC60 rail on pads,
//! sleepers and ballast, met through the contact search (`softway::track::rolling`).
//!
//! - On a smooth rail the mean contact force over whole sleeper bays is the static wheel
//!   load `F_axle + m_u g` (the axle's momentum balance: its mean acceleration is zero), and
//!   the force varies at the sleeper-passing frequency `V / s`.
//! - Over an irregularity made of harmonics at `V / lambda_i` between 27 and 63 Hz, the
//!   force's response per unit irregularity (the run with it less the smooth run, fitted by
//!   least squares at each `V / lambda_i`) peaks at the P2 frequency: the wheel's mass on
//!   its contact spring on the track's receptance (`track::receptance::p2_with`, an
//!   independent frequency-domain computation on the track alone, with the contact spring
//!   measured in the smooth run).

mod common;

use softway::contact::profile::Profile;
use softway::contact::{Restore, Treatment};
use softway::simulation::Simulation;
use softway::time::{Coriolis, Integrator};
use softway::track::receptance::p2_with;
use softway::track::rolling::{Vehicle, WheelOnTrack};
use softway::track::TrackSpec;
use softway::wheel::WheelModel;
use std::f64::consts::PI;
use std::sync::atomic::AtomicBool;

/// One step's record.
#[derive(Debug, Clone, Copy)]
struct Rec {
    t: f64,
    force: f64,
    axle_y: f64,
    rail_w: f64,
}

/// The runs' common data: 360 rim nodes (8 mm pitch), 40 m/s, three steps a rim node's
/// passage, 80 bays with 20 absorbing at each end, 0.5 s (20 m).
const RIM: usize = 360;
const SPEED: f64 = 40.0;
const BAYS: usize = 80;
const DURATION: f64 = 0.5;
const SETTLE: f64 = 0.05;
/// The fitted window, s.
const WINDOW: (f64, f64) = (0.15, 0.5);

fn track() -> TrackSpec {
    common::absorbing_track(BAYS)
}

/// A 0.46 m steel wheel 20 mm thick (plane strain) on a 0.1 m hub, turning at `V / R_s`.
fn wheel() -> WheelModel {
    common::steel_wheel_at(RIM, SPEED)
}

fn vehicle() -> Vehicle {
    Vehicle {
        unsprung_mass: 800.0,
        axle_load: 100e3,
        speed: SPEED,
        suspension_stiffness: 0.0,
        suspension_damping: 0.0,
        gravity: 9.81,
        settle: SETTLE,
        creepage: 0.0,
        wheelbase: None,
    }
}

/// The rail's abscissa under the axle at `t = 0`: just past the sponge.
fn start() -> f64 {
    21.0 * track().spacing
}

fn roll(treatment: Treatment, profile: Option<Profile>) -> (WheelOnTrack, Vec<Rec>) {
    roll_with(vehicle(), treatment, profile)
}

fn roll_with(
    vehicle: Vehicle,
    treatment: Treatment,
    profile: Option<Profile>,
) -> (WheelOnTrack, Vec<Rec>) {
    let wot = WheelOnTrack::new(wheel(), &track(), vehicle, start(), profile).unwrap();
    let pitch = 2.0 * PI * wot.rim_radius / RIM as f64;
    let h = pitch / SPEED / 3.0;
    let steps = (DURATION / h).round() as usize;
    let integrator = Integrator::SpaceTime {
        alpha: 0.8,
        gamma: 0.0,
        coriolis: Coriolis::Implicit,
    };
    let mut problem = wot.problem(integrator, h, steps);
    problem.treatment = treatment;
    let mut sim = Simulation::new(problem).unwrap();
    let mut recs = Vec::with_capacity(steps + 1);
    sim.run(&AtomicBool::new(false), |v| {
        let (t, u) = (v.state.t, &v.state.state.u);
        recs.push(Rec {
            t,
            force: v.contact_force,
            axle_y: wot.axle_ground(t, u)[1],
            rail_w: wot.rail_deflection(wot.under_axle(t), u).unwrap(),
        });
        Ok(())
    })
    .unwrap();
    (wot, recs)
}

/// The records from `t0` over a whole number of periods `period` up to `t1`.
fn whole_periods(recs: &[Rec], (t0, t1): (f64, f64), period: f64) -> &[Rec] {
    let n = ((t1 - t0) / period).floor();
    let end = t0 + n * period;
    let a = recs.iter().position(|r| r.t >= t0).unwrap();
    let b = recs.iter().position(|r| r.t >= end).unwrap_or(recs.len());
    &recs[a..b]
}

/// Least-squares amplitudes of `y(t)` at the frequencies `f` (with a constant).
fn amplitudes(t: &[f64], y: &[f64], f: &[f64]) -> Vec<f64> {
    let m = 2 * f.len() + 1;
    let basis = |tt: f64| {
        let mut row = vec![1.0];
        for &fi in f {
            let ph = 2.0 * PI * fi * tt;
            row.extend([ph.cos(), ph.sin()]);
        }
        row
    };
    let mut a = vec![vec![0.0; m + 1]; m];
    for (&tt, &yy) in t.iter().zip(y) {
        let r = basis(tt);
        for i in 0..m {
            for j in 0..m {
                a[i][j] += r[i] * r[j];
            }
            a[i][m] += r[i] * yy;
        }
    }
    // Gaussian elimination with partial pivoting.
    for c in 0..m {
        let p = (c..m)
            .max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))
            .unwrap();
        a.swap(c, p);
        let (top, below) = a.split_at_mut(c + 1);
        let pivot = &top[c];
        for row in below {
            let k = row[c] / pivot[c];
            for (x, y) in row[c..].iter_mut().zip(&pivot[c..]) {
                *x -= k * y;
            }
        }
    }
    let mut x = vec![0.0; m];
    for i in (0..m).rev() {
        let s: f64 = (i + 1..m).map(|j| a[i][j] * x[j]).sum();
        x[i] = (a[i][m] - s) / a[i][i];
    }
    (0..f.len())
        .map(|i| x[1 + 2 * i].hypot(x[2 + 2 * i]))
        .collect()
}

#[test]
fn on_a_smooth_rail_the_static_load_is_carried_and_the_force_varies_at_the_sleeper_passing_frequency(
) {
    let period = track().spacing / SPEED;
    let load = vehicle().static_load();
    for (name, treatment) in [
        ("exact", Treatment::Exact),
        (
            "soft way without restore",
            Treatment::SoftWay {
                restore: Restore::Nothing,
            },
        ),
    ] {
        let (_, recs) = roll(treatment, None);
        let w = whole_periods(&recs, WINDOW, period);
        let mean = w.iter().map(|r| r.force).sum::<f64>() / w.len() as f64;
        let err = mean / load - 1.0;
        println!(
            "{name}: mean contact force over {} sleeper bays {:.2} N against F_axle + m_u g = {load:.2} N ({err:+.2e})",
            ((WINDOW.1 - WINDOW.0) / period).floor(),
            mean
        );
        assert!(err.abs() < 5e-3, "{name}: mean force {mean} against {load}");
        // The force's spectrum below 1 kHz over the window: its largest line is V / s.
        let t: Vec<f64> = w.iter().map(|r| r.t).collect();
        let y: Vec<f64> = w.iter().map(|r| r.force - mean).collect();
        let span = t[t.len() - 1] - t[0] + (t[1] - t[0]);
        let lines: Vec<f64> = (1..(1000.0 * span) as usize)
            .map(|k| k as f64 / span)
            .collect();
        let dft = |f: f64| {
            let (c, s) = t.iter().zip(&y).fold((0.0, 0.0), |(c, s), (&tt, &yy)| {
                let ph = 2.0 * PI * f * tt;
                (c + yy * ph.cos(), s + yy * ph.sin())
            });
            2.0 * c.hypot(s) / y.len() as f64
        };
        let (best, amp) = lines
            .iter()
            .map(|&f| (f, dft(f)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap();
        println!(
            "{name}: strongest line {best:.2} Hz ({amp:.0} N) against V / s = {:.2} Hz",
            1.0 / period
        );
        assert!(
            (best - 1.0 / period).abs() < 0.5 / span,
            "{name}: strongest line {best} Hz, sleeper passing {} Hz",
            1.0 / period
        );
    }
}

/// With a primary suspension spring `k_s` about the axle's nominal position, the spring
/// carries `-k_s z` of the load (`z` the axle's drop): the mean contact force is
/// `F_axle + m_u g + k_s z_mean`.
#[test]
fn a_suspension_spring_takes_its_share_of_the_load() {
    let k_s = 2e6;
    let v = Vehicle {
        suspension_stiffness: k_s,
        suspension_damping: 2e4,
        ..vehicle()
    };
    let (_, recs) = roll_with(v, Treatment::Exact, None);
    let w = whole_periods(&recs, WINDOW, track().spacing / SPEED);
    let mean = |f: &dyn Fn(&Rec) -> f64| w.iter().map(f).sum::<f64>() / w.len() as f64;
    let (force, drop) = (mean(&|r| r.force), mean(&|r| r.axle_y));
    let expected = v.static_load() + k_s * drop;
    let err = force / expected - 1.0;
    println!("suspension: mean force {force:.1} N, axle {drop:.4e} m, expected {expected:.1} N ({err:+.2e})");
    assert!(
        k_s * drop < -0.01 * v.static_load(),
        "the spring carries a part"
    );
    assert!(err.abs() < 5e-3, "mean force {force} against {expected}");
}

#[test]
fn an_irregularity_excites_the_p2_resonance_where_v_over_the_wavelength_meets_it() {
    // Harmonics at 27, 30, .., 63 Hz at 40 m/s, 20 um each, faded in over the first 2 m.
    let freqs: Vec<f64> = (0..13).map(|i| 27.0 + 3.0 * i as f64).collect();
    let amp = 20e-6;
    let (x0, x1) = (start() - 1.0, start() + SPEED * DURATION + 2.0);
    let dx = 1e-3;
    let n = ((x1 - x0) / dx) as usize + 1;
    let phases: Vec<f64> = (0..freqs.len()).map(|i| 2.399 * i as f64).collect();
    let values: Vec<f64> = (0..n)
        .map(|k| {
            let x = k as f64 * dx;
            let fade = if x < 3.0 {
                0.5 * (1.0 - (PI * x / 3.0).cos())
            } else {
                1.0
            };
            fade * freqs
                .iter()
                .zip(&phases)
                .map(|(&f, &ph)| amp * (2.0 * PI * f / SPEED * x + ph).sin())
                .sum::<f64>()
        })
        .collect();
    let profile = Profile::sampled(x0, dx, values).unwrap();
    let treatment = Treatment::Exact;
    let (wot, smooth) = roll(treatment, None);
    let (_, rough) = roll(treatment, Some(profile));
    let a = smooth.iter().position(|r| r.t >= WINDOW.0).unwrap();
    let t: Vec<f64> = smooth[a..].iter().map(|r| r.t).collect();
    let df: Vec<f64> = rough[a..]
        .iter()
        .zip(&smooth[a..])
        .map(|(r, s)| r.force - s.force)
        .collect();
    let response: Vec<f64> = amplitudes(&t, &df, &freqs)
        .iter()
        .map(|a_f| a_f / amp)
        .collect();
    for (f, r) in freqs.iter().zip(&response) {
        println!("{f:5.1} Hz: {:.3e} N/m", r);
    }
    let i = (1..freqs.len() - 1)
        .max_by(|&i, &j| response[i].total_cmp(&response[j]))
        .unwrap();
    // The parabola through the peak and its neighbours.
    let (y0, y1, y2) = (response[i - 1], response[i], response[i + 1]);
    let peak = freqs[i] + 0.5 * 3.0 * (y0 - y2) / (y0 - 2.0 * y1 + y2);
    // The contact spring (wheel and contact in series) of the smooth run, and P2 on it.
    let load = vehicle().static_load();
    let w = &smooth[a..];
    let squeeze = w.iter().map(|r| r.rail_w - r.axle_y).sum::<f64>() / w.len() as f64;
    let k_c = load / squeeze;
    let built = track().build().unwrap();
    let mid = (BAYS / 2) as f64 * track().spacing + 0.5 * track().spacing;
    let above = (BAYS / 2) as f64 * track().spacing;
    let m_u = vehicle().unsprung_mass;
    let p2_mid = p2_with(&built, mid, m_u, k_c, 200).unwrap().unwrap();
    let p2_above = p2_with(&built, above, m_u, k_c, 200).unwrap().unwrap();
    let expected = 0.5 * (p2_mid + p2_above);
    let err = peak / expected - 1.0;
    println!(
        "contact spring {k_c:.3e} N/m; P2 {p2_mid:.2} Hz at mid-span, {p2_above:.2} Hz above a sleeper; rolling peak {peak:.2} Hz ({err:+.2e}); axle mass {:.1} kg",
        wot.axle_mass
    );
    assert!(
        response[i] > 1.5 * response[0] && response[i] > 1.5 * response[freqs.len() - 1],
        "a resonance peak inside the band: {response:?}"
    );
    assert!(err.abs() < 0.05, "peak {peak} Hz against P2 {expected} Hz");
}

/// The command line: `softway run` on the shipped wheel-on-track scenario (shortened to 6
/// recorded bays) writes its files, and its summary reads as physics: the mean contact
/// force over whole bays within 0.5% of the static load, the strongest line of the force at
/// the sleeper-passing frequency, P2 on the measured contact spring within 5% of the
/// receptance's (Hertz's 3D spring, a different contact: the track dominates the series).
/// A measured irregularity from a CSV next to the scenario is read and enters the gap.
#[test]
fn the_command_rolls_the_wheel_and_writes_its_files() {
    let dir = std::env::temp_dir().join(format!("softway-rolling-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/track.toml"))
            .unwrap()
            .replace("travel_bays = 20", "travel_bays = 6")
            .replace("settle_bays = 4", "settle_bays = 3");
    let scenario = dir.join("short.toml");
    std::fs::write(&scenario, &text).unwrap();
    let softway = |args: &[&str]| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_softway"))
            .args(args)
            .output()
            .unwrap();
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(
            o.status.success(),
            "{out}{}",
            String::from_utf8_lossy(&o.stderr)
        );
        out
    };
    let out = dir.join("run");
    print!(
        "{}",
        softway(&[
            "run",
            scenario.to_str().unwrap(),
            "--quiet",
            "--out",
            out.to_str().unwrap()
        ])
    );
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    assert!(history.starts_with(
        "run,t_s,distance_m,rail_x_m,settling,contact_force_N,nodes_in_contact,axle_displacement_m,axle_drift_m,rail_deflection_m,irregularity_m,pad_force_nearest_N,nearest_sleeper,tangential_force_N,slip_power_W,friction_energy_J\n"
    ));
    assert!(out.join("track.png").exists());
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let r = &s["runs"][0];
    let num = |k: &str| r[k].as_f64().unwrap_or_else(|| panic!("{k}: {}", r[k]));
    assert!(num("mean_over_static_minus_1").abs() < 5e-3, "{r}");
    let sleeper = num("sleeper_passing_hz");
    assert!(
        (num("dominant_frequency_hz") / sleeper - 1.0).abs() < 0.1,
        "{r}"
    );
    assert!(
        (num("p2_hz") / num("p2_hertz_hz") - 1.0).abs() < 0.05,
        "{r}"
    );
    assert!(num("time_per_step_us") > 0.0 && num("time_per_metre_s") > 0.0);
    // A measured profile: a 1 mm-deep dip 0.2 m long at 4.5 m from the start.
    let mut csv = String::from("x_m,r_m\n");
    for i in 0..=200 {
        let x = 4.4 + 0.001 * i as f64;
        let r = -0.5e-3 * (1.0 - (2.0 * PI * (x - 4.4) / 0.2).cos()) * 0.02;
        csv.push_str(&format!("{x},{r}\n"));
    }
    std::fs::write(dir.join("dip.csv"), csv).unwrap();
    let dipped = dir.join("dipped.toml");
    std::fs::write(
        &dipped,
        format!("{text}\n[irregularity]\ntype = \"measured\"\nfile = \"dip.csv\"\n"),
    )
    .unwrap();
    let out2 = dir.join("dipped");
    softway(&[
        "run",
        dipped.to_str().unwrap(),
        "--quiet",
        "--out",
        out2.to_str().unwrap(),
    ]);
    let h2 = std::fs::read_to_string(out2.join("history.csv")).unwrap();
    let deepest = h2
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(10).unwrap().parse::<f64>().unwrap())
        .fold(0.0, f64::min);
    assert!(
        (deepest + 2e-5).abs() < 1e-6,
        "the dip in the history: {deepest}"
    );
    // The same run to the dip, bit for bit; then the wheel drops into it.
    let rows = |h: &str| -> Vec<(f64, f64)> {
        h.lines()
            .skip(1)
            .map(|l| {
                let c: Vec<f64> = l.split(',').skip(1).map(|v| v.parse().unwrap()).collect();
                (c[1], c[4])
            })
            .collect()
    };
    let (a, b) = (rows(&history), rows(&h2));
    assert_eq!(a.len(), b.len());
    let mut after: f64 = 0.0;
    for (p, q) in a.iter().zip(&b) {
        if p.0 < 4.3 {
            assert_eq!(p.1, q.1, "before the dip at {} m", p.0);
        } else {
            after = after.max((p.1 - q.1).abs());
        }
    }
    println!("the dip changes the contact force by up to {after:.0} N");
    assert!(after > 1e3, "the dip changes the force: {after} N");
    let _ = std::fs::remove_dir_all(&dir);
}
