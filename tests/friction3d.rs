//! Coulomb friction in 3D: a solid block (hexahedra, `softway::bodies::solid`) pressed on a
//! rigid floor by a body force and sliding, or pushed, in an oblique direction, through the
//! joined model, the rows' Coulomb cone and the driver, with the space-time exact hold (the
//! treatment the planar sliding block is checked with in `tests/friction.rs`).
//!
//! The soft way is not used here: on this plate, whose vibrations the step resolves
//! (h = 5 us), the soft way with friction lets the plate's vertical vibration grow while it
//! slides (from 1e-4 to 0.1 m/s in 3 ms, the plate hopping off the floor), also at 0 degrees
//! where the second tangent carries nothing, while it stays at 1e-4 m/s without friction
//! and with the exact hold: a matter of the soft way's friction on a sliding body, not of
//! the cone.
//!
//! The exact answers are those of a rigid block on Coulomb's isotropic cone (the block is
//! steel and small: its elastic motion is a vibration about the rigid one): pressed by the
//! acceleration `g` and sliding at `v0`, it decelerates at `mu g` along `-v0 / |v0|` and
//! stops after `|v0| / (mu g)`, in a straight line (the elastic block's rocking turns it by
//! micro-radians); pushed sideways by the acceleration
//! `a < mu g` it sticks, by `a > mu g` it accelerates at `a - mu g` along the push. A box of
//! two 1D bounds in place of the cone would brake each component of an oblique slide by
//! `mu g`: the slide would turn toward the larger component and stop later, the checks
//! below would fail. The floor's tangential impulse is the block's change of momentum (the
//! only horizontal force besides the push), to round-off.

use std::sync::atomic::AtomicBool;

use softway::bodies::solid::{solid, SolidSpec};
use softway::bodies::{self};
use softway::contact::obstacle::{HalfSpace, Plane};
use softway::contact::search::Motion;
use softway::contact::{FrictionLaw, Obstacle, Pair, Treatment};
use softway::linalg::SparseLu;
use softway::material::{Elastic, PlaneModel};
use softway::mesh::generators::box_mesh;
use softway::mesh::CellKind;
use softway::simulation::Simulation;
use softway::time::Integrator;

const STEEL: Elastic = Elastic {
    young: 210e9,
    poisson: 0.3,
    density: 7850.0,
};

/// The pressing acceleration, m/s^2, and the friction coefficient.
const G: f64 = 1000.0;
const MU: f64 = 0.3;

/// What a run of the block gave.
struct Slide {
    /// Times, s, and the block's mean horizontal velocity (x, y) at each step, m/s.
    t: Vec<f64>,
    v: Vec<[f64; 2]>,
    /// The block's mean horizontal displacement at the end, m.
    x_end: [f64; 2],
    /// The block's mass, kg.
    mass: f64,
    /// The floor's tangential impulse along x and y over the run, N s.
    impulse: [f64; 2],
    /// The floor's largest tangential force over the normal force, once pressed.
    ratio: f64,
}

