//! Three-node constant-strain triangle (CST) for plane stress and plane strain.
//!
//! # Geometry
//!
//! For the nodes $(x_i, y_i)$, $i = 0, 1, 2$, in counter-clockwise order, the signed area is
//!
//! $$2A = (x_1 - x_0)(y_2 - y_0) - (x_2 - x_0)(y_1 - y_0),$$
//!
//! and the linear shape functions have the constant gradients
//!
//! $$\frac{\partial N_i}{\partial x} = \frac{y_j - y_k}{2A},\qquad
//!   \frac{\partial N_i}{\partial y} = \frac{x_k - x_j}{2A},\qquad
//!   (i, j, k)\ \text{a cyclic permutation of}\ (0, 1, 2).$$
//!
//! [`geometry`] rejects a triangle whose area is zero or tiny compared with its longest edge
//! $L$, $|A| < 10^{-12} L^2$ ([`ElementError::Degenerate`]), and a clockwise one, $A < 0$
//! ([`ElementError::Inverted`]).
//!
//! # Kinematics
//!
//! The element DOFs are ordered $u_e = [u_{0x}, u_{0y}, u_{1x}, u_{1y}, u_{2x}, u_{2y}]^T$ and
//! the strain is constant, in Voigt form
//!
//! $$\varepsilon = [\varepsilon_{xx}, \varepsilon_{yy}, \gamma_{xy}]^T = B\\, u_e,\qquad
//!   B = [B_0\ B_1\ B_2],\quad
//!   B_i = \begin{bmatrix} N_{i,x} & 0 \\\\ 0 & N_{i,y} \\\\ N_{i,y} & N_{i,x} \end{bmatrix},$$
//!
//! with the engineering shear strain $\gamma_{xy} = 2\varepsilon_{xy}$. The stress is
//! $\sigma = [\sigma_{xx}, \sigma_{yy}, \tau_{xy}]^T = D\,\varepsilon$ with the elasticity
//! matrix $D$ of [`crate::material::PlaneModel::elasticity_matrix`].
//!
//! # Element matrices
//!
//! With the thickness $t$ (plane strain: the length of the slice, usually 1) and density
//! $\rho$:
//!
//! $$K_e = t A\\, B^T D B,$$
//!
//! $$M_e^{\text{cons}}(ia, jb) = \delta_{ab}\\,\frac{\rho t A}{12}\\,(1 + \delta_{ij}),\qquad
//!   M_e^{\text{lump}} = \frac{\rho t A}{3}\\, I_6,$$
//!
//! where $i, j$ are nodes and $a, b \in \{x, y\}$ are components. The geometric
//! (initial-stress) stiffness of a uniform in-plane stress
//! $S = \begin{bmatrix}\sigma_{xx} & \tau_{xy}\\ \tau_{xy} & \sigma_{yy}\end{bmatrix}$ is
//!
//! $$K_\sigma(ia, jb) = \delta_{ab}\\, t A\\, \nabla N_i \cdot S\\, \nabla N_j,$$
//!
//! so that $u^T K_\sigma u = t A \sum_a \nabla u_a \cdot S\, \nabla u_a$.
//!
//! # Stress recovery
//!
//! The stress of an element is constant, $\sigma_e = D B u_e$ ([`stress`]), with $u_e$
//! gathered from the global vector ([`element_displacements`]); [`stresses_into`] does it
//! for every triangle of a mesh. Its invariants ($J_2$, von Mises), with the out-of-plane
//! stress $\sigma_{zz}$ of plane strain, are those of
//! [`crate::material::PlaneModel::stress_invariants`].
//!
//! All kernels overwrite the caller's buffer completely; they never allocate.

/// Relative tolerance of the degeneracy test `|A| < DEGENERATE_TOL * L_max^2`.
const DEGENERATE_TOL: f64 = 1e-12;

/// Geometric data of one triangle: its area and the constant shape-function gradients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tri3Geometry {
    /// Area `A` of the triangle (positive), m^2.
    pub area: f64,
    /// Gradients of the shape functions, `grad[i] = [dN_i/dx, dN_i/dy]`, 1/m.
    pub grad: [[f64; 2]; 3],
}

/// Why a triangle cannot be used as an element.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ElementError {
    /// The area is zero, not finite, or tiny compared with the squared longest edge
    /// (`|A| < 1e-12 L_max^2`): collinear or coincident nodes.
    #[error("degenerate triangle: area {area:e} is (near) zero relative to its longest edge")]
    Degenerate {
        /// The signed area that was found, m^2.
        area: f64,
    },
    /// The nodes are ordered clockwise (negative signed area).
    #[error("inverted triangle: signed area {area:e} is negative (nodes ordered clockwise)")]
    Inverted {
        /// The signed (negative) area, m^2.
        area: f64,
    },
}

