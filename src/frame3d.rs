//! The rotating frame of a 3D solid spinning about an axle: the 3D form of the terms of
//! [`crate::frame`] (paper §4: "all the forces arising from the circular motion were
//! introduced"; the semi-discrete equation `M v' + C v + K u = f` of the paper's Eq. 6,
//! stepped by Eqs. 18-24 of [`crate::time::step`]).
//!
//! The body is seen in a frame turning at the constant angular velocity
//! `Omega = rate e` about the axle, the line through the point `x0` along the unit vector
//! `e` ([`Spin`]). A material point at `x = X + u` moving with the velocity `v` in that
//! frame has the acceleration `a + 2 Omega x v + Omega x (Omega x (x - x0))`. With the
//! cross-product matrix `[Omega]_x` (`[Omega]_x w = Omega x w`), the shape functions `N`
//! and the scalar (one-component) mass `M_s = int rho N^T N`, every solid element of the
//! code having `M = M_s (x) I_3` (consistent or lumped alike: [`scalar_mass`] checks it):
//!
//! | term | equation | function |
//! |---|---|---|
//! | centrifugal load | `f_c = -int rho N^T Omega x (Omega x (X - x0)) = (M_s (x) Q) (X - x0)` | [`centrifugal_load`] |
//! | Coriolis (gyroscopic) matrix, in `C` | `G = 2 int rho N^T [Omega]_x N = 2 M_s (x) [Omega]_x`, skew-symmetric | [`add_coriolis`] |
//! | spin softening, in `K` | `K_s = -int rho N^T [Omega]_x^T [Omega]_x N = -M_s (x) Q` | [`add_spin_softening`] |
//! | centrifugal stress stiffening, in `K` | `K_sigma(ia, jb) = delta_ab int grad N_i . S grad N_j`, `S` the stress of `u_c` | [`stress_stiffening`] |
//!
//! with `Q = [Omega]_x^T [Omega]_x = rate^2 (I - e e^T)`: the centrifugal acceleration
//! `-Omega x (Omega x r) = Q r` points away from the axle, and neither the load nor the
//! softening acts along it. In the plane (`e = z`, `x0` the origin) the table is
//! [`crate::frame`]'s term for term: `Q = Omega^2 I_2`, `[Omega]_x = Omega J`.
//!
//! **The spinning equilibrium** `u_c` solves `K u_c = f_c`, and the dynamic model is
//! linearised about it as in 2D: `M u'' + G u' + K_eff (u - u_c) = r` with
//! `K_eff = K + K_sigma + K_s` ([`crate::bodies::spinning`] puts it in a body). The
//! stress stiffening `K_sigma` is what keeps the rigid rotation about the axle neutral:
//! for the infinitesimal rotation `u_rot = e x (X - x0)` of every node, `grad u_rot =
//! [e]_x` and `K_sigma u_rot` at node `i` is `[e]_x sum_q w_q S_q grad N_i(q)`, which is
//! `[e]_x` of the internal force `K u_c = f_c`, hence `K_sigma u_rot = -K_s u_rot`
//! exactly when `K_sigma` is integrated with the stiffness's own rule and the Gauss-point
//! stresses ([`GeometricStiffness`]): `K_eff u_rot = 0`.
//!
//! The Coriolis matrix `G` is skew (`G^T = -G`: `M_s` symmetric, `[Omega]_x` skew), so it
//! does no work: `d/dt (v^T M v/2 + u^T K_eff u/2) = -v^T G v = 0` for the free motion.

use crate::assembly::{Assembler, ElementMatrix};
use crate::element::continuum::{Continuum, SolidHex8, SolidTet10, SolidTet4};
use crate::element::solid::{jacobian, strain_of, stress_of_strain};
use crate::element::{hex8, tet10, tet4};
use crate::linalg::Pattern;
use crate::mesh::Mesh;

/// Why spin data or a model cannot take the 3D rotating-frame terms.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpinError {
    /// The axis is zero or not finite.
    #[error("the spin axis {axis:?} must be a finite non-zero vector")]
    Axis {
        /// The axis given.
        axis: [f64; 3],
    },
    /// A point of the axle or the rate is not finite.
    #[error("the spin {name} {value:e} must be finite")]
    NotFinite {
        /// `"rate"` or `"point"`.
        name: &'static str,
        /// The offending value.
        value: f64,
    },
    /// The model is not 3D (three dofs per node).
    #[error("the 3D rotating frame takes a 3D body (three dofs per node), not {dim}D")]
    Dimension {
        /// The model's dimension.
        dim: usize,
    },
    /// The mass is not `M_s (x) I_3` (the components of a node are coupled, or differ).
    #[error(
        "the mass matrix is not the same scalar mass on each component (entry ({row}, {col}) \
         = {value:e}, expected {expected:e}): the rotating-frame terms need M = M_s (x) I_3"
    )]
    MassNotScalar {
        /// Row of the entry.
        row: usize,
        /// Column of the entry.
        col: usize,
        /// Its value.
        value: f64,
        /// What `M_s (x) I_3` gives there.
        expected: f64,
    },
}

