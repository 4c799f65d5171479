//! Four-node linear tetrahedron (constant strain), isotropic linear elasticity.
//!
//! # Geometry
//!
//! The corners $x_0, \dots, x_3$ are in Gmsh's order: positive volume
//!
//! $$6V = (x_1 - x_0)\cdot\left[(x_2 - x_0)\times(x_3 - x_0)\right] > 0.$$
//!
//! The shape functions are the barycentric coordinates, $N_0 = 1 - \xi - \eta - \zeta$,
//! $N_1 = \xi$, $N_2 = \eta$, $N_3 = \zeta$, with constant gradients $\nabla N_i = J^{-T}
//! \nabla_\xi N_i$, $J = [x_1 - x_0,\ x_2 - x_0,\ x_3 - x_0]$, $\det J = 6V$. [`geometry`]
//! rejects a cell with $|V| < 10^{-12} L^3$ ($L$ its longest edge) or a non-finite one
//! ([`SolidError::Degenerate`]) and a cell with $V < 0$ ([`SolidError::Inverted`]).
//!
//! # Element matrices
//!
//! Voigt order and $B$ as in [`super::solid`] (strains $xx, yy, zz, yz, xz, xy$, engineering
//! shear); dofs interleaved per node ($u_{0x}, u_{0y}, u_{0z}, u_{1x}, \dots$). With the
//! elasticity matrix $D$ ([`elasticity_3d`]) and the density $\rho$:
//!
//! $$K_e = V B^T D B,\qquad M^{\text{cons}}_e(ia, jb) = \delta_{ab}\\,\frac{\rho V}{20}\\,
//!   (1 + \delta_{ij}),\qquad M^{\text{lump}}_e = \frac{\rho V}{4} I_{12}$$
//!
//! (from $\int_V N_i N_j\\,dV = V(1+\delta_{ij})/20$). The strain is constant,
//! $\varepsilon = B u_e$ ([`strain`]); so is the stress $\sigma = D\varepsilon$ ([`stress`])
//! and its von Mises value ([`super::solid::von_mises`]).
//!
//! The linear tetrahedron locks in bending (its constant strain cannot bend without shear):
//! a beam of few tets through the depth is much too stiff (`tests/solid_elements.rs`).
//!
//! All kernels overwrite the caller's buffer completely; they never allocate.

use super::solid::{add_btdb, check_measure, jacobian, longest_edge, strain_of, stress_of_strain};
pub use super::solid::{elasticity_3d, von_mises, SolidError};

/// Derivatives of the barycentric shape functions on the reference tetrahedron.
const DN: [[f64; 3]; 4] = [
    [-1.0, -1.0, -1.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];

/// Geometric data of one tetrahedron: its volume and the constant shape-function gradients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tet4Geometry {
    /// Volume `V` (positive), m^3.
    pub volume: f64,
    /// Gradients of the shape functions, `grad[i] = [dN_i/dx, dN_i/dy, dN_i/dz]`, 1/m.
    pub grad: [[f64; 3]; 4],
}

/// Volume and shape-function gradients of the tetrahedron with corners `p` (Gmsh's order,
/// positive volume).
///
/// # Errors
///
/// [`SolidError::Degenerate`] if `|V| < 1e-12 L_max^3` (or a coordinate is not finite),
/// [`SolidError::Inverted`] if the signed volume is negative.
pub fn geometry(p: &[[f64; 3]; 4]) -> Result<Tet4Geometry, SolidError> {
    let mut grad = [[0.0; 3]; 4];
    let det = jacobian(&DN, p, &mut grad);
    let volume = det / 6.0;
    check_measure("tet4", volume, longest_edge(p))?;
    Ok(Tet4Geometry { volume, grad })
}

/// Fills `out` with the element stiffness `K_e = V B^T D B` (`d` from [`elasticity_3d`] or
/// any symmetric 6x6 Voigt matrix).
pub fn stiffness_into(g: &Tet4Geometry, d: &[[f64; 6]; 6], out: &mut [[f64; 12]; 12]) {
    *out = [[0.0; 12]; 12];
    add_btdb(&g.grad, d, g.volume, out);
}

/// Fills `out` with the element mass matrix, consistent (`lumped = false`,
/// `rho V / 20 (1 + delta_ij)` per component) or lumped (`rho V / 4` on the diagonal).
pub fn mass_into(g: &Tet4Geometry, density: f64, lumped: bool, out: &mut [[f64; 12]; 12]) {
    let m = density * g.volume;
    for (r, row) in out.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            *v = if lumped {
                if r == c {
                    m / 4.0
                } else {
                    0.0
                }
            } else if r % 3 == c % 3 {
                if r == c {
                    m / 10.0
                } else {
                    m / 20.0
                }
            } else {
                0.0
            };
        }
    }
}

/// The constant Voigt strain (engineering shears) of the element displacements `u`.
pub fn strain(g: &Tet4Geometry, u: &[f64; 12]) -> [f64; 6] {
    strain_of(&g.grad, u)
}

/// The constant Voigt stress `D B u` of the element displacements `u`.
pub fn stress(g: &Tet4Geometry, d: &[[f64; 6]; 6], u: &[f64; 12]) -> [f64; 6] {
    stress_of_strain(d, &strain(g, u))
}

