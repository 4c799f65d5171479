//! A 3D body through the generic layers: a column of solid cells (built by
//! `softway::bodies::solid` from a box of hexahedra or tetrahedra) falls on a rigid floor
//! with the soft way, through the same joined model, contact pairs, driver and VTK writer as
//! the planar bodies.
//!
//! With Poisson's ratio 0 the column's axial wave is one-dimensional, and the impact is the
//! paper's bar against a rigid obstacle (Figs. 8-9) on its end: d'Alembert's solution holds
//! the floor's force at `rho c A v` for `2 L / c`, after which the column leaves the floor
//! with its velocity reversed and no strain. The checks are against that exact answer: the
//! contact time, the force, the impulse `2 m v`, the rebound velocity and the energy.

use std::sync::atomic::AtomicBool;

use softway::bodies::solid::{solid, SolidSpec};
use softway::bodies::{self};
use softway::contact::obstacle::{HalfSpace, Plane};
use softway::contact::search::Motion;
use softway::contact::{Obstacle, Pair};
use softway::material::{Elastic, PlaneModel};
use softway::mesh::generators::box_mesh;
use softway::mesh::CellKind;
use softway::simulation::Simulation;
use softway::time::Integrator;

const STEEL_NU0: Elastic = Elastic {
    young: 210e9,
    poisson: 0.0,
    density: 7850.0,
};

/// What one impact gave.
#[derive(Debug)]
struct Impact {
    /// First and last time with a floor force, s.
    contact: (f64, f64),
    /// The floor's largest force, N.
    peak: f64,
    /// Its time integral, N s.
    impulse: f64,
    /// The column's mean velocity along z at the end, m/s.
    v_end: f64,
    /// Kinetic plus strain energy at the start and at the end, J.
    energy: (f64, f64),
    /// The largest lateral displacement at the end, m.
    lateral: f64,
}

/// A column of `a x a x l` on its end at `z = 0`, meshed `n x n x nz` of `kind`, moving
/// down at `v`, stepped with `h` for `steps` steps.
fn impact(
    kind: CellKind,
    (a, l): (f64, f64),
    (n, nz): (usize, usize),
    v: f64,
    h: f64,
    steps: usize,
) -> Impact {
    let mesh = box_mesh(kind, [a, a, l], [n, n, nz]).unwrap();
    let bottom = mesh.node_set("z0").unwrap().to_vec();
    let spec = SolidSpec {
        material: STEEL_NU0,
        plane: PlaneModel::Stress,
        thickness: 1.0,
        lumped: false,
    };
    let column = solid("column", mesh, &spec, Motion::Fixed).unwrap();
    let bodies = vec![column.body];
    let joined = bodies::assemble(&bodies).unwrap();
    assert_eq!(joined.dim, 3);
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
    let n_dofs = problem.v0.len();
    problem.v0 = (0..n_dofs)
        .map(|d| if d % 3 == 2 { -v } else { 0.0 })
        .collect();
    let mass_z: Vec<f64> = {
        // M 1_z: the column's mass on each dof along z.
        let mut out = vec![0.0; n_dofs];
        let ones: Vec<f64> = (0..n_dofs)
            .map(|d| f64::from(u8::from(d % 3 == 2)))
            .collect();
        softway::linalg::spmv_add(
            problem.model.pattern(),
            &problem.model.m,
            1.0,
            &ones,
            &mut out,
        );
        out
    };
    let mass: f64 = mass_z.iter().sum();
    let mut sim = Simulation::new(problem).unwrap();
    let mut out = Impact {
        contact: (f64::NAN, f64::NAN),
        peak: 0.0,
        impulse: 0.0,
        v_end: 0.0,
        energy: (f64::NAN, 0.0),
        lateral: 0.0,
    };
    let mut t_prev = 0.0;
    sim.run(&AtomicBool::new(false), |s| {
        let t = s.state.t;
        let (kinetic, strain) = s.energies();
        if out.energy.0.is_nan() {
            out.energy.0 = kinetic + strain;
        }
        out.energy.1 = kinetic + strain;
        if s.contact_force > 0.0 {
            if out.contact.0.is_nan() {
                out.contact.0 = t_prev;
            }
            out.contact.1 = t;
            out.peak = out.peak.max(s.contact_force);
            out.impulse += s.contact_force * (t - t_prev);
        }
        let v = &s.state.v;
        out.v_end = mass_z.iter().zip(v).map(|(m, v)| m * v).sum::<f64>() / mass;
        out.lateral = s
            .state
            .u
            .iter()
            .enumerate()
            .filter(|(d, _)| d % 3 != 2)
            .fold(0.0, |m, (_, u)| m.max(u.abs()));
        t_prev = t;
        Ok(())
    })
    .unwrap();
    out
}

