//! What the 3D solid elements ([`super::tet4`], [`super::tet10`], [`super::hex8`]) share:
//! the isotropic elasticity matrix, the Voigt convention, the von Mises stress, the
//! strain-displacement products and the isoparametric Jacobian.
//!
//! # Voigt order
//!
//! Strains and stresses are 6-vectors in the order $xx, yy, zz, yz, xz, xy$, with the
//! **engineering** shear strains $\gamma_{yz} = 2\varepsilon_{yz}$, $\gamma_{xz} =
//! 2\varepsilon_{xz}$, $\gamma_{xy} = 2\varepsilon_{xy}$:
//!
//! $$\varepsilon = [\varepsilon_{xx}, \varepsilon_{yy}, \varepsilon_{zz}, \gamma_{yz},
//!   \gamma_{xz}, \gamma_{xy}]^T,\qquad \sigma = [\sigma_{xx}, \sigma_{yy}, \sigma_{zz},
//!   \tau_{yz}, \tau_{xz}, \tau_{xy}]^T,$$
//!
//! so that $\sigma^T\varepsilon$ is the strain energy density times two. The element dofs are
//! interleaved per node, $u_e = [u_{0x}, u_{0y}, u_{0z}, u_{1x}, \dots]$, and the node $i$'s
//! block of $B$ is
//!
//! $$B_i = \begin{bmatrix} N_{i,x} & 0 & 0\\\\ 0 & N_{i,y} & 0\\\\ 0 & 0 & N_{i,z}\\\\
//!   0 & N_{i,z} & N_{i,y}\\\\ N_{i,z} & 0 & N_{i,x}\\\\ N_{i,y} & N_{i,x} & 0
//!   \end{bmatrix}.$$
//!
//! # Isotropic elasticity
//!
//! With Lamé's $\lambda = E\nu/((1+\nu)(1-2\nu))$ and $\mu = E/(2(1+\nu))$,
//! $\sigma = D\varepsilon$ with ([`elasticity_3d`])
//!
//! $$D = \begin{bmatrix} \lambda + 2\mu & \lambda & \lambda & & & \\\\
//!   \lambda & \lambda + 2\mu & \lambda & & & \\\\ \lambda & \lambda & \lambda + 2\mu & & & \\\\
//!   & & & \mu & & \\\\ & & & & \mu & \\\\ & & & & & \mu \end{bmatrix}.$$
//!
//! The von Mises stress is $\sqrt{3J_2}$ with
//! $J_2 = \tfrac16[(\sigma_{xx}-\sigma_{yy})^2 + (\sigma_{yy}-\sigma_{zz})^2 +
//! (\sigma_{zz}-\sigma_{xx})^2] + \tau_{yz}^2 + \tau_{xz}^2 + \tau_{xy}^2$ ([`j2`],
//! [`von_mises`]).
//!
//! # Bad cells
//!
//! Every element's geometry is checked once, where it is built: the Jacobian determinant
//! $\det J$ at the element's check points (its corners and quadrature points), times the
//! volume of the reference element, must be at least $10^{-12} L^3$ with $L$ the longest
//! edge between corners. A smaller or non-finite value is [`SolidError::Degenerate`]; a
//! negative one is [`SolidError::Inverted`] (the nodes are in the wrong order, or a curved
//! element folds over itself).

use crate::material::Elastic;

/// Relative tolerance of the degeneracy test `detJ * V_ref < DEGENERATE_TOL * L_max^3`.
pub const DEGENERATE_TOL: f64 = 1e-12;

/// Why a cell cannot be used as a 3D solid element.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolidError {
    /// The volume measure is zero, not finite, or tiny compared with the cube of the longest
    /// edge (`< 1e-12 L_max^3`): flat or coincident nodes.
    #[error(
        "degenerate {element}: volume measure {value:e} m^3 is (near) zero relative to its \
         longest edge (allowed: at least 1e-12 L_max^3)"
    )]
    Degenerate {
        /// The element kind (`"tet4"`, `"tet10"`, `"hex8"`).
        element: &'static str,
        /// `detJ` times the reference volume at the offending point, m^3.
        value: f64,
    },
    /// The Jacobian determinant is negative somewhere: nodes in the wrong order (Gmsh's
    /// orientation gives positive volumes) or a curved element folded over itself.
    #[error(
        "inverted {element}: volume measure {value:e} m^3 is negative (nodes in the wrong \
         order or a folded curved element; allowed: positive)"
    )]
    Inverted {
        /// The element kind.
        element: &'static str,
        /// `detJ` times the reference volume at the offending point, m^3.
        value: f64,
    },
}

/// The 6x6 isotropic elasticity matrix `D` in the Voigt order of the module docs
/// (engineering shear strains).
pub fn elasticity_3d(m: &Elastic) -> [[f64; 6]; 6] {
    let (e, nu) = (m.young, m.poisson);
    let lam = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mu = e / (2.0 * (1.0 + nu));
    let mut d = [[0.0; 6]; 6];
    for (r, row) in d.iter_mut().enumerate().take(3) {
        for (c, v) in row.iter_mut().enumerate().take(3) {
            *v = lam + if r == c { 2.0 * mu } else { 0.0 };
        }
    }
    for k in 3..6 {
        d[k][k] = mu;
    }
    d
}