/// The twelve displacements of the tetrahedron with nodes `t`, gathered from the global
/// vector `u` (three dofs per node, interleaved).
pub fn element_displacements(u: &[f64], t: &[usize; 4]) -> [f64; 12] {
    let mut ue = [0.0; 12];
    for (l, &k) in t.iter().enumerate() {
        ue[3 * l..3 * l + 3].copy_from_slice(&u[3 * k..3 * k + 3]);
    }
    ue
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // index loops read best for small dense matrices
mod tests {
    use super::*;
    use crate::material::Elastic;

    const STEEL: Elastic = Elastic {
        young: 210e9,
        poisson: 0.3,
        density: 7850.0,
    };

    /// A deliberately irregular, positively oriented tetrahedron.
    const TET: [[f64; 3]; 4] = [
        [0.1, -0.2, 0.05],
        [1.3, 0.15, -0.1],
        [0.4, 0.95, 0.2],
        [0.35, 0.3, 1.1],
    ];

    #[test]
    fn geometry_of_the_unit_tetrahedron() {
        let g = geometry(&[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ])
        .unwrap();
        assert_eq!(g.volume, 1.0 / 6.0);
        assert_eq!(g.grad, DN);
    }

    #[test]
    fn gradients_reproduce_the_coordinates_and_the_volume_is_the_triple_product() {
        let g = geometry(&TET).unwrap();
        let d = |k: usize| [0, 1, 2].map(|a| TET[k][a] - TET[0][a]);
        let (a, b, c) = (d(1), d(2), d(3));
        let triple = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0]);
        assert!((g.volume - triple / 6.0).abs() < 1e-15);
        for a in 0..3 {
            for c in 0..3 {
                let s: f64 = (0..4).map(|i| TET[i][a] * g.grad[i][c]).sum();
                assert!(
                    (s - f64::from(u8::from(a == c))).abs() < 1e-14,
                    "{a} {c} {s}"
                );
            }
        }
    }

    #[test]
    fn bad_cells_are_rejected_with_an_error() {
        let mut flat = TET;
        flat[3] = [0.5, 0.2, 0.0];
        flat[0][2] = 0.0;
        flat[1][2] = 0.0;
        flat[2][2] = 0.0;
        assert!(matches!(
            geometry(&flat),
            Err(SolidError::Degenerate { .. })
        ));
        let mut swapped = TET;
        swapped.swap(1, 2);
        let e = geometry(&swapped).unwrap_err();
        assert!(matches!(e, SolidError::Inverted { .. }), "{e:?}");
        assert!(e.to_string().starts_with("inverted tet4"), "{e}");
        let mut nan = TET;
        nan[2][1] = f64::NAN;
        assert!(matches!(geometry(&nan), Err(SolidError::Degenerate { .. })));
        assert!(matches!(
            geometry(&[[1.0; 3]; 4]),
            Err(SolidError::Degenerate { .. })
        ));
    }

    #[test]
    fn consistent_mass_is_the_integral_of_n_i_n_j() {
        // Against the exact integral int N_i N_j dV = V (1 + delta_ij) / 20, computed here
        // from the barycentric monomial formula a! b! 3! V / (a + b + 3)!.
        let g = geometry(&TET).unwrap();
        let rho = 7850.0;
        let mut m = [[f64::NAN; 12]; 12];
        mass_into(&g, rho, false, &mut m);
        let fact = |n: u32| (1..=n).map(f64::from).product::<f64>();
        for i in 0..4 {
            for j in 0..4 {
                let exact = if i == j {
                    fact(2) * fact(3) / fact(5)
                } else {
                    fact(1) * fact(1) * fact(3) / fact(5)
                } * rho
                    * g.volume;
                for a in 0..3 {
                    assert!((m[3 * i + a][3 * j + a] - exact).abs() < 1e-12 * exact);
                }
            }
        }
        let total: f64 = m.iter().flatten().sum();
        assert!((total - 3.0 * rho * g.volume).abs() < 1e-12 * total);
        mass_into(&g, rho, true, &mut m);
        let total: f64 = m.iter().flatten().sum();
        assert!((total - 3.0 * rho * g.volume).abs() < 1e-12 * total);
    }

    #[test]
    fn stiffness_is_the_hessian_of_the_strain_energy_and_the_stress_is_uniform() {
        let g = geometry(&TET).unwrap();
        let d = elasticity_3d(&STEEL);
        let mut k = [[0.0; 12]; 12];
        stiffness_into(&g, &d, &mut k);
        // Energy of a uniform strain field u = G x: V/2 eps^T D eps = 1/2 u^T K u.
        let gm = [[1e-3, 2e-4, -3e-4], [5e-4, -7e-4, 1e-4], [2e-4, 3e-4, 4e-4]];
        let mut u = [0.0; 12];
        for i in 0..4 {
            for a in 0..3 {
                u[3 * i + a] = (0..3).map(|b| gm[a][b] * TET[i][b]).sum();
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
        let got = strain(&g, &u);
        for c in 0..6 {
            assert!((got[c] - e[c]).abs() < 1e-17, "{got:?} vs {e:?}");
        }
        let s = stress_of_strain(&d, &e);
        let w_exact = 0.5 * g.volume * (0..6).map(|c| s[c] * e[c]).sum::<f64>();
        let ku: Vec<f64> = (0..12)
            .map(|r| (0..12).map(|c| k[r][c] * u[c]).sum())
            .collect();
        let w = 0.5 * (0..12).map(|r| ku[r] * u[r]).sum::<f64>();
        assert!((w - w_exact).abs() < 1e-12 * w_exact, "{w} vs {w_exact}");
        for r in 0..12 {
            for c in 0..12 {
                assert!((k[r][c] - k[c][r]).abs() < 1e-14 * k[0][0].abs());
            }
        }
    }
}
