//! Two deformable 3D bodies meeting through the facet search, through the whole stack
//! (the joined model, the interface's search at every step, the soft way, the driver): a
//! small block of hexahedra dropped at speed on a larger block held at its base.
//!
//! The checks are invariants that hold whatever the meshes: the contact's impulse is the
//! falling block's change of momentum (the soft way's reactions are the only force on it),
//! no slave node is inside the base's deformed surface beyond a tolerance after any step
//! (measured by searching the placed facets again, not through the step's frozen rows),
//! and the energy of the two bodies is never created.

use std::sync::atomic::AtomicBool;

use softway::bodies::solid::{solid, SolidSpec};
use softway::bodies::{self, Body};
use softway::contact::facets::FacetSearch;
use softway::contact::search::{Motion, Placed};
use softway::contact::{Interface, Pair, PairMode};
use softway::material::{Elastic, PlaneModel};
use softway::mesh::generators::box_mesh;
use softway::mesh::{CellKind, Mesh};
use softway::simulation::Simulation;
use softway::time::Integrator;

const STEEL: Elastic = Elastic {
    young: 210e9,
    poisson: 0.3,
    density: 7850.0,
};

const SPEC: SolidSpec = SolidSpec {
    material: STEEL,
    plane: PlaneModel::Stress,
    thickness: 1.0,
    lumped: false,
};

/// What a drop gave.
#[derive(Debug)]
struct Drop {
    /// The contact's impulse, N s.
    impulse: f64,
    /// The impulse given back at releases, N s.
    restored: f64,
    /// The falling block's momentum along z at the start and at the end, N s.
    momentum: (f64, f64),
    /// The largest penetration of a slave node into the base's placed facets after a step
    /// (positive: inside), m.
    penetration: f64,
    /// Kinetic plus strain energy at the start, J.
    energy0: f64,
    /// The mean energy over the steps after the last contact (the bodies apart), J.
    energy_after: f64,
    /// Steps with a contact force.
    in_contact: usize,
    /// The first and last times with a contact force, s.
    contact: (f64, f64),
    /// The falling block's mass, kg.
    mass: f64,
}

/// The block `mesh` moved by `shift`.
fn shifted(mut mesh: Mesh, shift: [f64; 3]) -> Mesh {
    for (i, x) in mesh.coords.iter_mut().enumerate() {
        *x += shift[i % 3];
    }
    mesh
}