/// The column against d'Alembert on a ladder of meshes and steps (Courant number 1 on
/// every rung): on every rung the floor's impulse is the column's change of momentum (to
/// round-off: the soft way's reactions are the only external force); the errors of the
/// contact time, the mean force and the rebound velocity fall along the ladder (about as
/// `h^0.6`), and on the finest hexahedra are within 1.2 %; the hexahedra move no node sideways (the wave is
/// one-dimensional). The linear tetrahedra (Kuhn's cut, not layered across the section)
/// are checked on one rung within 5 %.
#[test]
fn a_3d_column_falling_on_its_end_is_the_bar_of_figs_8_9() {
    let (a, l, v) = (0.02, 0.2, 1.0);
    let c = (STEEL_NU0.young / STEEL_NU0.density).sqrt();
    let t_contact = 2.0 * l / c;
    let force = STEEL_NU0.density * c * a * a * v;
    let mass = STEEL_NU0.density * a * a * l;
    let mut last: Option<[f64; 3]> = None;
    for (kind, nz, tol) in [
        (CellKind::Hex8, 20, f64::INFINITY),
        (CellKind::Hex8, 40, f64::INFINITY),
        (CellKind::Hex8, 80, f64::INFINITY),
        (CellKind::Hex8, 160, 0.012),
        (CellKind::Tet4, 40, 0.05),
    ] {
        let h = l / nz as f64 / c;
        let steps = (1.6 * t_contact / h) as usize;
        let r = impact(kind, (a, l), (2, nz), v, h, steps);
        let duration = r.contact.1 - r.contact.0;
        let mean = r.impulse / duration;
        let errors = [
            duration / t_contact - 1.0,
            mean / force - 1.0,
            r.v_end / v - 1.0,
        ];
        println!(
            "{kind:?} nz = {nz}: contact {duration:.4e} s against 2L/c = {t_contact:.4e} s; \
             mean force {mean:.5e} N, peak {:.5e} N against rho c A v = {force:.5e} N; \
             rebound {:.5} m/s; energy {:.6e} -> {:.6e} J; lateral {:.2e} m; errors {errors:.3?}",
            r.peak, r.v_end, r.energy.0, r.energy.1, r.lateral
        );
        // The impulse-momentum balance, whatever the mesh.
        let momentum = mass * (r.v_end + v);
        assert!(
            (r.impulse - momentum).abs() < 1e-9 * momentum,
            "{kind:?} impulse {} against the change of momentum {momentum}",
            r.impulse
        );
        assert!(
            errors.iter().all(|e| e.abs() < tol),
            "{kind:?} nz = {nz}: {errors:?}"
        );
        if kind == CellKind::Hex8 {
            assert!(r.lateral < 1e-12 * l, "lateral {}", r.lateral);
            if let Some(prev) = last {
                for (e, p) in errors.iter().zip(prev) {
                    assert!(e.abs() <= p.abs(), "nz = {nz}: {errors:?} after {prev:?}");
                }
            }
            last = Some(errors);
        }
    }
}
