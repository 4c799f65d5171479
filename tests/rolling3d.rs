//! A 3D wheel rolling in its own frame on the rigid base (the paper's rotating frame, §4, in
//! 3D): a steel annulus of hexahedra spun up about its axle (`bodies::spinning`), held at
//! its bore, pressed by the flattening of a base that turns about it and slides under it
//! by a longitudinal, a lateral and a spin creepage (`contact::RotatingBase`), with
//! Coulomb's isotropic cone on each rim node, the soft way.
//!
//! What is checked against an independent answer:
//! - **the normal force** against the 2D plane-stress wheel of the same size, flattening,
//!   rim nodes and step (the `wheel` kind: triangles on a graded disk, another element and
//!   mesh), within 2 %;
//! - **full slip**: every loaded node slides, so the tangential force on the wheel is `mu`
//!   times the normal force; it opposes the slip of the wheel on the base, which is the
//!   rigid slip `V (xi t_b + eta e_z)` plus the elastic slip of the deformed rim passing
//!   through the patch: the force turns away from the creepage's direction by the elastic
//!   share, which falls as the creepage grows (a box of two bounds in place of the cone
//!   would turn it toward the diagonal and keep it there);
//! - **the mirror** of the wheel about its mid-plane maps `eta` to `-eta`, the lateral force
//!   to its opposite, and keeps the rest.
//!
//! Not checked here: the partial-slip creep forces, which on these meshes move by half
//! their value when the rings are doubled (docs/src/solids3d.md, "Rolling in 3D").

mod common;

use std::sync::atomic::AtomicBool;

use softway::bodies::rolling3d::{PatchForce, RollingSlice, SliceSpec};
use softway::contact::obstacle::Flattening;
use softway::contact::FrictionLaw;
use softway::material::Elastic;
use softway::simulation::Simulation;

const STEEL: Elastic = Elastic {
    young: 2.05e11,
    poisson: 0.3,
    density: 7830.0,
};
/// The wheel: radius, bore and thickness, m; rings, sectors and layers of hexahedra.
const R: f64 = 0.1;
const BORE: f64 = 0.04;
const T: f64 = 0.01;
const COUNTS: [usize; 3] = [12, 192, 1];
/// The spin, rad/s, the flattening, m, and its ramp, s; the friction coefficient; the step.
const OMEGA: f64 = 300.0;
const DEPTH: f64 = 1e-3;
const SETTLE: f64 = 3e-3;
const MU: f64 = 0.3;
const H: f64 = 1e-5;

/// The rolling part of a run: per step, the normal force and the tangential force on the
/// wheel along the base's travel `t_b` and along the axle `e_z`, N.
struct Rolled {
    normal: Vec<f64>,
    along: Vec<f64>,
    lateral: Vec<f64>,
}

