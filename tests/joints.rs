//! Discrete elements between bodies (`softway::bodies::Joints`): an axle node of its own
//! carrying a mass and a load on a spring to an elastic body, and springs joining two free
//! bodies, run through the driver (`Simulation`) on the joined model.
//!
//! - The axle (mass `m`, load `F` applied at `t = 0`) on a spring `k` to the top of a clamped
//!   elastic block of negligible mass: the axle sees the spring in series with the block's
//!   static flexibility at that node, `1 / k_s = 1 / k + c_b`, with `c_b` from a dense solve
//!   of the block's own stiffness (an independent computation): its period is
//!   `2 pi sqrt(m / k_s)` and its mean deflection `F / k_s`.
//! - Two free plates joined by a spring-damper between them and through an axle mass
//!   sprung to both: the forces are internal, so the total momentum (the axle's included)
//!   stays as it was while the spring passes it from one plate to the other.

use faer::linalg::solvers::Solve;
use softway::assembly::{assemble_mass_stiffness, Assembler, DofLayout};
use softway::bodies::{self, first_dofs, Body, Joints};
use softway::contact::search::Motion;
use softway::element::discrete::{Discrete, Hub, Link, SpringDamper, SpringKind};
use softway::linalg::spmv_add;
use softway::material::{Elastic, PlaneModel};
use softway::mesh::generators::rectangle;
use softway::model::LinearModel;
use softway::simulation::{Problem, Simulation};
use softway::time::Integrator;
use softway::wheel::triangle_geometry;
use std::f64::consts::PI;
use std::sync::atomic::AtomicBool;

const THICKNESS: f64 = 0.01;

/// A plate of steel's stiffness and `density`, `lx` by `ly` in `nx` by `ny` quads.
fn plate(lx: f64, ly: f64, nx: usize, ny: usize, density: f64) -> Body {
    let mat = Elastic {
        young: 2.1e11,
        poisson: 0.3,
        density,
    };
    let mesh = rectangle(lx, ly, nx, ny).unwrap();
    let (_, geometry) = triangle_geometry(&mesh).unwrap();
    let d = PlaneModel::Stress.elasticity_matrix(&mat);
    let asm = Assembler::new(&mesh);
    let (m, k) = assemble_mass_stiffness(&asm, &geometry, &d, &mat, THICKNESS, false);
    let model = LinearModel {
        c: asm.zeros(),
        assembler: asm,
        m,
        k: k.clone(),
    };
    Body::triangles("plate", mesh, model, k, Motion::Fixed)
}

/// The node of `set` nearest the abscissa `x`.
fn node_at(b: &Body, set: &str, x: f64) -> usize {
    let nodes = &b.mesh.node_sets[set];
    *nodes
        .iter()
        .min_by(|&&p, &&q| {
            let dx = |i: usize| (b.mesh.reference_positions()[2 * i] - x).abs();
            dx(p).total_cmp(&dx(q))
        })
        .unwrap()
}

/// The space-time scheme with `alpha = 0.8` (unconditionally stable; `alpha = 0.5` is not
/// past `omega h` ~ 2.8, which the plates' element modes exceed).
const SPACE_TIME: Integrator = Integrator::SpaceTime {
    alpha: 0.8,
    gamma: 0.0,
    coriolis: softway::time::Coriolis::Implicit,
};

/// `e_d^T K^-1 e_d` of the body's stiffness with its fixed dofs removed: a dense solve.
fn flexibility(b: &Body, dof: usize) -> f64 {
    let free: Vec<usize> = (0..b.mesh.n_dofs())
        .filter(|d| !b.fixed_dofs.contains(d))
        .collect();
    let full = b.model.assembler.to_dense(&b.elastic);
    let n = free.len();
    let k = faer::Mat::<f64>::from_fn(n, n, |i, j| full[(free[i], free[j])]);
    let mut e = faer::Mat::<f64>::zeros(n, 1);
    let at = free.iter().position(|&d| d == dof).unwrap();
    e[(at, 0)] = 1.0;
    let x = k.partial_piv_lu().solve(&e);
    x[(at, 0)]
}

