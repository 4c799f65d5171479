//! Ten-node quadratic tetrahedron, straight- or curved-sided (isoparametric), isotropic
//! linear elasticity.
//!
//! # Nodes (Gmsh's order, element type 11)
//!
//! Corners $0, 1, 2, 3$ as in [`super::tet4`] (positive volume), then the mid-edge nodes
//!
//! | node | 4 | 5 | 6 | 7 | 8 | 9 |
//! |---|---|---|---|---|---|---|
//! | edge | 0-1 | 1-2 | 2-0 | 3-0 | 3-2 | 3-1 |
//!
//! ([`EDGES`]). VTK's quadratic tetrahedron lists the last two the other way round
//! (8 = 1-3, 9 = 2-3): a writer swaps nodes 8 and 9.
//!
//! # Shape functions and geometry
//!
//! With the barycentric coordinates $L_0 = 1 - \xi - \eta - \zeta$, $L_1 = \xi$,
//! $L_2 = \eta$, $L_3 = \zeta$: corners $N_i = L_i(2L_i - 1)$, mid-edge nodes of the edge
//! $a$-$b$ $N = 4L_aL_b$. The map $x(\xi) = \sum_i N_i(\xi)\\,x_i$ is the same for the
//! geometry and the displacement (isoparametric): a mid-edge node off its edge's midpoint
//! makes a curved element, which represents any quadratic map of the reference tetrahedron
//! exactly. The volume $V = \int \det J\\,d\xi$ is exact on the 15-point rule (for a
//! quadratic map $\det J$ is a cubic).
//!
//! [`geometry`] checks $\det J / 6$ against $10^{-12}L^3$ at the corners, the mid-edge nodes
//! and the 15 points of the mass rule ([`super::solid`], "Bad cells").
//!
//! # Quadrature
//!
//! - Stiffness of a straight-sided element: $B$ is linear, $B^TDB$ quadratic: the 4-point
//!   rule of degree 2 ([`QUAD4`]) is exact.
//! - Stiffness of a curved element: the integrand is rational; the 15-point rule of degree 5
//!   ([`QUAD15`]) integrates $\int\nabla N_i\\,dV = \int \operatorname{cof}(J)\\,
//!   \nabla_\xi N_i\\,d\xi$ (a cubic) exactly, so curved elements pass the patch test.
//! - Mass: $\rho\int N_iN_j\\,dV$ is of degree 4 on a straight-sided element: the 15-point
//!   rule ([`QUAD15`], Keast 1986, degree 5, positive weights) is exact.
//!
//! # Mass
//!
//! Consistent $M(ia, jb) = \delta_{ab}\\,\rho\int N_iN_j\\,dV$. Lumped: **HRZ** (Hinton,
//! Rock and Zienkiewicz 1976), the consistent diagonal scaled so that each direction carries
//! the element's mass $\rho V$:
//! $M^{\text{lump}}_{ii} = \rho V\\,M_{ii}/\sum_j M_{jj}$. For a straight-sided element this
//! gives $\rho V/36$ at each corner and $4\rho V/27$ at each mid-edge node. Row-sum lumping
//! is **not** used: $\int N_i\\,dV = -V/20$ at a corner (and $V/5$ at a mid-edge node), a
//! negative corner mass, so an explicit integrator and a diagonal mass would be useless.
//!
//! # Stress
//!
//! $\varepsilon(\xi) = B(\xi)\\,u_e$ and $\sigma = D\varepsilon$ at any point of the
//! element ([`strain_at`], [`stress_at`]); the strain is linear in a straight-sided element.
//!
//! All kernels overwrite the caller's buffer completely; they never allocate.

use super::solid::{add_btdb, check_measure, jacobian, longest_edge, strain_of, stress_of_strain};
pub use super::solid::{elasticity_3d, von_mises, SolidError};

/// Corner pairs of the mid-edge nodes 4..=9, Gmsh's order (module docs).
pub const EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [3, 0], [3, 2], [3, 1]];

/// A quadrature rule on the reference tetrahedron (`0 <= xi, eta, zeta`, `xi + eta + zeta <=
/// 1`, volume 1/6): points `[xi, eta, zeta]` and weights summing to 1/6.
pub struct TetRule<const Q: usize> {
    /// The points.
    pub points: [[f64; 3]; Q],
    /// The weights.
    pub weights: [f64; Q],
}

