//! The 3D wheel's refined zone that moves with the contact (`mesh::zone3d`, the paper's
//! Fig. 4b in 3D): the annulus swept through stations fine under the base, its frame turned
//! back by one outer sector each time the base has turned half a sector past the zone's
//! centre, the state relabelled (`simulation::Relocation`), the matrix and its factor kept.
//!
//! What is checked against an independent answer:
//! - **a relocation is a relabelling**: on a zone of the outer pitch (every station lands on
//!   a station) the run with relocations rolls as the plain annulus, which never relocates,
//!   step by step to round-off (full slip, where no stick/slip decision sits on a knife's
//!   edge);
//! - **the zone gives the uniform rim of its pitch**: a 192-sector rim refined to the pitch
//!   of 768 under the base carries the normal force and the creep force of the uniform
//!   768-sector rim (another mesh, which never relocates), in partial slip, solving a
//!   quarter of its contact columns or fewer (the patch stays on the zone's nodes, whose
//!   columns are kept).

use std::sync::atomic::AtomicBool;

use softway::bodies::rolling3d::{PatchForce, RollingSlice, SliceSpec, SliceZone};
use softway::contact::obstacle::Flattening;
use softway::contact::{FrictionLaw, RotatingBase};
use softway::material::Elastic;
use softway::simulation::{Relocation, RunStats, Simulation};

const STEEL: Elastic = Elastic {
    young: 2.05e11,
    poisson: 0.3,
    density: 7830.0,
};
const OMEGA: f64 = 300.0;
const MU: f64 = 0.3;
const H: f64 = 1e-5;
const SETTLE: f64 = 1e-3;

fn slice(counts: [usize; 3], zone: Option<SliceZone>, xi: f64, eta: f64) -> RollingSlice {
    RollingSlice::new(&SliceSpec {
        radius: 0.1,
        bore: 0.04,
        thickness: 0.01,
        counts,
        material: STEEL,
        lumped: false,
        omega: OMEGA,
        flattening: Flattening {
            depth: 1e-3,
            settle_time: SETTLE,
        },
        creepages: [xi, eta, 0.0],
        zone,
        crown: None,
        coupling: softway::bodies::wheel::Coupling::Coupled,
        rail: None,
    })
    .unwrap()
}

/// Rolls `s` for `steps` steps, relocating its zone if it has one: per step the normal
/// force and the tangential forces along the base's travel and the axle, N.
fn roll(s: &RollingSlice, steps: usize) -> (Vec<[f64; 3]>, RunStats) {
    let mut sim =
        Simulation::new(s.problem((0.8, 0.2), H, steps, FrictionLaw::coulomb(MU))).unwrap();
    if let Some(z) = &s.zone {
        sim.set_relocation(Relocation {
            sources: z.sources.clone(),
            step: z.step,
            omega: OMEGA,
            angle0: 0.0,
            turned: z.turned,
        })
        .unwrap();
    }
    let mut forces = Vec::new();
    let stats = sim
        .run(&AtomicBool::new(false), |v| {
            // The base as the mesh's frame sees it.
            let mut b: RotatingBase = s.base;
            b.line.theta0 -= v.frame_angle;
            let f = PatchForce::of(&b, v.state.t, &v.state.pairs);
            forces.push([f.normal, f.along, f.lateral]);
            Ok(())
        })
        .unwrap();
    (forces, stats)
}

#[test]
fn a_relocation_of_a_zone_at_the_outer_pitch_is_a_relabelling() {
    let counts = [4, 96, 1];
    let (xi, eta) = (
        0.2 * 30_f64.to_radians().cos(),
        0.2 * 30_f64.to_radians().sin(),
    );
    let zone = SliceZone {
        sectors: 96,
        width: 30_f64.to_radians(),
        growth: None,
        depth: None,
        axial: None,
    };
    let steps = 400;
    let zoned = slice(counts, Some(zone), xi, eta);
    let z = zoned.zone.as_ref().unwrap();
    assert_eq!(z.exact_nodes, z.sources.len());
    let (with, st) = roll(&zoned, steps);
    let (plain, st0) = roll(&slice(counts, None, xi, eta), steps);
    let scale = plain.iter().map(|f| f[0]).fold(0.0, f64::max);
    let worst = with
        .iter()
        .zip(&plain)
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
        .fold(0.0, f64::max);
    // One relocation per sector the base turns: omega t / step, rounded.
    let expected = ((OMEGA * steps as f64 * H) / z.step + 0.5).floor() as usize;
    println!(
        "{} relocations ({} expected), {} steps; largest difference {:.2e} of the peak normal force {:.1} N",
        st.relocations,
        expected,
        st.steps,
        worst / scale,
        scale
    );
    assert_eq!(st0.relocations, 0);
    assert!(st.relocations.abs_diff(expected) <= 1, "{}", st.relocations);
    assert!(scale > 1e5, "{scale}");
    assert!(worst < 1e-9 * scale, "{worst}");
}

#[test]
fn a_refined_zone_rolls_as_the_uniform_rim_of_its_pitch() {
    let zone = SliceZone {
        sectors: 768,
        width: 40_f64.to_radians(),
        growth: None,
        depth: None,
        axial: None,
    };
    let steps = 700;
    let xi = 0.005;
    let zoned = slice([4, 192, 1], Some(zone), xi, 0.0);
    let (with, st) = roll(&zoned, steps);
    let (uniform, st_u) = roll(&slice([4, 768, 1], None, xi, 0.0), steps);
    // The last half of the rolling after the ramp and as long again.
    let from = ((2.0 * SETTLE / H) as usize + steps) / 2;
    let mean = |f: &[[f64; 3]], c: usize| {
        f[from..].iter().map(|x| x[c]).sum::<f64>() / (f.len() - from) as f64
    };
    let (n_z, n_u) = (mean(&with, 0), mean(&uniform, 0));
    let (q_z, q_u) = (
        -mean(&with, 1) / (MU * n_z),
        -mean(&uniform, 1) / (MU * n_u),
    );
    println!(
        "zone 768 on 192 ({} relocations, {} of {} unknowns): N = {:.1} N, Q/(mu N) = {q_z:.4}; uniform 768: N = {:.1} N, Q/(mu N) = {q_u:.4}; N {:+.3} %",
        st.relocations,
        3 * zoned.bodies[0].mesh.n_nodes(),
        3 * 5 * 768 * 2,
        n_z,
        n_u,
        100.0 * (n_z / n_u - 1.0)
    );
    // The patch stays on the zone's nodes: their columns are solved once and kept, where
    // the uniform rim solves one for every rim node the patch reaches.
    println!(
        "column solves: {} with the zone, {} on the uniform rim",
        st.column_solves, st_u.column_solves
    );
    assert!(
        4 * st.column_solves < st_u.column_solves,
        "{} vs {}",
        st.column_solves,
        st_u.column_solves
    );
    assert!(st.relocations > 10);
    assert!((n_z / n_u - 1.0).abs() < 5e-3, "{n_z} vs {n_u}");
    assert!((q_z - q_u).abs() < 0.01, "{q_z} vs {q_u}");
}