/// A steel plate of 0.1 x 0.1 x 0.02 m, 2 x 2 x 1 hexahedra, on the floor `z = 0`, pressed by `G`,
/// with the initial horizontal velocity `v0` and the horizontal body acceleration `push`,
/// for `steps` steps of `h`.
fn slide(v0: [f64; 2], push: [f64; 2], h: f64, steps: usize) -> Slide {
    let mesh = box_mesh(CellKind::Hex8, [0.1, 0.1, 0.02], [2, 2, 1]).unwrap();
    let bottom = mesh.node_set("z0").unwrap().to_vec();
    let spec = SolidSpec {
        material: STEEL,
        plane: PlaneModel::Stress,
        thickness: 1.0,
        lumped: false,
    };
    let mut block = solid("block", mesh, &spec, Motion::Fixed).unwrap().body;
    let n_dofs = block.model.n();
    // The nodal masses along each axis (M 1_c), for the body force and the momentum.
    let mass_along = |c: usize| {
        let ones: Vec<f64> = (0..n_dofs)
            .map(|d| f64::from(u8::from(d % 3 == c)))
            .collect();
        let mut out = vec![0.0; n_dofs];
        softway::linalg::spmv_add(block.model.pattern(), &block.model.m, 1.0, &ones, &mut out);
        out
    };
    let m_axis = [mass_along(0), mass_along(1), mass_along(2)];
    block.load = (0..n_dofs)
        .map(|d| {
            let a = [push[0], push[1], -G][d % 3];
            a * m_axis[d % 3][d]
        })
        .collect();
    let mass: f64 = m_axis[0].iter().sum();
    // The start: at rest on the floor under the pressing force alone (the static solution
    // with the bottom held), so that the run starts without a vertical vibration.
    block.u0 = {
        let mut fixed = vec![false; n_dofs];
        for &i in &bottom {
            for c in 0..3 {
                fixed[3 * i + c] = true;
            }
        }
        let pattern = block.model.pattern();
        let mut k = block.model.k.clone();
        softway::linalg::set_identity_rows(pattern, &mut k, &fixed);
        let mut u: Vec<f64> = (0..n_dofs)
            .map(|d| {
                if fixed[d] || d % 3 != 2 {
                    0.0
                } else {
                    block.load[d]
                }
            })
            .collect();
        SparseLu::new(pattern, &k).unwrap().solve_in_place(&mut u);
        u
    };
    let bodies = vec![block];
    let joined = bodies::assemble(&bodies).unwrap();
    let integrator = Integrator::SpaceTime {
        alpha: 0.8,
        gamma: 0.0,
        coriolis: softway::time::Coriolis::Implicit,
    };
    let mut problem = joined.problem(&bodies, (Vec::new(), Vec::new()), (integrator, h, steps));
    let floor: Box<dyn Obstacle> = Box::new(Plane {
        half_space: HalfSpace {
            normal: [0.0, 0.0, 1.0],
            offset: 0.0,
        },
    });
    problem.obstacles = vec![floor];
    problem.pairs = bottom
        .iter()
        .map(|&node| Pair::Obstacle { node, obstacle: 0 })
        .collect();
    problem.friction = Some(FrictionLaw::coulomb(MU));
    problem.treatment = Treatment::Exact;
    problem.v0 = (0..n_dofs)
        .map(|d| if d % 3 < 2 { v0[d % 3] } else { 0.0 })
        .collect();
    let mut sim = Simulation::new(problem).unwrap();
    let mut out = Slide {
        t: Vec::new(),
        v: Vec::new(),
        x_end: [0.0; 2],
        mass,
        impulse: [0.0; 2],
        ratio: 0.0,
    };
    sim.run(&AtomicBool::new(false), |s| {
        let st = s.state;
        let mean_of =
            |c: usize, w: &[f64]| m_axis[c].iter().zip(w).map(|(m, v)| m * v).sum::<f64>() / mass;
        let mean = |c: usize| mean_of(c, &st.v);
        out.x_end = [mean_of(0, &st.u), mean_of(1, &st.u)];
        if st.k > 0 {
            let (mut fx, mut fy, mut fn_) = (0.0, 0.0, 0.0);
            for ps in &st.pairs {
                fx += ps.tangential_force;
                fy += ps.tangential_force_2;
                fn_ += ps.force;
            }
            out.impulse[0] += fx * h;
            out.impulse[1] += fy * h;
            if st.t > 20.0 * h {
                out.ratio = out.ratio.max(fx.hypot(fy) / fn_);
            }
        }
        out.t.push(st.t);
        out.v.push([mean(0), mean(1)]);
        Ok(())
    })
    .unwrap();
    out
}

