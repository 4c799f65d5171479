//! Eight-node trilinear hexahedron, isotropic linear elasticity, full 2x2x2 Gauss
//! integration.
//!
//! # Nodes (Gmsh's and VTK's order)
//!
//! On the reference cube $[-1, 1]^3$ ([`NODES`]): the bottom face $\zeta = -1$
//! counter-clockwise seen from above, then the top face $\zeta = 1$ likewise,
//!
//! | node | 0 | 1 | 2 | 3 | 4 | 5 | 6 | 7 |
//! |---|---|---|---|---|---|---|---|---|
//! | $(\xi, \eta, \zeta)$ | $(-,-,-)$ | $(+,-,-)$ | $(+,+,-)$ | $(-,+,-)$ | $(-,-,+)$ | $(+,-,+)$ | $(+,+,+)$ | $(-,+,+)$ |
//!
//! and $N_i = \tfrac18(1 + \xi\xi_i)(1 + \eta\eta_i)(1 + \zeta\zeta_i)$.
//!
//! # Geometry
//!
//! [`geometry`] checks $\det J$ (times the reference volume 8) against $10^{-12}L^3$ at the
//! eight Gauss points and the centroid ([`super::solid`], "Bad cells"): where the
//! integration samples the map. A negative value is an inverted or a twisted (bow-tie) cell.
//! The corners are not checked: meshes that every code accepts have cells with a slightly
//! negative corner Jacobian (MacNeal and Harder's distorted patch: $8\det J = -0.0127$ at
//! its inner node $(0.320, 0.186, 0.643)$ in the cell towards the face $y = 0$), and the
//! 2x2x2 rule integrates them correctly (`tests/solid_elements.rs`). The volume is $\sum_g \det J_g$ (exact:
//! $\det J$ of a trilinear map is of degree at most 2 in each variable).
//!
//! # Element matrices
//!
//! Gauss points $\pm 1/\sqrt3$ in each direction, weight 1 ([`GAUSS`]):
//! $K_e = \sum_g B_g^T D B_g \det J_g$ (exact on a parallelepiped, where $B^TDB$ has degree
//! 2 in each variable). Consistent mass $M(ia, jb) = \delta_{ab}\sum_g \rho N_i N_j\det J_g$
//! (exact on a parallelepiped: on the cube of volume $V$, $M_{ij} = \rho V/216 \prod_k
//! (1 + [\xi_{ik} = \xi_{jk}])$). Lumped: row sums, $M^{\text{lump}}_{ii} = \rho\int N_i\\,dV$,
//! positive because $N_i \ge 0$ on the element ($\rho V/8$ on a parallelepiped).
//!
//! Full integration locks in bending (parasitic shear) when a beam has few hexahedra through
//! its depth; `tests/solid_elements.rs` measures it.
//!
//! # Stress
//!
//! At the Gauss points ([`gauss_stresses_into`], the superconvergent points of the
//! trilinear element) and at the centroid ([`stress_at`] with `[0, 0, 0]`).
//!
//! All kernels overwrite the caller's buffer completely; they never allocate.

use super::solid::{add_btdb, check_measure, jacobian, longest_edge, strain_of, stress_of_strain};
pub use super::solid::{elasticity_3d, von_mises, SolidError};

/// Reference coordinates of the eight nodes (module docs).
pub const NODES: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

const G: f64 = 0.577_350_269_189_625_8; // 1 / sqrt 3

/// The 2x2x2 Gauss points (weight 1 each), in the order of the nodes they are nearest to.
pub const GAUSS: [[f64; 3]; 8] = [
    [-G, -G, -G],
    [G, -G, -G],
    [G, G, -G],
    [-G, G, -G],
    [-G, -G, G],
    [G, -G, G],
    [G, G, G],
    [-G, G, G],
];

/// The eight shape functions at `xi` and their reference derivatives.
pub fn shape(xi: [f64; 3]) -> ([f64; 8], [[f64; 3]; 8]) {
    let mut n = [0.0; 8];
    let mut dn = [[0.0; 3]; 8];
    for (i, c) in NODES.iter().enumerate() {
        let f = [0, 1, 2].map(|k| 1.0 + xi[k] * c[k]);
        n[i] = 0.125 * f[0] * f[1] * f[2];
        dn[i] = [
            0.125 * c[0] * f[1] * f[2],
            0.125 * f[0] * c[1] * f[2],
            0.125 * f[0] * f[1] * c[2],
        ];
    }
    (n, dn)
}

/// A checked hexahedron.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hex8Geometry {
    /// Node coordinates, Gmsh's order, m.
    pub x: [[f64; 3]; 8],
    /// Volume, m^3.
    pub volume: f64,
}