/// A constant spin of the frame about an axle (module docs): `Omega = rate e` about the line
/// through `point` along the unit vector `e`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spin {
    point: [f64; 3],
    axis: [f64; 3],
    rate: f64,
}

impl Spin {
    /// The spin at `rate` (rad/s, counter-clockwise about `axis` by the right-hand rule)
    /// about the line through `point` (m) along `axis` (normalised here).
    ///
    /// # Errors
    /// [`SpinError::Axis`] for a zero or non-finite axis, [`SpinError::NotFinite`] for a
    /// non-finite point or rate.
    pub fn new(point: [f64; 3], axis: [f64; 3], rate: f64) -> Result<Self, SpinError> {
        let len = norm(axis);
        if !len.is_finite() || len == 0.0 {
            return Err(SpinError::Axis { axis });
        }
        if !rate.is_finite() {
            return Err(SpinError::NotFinite {
                name: "rate",
                value: rate,
            });
        }
        if let Some(&value) = point.iter().find(|p| !p.is_finite()) {
            return Err(SpinError::NotFinite {
                name: "point",
                value,
            });
        }
        Ok(Spin {
            point,
            axis: axis.map(|a| a / len),
            rate,
        })
    }

    /// A point of the axle, m.
    pub fn point(&self) -> [f64; 3] {
        self.point
    }

    /// The unit direction of the axle.
    pub fn axis(&self) -> [f64; 3] {
        self.axis
    }

    /// The rate, rad/s.
    pub fn rate(&self) -> f64 {
        self.rate
    }

    /// The angular velocity vector `Omega = rate e`, rad/s.
    pub fn omega(&self) -> [f64; 3] {
        self.axis.map(|a| self.rate * a)
    }

    /// `[Omega]_x`, the cross-product matrix of `Omega` (`[Omega]_x w = Omega x w`).
    pub fn cross_matrix(&self) -> [[f64; 3]; 3] {
        let [a, b, c] = self.omega();
        [[0.0, -c, b], [c, 0.0, -a], [-b, a, 0.0]]
    }

    /// `Q = [Omega]_x^T [Omega]_x = rate^2 (I - e e^T)` (module docs).
    pub fn centrifugal_matrix(&self) -> [[f64; 3]; 3] {
        let w2 = self.rate * self.rate;
        let e = self.axis;
        std::array::from_fn(|a| {
            std::array::from_fn(|b| w2 * (f64::from(u8::from(a == b)) - e[a] * e[b]))
        })
    }

    /// The centrifugal acceleration `-Omega x (Omega x (x - x0)) = Q (x - x0)` at `x`
    /// (m/s^2, away from the axle).
    pub fn centrifugal_acceleration(&self, x: [f64; 3]) -> [f64; 3] {
        let q = self.centrifugal_matrix();
        let r: [f64; 3] = std::array::from_fn(|a| x[a] - self.point[a]);
        std::array::from_fn(|a| q[a][0] * r[0] + q[a][1] * r[1] + q[a][2] * r[2])
    }

    /// The infinitesimal rigid rotation about the axle of every node of `x` (flat, three
    /// per node): `e x (X - x0)` per node (m per rad).
    pub fn rigid_rotation(&self, x: &[f64]) -> Vec<f64> {
        let e = self.axis;
        x.chunks_exact(3)
            .flat_map(|p| {
                let r = [
                    p[0] - self.point[0],
                    p[1] - self.point[1],
                    p[2] - self.point[2],
                ];
                [
                    e[1] * r[2] - e[2] * r[1],
                    e[2] * r[0] - e[0] * r[2],
                    e[0] * r[1] - e[1] * r[0],
                ]
            })
            .collect()
    }
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Checks that the assembled 3D mass `m` on `asm`'s pattern is `M_s (x) I_3` (no coupling
/// between the components, the same scalar mass on each), to a relative `1e-12` of the
/// largest entry.
///
/// # Errors
/// [`SpinError::Dimension`] if the pattern is not of three dofs per node,
/// [`SpinError::MassNotScalar`] naming the first entry that breaks the form.
pub fn scalar_mass(asm: &Assembler, m: &[f64]) -> Result<(), SpinError> {
    let n = asm.pattern.nrows();
    if n % 3 != 0 {
        return Err(SpinError::Dimension { dim: n % 3 });
    }
    let tol = 1e-12 * m.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let (cp, ri) = (asm.pattern.col_ptr(), asm.pattern.row_idx());
    for j in 0..n {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            let expected = if i % 3 == j % 3 {
                asm.slot(i - i % 3, j - j % 3).map_or(0.0, |s| m[s])
            } else {
                0.0
            };
            if (m[p] - expected).abs() > tol {
                return Err(SpinError::MassNotScalar {
                    row: i,
                    col: j,
                    value: m[p],
                    expected,
                });
            }
        }
    }
    Ok(())
}