/// The corners `[x, y]` of the triangle `t` of the planar `mesh` (a 3-node triangle is 2D),
/// as [`geometry`] takes them.
///
/// # Panics
/// If a node of `t` is not in the mesh or the mesh has fewer than two coordinates per node.
pub fn corners(mesh: &crate::mesh::Mesh, t: [usize; 3]) -> [[f64; 2]; 3] {
    t.map(|i| {
        let p = mesh.point(i);
        [p[0], p[1]]
    })
}

/// Area and shape-function gradients of the triangle with nodes `p` (counter-clockwise).
///
/// # Errors
///
/// [`ElementError::Degenerate`] if `|A| < 1e-12 L_max^2` (or the coordinates are not finite),
/// [`ElementError::Inverted`] if the signed area is negative.
pub fn geometry(p: &[[f64; 2]; 3]) -> Result<Tri3Geometry, ElementError> {
    let [[x0, y0], [x1, y1], [x2, y2]] = *p;
    let two_a = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
    let area = 0.5 * two_a;
    let edge2 = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
    let l2 = edge2(p[0], p[1])
        .max(edge2(p[1], p[2]))
        .max(edge2(p[2], p[0]));
    // Written so that NaN coordinates (and l2 == 0) end up as Degenerate.
    let sound = area.abs() >= DEGENERATE_TOL * l2 && area.abs() > 0.0;
    if !sound {
        return Err(ElementError::Degenerate { area });
    }
    if area < 0.0 {
        return Err(ElementError::Inverted { area });
    }
    let inv = 1.0 / two_a;
    let grad = [
        [(y1 - y2) * inv, (x2 - x1) * inv],
        [(y2 - y0) * inv, (x0 - x2) * inv],
        [(y0 - y1) * inv, (x1 - x0) * inv],
    ];
    Ok(Tri3Geometry { area, grad })
}

/// The 3x6 strain-displacement matrix `B`.
fn b_matrix(g: &Tri3Geometry) -> [[f64; 6]; 3] {
    let mut b = [[0.0; 6]; 3];
    for (i, &[nx, ny]) in g.grad.iter().enumerate() {
        b[0][2 * i] = nx;
        b[1][2 * i + 1] = ny;
        b[2][2 * i] = ny;
        b[2][2 * i + 1] = nx;
    }
    b
}

/// Fills `out` with the element stiffness matrix `K_e = t A B^T D B`.
///
/// `d` is the Voigt elasticity matrix (`PlaneModel::elasticity_matrix`), `thickness` the
/// out-of-plane thickness `t`.
pub fn stiffness_into(
    g: &Tri3Geometry,
    d: &[[f64; 3]; 3],
    thickness: f64,
    out: &mut [[f64; 6]; 6],
) {
    let b = b_matrix(g);
    // db = D B (3x6)
    let mut db = [[0.0; 6]; 3];
    for (r, row) in db.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            *v = (0..3).map(|k| d[r][k] * b[k][c]).sum();
        }
    }
    let ta = thickness * g.area;
    for (r, row) in out.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            *v = ta * (0..3).map(|k| b[k][r] * db[k][c]).sum::<f64>();
        }
    }
}

/// Fills `out` with the element mass matrix, consistent (`lumped = false`,
/// `rho t A / 12 (1 + delta_ij)` per component) or lumped (`rho t A / 3` on the diagonal).
pub fn mass_into(
    g: &Tri3Geometry,
    density: f64,
    thickness: f64,
    lumped: bool,
    out: &mut [[f64; 6]; 6],
) {
    let m = density * thickness * g.area;
    for (r, row) in out.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            *v = if lumped {
                if r == c {
                    m / 3.0
                } else {
                    0.0
                }
            } else if r % 2 == c % 2 {
                if r == c {
                    m / 6.0
                } else {
                    m / 12.0
                }
            } else {
                0.0
            };
        }
    }
}

/// Fills `out` with the geometric (initial-stress) stiffness of the uniform in-plane stress
/// `stress = [sxx, syy, txy]`: `K_sigma(ia, jb) = delta_ab t A grad_i . S grad_j`.
pub fn geometric_stiffness_into(
    g: &Tri3Geometry,
    stress: [f64; 3],
    thickness: f64,
    out: &mut [[f64; 6]; 6],
) {
    let [sxx, syy, txy] = stress;
    let ta = thickness * g.area;
    *out = [[0.0; 6]; 6];
    for (i, gi) in g.grad.iter().enumerate() {
        for (j, gj) in g.grad.iter().enumerate() {
            let s_gj = [sxx * gj[0] + txy * gj[1], txy * gj[0] + syy * gj[1]];
            let k = ta * (gi[0] * s_gj[0] + gi[1] * s_gj[1]);
            out[2 * i][2 * j] = k;
            out[2 * i + 1][2 * j + 1] = k;
        }
    }
}

