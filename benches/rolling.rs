//! The wheel rolling on the track (`softway::track::rolling`): 60 steps of the wheel on its
//! moving hub pressed by its full load onto the UIC60 track at 100 km/h, a third of a rim
//! node's passage a step, contact held from the first step, on 360 and 720 rim nodes (the
//! shipped scenario's); the model is built and factored outside the timed loop. The cost
//! per step is the time over 60; compare the two sizes as a ratio within one run.

use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use softway::contact::Treatment;
use softway::mesh::generators::{disk_graded, DiskOptions};
use softway::simulation::Simulation;
use softway::time::{Coriolis, Integrator};
use softway::track::rolling::{wheel_at_speed, Vehicle, WheelOnTrack};
use softway::track::TrackSpec;
use softway::wheel::{Support, WheelSpec};
use std::sync::atomic::AtomicBool;

const SPEED: f64 = 100.0 / 3.6;
const STEPS: usize = 60;

fn model(rim: usize) -> (WheelOnTrack, f64) {
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
        ..WheelSpec::paper()
    };
    let wheel = wheel_at_speed(mesh, spec, SPEED).unwrap();
    let r_s = wheel.spinning_radius();
    let vehicle = Vehicle {
        unsprung_mass: 800.0,
        axle_load: 100e3,
        speed: SPEED,
        suspension_stiffness: 0.0,
        suspension_damping: 0.0,
        gravity: 9.81,
        settle: 0.0,
        creepage: 0.0,
        wheelbase: None,
    };
    let h = 2.0 * std::f64::consts::PI * r_s / rim as f64 / SPEED / 3.0;
    let track = TrackSpec::uic60();
    let start = 0.5 * track.length();
    (
        WheelOnTrack::new(wheel, &track, vehicle, start, None).unwrap(),
        h,
    )
}

fn bench_rolling(c: &mut Criterion) {
    let mut g = c.benchmark_group("rolling");
    g.sample_size(10);
    for rim in [360usize, 720] {
        let (wot, h) = model(rim);
        let integrator = Integrator::SpaceTime {
            alpha: 0.8,
            gamma: 0.0,
            coriolis: Coriolis::Implicit,
        };
        g.bench_with_input(BenchmarkId::new("steps_60", rim), &rim, |b, _| {
            b.iter_batched(
                || {
                    let mut p = wot.problem(integrator, h, STEPS);
                    p.treatment = Treatment::Exact;
                    Simulation::new(p).unwrap()
                },
                |mut sim| sim.run(&AtomicBool::new(false), |_| Ok(())).unwrap(),
                BatchSize::PerIteration,
            )
        });
    }
    g.finish();
}

criterion_group!(benches, bench_rolling);
criterion_main!(benches);
