//! The wheel rolling on the track (issue 30): the elastic wheel in its rotating frame on a
//! moving hub with its unsprung mass, loaded through the axle, on the UIC60 rail on pads,
//! sleepers and ballast, through the contact search.

use softway::contact::profile::Profile;
use softway::mesh::generators::{disk_graded, DiskOptions};
use softway::simulation::Simulation;
use softway::time::{Coriolis, Integrator};
use softway::track::rolling::{Vehicle, WheelOnTrack};
use softway::track::TrackSpec;
use softway::wheel::{Support, WheelModel, WheelSpec};
use std::sync::atomic::AtomicBool;

/// One step's record.
#[derive(Debug, Clone, Copy)]
struct Rec {
    t: f64,
    force: f64,
    axle_y: f64,
    rail_w: f64,
}

struct Setup {
    rim: usize,
    speed: f64,
    h: f64,
    bays: usize,
    duration: f64,
    settle: f64,
    profile: Option<Profile>,
}

fn wheel(rim: usize, speed: f64) -> WheelModel {
    let mesh = disk_graded(
        0.46,
        rim,
        DiskOptions {
            hub: Some(0.1),
            grading: 1.3,
        },
    )
    .unwrap();
    let spec = WheelSpec {
        radius: 0.46,
        thickness: 0.02,
        plane: softway::material::PlaneModel::Strain,
        support: Support::Hub { radius: 0.1 },
        material: softway::material::Elastic {
            young: 2.1e11,
            poisson: 0.3,
            density: 7850.0,
        },
        ..WheelSpec::paper()
    };
    // omega = V / R_s: find R_s at a first omega, then rebuild (R_s moves by ~1e-7).
    let mut omega = speed / 0.46;
    for _ in 0..3 {
        let w = WheelModel::new(
            mesh.clone(),
            WheelSpec {
                omega,
                ..spec.clone()
            },
        )
        .unwrap();
        omega = speed / w.spinning_radius();
    }
    WheelModel::new(mesh, WheelSpec { omega, ..spec }).unwrap()
}

fn roll(s: Setup) -> (WheelOnTrack, Vec<Rec>) {
    let track = TrackSpec {
        bays: s.bays,
        ends: softway::track::Ends::Absorbing {
            bays: s.bays / 4,
            damping: 1000.0,
        },
        ..TrackSpec::uic60()
    };
    let vehicle = Vehicle {
        unsprung_mass: 800.0,
        axle_load: 100e3,
        speed: s.speed,
        suspension_stiffness: std::env::var("KS")
            .map(|v| v.parse().unwrap())
            .unwrap_or(0.0),
        suspension_damping: std::env::var("CS")
            .map(|v| v.parse().unwrap())
            .unwrap_or(0.0),
        gravity: 9.81,
        settle: s.settle,
    };
    let start = (s.bays / 4 + 1) as f64 * track.spacing;
    let wot = WheelOnTrack::new(wheel(s.rim, s.speed), &track, vehicle, start, s.profile).unwrap();
    let steps = (s.duration / s.h).round() as usize;
    let integ = Integrator::SpaceTime {
        alpha: std::env::var("ALPHA")
            .map(|v| v.parse().unwrap())
            .unwrap_or(0.8),
        gamma: 0.0,
        coriolis: Coriolis::Implicit,
    };
    let mut problem = wot.problem(integ, s.h, steps);
    match std::env::var("TREAT").as_deref() {
        Ok("exact") => problem.treatment = softway::contact::Treatment::Exact,
        Ok("nothing") => {
            problem.treatment = softway::contact::Treatment::SoftWay {
                restore: softway::contact::Restore::Nothing,
            }
        }
        Ok("braking") => {
            problem.treatment = softway::contact::Treatment::SoftWay {
                restore: softway::contact::Restore::BrakingReaction,
            }
        }
        _ => {}
    }
    let mut sim = Simulation::new(problem).unwrap();
    let mut recs = Vec::with_capacity(steps);
    let res = sim.run(&AtomicBool::new(false), |v| {
        let t = v.state.t;
        let u = &v.state.state.u;
        if v.state.k
            % std::env::var("EVERY")
                .map(|v| v.parse().unwrap())
                .unwrap_or(50)
            == 0
        {
            let a = wot.axle_ground(t, u);
            println!(
                "{:.4} F {:.1} kN axle {:.4} {:.4} mm rail {:.4} mm E {:.1} held {}",
                t,
                v.contact_force * 1e-3,
                a[0] * 1e3,
                a[1] * 1e3,
                wot.rail_deflection(wot.under_axle(t), u).unwrap() * 1e3,
                v.kinetic() + v.strain(),
                v.held
            );
        }
        if let Ok(dbg) = std::env::var("DBG") {
            let (a, b): (usize, usize) = {
                let mut it = dbg.split(',').map(|x| x.parse().unwrap());
                (it.next().unwrap(), it.next().unwrap())
            };
            if (a..=b).contains(&v.state.k) {
                let list: Vec<String> = v
                    .state
                    .pairs
                    .iter()
                    .enumerate()
                    .filter(|(_, p)| p.gap < 2e-4 || p.force != 0.0)
                    .map(|(i, p)| {
                        format!(
                            "[{i} {:?} g {:.2e} f {:.1} h{} b{} r{} bf {:.1} rs {:?}]",
                            p.mode,
                            p.gap,
                            p.force * 1e-3,
                            p.held as u8,
                            p.braked as u8,
                            p.released as u8,
                            p.brake_force * 1e-3,
                            p.restore
                        )
                    })
                    .collect();
                println!("k {} {}", v.state.k, list.join(" "));
            }
        }
        recs.push(Rec {
            t,
            force: v.contact_force,
            axle_y: wot.axle_ground(t, u)[1],
            rail_w: wot.rail_deflection(wot.under_axle(t), u).unwrap(),
        });
        Ok(())
    });
    if let Err(e) = res {
        println!("FAILED at {:.4}: {e}", recs.last().map_or(0.0, |r| r.t));
    }
    (wot, recs)
}

#[test]
fn experiment() {
    let t0 = std::time::Instant::now();
    let (wot, recs) = roll(Setup {
        rim: std::env::var("RIM")
            .map(|v| v.parse().unwrap())
            .unwrap_or(360),
        speed: std::env::var("V")
            .map(|v| v.parse().unwrap())
            .unwrap_or(27.78),
        h: std::env::var("H")
            .map(|v| v.parse().unwrap())
            .unwrap_or(1e-4),
        bays: 60,
        duration: 0.3,
        settle: 0.05,
        profile: None,
    });
    let half = &recs[recs.len() / 2..];
    let mean = half.iter().map(|r| r.force).sum::<f64>() / half.len() as f64;
    let sd =
        (half.iter().map(|r| (r.force - mean).powi(2)).sum::<f64>() / half.len() as f64).sqrt();
    println!(
        "mean F (second half) {:.2} kN, sd {:.2} kN, reached t = {:.4}",
        mean * 1e-3,
        sd * 1e-3,
        recs.last().unwrap().t
    );
    println!(
        "{} dofs, wheel {:.1} kg, axle {:.1} kg, {:?}",
        wot.joined.model.n(),
        wot.wheel_mass,
        wot.axle_mass,
        t0.elapsed()
    );
    for r in recs.iter().step_by(100) {
        println!(
            "{:.4} F {:.1} kN axle {:.3} mm rail {:.3} mm",
            r.t,
            r.force * 1e-3,
            r.axle_y * 1e3,
            r.rail_w * 1e3
        );
    }
}
