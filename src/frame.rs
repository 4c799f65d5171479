//! The wheel's rotating frame (paper §4: "all the forces arising from the circular motion
//! were introduced").
//!
//! The wheel spins about the axle at `omega` (rad/s). In the frame turning with it the
//! material sees, for a frame angular velocity `Omega` about z (`Omega = -omega`: the wheel
//! rolls clockwise, the base turns counter-clockwise in its frame):
//!
//! - the centrifugal load `f_c = Omega^2 M X` (X: reference positions from the axle);
//! - the Coriolis (gyroscopic) term `G v` with `G = 2 Omega (M_s \otimes J)`,
//!   `J = [[0, -1], [1, 0]]`, skew-symmetric, in the damping matrix `C`;
//! - spin softening `-Omega^2 M` in the stiffness;
//! - stress stiffening `K_sigma` (initial-stress matrix of the centrifugal prestress).
//!
//! Why stress stiffening: with the centre node pinned, the wheel may turn rigidly about the
//! axle, and spin softening alone gives that rigid rotation a negative stiffness
//! `-Omega^2 I`, an instability growing like `e^{|Omega| t}` that does not exist (a rotated
//! spinning disk is still in equilibrium). The prestress `sigma_0` of the centrifugal
//! equilibrium `K u_c = f_c` gives `K_sigma u_rot = Omega^2 M u_rot` exactly for the discrete
//! rigid rotation `u_rot`, so `K + K_sigma - Omega^2 M` leaves it neutral, as it must be.
//!
//! The dynamic model is linearised about the spinning equilibrium `u_c`:
//! `M u'' + G u' + K_eff (u - u_c) = r` with `K_eff = K + K_sigma - Omega^2 M`, written as
//! `M u'' + G u' + K_eff u = K_eff u_c + r`; the run starts from `u = u_c`, `v = 0`.

use crate::assembly::Assembler;

/// Adds the Coriolis matrix `2 Omega (M_s \otimes J)` into `c`, from the assembled 2D mass
/// matrix `m` (whose x-x and y-y blocks are the scalar mass `M_s`).
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
