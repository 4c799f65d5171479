//! Hertz's point contact in 3D: a rigid sphere pressed on a graded steel block, one short rung
//! of the ladder of `examples/hertz_ladder.rs`, against Hertz's solution (K. L. Johnson,
//! *Contact Mechanics*, 1985, Eq. 4.22; the elliptic case of Eq. 4.39 in the example).

use softway::contact::statics::indent::{indent, IndentSpec};
use softway::material::Elastic;
use softway::mesh::generators::graded::GradedBlock;
use softway::mesh::CellKind;

const STEEL: Elastic = Elastic {
    young: 210e9,
    poisson: 0.3,
    density: 7850.0,
};

/// A rigid sphere of R = 0.3 m under 50 kN on steel (E* = E / (1 - nu^2)): Hertz's
/// a = (3 P R / 4 E*)^(1/3), p0 = 3 P / (2 pi a^2), delta = a^2 / R at the computed load.
/// The rung has 4 cells per contact radius in its core, a block of 30 a graded by 1.35;
/// issue 49 asks for 2 % on a ladder's finest rung, which this coarse one already meets.
#[test]
fn a_rigid_sphere_on_a_graded_block_against_hertz() {
    let (r, load) = (0.3, 50e3);
    let e_star = STEEL.young / (1.0 - STEEL.poisson.powi(2));
    let a0 = (3.0 * load * r / (4.0 * e_star)).cbrt();
    let l = 30.0 * a0;
    let spec = IndentSpec {
        block: GradedBlock {
            kind: CellKind::Hex8,
            extent: [l, l, l],
            core: [1.4 * a0, 1.4 * a0, a0],
            h: a0 / 4.0,
            ratio: 1.35,
        },
        material: STEEL,
        radius_x: r,
        radius_y: r,
        load,
    };
    let res = indent(&spec).unwrap();
    assert!(res.inside, "the patch lies inside the candidates");
    // The secant reaches the target load.
    assert!((res.load / load - 1.0).abs() < 1e-3, "{}", res.load);
    // Hertz at the computed load, in closed form (Eq. 4.22).
    let a = (3.0 * res.load * r / (4.0 * e_star)).cbrt();
    let p0 = 3.0 * res.load / (2.0 * std::f64::consts::PI * a * a);
    let delta = a * a / r;
    let err = |v: f64, h: f64| (v / h - 1.0).abs();
    eprintln!(
        "dofs {} a {:?} (Hertz {a}) p0 {} ({p0}) delta {} ({delta})",
        res.dofs, res.semi_axes, res.peak_pressure, res.approach
    );
    assert!(err(res.semi_axes[0], a) < 0.02, "a_x {}", res.semi_axes[0]);
    assert!(err(res.semi_axes[1], a) < 0.02, "a_y {}", res.semi_axes[1]);
    // The symmetric patch: the same semi-axis along x and y (the mesh is symmetric).
    assert!(err(res.semi_axes[0], res.semi_axes[1]) < 1e-6);
    assert!(
        err(res.peak_pressure, p0) < 0.02,
        "p0 {}",
        res.peak_pressure
    );
    assert!(err(res.approach, delta) < 0.02, "delta {}", res.approach);
}