/// The constant strain `[exx, eyy, gxy]` (engineering shear `gxy = 2 exy`) of the element
/// displacements `u`.
#[inline]
pub fn strain(g: &Tri3Geometry, u: &[f64; 6]) -> [f64; 3] {
    let mut e = [0.0; 3];
    for (i, &[nx, ny]) in g.grad.iter().enumerate() {
        let (ux, uy) = (u[2 * i], u[2 * i + 1]);
        e[0] += nx * ux;
        e[1] += ny * uy;
        e[2] += ny * ux + nx * uy;
    }
    e
}

/// The constant stress `[sxx, syy, txy] = D B u` of the element displacements `u`.
#[inline]
pub fn stress(g: &Tri3Geometry, d: &[[f64; 3]; 3], u: &[f64; 6]) -> [f64; 3] {
    let e = strain(g, u);
    let mut s = [0.0; 3];
    for (si, di) in s.iter_mut().zip(d) {
        *si = di[0] * e[0] + di[1] * e[1] + di[2] * e[2];
    }
    s
}

/// The six displacements `[u0x, u0y, u1x, u1y, u2x, u2y]` of the triangle with nodes `t`,
/// gathered from the global vector `u` (two dofs per node, interleaved).
#[inline(always)]
pub fn element_displacements(u: &[f64], t: &[usize; 3]) -> [f64; 6] {
    [
        u[2 * t[0]],
        u[2 * t[0] + 1],
        u[2 * t[1]],
        u[2 * t[1] + 1],
        u[2 * t[2]],
        u[2 * t[2] + 1],
    ]
}

/// The stress `[sxx, syy, txy]` (Pa) of every triangle (nodes `triangles[e]`, geometry
/// `geometry[e]`) under the global displacement `u`, into `out` (one per triangle).
/// No allocation.
///
/// # Panics
/// If `out`, `geometry` and `triangles` differ in length.
pub fn stresses_into(
    geometry: &[Tri3Geometry],
    triangles: &[[usize; 3]],
    d: &[[f64; 3]; 3],
    u: &[f64],
    out: &mut [[f64; 3]],
) {
    assert!(geometry.len() == triangles.len() && out.len() == triangles.len());
    for ((s, g), t) in out.iter_mut().zip(geometry).zip(triangles) {
        *s = stress(g, d, &element_displacements(u, t));
    }
}