/// `J2 = 1/2 s:s` (Pa^2) of the Voigt stress `s` (module docs).
pub fn j2(s: &[f64; 6]) -> f64 {
    ((s[0] - s[1]).powi(2) + (s[1] - s[2]).powi(2) + (s[2] - s[0]).powi(2)) / 6.0
        + s[3] * s[3]
        + s[4] * s[4]
        + s[5] * s[5]
}

/// The von Mises stress `sqrt(3 J2)` (Pa) of the Voigt stress `s`.
pub fn von_mises(s: &[f64; 6]) -> f64 {
    (3.0 * j2(s)).sqrt()
}

/// `D e`.
pub fn stress_of_strain(d: &[[f64; 6]; 6], e: &[f64; 6]) -> [f64; 6] {
    let mut s = [0.0; 6];
    for (si, di) in s.iter_mut().zip(d) {
        *si = di.iter().zip(e).map(|(a, b)| a * b).sum();
    }
    s
}

/// The Voigt strain `B u` of the shape-function gradients `grad` (`[dN/dx, dN/dy, dN/dz]` per
/// node) and the interleaved nodal displacements `u` (`ND = 3 NN`).
pub fn strain_of<const NN: usize, const ND: usize>(
    grad: &[[f64; 3]; NN],
    u: &[f64; ND],
) -> [f64; 6] {
    debug_assert_eq!(ND, 3 * NN);
    let mut e = [0.0; 6];
    for (i, &[nx, ny, nz]) in grad.iter().enumerate() {
        let (ux, uy, uz) = (u[3 * i], u[3 * i + 1], u[3 * i + 2]);
        e[0] += nx * ux;
        e[1] += ny * uy;
        e[2] += nz * uz;
        e[3] += nz * uy + ny * uz;
        e[4] += nz * ux + nx * uz;
        e[5] += ny * ux + nx * uy;
    }
    e
}

/// `out += w B^T D B` for the gradients `grad` (`ND = 3 NN`).
pub fn add_btdb<const NN: usize, const ND: usize>(
    grad: &[[f64; 3]; NN],
    d: &[[f64; 6]; 6],
    w: f64,
    out: &mut [[f64; ND]; ND],
) {
    debug_assert_eq!(ND, 3 * NN);
    // db[j][r][b] = (D B_j)[r][b].
    let mut db = [[[0.0; 3]; 6]; NN];
    for (dbj, g) in db.iter_mut().zip(grad) {
        let bj = b_block(g);
        for (r, row) in dbj.iter_mut().enumerate() {
            for (b, v) in row.iter_mut().enumerate() {
                *v = (0..6).map(|k| d[r][k] * bj[k][b]).sum();
            }
        }
    }
    for (i, gi) in grad.iter().enumerate() {
        let bi = b_block(gi);
        for (j, dbj) in db.iter().enumerate() {
            for a in 0..3 {
                for b in 0..3 {
                    let v: f64 = (0..6).map(|k| bi[k][a] * dbj[k][b]).sum();
                    out[3 * i + a][3 * j + b] += w * v;
                }
            }
        }
    }
}

/// `out += w B^T s` (the nodal forces of the stress `s` over the weight `w`).
pub fn add_bts<const NN: usize, const ND: usize>(
    grad: &[[f64; 3]; NN],
    s: &[f64; 6],
    w: f64,
    out: &mut [f64; ND],
) {
    debug_assert_eq!(ND, 3 * NN);
    for (i, &[nx, ny, nz]) in grad.iter().enumerate() {
        out[3 * i] += w * (nx * s[0] + nz * s[4] + ny * s[5]);
        out[3 * i + 1] += w * (ny * s[1] + nz * s[3] + nx * s[5]);
        out[3 * i + 2] += w * (nz * s[2] + ny * s[3] + nx * s[4]);
    }
}

/// The 6x3 block `B_i` of one node (module docs).
fn b_block(&[nx, ny, nz]: &[f64; 3]) -> [[f64; 3]; 6] {
    [
        [nx, 0.0, 0.0],
        [0.0, ny, 0.0],
        [0.0, 0.0, nz],
        [0.0, nz, ny],
        [nz, 0.0, nx],
        [ny, nx, 0.0],
    ]
}