/// The centrifugal load `f_c = (M_s (x) Q) (X - x0)` (N) of `spin` on the reference
/// positions `x` (m, three per node), from the assembled mass `m` (`M_s (x) I_3`,
/// [`scalar_mass`]): `M` applied to the nodal centrifugal accelerations.
pub fn centrifugal_load(pattern: &Pattern, m: &[f64], spin: &Spin, x: &[f64]) -> Vec<f64> {
    let acc: Vec<f64> = x
        .chunks_exact(3)
        .flat_map(|p| spin.centrifugal_acceleration([p[0], p[1], p[2]]))
        .collect();
    let mut f = vec![0.0; x.len()];
    crate::linalg::spmv_add(pattern, m, 1.0, &acc, &mut f);
    f
}

/// Adds `s M_s (x) B` into `out` (same pattern as the mass `m`, `M_s` read off its
/// x-x entries, those above the diagonal for both blocks of a pair of nodes: an assembled
/// mass may differ from its transpose in the last bit, and `G` is then skew and `K_s`
/// symmetric bit for bit).
fn add_kronecker(asm: &Assembler, m: &[f64], b: &[[f64; 3]; 3], s: f64, out: &mut [f64]) {
    let n = asm.pattern.nrows();
    let (cp, ri) = (asm.pattern.col_ptr(), asm.pattern.row_idx());
    for j in (0..n).step_by(3) {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            if i % 3 != 0 || m[p] == 0.0 {
                continue;
            }
            let mij = if i <= j {
                m[p]
            } else {
                asm.slot(j, i).map_or(m[p], |t| m[t])
            };
            for (r, row) in b.iter().enumerate() {
                for (c, &v) in row.iter().enumerate() {
                    if v == 0.0 {
                        continue;
                    }
                    if let Some(slot) = asm.slot(i + r, j + c) {
                        out[slot] += s * mij * v;
                    }
                }
            }
        }
    }
}

/// Adds the Coriolis (gyroscopic) matrix `G = 2 M_s (x) [Omega]_x` of `spin` into `c`,
/// from the assembled 3D mass `m` (`M_s (x) I_3`, [`scalar_mass`]); skew-symmetric.
pub fn add_coriolis(asm: &Assembler, m: &[f64], spin: &Spin, c: &mut [f64]) {
    add_kronecker(asm, m, &spin.cross_matrix(), 2.0, c);
}

/// Adds the spin softening `K_s = -M_s (x) Q` of `spin` into the stiffness values `k`
/// (same pattern as the 3D mass `m`).
pub fn add_spin_softening(asm: &Assembler, m: &[f64], spin: &Spin, k: &mut [f64]) {
    add_kronecker(asm, m, &spin.centrifugal_matrix(), -1.0, k);
}

/// A solid element's geometric (initial-stress) stiffness: `K_sigma(ia, jb) = delta_ab
/// sum_q w_q grad N_i(q) . S_q grad N_j(q)`, `S_q` the stress of the cell's displacements
/// at the quadrature points `q` of the element's own stiffness rule (module docs).
pub trait GeometricStiffness<const N: usize>: Continuum<N> {
    /// The geometric stiffness of the cell of geometry `g` whose displacements `u` give the
    /// stress, into `out`.
    fn geometric_stiffness_into(&self, g: &Self::Geometry, u: &[f64; N], out: &mut [[f64; N]; N]);
}

/// `out += w delta_ab grad N_i . S grad N_j` for the stress `s` (Voigt) at one point.
fn add_initial_stress<const NN: usize, const ND: usize>(
    grad: &[[f64; 3]; NN],
    s: &[f64; 6],
    w: f64,
    out: &mut [[f64; ND]; ND],
) {
    // The symmetric stress tensor of the Voigt order xx, yy, zz, yz, xz, xy.
    let t = [[s[0], s[5], s[4]], [s[5], s[1], s[3]], [s[4], s[3], s[2]]];
    for (i, gi) in grad.iter().enumerate() {
        let sg: [f64; 3] =
            std::array::from_fn(|a| t[a][0] * gi[0] + t[a][1] * gi[1] + t[a][2] * gi[2]);
        for (j, gj) in grad.iter().enumerate() {
            let v = w * (sg[0] * gj[0] + sg[1] * gj[1] + sg[2] * gj[2]);
            for a in 0..3 {
                out[3 * i + a][3 * j + a] += v;
            }
        }
    }
}