/// Checks the hexahedron with nodes `p` (Gmsh's order) and computes its volume.
///
/// # Errors
///
/// [`SolidError::Degenerate`] if `8 det J < 1e-12 L_max^3` at the centroid or a Gauss point
/// (or a coordinate is not finite), [`SolidError::Inverted`] if `det J < 0` there.
pub fn geometry(p: &[[f64; 3]; 8]) -> Result<Hex8Geometry, SolidError> {
    let l = longest_edge(p);
    let mut grad = [[0.0; 3]; 8];
    let det = jacobian(&shape([0.0; 3]).1, p, &mut grad);
    check_measure("hex8", 8.0 * det, l)?;
    let mut volume = 0.0;
    for xi in GAUSS {
        let det = jacobian(&shape(xi).1, p, &mut grad);
        check_measure("hex8", 8.0 * det, l)?;
        volume += det;
    }
    Ok(Hex8Geometry { x: *p, volume })
}

/// Fills `out` with the element stiffness `sum_g B_g^T D B_g det J_g` (2x2x2 Gauss).
pub fn stiffness_into(g: &Hex8Geometry, d: &[[f64; 6]; 6], out: &mut [[f64; 24]; 24]) {
    *out = [[0.0; 24]; 24];
    let mut grad = [[0.0; 3]; 8];
    for xi in GAUSS {
        let det = jacobian(&shape(xi).1, &g.x, &mut grad);
        add_btdb(&grad, d, det, out);
    }
}

/// Fills `out` with the element mass matrix, consistent (`lumped = false`) or row-sum
/// lumped (module docs).
pub fn mass_into(g: &Hex8Geometry, density: f64, lumped: bool, out: &mut [[f64; 24]; 24]) {
    let mut m = [[0.0; 8]; 8];
    let mut grad = [[0.0; 3]; 8];
    for xi in GAUSS {
        let (n, dn) = shape(xi);
        let w = density * jacobian(&dn, &g.x, &mut grad);
        for i in 0..8 {
            for j in 0..8 {
                m[i][j] += w * n[i] * n[j];
            }
        }
    }
    *out = [[0.0; 24]; 24];
    for i in 0..8 {
        let row: f64 = m[i].iter().sum();
        for a in 0..3 {
            if lumped {
                out[3 * i + a][3 * i + a] = row;
            } else {
                for j in 0..8 {
                    out[3 * i + a][3 * j + a] = m[i][j];
                }
            }
        }
    }
}

/// The Voigt strain (engineering shears) at the reference point `xi` of the element
/// displacements `u` (NaN where `det J` is zero).
pub fn strain_at(g: &Hex8Geometry, xi: [f64; 3], u: &[f64; 24]) -> [f64; 6] {
    let mut grad = [[f64::NAN; 3]; 8];
    jacobian(&shape(xi).1, &g.x, &mut grad);
    strain_of(&grad, u)
}

/// The Voigt stress `D B(xi) u` at the reference point `xi` (the centroid: `[0, 0, 0]`).
pub fn stress_at(g: &Hex8Geometry, d: &[[f64; 6]; 6], xi: [f64; 3], u: &[f64; 24]) -> [f64; 6] {
    stress_of_strain(d, &strain_at(g, xi, u))
}

/// The stresses at the eight Gauss points ([`GAUSS`]' order) into `out`.
pub fn gauss_stresses_into(
    g: &Hex8Geometry,
    d: &[[f64; 6]; 6],
    u: &[f64; 24],
    out: &mut [[f64; 6]; 8],
) {
    for (s, xi) in out.iter_mut().zip(GAUSS) {
        *s = stress_at(g, d, xi, u);
    }
}