const A4: f64 = 0.585_410_196_624_968_5; // (5 + 3 sqrt 5) / 20
const B4: f64 = 0.138_196_601_125_010_5; // (5 - sqrt 5) / 20

/// The symmetric 4-point rule of degree 2 (points at barycentric `(a, b, b, b)`,
/// `a = (5 + 3 sqrt 5) / 20`, `b = (5 - sqrt 5) / 20`, weights `1/24`).
pub const QUAD4: TetRule<4> = TetRule {
    points: [[B4, B4, B4], [A4, B4, B4], [B4, A4, B4], [B4, B4, A4]],
    weights: [1.0 / 24.0; 4],
};

const W15_0: f64 = 0.030_283_678_097_089_186;
const W15_1: f64 = 0.006_026_785_714_285_716;
const W15_2: f64 = 0.011_645_249_086_028_992;
const W15_3: f64 = 0.010_949_141_561_386_453;
const C15_2A: f64 = 0.727_272_727_272_727_3; // 8 / 11
const C15_2B: f64 = 0.090_909_090_909_090_91; // 1 / 11
const C15_3A: f64 = 0.066_550_153_573_664_28;
const C15_3B: f64 = 0.433_449_846_426_335_7;

/// Keast's 15-point rule of degree 5 with positive weights (P. Keast, Comput. Methods Appl.
/// Mech. Eng. 55, 1986): the centroid; the four face centroids (barycentric
/// `(0, 1/3, 1/3, 1/3)`); four points at `(8/11, 1/11, 1/11, 1/11)`; six at
/// `(a, a, b, b)`, `a = 0.0665501535736643`, `b = 0.4334498464263357`.
pub const QUAD15: TetRule<15> = TetRule {
    points: [
        [0.25, 0.25, 0.25],
        // Face centroids: L0 = 0, then L1 = 0, L2 = 0, L3 = 0.
        [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
        [0.0, 1.0 / 3.0, 1.0 / 3.0],
        [1.0 / 3.0, 0.0, 1.0 / 3.0],
        [1.0 / 3.0, 1.0 / 3.0, 0.0],
        [C15_2B, C15_2B, C15_2B],
        [C15_2A, C15_2B, C15_2B],
        [C15_2B, C15_2A, C15_2B],
        [C15_2B, C15_2B, C15_2A],
        // (L0, L1, L2, L3) with two of each value: xi = L1, eta = L2, zeta = L3.
        [C15_3A, C15_3B, C15_3B],
        [C15_3B, C15_3A, C15_3B],
        [C15_3B, C15_3B, C15_3A],
        [C15_3A, C15_3A, C15_3B],
        [C15_3A, C15_3B, C15_3A],
        [C15_3B, C15_3A, C15_3A],
    ],
    weights: [
        W15_0, W15_1, W15_1, W15_1, W15_1, W15_2, W15_2, W15_2, W15_2, W15_3, W15_3, W15_3, W15_3,
        W15_3, W15_3,
    ],
};

/// The ten shape functions at `xi = [xi, eta, zeta]` and their reference derivatives.
pub fn shape(xi: [f64; 3]) -> ([f64; 10], [[f64; 3]; 10]) {
    let l = [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]];
    // dl[i] = dL_i / dxi
    let dl = [
        [-1.0, -1.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let mut n = [0.0; 10];
    let mut dn = [[0.0; 3]; 10];
    for i in 0..4 {
        n[i] = l[i] * (2.0 * l[i] - 1.0);
        for k in 0..3 {
            dn[i][k] = (4.0 * l[i] - 1.0) * dl[i][k];
        }
    }
    for (e, &[a, b]) in EDGES.iter().enumerate() {
        n[4 + e] = 4.0 * l[a] * l[b];
        for k in 0..3 {
            dn[4 + e][k] = 4.0 * (l[b] * dl[a][k] + l[a] * dl[b][k]);
        }
    }
    (n, dn)
}

/// Reference coordinates of the ten nodes.
pub const NODES: [[f64; 3]; 10] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.5, 0.0, 0.0],
    [0.5, 0.5, 0.0],
    [0.0, 0.5, 0.0],
    [0.0, 0.0, 0.5],
    [0.0, 0.5, 0.5],
    [0.5, 0.0, 0.5],
];