/// The stress `D B u` at a point of the shape-function gradients `grad`.
fn point_stress<const NN: usize, const ND: usize>(
    d: &[[f64; 6]; 6],
    grad: &[[f64; 3]; NN],
    u: &[f64; ND],
) -> [f64; 6] {
    stress_of_strain(d, &strain_of(grad, u))
}

impl GeometricStiffness<12> for SolidTet4 {
    fn geometric_stiffness_into(
        &self,
        g: &tet4::Tet4Geometry,
        u: &[f64; 12],
        out: &mut [[f64; 12]; 12],
    ) {
        *out = [[0.0; 12]; 12];
        let s = point_stress(&self.d, &g.grad, u);
        add_initial_stress(&g.grad, &s, g.volume, out);
    }
}

impl GeometricStiffness<24> for SolidHex8 {
    fn geometric_stiffness_into(
        &self,
        g: &hex8::Hex8Geometry,
        u: &[f64; 24],
        out: &mut [[f64; 24]; 24],
    ) {
        *out = [[0.0; 24]; 24];
        let mut grad = [[0.0; 3]; 8];
        for xi in hex8::GAUSS {
            let det = jacobian(&hex8::shape(xi).1, &g.x, &mut grad);
            let s = point_stress(&self.d, &grad, u);
            add_initial_stress(&grad, &s, det, out);
        }
    }
}

impl GeometricStiffness<30> for SolidTet10 {
    fn geometric_stiffness_into(
        &self,
        g: &tet10::Tet10Geometry,
        u: &[f64; 30],
        out: &mut [[f64; 30]; 30],
    ) {
        *out = [[0.0; 30]; 30];
        // The stiffness's rule (tet10::stiffness_into): 4 points straight, 15 curved.
        let (points, weights): (&[[f64; 3]], &[f64]) = if g.curved {
            (&tet10::QUAD15.points, &tet10::QUAD15.weights)
        } else {
            (&tet10::QUAD4.points, &tet10::QUAD4.weights)
        };
        let mut grad = [[0.0; 3]; 10];
        for (xi, w) in points.iter().zip(weights) {
            let det = jacobian(&tet10::shape(*xi).1, &g.x, &mut grad);
            let s = point_stress(&self.d, &grad, u);
            add_initial_stress(&grad, &s, w * det, out);
        }
    }
}

/// The geometric stiffness of a mesh's cells under the displacements `u` as an
/// [`ElementMatrix`].
#[derive(Debug, Clone, Copy)]
pub struct ContinuumGeometric<'a, E: Continuum<N>, const N: usize> {
    /// The element.
    pub element: &'a E,
    /// One geometry per cell.
    pub geometry: &'a [E::Geometry],
    /// The cells' nodes, flat.
    pub connectivity: &'a [usize],
    /// The displacements whose stress the cells carry, m (three per node).
    pub u: &'a [f64],
}

impl<E: GeometricStiffness<N>, const N: usize> ElementMatrix<N> for ContinuumGeometric<'_, E, N> {
    fn element_matrix_into(&self, e: usize, out: &mut [[f64; N]; N]) {
        let per = N / 3;
        let nodes = &self.connectivity[per * e..per * (e + 1)];
        let mut ue = [0.0; N];
        for (a, &node) in nodes.iter().enumerate() {
            ue[3 * a..3 * a + 3].copy_from_slice(&self.u[3 * node..3 * node + 3]);
        }
        self.element
            .geometric_stiffness_into(&self.geometry[e], &ue, out);
    }
}

/// The centrifugal stress stiffening `K_sigma` (N/m) of `mesh`'s cells of the element
/// `el` (with their `geometry`) under the spinning equilibrium `u_c` (m), on `asm`'s
/// pattern (module docs).
pub fn stress_stiffening<E: GeometricStiffness<N>, const N: usize>(
    asm: &Assembler,
    mesh: &Mesh,
    el: &E,
    geometry: &[E::Geometry],
    u_c: &[f64],
) -> Vec<f64> {
    asm.assemble(&ContinuumGeometric {
        element: el,
        geometry,
        connectivity: mesh.cells.connectivity(),
        u: u_c,
    })
}

#[cfg(test)]
mod tests;