/// The stress `D E` of the Green strain `E = (F^T F - I) / 2` per triangle under the
/// nodal displacements `u` (Voigt `[s_xx, s_yy, s_xy]`, Pa): the second Piola-Kirchhoff
/// stress of a Saint Venant-Kirchhoff triangle (the paper's Eq. 13; in plane stress exactly,
/// the out-of-plane strain taken by `S_33 = 0`), on the reference configuration, so that a
/// rigid rotation of the triangle leaves it unchanged, where [`stresses_into`]'s linear
/// strain reads the rotation as strain.
///
/// # Panics
/// If the slices' lengths differ.
pub fn green_stresses_into(
    geometry: &[Tri3Geometry],
    triangles: &[[usize; 3]],
    d: &[[f64; 3]; 3],
    u: &[f64],
    out: &mut [[f64; 3]],
) {
    assert!(geometry.len() == triangles.len() && out.len() == triangles.len());
    for ((s, g), t) in out.iter_mut().zip(geometry).zip(triangles) {
        // H = grad u: h[i][j] = d u_i / d x_j.
        let mut h = [[0.0; 2]; 2];
        for (a, &n) in t.iter().enumerate() {
            for (i, row) in h.iter_mut().enumerate() {
                row[0] += u[2 * n + i] * g.grad[a][0];
                row[1] += u[2 * n + i] * g.grad[a][1];
            }
        }
        let e = [
            h[0][0] + 0.5 * (h[0][0] * h[0][0] + h[1][0] * h[1][0]),
            h[1][1] + 0.5 * (h[0][1] * h[0][1] + h[1][1] * h[1][1]),
            h[0][1] + h[1][0] + h[0][0] * h[0][1] + h[1][0] * h[1][1],
        ];
        for (si, row) in s.iter_mut().zip(d) {
            *si = row[0] * e[0] + row[1] * e[1] + row[2] * e[2];
        }
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // index loops read best for small dense matrices
mod tests {
    use super::*;
    use crate::material::{Elastic, PlaneModel};

    const STEEL: Elastic = Elastic {
        young: 210e9,
        poisson: 0.3,
        density: 7850.0,
    };

    /// A deliberately irregular counter-clockwise triangle.
    const TRI: [[f64; 2]; 3] = [[0.1, -0.2], [1.3, 0.15], [0.4, 0.95]];

    /// Deterministic pseudo-random numbers in [-1, 1) (xorshift64*).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            let v = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
            (v >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    fn matvec(k: &[[f64; 6]; 6], u: &[f64; 6]) -> [f64; 6] {
        let mut f = [0.0; 6];
        for (fi, row) in f.iter_mut().zip(k) {
            *fi = row.iter().zip(u).map(|(a, b)| a * b).sum();
        }
        f
    }

    fn quad(k: &[[f64; 6]; 6], u: &[f64; 6]) -> f64 {
        matvec(k, u).iter().zip(u).map(|(a, b)| a * b).sum()
    }

    fn max_abs(k: &[[f64; 6]; 6]) -> f64 {
        k.iter().flatten().fold(0.0, |m: f64, v| m.max(v.abs()))
    }

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
    }

    /// Eigenvalues of a symmetric 6x6 matrix by cyclic Jacobi rotations.
    fn jacobi_eigenvalues(mut a: [[f64; 6]; 6]) -> [f64; 6] {
        for _sweep in 0..100 {
            let off: f64 = (0..6)
                .flat_map(|p| (0..6).filter(move |&q| q != p).map(move |q| (p, q)))
                .map(|(p, q)| a[p][q] * a[p][q])
                .sum();
            if off.sqrt() <= 1e-15 * max_abs(&a) {
                break;
            }
            for p in 0..6 {
                for q in p + 1..6 {
                    if a[p][q] == 0.0 {
                        continue;
                    }
                    let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                    let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                    let t = if theta == 0.0 { 1.0 } else { t };
                    let c = 1.0 / (t * t + 1.0).sqrt();
                    let s = t * c;
                    for k in 0..6 {
                        let (akp, akq) = (a[k][p], a[k][q]);
                        a[k][p] = c * akp - s * akq;
                        a[k][q] = s * akp + c * akq;
                    }
                    for k in 0..6 {
                        let (apk, aqk) = (a[p][k], a[q][k]);
                        a[p][k] = c * apk - s * aqk;
                        a[q][k] = s * apk + c * aqk;
                    }
                }
            }
        }
        let mut ev = [0.0; 6];
        for (i, e) in ev.iter_mut().enumerate() {
            *e = a[i][i];
        }
        ev.sort_by(|x, y| x.total_cmp(y));
        ev
    }

    /// Nodal values of the field `f` at the nodes `p`, interleaved per node.
    fn nodal(p: &[[f64; 2]; 3], f: impl Fn(f64, f64) -> [f64; 2]) -> [f64; 6] {
        let mut u = [0.0; 6];
        for (i, &[x, y]) in p.iter().enumerate() {
            let v = f(x, y);
            u[2 * i] = v[0];
            u[2 * i + 1] = v[1];
        }
        u
    }

    #[test]
    fn geometry_of_the_unit_right_triangle() {
        let g = geometry(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]).unwrap();
        assert_eq!(g.area, 0.5);
        assert_eq!(g.grad, [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]]);
    }

    #[test]
    fn gradients_sum_to_zero_and_reproduce_coordinates() {
        let g = geometry(&TRI).unwrap();
        for c in 0..2 {
            let s: f64 = g.grad.iter().map(|gi| gi[c]).sum();
            assert!(s.abs() < 1e-14);
        }
        // sum_i x_i grad N_i = grad x = (1, 0); same for y.
        for (a, unit) in [[1.0, 0.0], [0.0, 1.0]].iter().enumerate() {
            for c in 0..2 {
                let s: f64 = (0..3).map(|i| TRI[i][a] * g.grad[i][c]).sum();
                assert!((s - unit[c]).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn degenerate_and_inverted_triangles_are_rejected() {
        // Collinear.
        let e = geometry(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]).unwrap_err();
        assert!(matches!(e, ElementError::Degenerate { .. }), "{e:?}");
        // Almost collinear: |A| / L^2 ~ 2.5e-14.
        let e = geometry(&[[0.0, 0.0], [2.0, 0.0], [1.0, 1e-13]]).unwrap_err();
        assert!(matches!(e, ElementError::Degenerate { .. }), "{e:?}");
        // Coincident nodes.
        let e = geometry(&[[1.0, 1.0], [1.0, 1.0], [1.0, 1.0]]).unwrap_err();
        assert!(matches!(e, ElementError::Degenerate { .. }), "{e:?}");
        // Not finite.
        let e = geometry(&[[f64::NAN, 0.0], [1.0, 0.0], [0.0, 1.0]]).unwrap_err();
        assert!(matches!(e, ElementError::Degenerate { .. }), "{e:?}");
        // Tiny but well-shaped elements are fine: the test is relative.
        let s = 1e-9;
        assert!(geometry(&[[0.0, 0.0], [s, 0.0], [0.0, s]]).is_ok());
        // Clockwise.
        let e = geometry(&[TRI[0], TRI[2], TRI[1]]).unwrap_err();
        match e {
            ElementError::Inverted { area } => {
                let a = geometry(&TRI).unwrap().area;
                assert!((area + a).abs() < 1e-15);
            }
            other => panic!("expected Inverted, got {other:?}"),
        }
        assert!(e.to_string().contains("inverted"));
    }

    #[test]
    fn stiffness_is_symmetric_with_exactly_three_zero_eigenvalues() {
        let g = geometry(&TRI).unwrap();
        for model in [PlaneModel::Stress, PlaneModel::Strain] {
            let d = model.elasticity_matrix(&STEEL);
            let mut k = [[0.0; 6]; 6];
            stiffness_into(&g, &d, 0.01, &mut k);
            let scale = max_abs(&k);
            for r in 0..6 {
                for c in 0..6 {
                    assert!((k[r][c] - k[c][r]).abs() <= 1e-14 * scale);
                }
            }
            let ev = jacobi_eigenvalues(k);
            for &e in &ev[..3] {
                assert!(e.abs() < 1e-12 * scale, "{ev:?}");
            }
            for &e in &ev[3..] {
                assert!(e > 1e-3 * scale, "{ev:?}");
            }
            // Trace is preserved by the rotations.
            let tr: f64 = (0..6).map(|i| k[i][i]).sum();
            assert!(close(ev.iter().sum::<f64>(), tr, 1e-12));
        }
    }

    #[test]
    fn rigid_motions_give_no_force_and_other_motions_positive_energy() {
        let g = geometry(&TRI).unwrap();
        let d = PlaneModel::Stress.elasticity_matrix(&STEEL);
        let mut k = [[0.0; 6]; 6];
        stiffness_into(&g, &d, 0.02, &mut k);
        let scale = max_abs(&k);
        let rigid = [
            nodal(&TRI, |_, _| [1.0, 0.0]),
            nodal(&TRI, |_, _| [0.0, 1.0]),
            nodal(&TRI, |x, y| [-y, x]),
        ];
        for u in &rigid {
            for f in matvec(&k, u) {
                assert!(f.abs() < 1e-13 * scale, "{f}");
            }
            assert_eq!(strain(&g, u).map(|e| (e.abs() < 1e-14) as u8), [1, 1, 1]);
        }
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        for _ in 0..100 {
            let mut u = [0.0; 6];
            u.iter_mut().for_each(|v| *v = rng.next());
            // Remove the rigid part: project on the orthogonal complement of the rigid modes
            // (Gram-Schmidt on the three modes first).
            let mut basis: Vec<[f64; 6]> = Vec::new();
            for r in &rigid {
                let mut v = *r;
                for b in &basis {
                    let p: f64 = v.iter().zip(b).map(|(a, c)| a * c).sum();
                    v.iter_mut().zip(b).for_each(|(a, c)| *a -= p * c);
                }
                let n = v.iter().map(|a| a * a).sum::<f64>().sqrt();
                v.iter_mut().for_each(|a| *a /= n);
                basis.push(v);
            }
            for b in &basis {
                let p: f64 = u.iter().zip(b).map(|(a, c)| a * c).sum();
                u.iter_mut().zip(b).for_each(|(a, c)| *a -= p * c);
            }
            let unorm2: f64 = u.iter().map(|a| a * a).sum();
            assert!(quad(&k, &u) > 1e-4 * scale * unorm2);
        }
    }

    #[test]
    fn stiffness_is_the_hessian_of_the_strain_energy() {
        let g = geometry(&TRI).unwrap();
        // A full, non-isotropic symmetric D exercises every entry.
        let d = [[3.0, 1.2, 0.4], [1.2, 2.5, -0.3], [0.4, -0.3, 1.1]];
        let t = 0.7;
        let energy = |u: &[f64; 6]| {
            let e = strain(&g, u);
            let s = stress(&g, &d, u);
            0.5 * t * g.area * (e[0] * s[0] + e[1] * s[1] + e[2] * s[2])
        };
        let mut k = [[0.0; 6]; 6];
        stiffness_into(&g, &d, t, &mut k);
        let mut rng = Rng(42);
        let mut u0 = [0.0; 6];
        u0.iter_mut().for_each(|v| *v = rng.next());
        let h = 1e-3;
        let shifted = |i: usize, si: f64, j: usize, sj: f64| {
            let mut u = u0;
            u[i] += si * h;
            u[j] += sj * h;
            energy(&u)
        };
        for i in 0..6 {
            // Gradient by central differences: dW/du_i = (K u)_i.
            let mut up = u0;
            let mut um = u0;
            up[i] += h;
            um[i] -= h;
            let grad = (energy(&up) - energy(&um)) / (2.0 * h);
            assert!(
                close(grad, matvec(&k, &u0)[i], 1e-8),
                "{grad} vs {:?}",
                matvec(&k, &u0)
            );
            for j in 0..6 {
                let hess =
                    (shifted(i, 1.0, j, 1.0) - shifted(i, 1.0, j, -1.0) - shifted(i, -1.0, j, 1.0)
                        + shifted(i, -1.0, j, -1.0))
                        / (4.0 * h * h);
                assert!(
                    close(hess, k[i][j], 1e-6),
                    "K[{i}][{j}] = {} vs FD {hess}",
                    k[i][j]
                );
            }
        }
    }

    #[test]
    fn mass_sums_to_the_element_mass_per_component() {
        let g = geometry(&TRI).unwrap();
        let (rho, t) = (7850.0, 0.015);
        let total = rho * t * g.area;
        for lumped in [false, true] {
            let mut m = [[f64::NAN; 6]; 6];
            mass_into(&g, rho, t, lumped, &mut m);
            for a in 0..2 {
                let s: f64 = (0..3)
                    .flat_map(|i| (0..3).map(move |j| (i, j)))
                    .map(|(i, j)| m[2 * i + a][2 * j + a])
                    .sum();
                assert!(close(s, total, 1e-14), "lumped={lumped}: {s} vs {total}");
            }
            // No coupling between components, symmetric.
            for r in 0..6 {
                for c in 0..6 {
                    if r % 2 != c % 2 {
                        assert_eq!(m[r][c], 0.0);
                    }
                    assert_eq!(m[r][c], m[c][r]);
                }
            }
            // Kinetic energy of a rigid translation with unit speed: total / 2.
            let v = nodal(&TRI, |_, _| [0.6, 0.8]);
            assert!(close(0.5 * quad(&m, &v), 0.5 * total, 1e-14));
        }
        let mut m = [[0.0; 6]; 6];
        mass_into(&g, rho, t, false, &mut m);
        assert!(close(m[0][0], total / 6.0, 1e-15) && close(m[0][2], total / 12.0, 1e-15));
    }

    #[test]
    fn patch_test_reproduces_a_linear_field_exactly() {
        // Interior node 0 surrounded by six irregularly placed boundary nodes.
        let nodes: [[f64; 2]; 7] = [
            [0.52, 0.47],
            [0.0, 0.0],
            [1.1, 0.05],
            [1.2, 0.9],
            [0.6, 1.3],
            [-0.1, 1.0],
            [-0.2, 0.4],
        ];
        let tris: Vec<[usize; 3]> = (1..=6).map(|k| [0, k, k % 6 + 1]).collect();
        // Linear displacement field u = a + G x.
        let a = [1e-3, -2e-3];
        let gm = [[2e-4, -3e-4], [5e-4, 1e-4]];
        let field = |x: f64, y: f64| {
            [
                a[0] + gm[0][0] * x + gm[0][1] * y,
                a[1] + gm[1][0] * x + gm[1][1] * y,
            ]
        };
        let eps_exact = [gm[0][0], gm[1][1], gm[0][1] + gm[1][0]];
        for model in [PlaneModel::Stress, PlaneModel::Strain] {
            let d = model.elasticity_matrix(&STEEL);
            let sig_exact: Vec<f64> = (0..3)
                .map(|r| (0..3).map(|c| d[r][c] * eps_exact[c]).sum())
                .collect();
            let n = 2 * nodes.len();
            let mut kg = vec![vec![0.0; n]; n];
            let mut ke = [[0.0; 6]; 6];
            let mut area = 0.0;
            for t in &tris {
                let p = [nodes[t[0]], nodes[t[1]], nodes[t[2]]];
                let g = geometry(&p).unwrap();
                area += g.area;
                stiffness_into(&g, &d, 0.01, &mut ke);
                for (li, &gi) in t.iter().enumerate() {
                    for (lj, &gj) in t.iter().enumerate() {
                        for a in 0..2 {
                            for b in 0..2 {
                                kg[2 * gi + a][2 * gj + b] += ke[2 * li + a][2 * lj + b];
                            }
                        }
                    }
                }
            }
            // The patch tiles its polygon: sanity check of the mesh.
            let shoelace: f64 = (1..=6)
                .map(|k| {
                    let (p, q) = (nodes[k], nodes[k % 6 + 1]);
                    0.5 * (p[0] * q[1] - q[0] * p[1])
                })
                .sum();
            assert!(close(area, shoelace, 1e-14));
            // Boundary DOFs prescribed, solve K_ii u_i = -K_ib u_b for the interior node.
            let mut u = vec![0.0; n];
            for (k, &[x, y]) in nodes.iter().enumerate().skip(1) {
                let v = field(x, y);
                u[2 * k] = v[0];
                u[2 * k + 1] = v[1];
            }
            let rhs: Vec<f64> = (0..2)
                .map(|r| -(2..n).map(|c| kg[r][c] * u[c]).sum::<f64>())
                .collect();
            let det = kg[0][0] * kg[1][1] - kg[0][1] * kg[1][0];
            u[0] = (rhs[0] * kg[1][1] - kg[0][1] * rhs[1]) / det;
            u[1] = (kg[0][0] * rhs[1] - kg[1][0] * rhs[0]) / det;
            let exact = field(nodes[0][0], nodes[0][1]);
            assert!(
                (u[0] - exact[0]).abs() < 1e-15 && (u[1] - exact[1]).abs() < 1e-15,
                "{:?} vs {exact:?}",
                &u[..2]
            );
            for t in &tris {
                let p = [nodes[t[0]], nodes[t[1]], nodes[t[2]]];
                let g = geometry(&p).unwrap();
                let mut ue = [0.0; 6];
                for (l, &k) in t.iter().enumerate() {
                    ue[2 * l] = u[2 * k];
                    ue[2 * l + 1] = u[2 * k + 1];
                }
                let e = strain(&g, &ue);
                let s = stress(&g, &d, &ue);
                for c in 0..3 {
                    assert!(
                        (e[c] - eps_exact[c]).abs() < 1e-15,
                        "{e:?} vs {eps_exact:?}"
                    );
                    assert!(close(s[c], sig_exact[c], 1e-11), "{s:?} vs {sig_exact:?}");
                }
            }
        }
    }

    #[test]
    fn recovered_stresses_and_invariants_of_hand_computed_states() {
        // Two triangles of the unit square; the displacement fields below give uniform
        // strains whose stresses and J2 are computed by hand.
        let points = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let triangles = [[0, 1, 2], [0, 2, 3]];
        let geom: Vec<Tri3Geometry> = triangles
            .iter()
            .map(|t| geometry(&[points[t[0]], points[t[1]], points[t[2]]]).unwrap())
            .collect();
        let field = |f: &dyn Fn(f64, f64) -> [f64; 2]| -> Vec<f64> {
            points.iter().flat_map(|p| f(p[0], p[1])).collect()
        };
        let (e, nu) = (STEEL.young, STEEL.poisson);
        let mut s = [[f64::NAN; 3]; 2];
        // Plane stress, uniaxial stress sigma: eps_xx = sigma/E, eps_yy = -nu sigma/E, so
        // sigma_xx = sigma, sigma_yy = tau_xy = sigma_zz = 0 and J2 = sigma^2/3.
        let sigma = 150.0e6;
        let u = field(&|x, y| [sigma / e * x, -nu * sigma / e * y]);
        let ps = PlaneModel::Stress;
        stresses_into(&geom, &triangles, &ps.elasticity_matrix(&STEEL), &u, &mut s);
        for se in s {
            assert!(close(se[0], sigma, 1e-12) && se[1].abs() < 1e-6 && se[2].abs() < 1e-6);
            let (j2, vm) = ps.stress_invariants(&STEEL, se);
            assert!(close(j2, sigma * sigma / 3.0, 1e-12), "{j2}");
            assert!(close(vm, sigma, 1e-12), "{vm}");
        }
        // Simple shear gamma in either model: tau = G gamma, G = E / (2 (1 + nu)),
        // sigma_zz = 0 (plane strain: nu (0 + 0)), J2 = tau^2, von Mises = sqrt(3) tau.
        let gamma = 1e-3;
        let tau = e / (2.0 * (1.0 + nu)) * gamma;
        let u = field(&|_, y| [gamma * y, 0.0]);
        for pm in [PlaneModel::Stress, PlaneModel::Strain] {
            stresses_into(&geom, &triangles, &pm.elasticity_matrix(&STEEL), &u, &mut s);
            for se in s {
                assert!(se[0].abs() < 1e-6 && se[1].abs() < 1e-6 && close(se[2], tau, 1e-12));
                let (j2, vm) = pm.stress_invariants(&STEEL, se);
                assert!(close(j2, tau * tau, 1e-12), "{pm:?}: {j2} vs {}", tau * tau);
                assert!(close(vm, 3f64.sqrt() * tau, 1e-12));
            }
        }
        // Plane strain, eps_xx = eps only: sigma_xx = E (1 - nu) eps / ((1 + nu)(1 - 2 nu)),
        // sigma_yy = sigma_zz = E nu eps / ((1 + nu)(1 - 2 nu)); J2 = (sxx - syy)^2 / 3.
        let eps = 1e-3;
        let c = e * eps / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let (sxx, syy) = (c * (1.0 - nu), c * nu);
        let u = field(&|x, _| [eps * x, 0.0]);
        let pe = PlaneModel::Strain;
        stresses_into(&geom, &triangles, &pe.elasticity_matrix(&STEEL), &u, &mut s);
        for se in s {
            assert!(close(se[0], sxx, 1e-12) && close(se[1], syy, 1e-12));
            assert!(close(pe.sigma_zz(&STEEL, se[0], se[1]), syy, 1e-12));
            let (j2, _) = pe.stress_invariants(&STEEL, se);
            assert!(close(j2, (sxx - syy).powi(2) / 3.0, 1e-12), "{j2}");
        }
    }

    #[test]
    fn geometric_stiffness_quadratic_form() {
        let g = geometry(&TRI).unwrap();
        let sig = [3.0e6, -1.2e6, 0.8e6];
        let t = 0.05;
        let mut ks = [[f64::NAN; 6]; 6];
        geometric_stiffness_into(&g, sig, t, &mut ks);
        let s = [[sig[0], sig[2]], [sig[2], sig[1]]];
        let mut rng = Rng(7);
        for _ in 0..20 {
            let mut u = [0.0; 6];
            u.iter_mut().for_each(|v| *v = rng.next());
            // grad(u_a) = sum_i u_ia grad N_i, computed from the nodal coordinates directly:
            // solve [x1-x0 y1-y0; x2-x0 y2-y0] grad = [u1-u0; u2-u0].
            let (dx1, dy1) = (TRI[1][0] - TRI[0][0], TRI[1][1] - TRI[0][1]);
            let (dx2, dy2) = (TRI[2][0] - TRI[0][0], TRI[2][1] - TRI[0][1]);
            let det = dx1 * dy2 - dx2 * dy1;
            let mut expected = 0.0;
            for a in 0..2 {
                let (du1, du2) = (u[2 + a] - u[a], u[4 + a] - u[a]);
                let gr = [(du1 * dy2 - du2 * dy1) / det, (dx1 * du2 - dx2 * du1) / det];
                let sg = [
                    s[0][0] * gr[0] + s[0][1] * gr[1],
                    s[1][0] * gr[0] + s[1][1] * gr[1],
                ];
                expected += t * (0.5 * det) * (gr[0] * sg[0] + gr[1] * sg[1]);
            }
            assert!(
                close(quad(&ks, &u), expected, 1e-12),
                "{} vs {expected}",
                quad(&ks, &u)
            );
        }
        // Symmetric, no x-y coupling, and blind to translations.
        for r in 0..6 {
            for c in 0..6 {
                assert!((ks[r][c] - ks[c][r]).abs() <= 1e-15 * max_abs(&ks));
                if r % 2 != c % 2 {
                    assert_eq!(ks[r][c], 0.0);
                }
            }
        }
        for f in matvec(&ks, &nodal(&TRI, |_, _| [1.0, -2.0])) {
            assert!(f.abs() < 1e-12 * max_abs(&ks));
        }
    }

    #[test]
    fn kernels_overwrite_the_whole_buffer() {
        let g = geometry(&TRI).unwrap();
        let d = PlaneModel::Strain.elasticity_matrix(&STEEL);
        let mut k = [[f64::NAN; 6]; 6];
        stiffness_into(&g, &d, 1.0, &mut k);
        assert!(k.iter().flatten().all(|v| v.is_finite()));
        let mut m = [[f64::NAN; 6]; 6];
        mass_into(&g, 1.0, 1.0, true, &mut m);
        assert!(m.iter().flatten().all(|v| v.is_finite()));
        let mut ks = [[f64::NAN; 6]; 6];
        geometric_stiffness_into(&g, [1.0, 2.0, 3.0], 1.0, &mut ks);
        assert!(ks.iter().flatten().all(|v| v.is_finite()));
    }

    #[test]
    fn the_green_stress_ignores_a_rigid_rotation_and_is_the_linear_one_at_small_strain() {
        let p = [[0.0, 0.0], [0.012, 0.003], [0.004, 0.01]];
        let g = geometry(&p).unwrap();
        let d = PlaneModel::Stress.elasticity_matrix(&STEEL);
        let t = [[0usize, 1, 2]];
        let mut s = [[0.0; 3]];
        for a in [0.3, 1.7, 3.0] {
            let (sn, cs) = f64::sin_cos(a);
            let u: Vec<f64> = p
                .iter()
                .flat_map(|q| [cs * q[0] - sn * q[1] - q[0], sn * q[0] + cs * q[1] - q[1]])
                .collect();
            green_stresses_into(&[g], &t, &d, &u, &mut s);
            assert!(s[0].iter().all(|v| v.abs() < 1e-3), "{a}: {:?}", s[0]);
            stresses_into(&[g], &t, &d, &u, &mut s);
            assert!(
                s[0].iter().any(|v| v.abs() > 1e9),
                "{a}: the linear reading"
            );
        }
        let u = [1e-7, -2e-7, 3e-7, 1e-7, -1e-7, 2e-7];
        let (mut sl, mut sg) = ([[0.0; 3]], [[0.0; 3]]);
        stresses_into(&[g], &t, &d, &u, &mut sl);
        green_stresses_into(&[g], &t, &d, &u, &mut sg);
        for i in 0..3 {
            assert!((sl[0][i] - sg[0][i]).abs() < 1e-4 * sl[0][i].abs().max(1e6));
        }
    }
}