/// A checked ten-node tetrahedron.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tet10Geometry {
    /// Node coordinates, Gmsh's order, m.
    pub x: [[f64; 3]; 10],
    /// Volume (exact for the quadratic map), m^3.
    pub volume: f64,
    /// True when a mid-edge node is off its edge's midpoint by more than `1e-12 L_max`.
    pub curved: bool,
}

/// Checks the ten-node tetrahedron with nodes `p` (Gmsh's order) and computes its volume.
///
/// # Errors
///
/// [`SolidError::Degenerate`] if `det J / 6 < 1e-12 L_max^3` at a check point or a
/// coordinate is not finite, [`SolidError::Inverted`] if `det J < 0` at a check point
/// (module docs).
pub fn geometry(p: &[[f64; 3]; 10]) -> Result<Tet10Geometry, SolidError> {
    let corners = [p[0], p[1], p[2], p[3]];
    let l = longest_edge(&corners);
    let mut grad = [[0.0; 3]; 10];
    let mut check = |xi: [f64; 3]| -> Result<f64, SolidError> {
        let det = jacobian(&shape(xi).1, p, &mut grad);
        check_measure("tet10", det / 6.0, l)?;
        Ok(det)
    };
    for xi in NODES {
        check(xi)?;
    }
    let mut volume = 0.0;
    for (xi, w) in QUAD15.points.iter().zip(QUAD15.weights) {
        volume += w * check(*xi)?;
    }
    let curved = EDGES.iter().enumerate().any(|(e, &[a, b])| {
        let off = (0..3)
            .map(|k| (p[4 + e][k] - 0.5 * (p[a][k] + p[b][k])).powi(2))
            .sum::<f64>()
            .sqrt();
        off > 1e-12 * l
    });
    Ok(Tet10Geometry {
        x: *p,
        volume,
        curved,
    })
}

/// `out += ` the stiffness over the rule `rule`.
fn add_stiffness<const Q: usize>(
    g: &Tet10Geometry,
    d: &[[f64; 6]; 6],
    rule: &TetRule<Q>,
    out: &mut [[f64; 30]; 30],
) {
    let mut grad = [[0.0; 3]; 10];
    for (xi, w) in rule.points.iter().zip(rule.weights) {
        let det = jacobian(&shape(*xi).1, &g.x, &mut grad);
        add_btdb(&grad, d, w * det, out);
    }
}

/// Fills `out` with the element stiffness `int B^T D B dV`: 4-point rule on a
/// straight-sided element (exact), 15-point rule on a curved one (module docs).
pub fn stiffness_into(g: &Tet10Geometry, d: &[[f64; 6]; 6], out: &mut [[f64; 30]; 30]) {
    *out = [[0.0; 30]; 30];
    if g.curved {
        add_stiffness(g, d, &QUAD15, out);
    } else {
        add_stiffness(g, d, &QUAD4, out);
    }
}

/// `m[i][j] = int N_i N_j dV` (one component), 15-point rule.
fn scalar_mass(g: &Tet10Geometry) -> [[f64; 10]; 10] {
    let mut m = [[0.0; 10]; 10];
    let mut grad = [[0.0; 3]; 10];
    for (xi, w) in QUAD15.points.iter().zip(QUAD15.weights) {
        let (n, dn) = shape(*xi);
        let wd = w * jacobian(&dn, &g.x, &mut grad);
        for i in 0..10 {
            for j in 0..10 {
                m[i][j] += wd * n[i] * n[j];
            }
        }
    }
    m
}

/// Fills `out` with the element mass matrix: consistent (`lumped = false`) or HRZ-lumped
/// (module docs).
pub fn mass_into(g: &Tet10Geometry, density: f64, lumped: bool, out: &mut [[f64; 30]; 30]) {
    let m = scalar_mass(g);
    *out = [[0.0; 30]; 30];
    if lumped {
        let trace: f64 = (0..10).map(|i| m[i][i]).sum();
        let s = density * g.volume / trace;
        for i in 0..10 {
            for a in 0..3 {
                out[3 * i + a][3 * i + a] = s * m[i][i];
            }
        }
    } else {
        for i in 0..10 {
            for j in 0..10 {
                for a in 0..3 {
                    out[3 * i + a][3 * j + a] = density * m[i][j];
                }
            }
        }
    }
}

