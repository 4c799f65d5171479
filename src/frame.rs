//! The wheel's rotating frame (paper §4: "all the forces arising from the circular motion
//! were introduced"): every term of the circular motion, with its equation.
//!
//! The wheel spins about the axle at `omega` (rad/s). In the frame turning with it the
//! material sees a frame angular velocity `Omega` about z (`Omega = -omega`: the wheel
//! rolls clockwise, the base turns counter-clockwise in its frame). With the reference
//! positions `X` measured from the axle, the scalar (one-component) mass matrix `M_s` and
//! `M = M_s \otimes I_2`, `J = [[0, -1], [1, 0]]`:
//!
//! | term | equation | function |
//! |---|---|---|
//! | centrifugal load | `f_c = Omega^2 M X` | [`centrifugal_load`] |
//! | Coriolis (gyroscopic) matrix, in `C` | `G = 2 Omega (M_s \otimes J)`, skew-symmetric | [`add_coriolis`] |
//! | spin softening, in `K` | `-Omega^2 M` | [`add_spin_softening`] |
//! | centrifugal stress stiffening, in `K` | `K_sigma(ia, jb) = delta_ab sum_e t A_e grad N_i . S_e grad N_j`, `S_e` the stress of `u_c` | [`stress_stiffening`] |
//!
//! The acceleration of a material point at `x` moving with velocity `v` in the frame is
//! `a + 2 Omega x v + Omega x (Omega x x)`; in the plane `Omega x w = Omega J w` and
//! `Omega x (Omega x x) = -Omega^2 x`, which on the finite element space give `G v` and the
//! load `Omega^2 M (X + u)`, i.e. `f_c` plus the softening `-Omega^2 M u` moved to the
//! left-hand side.
//!
//! **The spinning equilibrium.** `u_c` solves the static `K u_c = f_c` (the wheel held as at
//! the axle); its element stresses `S_e` are the centrifugal prestress.
//!
//! Why stress stiffening: with the centre node pinned, the wheel may turn rigidly about the
//! axle, and spin softening alone gives that rigid rotation a negative stiffness
//! `-Omega^2 I`, an instability growing like `e^{|Omega| t}` that does not exist (a rotated
//! spinning disk is still in equilibrium). The prestress `sigma_0` of the centrifugal
//! equilibrium `K u_c = f_c` gives `K_sigma u_rot = Omega^2 M u_rot` exactly for the discrete
//! rigid rotation `u_rot`, so `K + K_sigma - Omega^2 M` leaves it neutral, as it must be.
//!
//! The dynamic model is linearised about the spinning equilibrium `u_c`:
//! `M u'' + G u' + K_eff (u - u_c) = r` with `K_eff = K + K_sigma - Omega^2 M`
//! ([`effective_stiffness`]), written as `M u'' + G u' + K_eff u = K_eff u_c + r`; the run
//! starts from `u = u_c`, `v = 0`.

use crate::assembly::{Assembler, Tri3GeometricStiffness};
use crate::element::tri3::{self, Tri3Geometry};
use crate::linalg::Pattern;

/// The centrifugal load `f_c = Omega^2 M X` (N) of the frame angular velocity `omega_frame`
/// (rad/s) on the reference positions `x` (m, from the axle), from the assembled mass `m`.
pub fn centrifugal_load(pattern: &Pattern, m: &[f64], omega_frame: f64, x: &[f64]) -> Vec<f64> {
    let mut f = vec![0.0; x.len()];
    crate::linalg::spmv_add(pattern, m, omega_frame * omega_frame, x, &mut f);
    f
}

/// Adds the Coriolis matrix `2 Omega (M_s \otimes J)` into `c`, from the assembled 2D mass
/// matrix `m` (whose x-x and y-y blocks are the scalar mass `M_s`): the x-row of node `a`
/// and y-column of node `b` get `-2 Omega m_ab`, the y-row / x-column `+2 Omega m_ab`.
pub fn add_coriolis(asm: &Assembler, m: &[f64], omega_frame: f64, c: &mut [f64]) {
    let n = asm.pattern.nrows();
    let cp = asm.pattern.col_ptr();
    let ri = asm.pattern.row_idx();
    for j in 0..n {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            // Entry (i, j) with i, j of the same component: the scalar mass m_ab.
            if i % 2 != j % 2 || m[p] == 0.0 {
                continue;
            }
            let (a, b) = (i / 2, j / 2);
            if i % 2 == 0 {
                // x-row of node a, y-column of node b: -2 Omega m_ab.
                if let Some(s) = asm.slot(2 * a, 2 * b + 1) {
                    c[s] -= 2.0 * omega_frame * m[p];
                }
            } else if let Some(s) = asm.slot(2 * a + 1, 2 * b) {
                // y-row of node a, x-column of node b: +2 Omega m_ab.
                c[s] += 2.0 * omega_frame * m[p];
            }
        }
    }
}