impl Rolled {
    fn mean(v: &[f64]) -> f64 {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

fn slice(xi: f64, eta: f64, phi: f64) -> RollingSlice {
    RollingSlice::new(&SliceSpec {
        radius: R,
        bore: BORE,
        thickness: T,
        counts: COUNTS,
        material: STEEL,
        lumped: false,
        omega: OMEGA,
        flattening: Flattening {
            depth: DEPTH,
            settle_time: SETTLE,
        },
        creepages: [xi, eta, phi],
        zone: None,
        crown: None,
        coupling: softway::bodies::wheel::Coupling::Coupled,
        rail: None,
    })
    .unwrap()
}

/// Rolls the wheel `steps` steps with the creepages `(xi, eta, phi)`, the soft way;
/// records the steps after the flattening's ramp and a settling of as long again.
fn roll(xi: f64, eta: f64, phi: f64, steps: usize) -> Rolled {
    let slice = slice(xi, eta, phi);
    let problem = slice.problem((0.8, 0.2), H, steps, FrictionLaw::coulomb(MU));
    let mut sim = Simulation::new(problem).unwrap();
    let mut out = Rolled {
        normal: Vec::new(),
        along: Vec::new(),
        lateral: Vec::new(),
    };
    let base = slice.base;
    sim.run(&AtomicBool::new(false), |v| {
        let st = v.state;
        if st.t >= 2.0 * SETTLE {
            let f = PatchForce::of(&base, st.t, &st.pairs);
            out.normal.push(f.normal);
            out.along.push(f.along);
            out.lateral.push(f.lateral);
        }
        Ok(())
    })
    .unwrap();
    out
}

const STEPS: usize = 1000;

/// The mean of a run's normal force and of its tangential force along `t_b` and `e_z`.
fn means(r: &Rolled) -> (f64, f64, f64) {
    (
        Rolled::mean(&r.normal),
        Rolled::mean(&r.along),
        Rolled::mean(&r.lateral),
    )
}

/// Full slip at 20 % and 40 % creepage, 30 degrees off the rolling direction: the mean
/// tangential force is `mu` times the mean normal force; it opposes the rigid slip but for
/// the elastic slip's turn, which falls as the creepage grows; the mirrored creepage
/// mirrors the lateral force and keeps the longitudinal and normal ones.
#[test]
fn in_full_slip_the_force_is_mu_n_against_the_slip_and_mirrors_with_it() {
    let angle = 30_f64.to_radians();
    let mut turns = Vec::new();
    for c in [0.2_f64, 0.4] {
        let (xi, eta) = (c * angle.cos(), c * angle.sin());
        let r = roll(xi, eta, 0.0, STEPS);
        let (n, fa, fl) = means(&r);
        let ratio = fa.hypot(fl) / (MU * n);
        // The force on the wheel opposes its slip on the base.
        let turn = (fl.atan2(fa) - (-eta).atan2(-xi)).abs();
        println!(
            "full slip at {c} x ({xi:.4}, {eta:.4}): N = {n:.1} N, F = ({fa:.1}, {fl:.1}) N, |F|/(mu N) = {ratio:.5}, turned {:.2} degrees from the creepage",
            turn.to_degrees()
        );
        assert!(n > 1e5, "{n}");
        assert!((ratio - 1.0).abs() < 5e-3, "{c}: {ratio}");
        turns.push(turn);
        if c == 0.2 {
            let (nb, fab, flb) = means(&roll(xi, -eta, 0.0, STEPS));
            println!("mirrored: N = {nb:.1} N, F = ({fab:.1}, {flb:.1}) N");
            assert!((nb / n - 1.0).abs() < 1e-9, "{nb} {n}");
            assert!((fab / fa - 1.0).abs() < 1e-9, "{fab} {fa}");
            assert!((flb / fl + 1.0).abs() < 1e-9, "{flb} {fl}");
        }
    }
    assert!(turns[0] < 10_f64.to_radians(), "{turns:?}");
    assert!(turns[1] < 0.7 * turns[0], "{turns:?}");
}

/// Rolling freely, the 3D slice carries the 2D plane-stress wheel's normal force (the
/// `wheel` kind on its graded disk of triangles, the same radius, bore, thickness,
/// flattening, rim nodes and step) within 2 %.
#[test]
fn the_slice_carries_the_plane_stress_wheels_force() {
    let (n, fa, _) = means(&roll(0.0, 0.0, 0.0, STEPS));
    let text = format!(
        r#"
name = "slice-2d"
kind = "wheel"
[time]
alpha = 0.8
gamma = 0.2
h = {H}
[wheel]
radius = {R}
thickness = {T}
rim_nodes = {}
plane = "stress"
mass = "consistent"
support = "hub"
hub_radius = {BORE}
[material]
young = {}
poisson = {}
density = {}
[rolling]
omega = {OMEGA}
flattening = {DEPTH}
settle_time = {SETTLE}
turns = 0.3
creepage = 0.0
[contact]
method = "soft_way"
friction = {MU}
"#,
        COUNTS[1], STEEL.young, STEEL.poisson, STEEL.density
    );
    let (_dir, s) = common::run_in_process(std::path::Path::new("slice-2d.toml"), &text, "slice");
    let n2 = s["mean_contact_force"].as_f64().unwrap();
    let q2 = s["traction"]["traction"].as_f64().unwrap();
    println!(
        "free rolling: 3D slice N = {n:.1} N, Q = {:.1} N; 2D plane stress N = {n2:.1} N, Q = {q2:.1} N; N {:+.2} %",
        -fa,
        100.0 * (n / n2 - 1.0)
    );
    assert!((n / n2 - 1.0).abs() < 0.02, "{n} against {n2}");
}

/// The rim repeats round the axle, so the contact's columns of every rim node are one
/// sector's turned (`contact::cyclic`): with them turned, the run solves only the base
/// sector's columns (three per rim node of one sector, and the check's one) where it
/// solved one per new rim dof, and rolls the same, step by step, to round-off (full slip,
/// where no stick/slip decision sits on a knife's edge). A symmetry turned the wrong way
/// round is refused by the set-up's check.
#[test]
fn the_rims_columns_turned_from_one_sector_roll_as_the_solved_ones() {
    let (xi, eta) = (
        0.2 * 30_f64.to_radians().cos(),
        0.2 * 30_f64.to_radians().sin(),
    );
    let steps = 700;
    let s = slice(xi, eta, 0.0);
    let run = |turned: bool, again: bool| {
        let mut sim =
            Simulation::new(s.problem((0.8, 0.2), H, steps, FrictionLaw::coulomb(MU))).unwrap();
        if turned {
            sim.set_cyclic_symmetry(s.symmetry(COUNTS)).unwrap();
        }
        sim.set_predictions_again(again);
        let mut forces = Vec::new();
        let stats = sim
            .run(&AtomicBool::new(false), |v| {
                let f = PatchForce::of(&s.base, v.state.t, &v.state.pairs);
                forces.push([f.normal, f.along, f.lateral]);
                Ok(())
            })
            .unwrap();
        (forces, stats)
    };
    let (solved, st_solved) = run(false, true);
    let (turned, st_turned) = run(true, true);
    let scale = solved.iter().map(|f| f[0]).fold(0.0, f64::max);
    let apart = |x: &[[f64; 3]], y: &[[f64; 3]]| {
        x.iter()
            .zip(y)
            .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
            .fold(0.0, f64::max)
    };
    let worst = apart(&solved, &turned);

    // Every prediction solved: the same steps to round-off, with more solves. A re-solve
    // after a release and the interval a step back repeats are predicted again from the
    // cached columns.
    let (each, st_each) = run(true, false);
    let worst_each = apart(&each, &turned);
    println!(
        "predictions solved {} -> {} ({} made again, {} steps); largest difference {:.2e}",
        st_each.predictions,
        st_turned.predictions,
        st_turned.predictions_again,
        st_turned.steps,
        worst_each / scale
    );
    assert_eq!(st_each.predictions_again, 0);
    assert_eq!(
        st_each.predictions,
        st_turned.predictions + st_turned.predictions_again
    );
    assert!(st_turned.predictions_again > st_turned.steps / 20);
    assert!(worst_each < 1e-8 * scale, "{worst_each} of {scale}");
    let rim_per_sector = COUNTS[2] + 1;
    println!(
        "column solves {} -> {} ({} turned); largest difference of a step's force {:.2e} of the peak normal force {scale:.1} N",
        st_solved.column_solves,
        st_turned.column_solves,
        st_turned.columns_turned,
        worst / scale
    );
    assert_eq!(st_solved.columns_turned, 0);
    assert!(st_solved.column_solves > 20 * 3 * rim_per_sector);
    assert!(st_turned.column_solves <= 3 * rim_per_sector + 1);
    assert!(st_turned.columns_turned >= st_solved.column_solves);
    assert!(worst < 1e-8 * scale, "{worst} of {scale}");

    // The copies numbered the wrong way round: the check finds it.
    let [nr, nt, nz] = COUNTS;
    let mut labels = vec![(0, 0); (nr + 1) * nt * (nz + 1)];
    for k in 0..=nz {
        for j in 0..nt {
            for i in 0..=nr {
                labels[i + (nr + 1) * (j + nt * k)] = (i + (nr + 1) * k, (nt - j) % nt);
            }
        }
    }
    let wrong = softway::contact::cyclic::CyclicSymmetry::new(3, nt, &labels).unwrap();
    let mut sim =
        Simulation::new(s.problem((0.8, 0.2), H, steps, FrictionLaw::coulomb(MU))).unwrap();
    let err = sim.set_cyclic_symmetry(wrong).unwrap_err().to_string();
    assert!(err.contains("does not repeat round its axle"), "{err}");
}