/// The Voigt strain (engineering shears) at the reference point `xi` of the element
/// displacements `u` (NaN where `det J` is zero there, which [`geometry`] excludes at its
/// check points).
pub fn strain_at(g: &Tet10Geometry, xi: [f64; 3], u: &[f64; 30]) -> [f64; 6] {
    let mut grad = [[f64::NAN; 3]; 10];
    jacobian(&shape(xi).1, &g.x, &mut grad);
    strain_of(&grad, u)
}

/// The Voigt stress `D B(xi) u` at the reference point `xi`.
pub fn stress_at(g: &Tet10Geometry, d: &[[f64; 6]; 6], xi: [f64; 3], u: &[f64; 30]) -> [f64; 6] {
    stress_of_strain(d, &strain_at(g, xi, u))
}

/// The thirty displacements of the tetrahedron with nodes `t`, gathered from the global
/// vector `u` (three dofs per node, interleaved).
pub fn element_displacements(u: &[f64], t: &[usize; 10]) -> [f64; 30] {
    let mut ue = [0.0; 30];
    for (l, &k) in t.iter().enumerate() {
        ue[3 * l..3 * l + 3].copy_from_slice(&u[3 * k..3 * k + 3]);
    }
    ue
}

/// The ten nodes of the straight-sided tetrahedron with corners `c` (mid-edge nodes at the
/// edge midpoints, Gmsh's order).
pub fn straight(c: &[[f64; 3]; 4]) -> [[f64; 3]; 10] {
    let mut p = [[0.0; 3]; 10];
    p[..4].copy_from_slice(c);
    for (e, &[a, b]) in EDGES.iter().enumerate() {
        p[4 + e] = [0, 1, 2].map(|k| 0.5 * (c[a][k] + c[b][k]));
    }
    p
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // index loops read best for small dense matrices
mod tests {
    use super::*;

    fn fact(n: u32) -> f64 {
        (1..=n).map(f64::from).product()
    }

    /// int over the reference tetrahedron of xi^a eta^b zeta^c = a! b! c! / (a+b+c+3)!.
    fn monomial(a: u32, b: u32, c: u32) -> f64 {
        fact(a) * fact(b) * fact(c) / fact(a + b + c + 3)
    }

    fn rule_error<const Q: usize>(rule: &TetRule<Q>, degree: u32) -> f64 {
        let mut worst: f64 = 0.0;
        for a in 0..=degree {
            for b in 0..=degree - a {
                for c in 0..=degree - a - b {
                    let q: f64 = rule
                        .points
                        .iter()
                        .zip(rule.weights)
                        .map(|(p, w)| {
                            w * p[0].powi(a as i32) * p[1].powi(b as i32) * p[2].powi(c as i32)
                        })
                        .sum();
                    let exact = monomial(a, b, c);
                    worst = worst.max((q - exact).abs() / exact);
                }
            }
        }
        worst
    }

    #[test]
    fn the_rules_integrate_monomials_to_their_degree() {
        assert!(rule_error(&QUAD4, 2) < 1e-14, "{}", rule_error(&QUAD4, 2));
        assert!(rule_error(&QUAD4, 3) > 1e-3);
        assert!(rule_error(&QUAD15, 5) < 1e-13, "{}", rule_error(&QUAD15, 5));
        assert!(rule_error(&QUAD15, 6) > 1e-4);
        for p in QUAD15.points {
            assert!(p.iter().all(|&v| v >= 0.0) && p.iter().sum::<f64>() <= 1.0 + 1e-15);
        }
        assert!(QUAD15.weights.iter().all(|&w| w > 0.0));
    }

    #[test]
    fn shape_functions_are_a_partition_of_unity_and_interpolate() {
        for (k, &xk) in NODES.iter().enumerate() {
            let (n, _) = shape(xk);
            for i in 0..10 {
                assert!((n[i] - f64::from(u8::from(i == k))).abs() < 1e-15);
            }
        }
        // Derivatives against central differences at an interior point.
        let xi = [0.21, 0.17, 0.33];
        let (n, dn) = shape(xi);
        assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        let h = 1e-6;
        for k in 0..3 {
            let mut p = xi;
            let mut m = xi;
            p[k] += h;
            m[k] -= h;
            let (np, _) = shape(p);
            let (nm, _) = shape(m);
            for i in 0..10 {
                assert!((dn[i][k] - (np[i] - nm[i]) / (2.0 * h)).abs() < 1e-8);
            }
        }
    }

    #[test]
    fn straight_mass_is_the_exact_integral_and_hrz_gives_v_over_36_and_4v_over_27() {
        let c = [
            [0.1, -0.2, 0.05],
            [1.3, 0.15, -0.1],
            [0.4, 0.95, 0.2],
            [0.35, 0.3, 1.1],
        ];
        let g = geometry(&straight(&c)).unwrap();
        assert!(!g.curved);
        let v4 = super::super::tet4::geometry(&c).unwrap().volume;
        assert!((g.volume - v4).abs() < 1e-15);
        let rho = 7850.0;
        let mut m = [[f64::NAN; 30]; 30];
        mass_into(&g, rho, false, &mut m);
        // The classical matrix (rho V / 420) [6 corner diagonal, 1 corner-corner, -4 corner
        // with a mid-edge node of its edges, -6 with the others, 32 mid-edge diagonal], from
        // int L_i^a L_j^b ... dV = a! b! ... 3! V / (a + b + ... + 3)!.
        let rv = rho * g.volume;
        assert!((m[0][0] - 6.0 * rv / 420.0).abs() < 1e-12 * rv);
        assert!(
            (m[0][3] - rv / 420.0).abs() < 1e-12 * rv,
            "{}",
            m[0][3] / rv
        );
        assert!(
            (m[0][12] + 4.0 * rv / 420.0).abs() < 1e-12 * rv,
            "node 4: edge 0-1"
        );
        assert!(
            (m[0][15] + 6.0 * rv / 420.0).abs() < 1e-12 * rv,
            "node 5: edge 1-2"
        );
        assert!((m[12][12] - 32.0 * rv / 420.0).abs() < 1e-12 * rv);
        assert_eq!(m[0][1], 0.0);
        let total: f64 = m.iter().flatten().sum();
        assert!((total - 3.0 * rv).abs() < 1e-12 * rv);
        mass_into(&g, rho, true, &mut m);
        for i in 0..10 {
            let expect = if i < 4 { rv / 36.0 } else { 4.0 * rv / 27.0 };
            for a in 0..3 {
                assert!((m[3 * i + a][3 * i + a] - expect).abs() < 1e-12 * rv);
            }
        }
        let total: f64 = m.iter().flatten().sum();
        assert!((total - 3.0 * rv).abs() < 1e-12 * rv);
    }

    #[test]
    fn both_rules_give_the_same_exact_stiffness_of_a_straight_element() {
        // B^T D B is quadratic on a straight-sided element: the 4-point rule (degree 2) and
        // the 15-point rule (degree 5) must agree to rounding.
        let c = [
            [0.1, -0.2, 0.05],
            [1.3, 0.15, -0.1],
            [0.4, 0.95, 0.2],
            [0.35, 0.3, 1.1],
        ];
        let g = geometry(&straight(&c)).unwrap();
        let d = elasticity_3d(&crate::material::Elastic {
            young: 70e9,
            poisson: 0.33,
            density: 2700.0,
        });
        let mut k4 = [[f64::NAN; 30]; 30];
        stiffness_into(&g, &d, &mut k4);
        let mut k15 = [[f64::NAN; 30]; 30];
        stiffness_into(&Tet10Geometry { curved: true, ..g }, &d, &mut k15);
        let scale = k4.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        for r in 0..30 {
            for c in 0..30 {
                assert!((k4[r][c] - k15[r][c]).abs() < 1e-12 * scale, "{r} {c}");
            }
        }
    }

    #[test]
    fn the_volume_of_a_curved_element_is_exact() {
        // The quadratic map x = xi (1 + a xi), y = eta, z = zeta of the unit reference tet:
        // for fixed (y, z) the section runs from 0 to s + a s^2, s = 1 - y - z, so
        // V = int_0^1 (s + a s^2) (1 - s) ds = 1/6 + a/12.
        let a = 0.4;
        let map = |p: [f64; 3]| [p[0] * (1.0 + a * p[0]), p[1], p[2]];
        let g = geometry(&NODES.map(map)).unwrap();
        assert!(g.curved);
        assert!(
            (g.volume - (1.0 / 6.0 + a / 12.0)).abs() < 1e-15,
            "{}",
            g.volume
        );
        // A scaled, rotated and bent one: the map X(xi) = R S (xi + q(xi)) with
        // q = (0, b xi^2, c xi zeta): det(dX) = det(R S) det(I + dq) = s1 s2 s3 (1 + c xi),
        // (the Jacobian of xi + q is lower triangular with diagonal 1, 1, 1 + c xi), so
        // V = s1 s2 s3 (1/6 + c/24).
        let (b, cc) = (0.3, -0.5);
        let s = [2.0, 0.5, 1.5];
        let (ca, sa) = (0.6f64, 0.8f64);
        let map2 = |p: [f64; 3]| {
            let y = [p[0], p[1] + b * p[0] * p[0], p[2] + cc * p[0] * p[2]];
            let y = [s[0] * y[0], s[1] * y[1], s[2] * y[2]];
            [ca * y[0] - sa * y[1], sa * y[0] + ca * y[1], y[2]]
        };
        let g = geometry(&NODES.map(map2)).unwrap();
        let exact = s[0] * s[1] * s[2] * (1.0 / 6.0 + cc / 24.0);
        assert!(
            (g.volume - exact).abs() < 1e-14 * exact,
            "{} vs {exact}",
            g.volume
        );
        // The mass is rho V per direction, lumped and consistent.
        for lumped in [false, true] {
            let mut m = [[0.0; 30]; 30];
            mass_into(&g, 2.0, lumped, &mut m);
            let total: f64 = m.iter().flatten().sum();
            assert!((total - 6.0 * exact).abs() < 1e-13 * exact, "{lumped}");
        }
    }

    #[test]
    fn bad_cells_are_rejected() {
        let c = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let mut p = straight(&c);
        p.swap(1, 2);
        // Swapping two corners without their edges also breaks the map; either way an error.
        assert!(geometry(&p).is_err());
        let mut inverted = straight(&[c[0], c[2], c[1], c[3]]);
        assert!(matches!(
            geometry(&inverted),
            Err(SolidError::Inverted {
                element: "tet10",
                ..
            })
        ));
        // A mid-edge node pulled past the opposite corner folds the element.
        inverted = straight(&c);
        inverted[4] = [0.5, 1.2, 1.2];
        assert!(geometry(&inverted).is_err());
        let mut flat = straight(&c);
        for q in &mut flat {
            q[2] = 0.0;
        }
        assert!(matches!(
            geometry(&flat),
            Err(SolidError::Degenerate { .. })
        ));
        let mut nan = straight(&c);
        nan[7][0] = f64::NAN;
        assert!(geometry(&nan).is_err());
    }

    #[test]
    fn a_quadratic_displacement_gives_its_linear_strain() {
        // u = (x^2, x y, z^2 + y) is in the span of a straight-sided element (its map is
        // affine): the strain is reproduced exactly at any point.
        let c = [
            [0.1, -0.2, 0.05],
            [1.3, 0.15, -0.1],
            [0.4, 0.95, 0.2],
            [0.35, 0.3, 1.1],
        ];
        let p = straight(&c);
        let g = geometry(&p).unwrap();
        let f = |x: [f64; 3]| [x[0] * x[0], x[0] * x[1], x[2] * x[2] + x[1]];
        let mut u = [0.0; 30];
        for i in 0..10 {
            u[3 * i..3 * i + 3].copy_from_slice(&f(p[i]));
        }
        let xi = [0.2, 0.3, 0.1];
        let (n, _) = shape(xi);
        let x = [0, 1, 2].map(|k| (0..10).map(|i| n[i] * p[i][k]).sum::<f64>());
        let e = strain_at(&g, xi, &u);
        let exact = [2.0 * x[0], x[0], 2.0 * x[2], 1.0, 0.0, x[1]];
        for k in 0..6 {
            assert!((e[k] - exact[k]).abs() < 1e-13, "{e:?} vs {exact:?}");
        }
    }
}