/// The base, `base = (size, cells)` held at `z = 0`, and the block `block = (size, cells)`
/// centred above its top with a gap `gap0`, falling at `v`; `steps` steps of `h`.
fn drop(
    (kind, material): (CellKind, Elastic),
    base: ([f64; 3], [usize; 3]),
    block: ([f64; 3], [usize; 3]),
    (v, gap0): (f64, f64),
    (h, steps): (f64, usize),
) -> Drop {
    let base_mesh = box_mesh(kind, base.0, base.1).unwrap();
    let shift = [
        0.5 * (base.0[0] - block.0[0]),
        0.5 * (base.0[1] - block.0[1]),
        base.0[2] + gap0,
    ];
    let block_mesh = shifted(box_mesh(kind, block.0, block.1).unwrap(), shift);
    let held = base_mesh.node_set("z0").unwrap().to_vec();
    let bottom = block_mesh.node_set("z0").unwrap().to_vec();
    let spec = SolidSpec { material, ..SPEC };
    let mut base_body = solid("base", base_mesh.clone(), &spec, Motion::Fixed)
        .unwrap()
        .body;
    base_body.fixed_dofs = held.iter().flat_map(|&i| 3 * i..3 * i + 3).collect();
    let block_body = solid("block", block_mesh.clone(), &spec, Motion::Fixed)
        .unwrap()
        .body;
    let bodies: Vec<Body> = vec![base_body, block_body];
    let joined = bodies::assemble(&bodies).unwrap();
    let master = Placed {
        motion: Motion::Fixed,
        first_dof: joined.first_dof[0],
    };
    let slave = Placed {
        motion: Motion::Fixed,
        first_dof: joined.first_dof[1],
    };
    let reach = 0.25 * base.0[2];
    let search = FacetSearch::on_mesh(&base_mesh, base_mesh.node_set("z1"), master, reach).unwrap();
    let mut probe = search.clone();
    let iface = Interface::new(search, slave, bottom.clone(), &block_mesh.coords);
    let pairs = Pair::searched(0, &iface, joined.first_node[1]);
    let integrator = Integrator::SpaceTime {
        alpha: 0.8,
        gamma: 0.0,
        coriolis: softway::time::Coriolis::Implicit,
    };
    let mut problem = joined.problem(&bodies, (vec![iface], pairs), (integrator, h, steps));
    let n = problem.v0.len();
    let first = joined.first_dof[1];
    problem.v0 = (0..n)
        .map(|d| if d >= first && d % 3 == 2 { -v } else { 0.0 })
        .collect();
    // M 1_z on the block's dofs: its momentum along z is (M 1_z) . v.
    let ones: Vec<f64> = (0..n)
        .map(|d| f64::from(u8::from(d >= first && d % 3 == 2)))
        .collect();
    let mut mass_z = vec![0.0; n];
    softway::linalg::spmv_add(
        problem.model.pattern(),
        &problem.model.m,
        1.0,
        &ones,
        &mut mass_z,
    );
    let momentum = |v: &[f64]| mass_z.iter().zip(v).map(|(m, v)| m * v).sum::<f64>();
    let mut out = Drop {
        impulse: 0.0,
        restored: 0.0,
        momentum: (momentum(&problem.v0), 0.0),
        penetration: f64::NEG_INFINITY,
        energy0: f64::NAN,
        energy_after: f64::NAN,
        in_contact: 0,
        contact: (f64::NAN, f64::NAN),
        mass: mass_z.iter().sum(),
    };
    let mut sim = Simulation::new(problem).unwrap();
    let mut t_prev = 0.0;
    let mut brake_prev = vec![0.0; bottom.len()];
    let mut energies = Vec::new();
    sim.run(&AtomicBool::new(false), |s| {
        let (t, u) = (s.state.t, &s.state.u);
        let (kinetic, strain) = s.energies();
        if out.energy0.is_nan() {
            out.energy0 = kinetic + strain;
        }
        energies.push((t, kinetic + strain));
        if s.contact_force > 0.0 {
            out.in_contact += 1;
            if out.contact.0.is_nan() {
                out.contact.0 = t_prev;
            }
            out.contact.1 = t;
        }
        out.impulse += s.contact_force * (t - t_prev);
        // The momentum the soft way gives back at a release (a force on the braking row
        // for the step; module docs of softway.rs, Release), counted with the impulse.
        for (p, st) in s.state.pairs.iter().enumerate() {
            if st.released && st.mode == PairMode::Free {
                out.restored += brake_prev[p] * (t - t_prev);
            }
            brake_prev[p] = st.brake_force;
        }
        t_prev = t;
        out.momentum.1 = momentum(&s.state.v);
        probe.update(t, u);
        for &i in &bottom {
            let x = std::array::from_fn(|c| block_mesh.coords[3 * i + c] + u[first + 3 * i + c]);
            if let Some(target) = probe.find(x) {
                out.penetration = out.penetration.max(-target.gap);
            }
        }
        Ok(())
    })
    .unwrap();
    let after: Vec<f64> = energies
        .iter()
        .filter(|&&(t, _)| t > out.contact.1)
        .map(|&(_, e)| e)
        .collect();
    out.energy_after = after.iter().sum::<f64>() / after.len() as f64;
    out
}

/// A 4 cm block of 2 x 2 x 2 hexahedra dropped at 1 m/s on a 10 x 10 x 5 cm block of
/// 4 x 4 x 2 held at its base (its top's facets the master surface; the block's bottom
/// nodes, which fall inside and on the edges of the base's facets, the slave nodes): the
/// block bounces; the impulse the contact transmits (the pairs' forces, and the momentum
/// the soft way gives back at the release) is its change of momentum (within 1e-7 of the
/// initial momentum; measured 5.5e-9, 2.7e-9 N s on 0.88 N s); the
/// bottom nodes never sink into the base's deformed top by more than a nanometre (measured
/// 5e-11 m); and the bodies' energy once apart, averaged over the steps after the contact
/// (the kinetic plus strain energy of the space-time scheme at alpha = 0.8 swings by a few
/// per cent from step to step in free vibration on meshes this coarse), is not above its
/// initial value by more than 5 %.
///
/// The same with both bodies of 4-node tetrahedra (the base's top facets triangles).
///
/// The energy is the weak point, and the treatment's, not the search's: measured once
/// apart, -0.03 % on the hexahedra and +2.9 % on the tetrahedra with the soft way; on the
/// hexahedra +3.2 % with exact enforcement (no braking: the node held at once, 1.3 um of
/// penetration) and -16 % with the soft way giving nothing back (`Restore::Nothing`). The
/// momentum balance, which the search's rows decide, holds in every case.
#[test]
fn a_block_dropped_on_a_held_block_bounces_with_its_momentum_balanced() {
    let (v, h) = (1.0, 2e-6);
    for kind in [CellKind::Hex8, CellKind::Tet4] {
        let r = drop(
            (kind, STEEL),
            ([0.1, 0.1, 0.05], [4, 4, 2]),
            ([0.04, 0.04, 0.04], [2, 2, 2]),
            (v, 1e-5),
            (h, 150),
        );
        println!(
            "{kind:?}: {r:?}; energy once apart {:+.2} %",
            100.0 * (r.energy_after / r.energy0 - 1.0)
        );
        check_balances(&r, 0.05);
        assert!(r.momentum.1 > 0.0, "the block bounced: {:?}", r.momentum);
    }
}