/// The 24 displacements of the hexahedron with nodes `t`, gathered from the global vector
/// `u` (three dofs per node, interleaved).
pub fn element_displacements(u: &[f64], t: &[usize; 8]) -> [f64; 24] {
    let mut ue = [0.0; 24];
    for (l, &k) in t.iter().enumerate() {
        ue[3 * l..3 * l + 3].copy_from_slice(&u[3 * k..3 * k + 3]);
    }
    ue
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // index loops read best for small dense matrices
mod tests {
    use super::*;

    fn boxed(a: f64, b: f64, c: f64) -> [[f64; 3]; 8] {
        NODES.map(|p| {
            [
                0.5 * a * (1.0 + p[0]),
                0.5 * b * (1.0 + p[1]),
                0.5 * c * (1.0 + p[2]),
            ]
        })
    }

    #[test]
    fn the_mass_of_a_box_is_the_tensor_product_of_bar_masses() {
        // Consistent mass of a brick: rho V / 216 prod_k (2 if the nodes share coordinate k,
        // else 1), the product of three two-node bar matrices (L/6) [2 1; 1 2].
        let (a, b, c, rho) = (0.3, 0.2, 0.7, 2700.0);
        let g = geometry(&boxed(a, b, c)).unwrap();
        let rv = rho * a * b * c;
        assert!((g.volume - a * b * c).abs() < 1e-15);
        let mut m = [[f64::NAN; 24]; 24];
        mass_into(&g, rho, false, &mut m);
        for i in 0..8 {
            for j in 0..8 {
                let f: f64 = (0..3)
                    .map(|k| if NODES[i][k] == NODES[j][k] { 2.0 } else { 1.0 })
                    .product();
                for a in 0..3 {
                    assert!((m[3 * i + a][3 * j + a] - rv * f / 216.0).abs() < 1e-12 * rv);
                    assert_eq!(m[3 * i + a][3 * j + (a + 1) % 3], 0.0);
                }
            }
        }
        mass_into(&g, rho, true, &mut m);
        for r in 0..24 {
            assert!((m[r][r] - rv / 8.0).abs() < 1e-12 * rv);
        }
    }

    #[test]
    fn distorted_volume_and_mass_totals() {
        // A hexahedron whose top face is a shifted, scaled copy of the bottom one, with a
        // twisted corner; the volume by the divergence theorem on its triangulated faces
        // would need planar faces, so compare with the exact integral of det J instead:
        // for x = X(xi) trilinear the volume is int det J, which 3-point Gauss (exact to
        // degree 5) gives independently of the 2-point rule.
        let mut p = boxed(1.0, 1.0, 1.0);
        p[6] = [1.2, 1.1, 1.3];
        p[4][0] = -0.1;
        p[1][2] = 0.1;
        let g = geometry(&p).unwrap();
        let pts = [-(0.6f64).sqrt(), 0.0, 0.6f64.sqrt()];
        let wts = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
        let mut v3 = 0.0;
        let mut grad = [[0.0; 3]; 8];
        for (i, &x) in pts.iter().enumerate() {
            for (j, &y) in pts.iter().enumerate() {
                for (k, &z) in pts.iter().enumerate() {
                    v3 += wts[i] * wts[j] * wts[k] * jacobian(&shape([x, y, z]).1, &p, &mut grad);
                }
            }
        }
        assert!((g.volume - v3).abs() < 1e-14, "{} vs {v3}", g.volume);
        for lumped in [false, true] {
            let mut m = [[0.0; 24]; 24];
            mass_into(&g, 3.0, lumped, &mut m);
            let total: f64 = m.iter().flatten().sum();
            assert!((total - 9.0 * g.volume).abs() < 1e-13, "{lumped}");
            for r in 0..24 {
                assert!(m[r][r] > 0.0);
            }
        }
    }

    #[test]
    fn bad_cells_are_rejected() {
        let p = boxed(1.0, 2.0, 3.0);
        let mut mirrored = p;
        mirrored.swap(1, 3);
        mirrored.swap(5, 7);
        assert!(matches!(
            geometry(&mirrored),
            Err(SolidError::Inverted {
                element: "hex8",
                ..
            })
        ));
        let mut bowtie = p;
        bowtie.swap(6, 7);
        assert!(geometry(&bowtie).is_err());
        let mut flat = p;
        for q in &mut flat {
            q[2] = 0.0;
        }
        assert!(matches!(
            geometry(&flat),
            Err(SolidError::Degenerate { .. })
        ));
        let mut nan = p;
        nan[3][1] = f64::INFINITY;
        assert!(geometry(&nan).is_err());
    }

    #[test]
    fn gauss_and_centroid_stresses_of_a_linear_field() {
        // A linear displacement field gives its constant stress at every point of a
        // distorted element; the bilinear field u_x = kappa x z (in the span of the element)
        // gives eps_xx = kappa z and gamma_xz = kappa x exactly at every point.
        let mut p = boxed(1.0, 1.0, 1.0);
        p[6] = [1.1, 0.9, 1.2];
        let g = geometry(&p).unwrap();
        let d = elasticity_3d(&crate::material::Elastic {
            young: 1.0,
            poisson: 0.25,
            density: 1.0,
        });
        let gm = [[1e-3, 2e-4, -3e-4], [5e-4, -7e-4, 1e-4], [2e-4, 3e-4, 4e-4]];
        let mut u = [0.0; 24];
        for i in 0..8 {
            for a in 0..3 {
                u[3 * i + a] = (0..3).map(|b| gm[a][b] * p[i][b]).sum();
            }
        }
        let e = [
            gm[0][0],
            gm[1][1],
            gm[2][2],
            gm[1][2] + gm[2][1],
            gm[0][2] + gm[2][0],
            gm[0][1] + gm[1][0],
        ];
        let s = stress_of_strain(&d, &e);
        let mut sg = [[f64::NAN; 6]; 8];
        gauss_stresses_into(&g, &d, &u, &mut sg);
        for sp in sg.iter().chain([stress_at(&g, &d, [0.0; 3], &u)].iter()) {
            for k in 0..6 {
                assert!((sp[k] - s[k]).abs() < 1e-15, "{sp:?} vs {s:?}");
            }
        }
        let q = boxed(1.0, 1.0, 1.0);
        let g = geometry(&q).unwrap();
        let kappa = 1e-3;
        let mut u = [0.0; 24];
        for i in 0..8 {
            u[3 * i] = kappa * q[i][0] * q[i][2];
        }
        let c = strain_at(&g, [0.0; 3], &u);
        assert!((c[0] - kappa * 0.5).abs() < 1e-16);
        for (xi, sp) in GAUSS.iter().zip(0..8) {
            let e = strain_at(&g, *xi, &u);
            let z = 0.5 * (1.0 + xi[2]);
            let x = 0.5 * (1.0 + xi[0]);
            assert!((e[0] - kappa * z).abs() < 1e-16, "{sp}");
            assert!((e[4] - kappa * x).abs() < 1e-16);
        }
    }
}