/// The Jacobian determinant of the map `x(xi) = sum_i N_i(xi) x_i` with the reference
/// derivatives `dn[i] = dN_i/dxi`, and the physical gradients `grad[i] = J^-T dn[i]` into
/// `grad` (left untouched when `detJ` is zero or not finite).
pub fn jacobian<const NN: usize>(
    dn: &[[f64; 3]; NN],
    x: &[[f64; 3]; NN],
    grad: &mut [[f64; 3]; NN],
) -> f64 {
    // j[a][b] = dx_a / dxi_b
    let mut j = [[0.0; 3]; 3];
    for (xi, di) in x.iter().zip(dn) {
        for a in 0..3 {
            for b in 0..3 {
                j[a][b] += xi[a] * di[b];
            }
        }
    }
    // Cofactors: inv(J) = cof(J)^T / det.
    let cof = [
        [
            j[1][1] * j[2][2] - j[1][2] * j[2][1],
            j[1][2] * j[2][0] - j[1][0] * j[2][2],
            j[1][0] * j[2][1] - j[1][1] * j[2][0],
        ],
        [
            j[0][2] * j[2][1] - j[0][1] * j[2][2],
            j[0][0] * j[2][2] - j[0][2] * j[2][0],
            j[0][1] * j[2][0] - j[0][0] * j[2][1],
        ],
        [
            j[0][1] * j[1][2] - j[0][2] * j[1][1],
            j[0][2] * j[1][0] - j[0][0] * j[1][2],
            j[0][0] * j[1][1] - j[0][1] * j[1][0],
        ],
    ];
    let det = j[0][0] * cof[0][0] + j[0][1] * cof[0][1] + j[0][2] * cof[0][2];
    if det == 0.0 || !det.is_finite() {
        return det;
    }
    // grad_x N = J^-T grad_xi N, J^-T = cof / det.
    for (g, d) in grad.iter_mut().zip(dn) {
        for a in 0..3 {
            g[a] = (cof[a][0] * d[0] + cof[a][1] * d[1] + cof[a][2] * d[2]) / det;
        }
    }
    det
}

/// The longest distance between two of the points `p`, m.
pub fn longest_edge(p: &[[f64; 3]]) -> f64 {
    let mut l2: f64 = 0.0;
    for (k, a) in p.iter().enumerate() {
        for b in &p[k + 1..] {
            let d = (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2);
            // NaN propagates to the test below through `max` only if written this way.
            l2 = if d.is_nan() { f64::NAN } else { l2.max(d) };
            if l2.is_nan() {
                return f64::NAN;
            }
        }
    }
    l2.sqrt()
}

/// Checks one volume measure `value` (`detJ * V_ref`) against the element size `l`
/// (module docs).
pub fn check_measure(element: &'static str, value: f64, l: f64) -> Result<(), SolidError> {
    let sound = value.abs() >= DEGENERATE_TOL * l * l * l && value.abs() > 0.0;
    if !sound {
        return Err(SolidError::Degenerate { element, value });
    }
    if value < 0.0 {
        return Err(SolidError::Inverted { element, value });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn d_gives_hookes_law_for_uniaxial_stress_and_shear() {
        let m = Elastic {
            young: 200e9,
            poisson: 0.27,
            density: 7800.0,
        };
        let d = elasticity_3d(&m);
        // Uniaxial stress sigma: eps = sigma/E [1, -nu, -nu, 0, 0, 0].
        let s = 120e6;
        let e = [
            s / m.young,
            -m.poisson * s / m.young,
            -m.poisson * s / m.young,
            0.0,
            0.0,
            0.0,
        ];
        let sig = stress_of_strain(&d, &e);
        assert!((sig[0] - s).abs() < 1e-6 * s);
        for v in &sig[1..] {
            assert!(v.abs() < 1e-6 * s, "{sig:?}");
        }
        assert!((von_mises(&sig) - s).abs() < 1e-6 * s);
        // Engineering shear gamma: tau = G gamma.
        let g = m.young / (2.0 * (1.0 + m.poisson));
        for k in 3..6 {
            let mut e = [0.0; 6];
            e[k] = 1e-3;
            let sig = stress_of_strain(&d, &e);
            assert!((sig[k] - g * 1e-3).abs() < 1e-9 * g);
            assert!((j2(&sig) - (g * 1e-3).powi(2)).abs() < 1e-9 * (g * 1e-3).powi(2));
        }
        // Bulk modulus: hydrostatic strain e gives p = E / (3 (1 - 2 nu)) * 3 e.
        let sig = stress_of_strain(&d, &[1e-3, 1e-3, 1e-3, 0.0, 0.0, 0.0]);
        let k = m.young / (3.0 * (1.0 - 2.0 * m.poisson));
        assert!((sig[0] - 3.0 * k * 1e-3).abs() < 1e-9 * sig[0]);
        assert!(j2(&sig).sqrt() < 1e-6 * sig[0]);
    }

    #[test]
    fn measure_check_names_the_element_and_the_rule() {
        let e = check_measure("hex8", -1.0, 1.0).unwrap_err();
        assert!(matches!(e, SolidError::Inverted { .. }));
        assert!(e.to_string().contains("hex8") && e.to_string().contains("positive"));
        let e = check_measure("tet4", 1e-15, 1.0).unwrap_err();
        assert!(matches!(e, SolidError::Degenerate { .. }));
        assert!(e.to_string().contains("1e-12 L_max^3"), "{e}");
        assert!(check_measure("tet4", f64::NAN, 1.0).is_err());
        assert!(check_measure("tet4", 1.0, f64::NAN).is_err());
        assert!(check_measure("tet4", 1e-3, 1.0).is_ok());
    }
}