/// Adds the spin softening `-Omega^2 M` into the stiffness values `k` (same pattern as `m`).
pub fn add_spin_softening(m: &[f64], omega_frame: f64, k: &mut [f64]) {
    let om = omega_frame;
    for (a, b) in k.iter_mut().zip(m) {
        *a -= om * om * b;
    }
}

/// The centrifugal stress stiffening `K_sigma` (N/m) of a triangle mesh: the geometric
/// stiffness of the element stresses of the spinning equilibrium `u_c` (m),
/// `S_e = D B u_{c,e}` ([`tri3::stresses_into`]), assembled through
/// [`Tri3GeometricStiffness`].
pub fn stress_stiffening(
    asm: &Assembler,
    geometry: &[Tri3Geometry],
    triangles: &[[usize; 3]],
    d: &[[f64; 3]; 3],
    thickness: f64,
    u_c: &[f64],
) -> Vec<f64> {
    let mut stress = vec![[0.0; 3]; triangles.len()];
    tri3::stresses_into(geometry, triangles, d, u_c, &mut stress);
    asm.assemble(&Tri3GeometricStiffness {
        geometry,
        stress: &stress,
        thickness,
    })
}

/// `K_eff = K + K_sigma - Omega^2 M` (module docs): the elastic stiffness `k`, the stress
/// stiffening `k_sigma` when given, and the spin softening.
pub fn effective_stiffness(
    k: &[f64],
    k_sigma: Option<&[f64]>,
    m: &[f64],
    omega_frame: f64,
) -> Vec<f64> {
    let mut k_eff = k.to_vec();
    if let Some(ks) = k_sigma {
        for (a, b) in k_eff.iter_mut().zip(ks) {
            *a += b;
        }
    }
    add_spin_softening(m, omega_frame, &mut k_eff);
    k_eff
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assembly::assemble_mass_stiffness;
    use crate::material::{Elastic, PlaneModel};
    use crate::mesh::generators::disk_rings;
    use crate::mesh::Cells;

    const STEEL: Elastic = Elastic {
        young: 2.05e11,
        poisson: 0.3,
        density: 7830.0,
    };

    #[test]
    fn coriolis_is_skew_and_gives_the_gyroscopic_force_of_a_rigid_velocity() {
        let mesh = disk_rings(0.1, 4).unwrap();
        let Cells::Tri3(tris) = &mesh.cells else {
            panic!()
        };
        let geom: Vec<_> = tris
            .iter()
            .map(|t| tri3::geometry(&tri3::corners(&mesh, *t)).unwrap())
            .collect();
        let asm = Assembler::new(&mesh);
        let d = PlaneModel::Stress.elasticity_matrix(&STEEL);
        let (m, _) = assemble_mass_stiffness(&asm, &geom, &d, &STEEL, 0.01, false);
        let om = -300.0;
        let mut c = asm.zeros();
        add_coriolis(&asm, &m, om, &mut c);
        let cd = asm.to_dense(&c);
        let n = mesh.n_dofs();
        for i in 0..n {
            for j in 0..n {
                assert!((cd[(i, j)] + cd[(j, i)]).abs() < 1e-12 * (cd[(i, j)].abs() + 1.0));
            }
        }
        // A uniform velocity (1, 0): G v = 2 Omega M (J v) = 2 Omega M (0, 1), total force
        // 2 Omega (mass) along y.
        let v: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { 1.0 } else { 0.0 }).collect();
        let mut gv = vec![0.0; n];
        crate::linalg::spmv_into(&asm.pattern, &c, &v, &mut gv);
        let mass: f64 = 7830.0 * 0.01 * geom.iter().map(|g| g.area).sum::<f64>();
        let fy: f64 = gv.iter().skip(1).step_by(2).sum();
        let fx: f64 = gv.iter().step_by(2).sum();
        assert!((fy - 2.0 * om * mass).abs() < 1e-10 * (2.0 * om * mass).abs());
        assert!(fx.abs() < 1e-10 * (2.0 * om * mass).abs());
        // Centrifugal load: total zero (disk centred), radial moment Omega^2 int r^2 dm.
        let x = mesh.reference_positions();
        let fc = centrifugal_load(&asm.pattern, &m, om, &x);
        let fsum: f64 = fc.iter().step_by(2).sum();
        assert!(fsum.abs() < 1e-9 * om * om * mass * 0.1);
        let xf: f64 = fc.iter().zip(&x).map(|(a, b)| a * b).sum();
        // Exact polar moment of the polygon is close to the disk's m R^2 / 2.
        let j = mass * 0.01 / 2.0;
        assert!(
            (xf / (om * om) - j).abs() < 0.05 * j,
            "{} vs {j}",
            xf / (om * om)
        );
        // Spin softening and K_eff without K_sigma: K - Omega^2 M.
        let k = vec![1.0; m.len()];
        let ke = effective_stiffness(&k, None, &m, om);
        for ((a, b), c) in ke.iter().zip(&k).zip(&m) {
            assert_eq!(*a, b - om * om * c);
        }
    }
}