/// The checks every drop passes (module docs), the energy once apart within `energy_tol`
/// of the initial energy (relative).
fn check_balances(r: &Drop, energy_tol: f64) {
    assert!(r.in_contact > 0, "the block reached the base");
    let dp = r.momentum.1 - r.momentum.0;
    let transmitted = r.impulse + r.restored;
    assert!(
        (transmitted - dp).abs() < 1e-7 * r.momentum.0.abs(),
        "impulse {transmitted} against the change of momentum {dp}"
    );
    assert!(r.penetration < 1e-9, "penetration {}", r.penetration);
    assert!(
        r.energy_after <= r.energy0 * (1.0 + energy_tol),
        "energy {} once apart against {} at the start",
        r.energy_after,
        r.energy0
    );
}

/// The 3D column of tests/solid3d.rs (2 x 2 cm, 20 cm, Poisson's ratio 0: a one-dimensional
/// wave) falling at 1 m/s on a deformable floor: a column of the same section, twice as
/// long, held at its far end, its top's facets under the column's bottom nodes (which sit
/// on the facets' vertices and edges). Two bars of equal impedance (d'Alembert; e.g.
/// Graff 1975, *Wave Motion in Elastic Solids*, section 2.1.4): the contact force is
/// `rho c A v / 2` for `2 L / c`, after which the falling column is at rest and free of
/// strain and leaves the floor; the floor's wave, reflected at its held end, comes back at
/// `4 L / c`, after the run. On a ladder of 20 ... 160 cells along the column at Courant
/// number 1 (the column starts 3.5 steps' travel above the floor, so that it is braked), the
/// errors of the contact time, of the mean force and of the final velocity fall on every
/// rung at an order above 0.6 (measured: 10.0, 6.3, 3.8, 2.2 %; -6.7, -4.5, -2.8, -1.7 %;
/// 2.6, 1.5, 0.85, 0.49 % of `v`: orders 0.73, 0.67, 0.81; tests/solid3d.rs's rigid floor
/// converges at about 0.6), and are within 2.5 % on the finest; every rung passes the
/// balances of the block's drop.
#[test]
fn the_3d_column_on_a_deformable_floor_is_two_bars_of_equal_impedance() {
    let material = Elastic {
        poisson: 0.0,
        ..STEEL
    };
    let (a, l, v) = (0.02, 0.2, 1.0);
    let ladder = [20.0, 40.0, 80.0, 160.0];
    let errors: Vec<[f64; 3]> = ladder
        .iter()
        .map(|&nz| column_on_column(material, (a, l, v), nz as usize))
        .collect();
    for k in 0..3 {
        let e: Vec<f64> = errors.iter().map(|e| e[k].abs()).collect();
        assert!(
            e.windows(2).all(|w| w[1] < w[0]),
            "error {k} along the ladder: {e:?}"
        );
        let order = -log_slope(&ladder, &e);
        println!("error {k}: {e:.4?}, order {order:.2}");
        assert!(order > 0.6, "error {k}: {e:?}, order {order}");
        assert!(e[3] < 0.025, "error {k} on the finest rung: {e:?}");
    }
}

/// The least-squares slope of `ln y` against `ln x`.
fn log_slope(x: &[f64], y: &[f64]) -> f64 {
    let (lx, ly): (Vec<f64>, Vec<f64>) = x.iter().zip(y).map(|(a, b)| (a.ln(), b.ln())).unzip();
    let n = lx.len() as f64;
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

/// One rung of the column on the floor column, `nz` cells along the falling column, at
/// Courant number 1: the relative errors of the contact time, the mean force and the
/// final velocity (against `v`).
fn column_on_column(material: Elastic, (a, l, v): (f64, f64, f64), nz: usize) -> [f64; 3] {
    let c = (material.young / material.density).sqrt();
    let h = l / nz as f64 / c;
    let steps = (3.0 * l / c / h).round() as usize + 4;
    let r = drop(
        (CellKind::Hex8, material),
        ([a, a, 2.0 * l], [2, 2, 2 * nz]),
        ([a, a, l], [2, 2, nz]),
        (v, 3.5 * v * h),
        (h, steps),
    );
    let (t_contact, force) = (2.0 * l / c, 0.5 * material.density * c * a * a * v);
    let duration = r.contact.1 - r.contact.0;
    let mean = (r.impulse + r.restored) / duration;
    let v_end = r.momentum.1 / r.mass;
    let errors = [duration / t_contact - 1.0, mean / force - 1.0, v_end / v];
    println!(
        "nz = {nz}: {r:?}: contact {duration:.4e} s against 2L/c = {t_contact:.4e} s, mean force \
         {mean:.5e} N against rho c A v / 2 = {force:.5e} N, final velocity {v_end:.4e} m/s; \
         errors {errors:.4?}"
    );
    check_balances(&r, 1e-3);
    errors
}