/// Sliding at 1.5 m/s at 30 degrees: the block decelerates at `mu g` along its velocity and
/// stops at `|v0| / (mu g)` = 5 ms in a straight line (the velocity across the initial
/// direction below 0.2 % of `|v0|` while it slides), then stays at rest; the friction force never exceeds `mu`
/// times the normal force; the floor's tangential impulse is the block's change of
/// momentum. A box of two bounds would stop the y component (0.75 m/s) at 2.5 ms and turn
/// the slide onto the x axis.
#[test]
fn an_oblique_slide_decelerates_at_mu_g_in_a_straight_line_and_stops() {
    let (speed, angle) = (1.5_f64, 30_f64.to_radians());
    let v0 = [speed * angle.cos(), speed * angle.sin()];
    let h = 5e-6;
    let out = slide(v0, [0.0, 0.0], h, 1600);
    let t_stop = speed / (MU * G);
    // The direction while it slides (speed above 5 % of the start).
    for (t, v) in out.t.iter().zip(&out.v) {
        let s = v[0].hypot(v[1]);
        if s > 0.05 * speed {
            // The velocity across the initial direction: the elastic plate's vibration alone.
            let across = (v[1] * angle.cos() - v[0] * angle.sin()).abs();
            assert!(
                across < 2e-3 * speed,
                "t = {t}: {across} m/s across the slide"
            );
            // The speed follows v0 - mu g t within the block's vibration (1 %).
            let want = speed - MU * G * t;
            assert!(
                (s - want).abs() < 0.01 * speed,
                "t = {t}: {s} m/s, want {want}"
            );
        }
    }
    // Stopped within 2 % of the exact time, and at rest after it.
    let stop = out
        .t
        .iter()
        .zip(&out.v)
        .find(|(_, v)| v[0].hypot(v[1]) < 1e-3 * speed)
        .map(|(t, _)| *t)
        .expect("the block stops");
    assert!(
        (stop - t_stop).abs() < 0.02 * t_stop,
        "stopped at {stop} s, exact {t_stop} s"
    );
    let last = out.v.last().unwrap();
    assert!(last[0].hypot(last[1]) < 1e-3 * speed, "at rest: {last:?}");
    assert!(
        out.ratio <= MU * (1.0 + 1e-9),
        "|F_t| / F_n = {}",
        out.ratio
    );
    for c in 0..2 {
        let dp = out.mass * (last[c] - v0[c]);
        assert!(
            (out.impulse[c] - dp).abs() < 1e-6 * out.mass * speed,
            "axis {c}: impulse {} vs momentum change {dp}",
            out.impulse[c]
        );
    }
}

/// Pushed sideways at 40 degrees by half the friction's hold (`a = 0.5 mu g`) the block
/// sticks (its mean moves by its elastic shear and the corners' micro-slip after the sudden
/// push alone: 0.3 % of the free
/// motion `a t^2 / 2`, asserted below 1 %); pushed by twice it (`a = 2
/// mu g`) it slides along the push at `a - mu g`.
#[test]
fn a_push_inside_the_cone_sticks_and_beyond_it_slides_along_the_push() {
    let angle = 40_f64.to_radians();
    let dir = [angle.cos(), angle.sin()];
    let h = 5e-6;
    let steps = 800;
    let hold = slide([0.0; 2], dir.map(|d| 0.5 * MU * G * d), h, steps);
    let moved = hold.x_end[0].hypot(hold.x_end[1]);
    let free = 0.5 * (0.5 * MU * G) * hold.t.last().unwrap().powi(2);
    eprintln!("stuck: moved {moved:.3e} m, free {free:.3e} m");
    assert!(moved < 1e-2 * free, "stuck: moved {moved} m");
    let go = slide([0.0; 2], dir.map(|d| 2.0 * MU * G * d), h, steps);
    let (t, v) = (go.t.last().unwrap(), go.v.last().unwrap());
    let want = MU * G * t;
    let s = v[0].hypot(v[1]);
    eprintln!("pushed: {s} m/s, want {want}, angle {}", v[1].atan2(v[0]));
    assert!((s - want).abs() < 0.01 * want, "{s} m/s, want {want}");
    let across = (v[1] * angle.cos() - v[0] * angle.sin()).abs();
    assert!(
        across < 2e-3 * s,
        "slides along the push: {across} m/s across it"
    );
}