/// The axle on a spring to a clamped block's top: period and mean against the series
/// spring's exact values, at 400 steps a period (errors 2.9e-5 and 6.6e-8 when written: the
/// period's is the scheme's own at this step, `alpha = 0.8`).
#[test]
fn an_axle_on_a_spring_to_an_elastic_block_sees_the_series_stiffness() {
    let mut block = plate(0.04, 0.01, 8, 2, 1.0);
    let bottom = block.mesh.node_sets["bottom"].clone();
    block.fixed_dofs = bottom.iter().flat_map(|&i| [2 * i, 2 * i + 1]).collect();
    let top = node_at(&block, "top", 0.02);
    let (mass, k, load) = (2.0, 2.0e8, -1.0e4);
    let c_b = flexibility(&block, 2 * top + 1);
    let k_s = 1.0 / (1.0 / k + c_b);
    let bodies = vec![block];
    let n_b = first_dofs(&bodies)[1];
    // The axle is node `n_b / 2` of the joined layout (two translations).
    let mut layout = DofLayout::new();
    layout.push_nodes(n_b / 2, 2);
    let axle = layout.push_nodes(1, 2).start;
    let mut discrete = Discrete::new();
    discrete
        .add_hub(
            &layout,
            &Hub {
                node: axle,
                translations: 2,
                mass,
                inertia: 0.0,
                load: vec![0.0, load],
            },
        )
        .unwrap();
    for c in 0..2 {
        discrete
            .add_spring(SpringDamper {
                link: Link::Between(2 * top + c, layout.dof(axle, c).unwrap()),
                kind: SpringKind::Translational,
                stiffness: k,
                damping: 0.0,
            })
            .unwrap();
    }
    let joints = Joints { dofs: 2, discrete };
    let joined = bodies::assemble_with(&bodies, &joints).unwrap();
    assert_eq!(joined.model.n(), n_b + 2);
    let period = 2.0 * PI * (mass / k_s).sqrt();
    let per = 400;
    let h = period / per as f64;
    let problem = joined.problem(&bodies, (Vec::new(), Vec::new()), (SPACE_TIME, h, 10 * per));
    let y = n_b + 1;
    let y_static = load / k_s;
    let (mut crossings, mut prev, mut t_prev) = (Vec::new(), 0.0 - y_static, 0.0);
    let (mut sum, mut count) = (0.0, 0usize);
    let mut sim = Simulation::new(problem).unwrap();
    sim.run(&AtomicBool::new(false), |s| {
        let (t, now) = (s.state.t, s.state.u[y] - y_static);
        if prev < 0.0 && now >= 0.0 {
            crossings.push(t_prev + (t - t_prev) * prev / (prev - now));
        }
        if crossings.len() == 1 || (crossings.len() > 1 && crossings.len() < 9) {
            sum += s.state.u[y];
            count += 1;
        }
        (prev, t_prev) = (now, t);
        Ok(())
    })
    .unwrap();
    let measured = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let (ep, em) = (
        (measured - period) / period,
        (sum / count as f64 - y_static) / y_static,
    );
    println!(
        "axle on a spring to a block: k_s {k_s:.6e} N/m (block {:.3e} m/N), period {measured:.6e} s against {period:.6e} s ({ep:.2e}), mean against F/k_s ({em:.2e})",
        c_b
    );
    assert!(c_b > 0.1 / k, "the block's flexibility {c_b} should matter");
    assert!(ep.abs() < 5e-4, "period error {ep}");
    assert!(em.abs() < 5e-4, "mean error {em}");
}

/// Two free plates side by side, joined by a spring-damper from the left one's right edge to
/// the right one's left edge and through an axle mass sprung to both; the left plate moves
/// at 1 m/s along x: the total momentum (plates and axle) is the same at every step to 1e-9
/// (round-off) while the right plate takes up a share of it.
#[test]
fn joints_between_free_bodies_pass_momentum_and_keep_it() {
    let left = plate(0.02, 0.01, 4, 2, 7800.0);
    let right = plate(0.02, 0.01, 4, 2, 7800.0);
    let (a, b) = (node_at(&left, "top", 0.02), node_at(&right, "top", 0.0));
    let bodies = vec![left, right];
    let first = first_dofs(&bodies);
    let axle = first[2];
    let mut discrete = Discrete::new();
    let spring = |link, k, c| SpringDamper {
        link,
        kind: SpringKind::Translational,
        stiffness: k,
        damping: c,
    };
    for c in 0..2 {
        let (da, db) = (first[0] + 2 * a + c, first[1] + 2 * b + c);
        discrete
            .add_spring(spring(Link::Between(da, db), 1e8, 1e3))
            .unwrap();
        discrete
            .add_spring(spring(Link::Between(da, axle + c), 5e7, 0.0))
            .unwrap();
        discrete
            .add_spring(spring(Link::Between(axle + c, db), 5e7, 0.0))
            .unwrap();
        discrete
            .add_mass(softway::element::discrete::PointMass {
                dof: axle + c,
                mass: 0.5,
            })
            .unwrap();
    }
    let joined = bodies::assemble_with(&bodies, &Joints { dofs: 2, discrete }).unwrap();
    let n = joined.model.n();
    let mut v0 = vec![0.0; n];
    for d in (first[0]..first[1]).step_by(2) {
        v0[d] = 1.0;
    }
    let momentum = |v: &[f64]| {
        let mut mv = vec![0.0; n];
        spmv_add(joined.model.pattern(), &joined.model.m, 1.0, v, &mut mv);
        let px: f64 = mv.iter().step_by(2).sum();
        let py: f64 = mv.iter().skip(1).step_by(2).sum();
        let right: f64 = mv[first[1]..first[2]].iter().step_by(2).sum();
        (px, py, right)
    };
    let (p0, _, _) = momentum(&v0);
    let problem = Problem {
        v0,
        ..joined.problem(&bodies, (Vec::new(), Vec::new()), (SPACE_TIME, 1e-6, 2000))
    };
    let (mut worst, mut share) = (0.0_f64, 0.0_f64);
    let mut sim = Simulation::new(problem).unwrap();
    sim.run(&AtomicBool::new(false), |s| {
        let (px, py, pr) = momentum(&s.state.v);
        worst = worst.max((px - p0).abs().max(py.abs()) / p0);
        share = share.max(pr / p0);
        Ok(())
    })
    .unwrap();
    println!(
        "joined free plates: momentum drift {worst:.2e}, right plate's share up to {share:.3}"
    );
    assert!(worst < 1e-9, "momentum drift {worst}");
    assert!(share > 0.3, "the right plate took {share}");
}
