//! Large deformation: the geometrically nonlinear internal force of hyperelastic triangles
//! (tri3) and of the solid cells (tet4, tet10, hex8) behind the contract of
//! [`crate::model::InternalForce`].
//!
//! # The paper's form and the one used here
//!
//! The paper states its problem in the instantaneous updated Lagrangian form: the domain at
//! `t` follows from the velocities (Eqs. 1-2: `Omega_t` interpolated between `Omega_{t0}`
//! and `Omega_{t1}`, `x = x_0 + v_0 (2 - tau) h / 2 + v_1 tau h / 2`), the displacement is
//! the integral of the velocity (Eq. 15) and the stress is the second Piola-Kirchhoff tensor
//! of a strain (Eq. 13, `sigma = E eps`). The updated form refers each step's virtual power
//! to the configuration at the step's start; the total Lagrangian form here refers it to the
//! initial one. The two are the same equations written in two reference configurations:
//! with `F` the deformation gradient from the initial configuration, the updated form's
//! Cauchy stress `sigma = J^{-1} F S F^T` and the current virtual strain rate `sym(grad_x
//! v*)` give the virtual power `int_{Omega_t} sigma : grad_x v* dv = int_{Omega_0} S :
//! (F^T grad_X v*) dV = int_{Omega_0} P : grad_X v* dV` with `P = F S` (the first
//! Piola-Kirchhoff stress), which is the total form. The nodal internal force is therefore
//! the same vector `f_int(u)` whichever configuration the integral is written on, for the
//! same constitutive law `S(E)` of the Green strain `E = (F^T F - I) / 2`; only the
//! bookkeeping differs. The total form needs no update of the element geometry in the time
//! loop (the shape-function gradients of the initial mesh are kept), so it allocates
//! nothing and is exact for any rotation: a rigid rotation `F = R` gives `E = 0`, `S = 0`,
//! `f_int = 0` and zero stored energy, whatever the angle. The space-time interpolation of
//! the velocity (Eqs. 1-2, 15) stays that of the integrator: the internal force enters at the
//! integrator's stiffness point `u_k` as in [`crate::model::internal`].
//!
//! # Materials
//!
//! With the Lame constants `lambda`, `mu` of the elastic constants (the same as the linear
//! model's, so that both agree to first order in the strain):
//!
//! - Saint Venant-Kirchhoff ([`Hyperelastic::SaintVenantKirchhoff`]):
//!   `S = lambda tr(E) I + 2 mu E`, `W = lambda tr(E)^2 / 2 + mu E : E` (the paper's Eq. 13
//!   with the Green strain);
//! - compressible neo-Hookean ([`Hyperelastic::NeoHookean`]): `W = mu (I_1 - 3) / 2 - mu ln
//!   J + lambda (ln J)^2 / 2`, `P = mu (F - F^{-T}) + lambda ln J F^{-T}` (`I_1 = tr F^T F`,
//!   `J = det F > 0`).
//!
//! The triangles are in plane strain (`F_33 = 1`) or plane stress (`F_33` such that `P_33 =
//! 0`: closed form for Saint Venant-Kirchhoff, `E_33 = -lambda (E_11 + E_22) / (lambda + 2
//! mu)`; a scalar Newton on `C_33` for neo-Hookean, `mu (C_33 - 1) + lambda ln J = 0`), the
//! in-plane `P` and the 3D `W` at that `F_33` (stationary in `F_33`, so the in-plane `P` is
//! the gradient of `W` in either case).
//!
//! # The body ([`FiniteBody`])
//!
//! `f_int(u) = sum_q V_q P(F_q) : grad N` over the integration points `q` (`V_q = A t` for a
//! triangle of thickness `t`, the volume of a linear tetrahedron, `w_q det J_q` at the points
//! of the hexahedron's 2 x 2 x 2 Gauss rule and of the ten-node tetrahedron's 4-point rule,
//! 15 points on a curved one: the rules of the linear elements' stiffness, so that the
//! linear force below is the assembled `K u` to round-off; [`FiniteBody::of_mesh`] picks
//! them from a mesh's cells),
//! `f_nl(u) = K u - f_int(u)` with the elastic `K u = sum_e V_e B^T D B u_e` computed cell by
//! cell (the linear force of the same cells) and `energy_correction = W(u) - u^T K u / 2`.
//! The state of the contract is `f_nl` at the last two committed stiffness points (`t_k`
//! and `t_{k-1}`), so that [`InternalForce::pseudo_load`] predicts a step with the
//! nonlinear force extrapolated to it, `2 f_nl(t_k) - f_nl(t_{k-1})`: the stiffness points
//! are a step apart, the error of the prediction second order in the step, and the step's
//! iteration starts that much closer (on the paper's wheel in large deformation: 2.4
//! corrections a step where the force of the start took 4.4, at the tolerance 1e-8).
//!
//! No call allocates.

use crate::element::continuum::CellError;
use crate::element::hex8::{self, Hex8Geometry};
use crate::element::solid::jacobian;
use crate::element::tet10::{self, Tet10Geometry};
use crate::element::tet4::Tet4Geometry;
use crate::element::tri3::Tri3Geometry;
use crate::material::{Elastic, PlaneModel};
use crate::mesh::{CellKind, Mesh};
use crate::model::InternalForce;

/// Iterations of the plane-stress Newton on `C_33` (neo-Hookean) before keeping the last
/// iterate.
const PLANE_STRESS_ITER: usize = 50;

type M3 = [[f64; 3]; 3];

/// A hyperelastic law (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Hyperelastic {
    /// `S = lambda tr(E) I + 2 mu E` of the Green strain `E`.
    SaintVenantKirchhoff,
    /// Compressible neo-Hookean (module docs).
    NeoHookean,
}

/// The Lame constants `(lambda, mu)` of `m`, Pa.
pub fn lame(m: &Elastic) -> (f64, f64) {
    let (e, nu) = (m.young, m.poisson);
    (
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        e / (2.0 * (1.0 + nu)),
    )
}

fn det3(a: &M3) -> f64 {
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

/// `A^{-T}` (the cofactor matrix over the determinant) and `det A`.
fn inv_t3(a: &M3) -> (M3, f64) {
    let d = det3(a);
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            *v = (a[i1][j1] * a[i2][j2] - a[i1][j2] * a[i2][j1]) / d;
        }
    }
    (c, d)
}

/// The right Cauchy-Green `C = F^T F`.
fn right_cauchy_green(f: &M3) -> M3 {
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = (0..3).map(|k| f[k][i] * f[k][j]).sum();
        }
    }
    c
}

/// The energy density `W` (J/m^3) and the first Piola-Kirchhoff stress `P` (Pa) of the law
/// at the deformation gradient `f` (module docs).
pub fn piola_3d(law: Hyperelastic, lam: f64, mu: f64, f: &M3) -> (f64, M3) {
    match law {
        Hyperelastic::SaintVenantKirchhoff => {
            let c = right_cauchy_green(f);
            let mut e = c;
            for (i, row) in e.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = 0.5 * (*v - if i == j { 1.0 } else { 0.0 });
                }
            }
            let tr = e[0][0] + e[1][1] + e[2][2];
            let ee: f64 = e.iter().flatten().map(|v| v * v).sum();
            let mut s = e;
            for (i, row) in s.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = 2.0 * mu * *v + if i == j { lam * tr } else { 0.0 };
                }
            }
            let mut p = [[0.0; 3]; 3];
            for (i, row) in p.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = (0..3).map(|k| f[i][k] * s[k][j]).sum();
                }
            }
            (0.5 * lam * tr * tr + mu * ee, p)
        }
        Hyperelastic::NeoHookean => {
            let (fit, j) = inv_t3(f);
            let lnj = j.ln();
            let i1: f64 = f.iter().flatten().map(|v| v * v).sum();
            let mut p = [[0.0; 3]; 3];
            for (i, row) in p.iter_mut().enumerate() {
                for (k, v) in row.iter_mut().enumerate() {
                    *v = mu * (f[i][k] - fit[i][k]) + lam * lnj * fit[i][k];
                }
            }
            (0.5 * mu * (i1 - 3.0) - mu * lnj + 0.5 * lam * lnj * lnj, p)
        }
    }
}

/// The out-of-plane stretch `F_33` of plane stress at the in-plane gradient `f` (the upper
/// left 2x2 block; module docs).
fn plane_stress_stretch(law: Hyperelastic, lam: f64, mu: f64, f: &M3) -> f64 {
    let c = right_cauchy_green(f);
    match law {
        Hyperelastic::SaintVenantKirchhoff => {
            let e33 = -lam * 0.5 * (c[0][0] + c[1][1] - 2.0) / (lam + 2.0 * mu);
            (1.0 + 2.0 * e33).sqrt()
        }
        Hyperelastic::NeoHookean => {
            let j2 = f[0][0] * f[1][1] - f[0][1] * f[1][0];
            let lnj2 = j2.ln();
            // g(x) = mu (x - 1) + lambda (ln J2 + ln x / 2), increasing and concave in x.
            let mut x: f64 = 1.0;
            for _ in 0..PLANE_STRESS_ITER {
                let g = mu * (x - 1.0) + lam * (lnj2 + 0.5 * x.ln());
                let dg = mu + 0.5 * lam / x;
                let mut next = x - g / dg;
                if next <= 0.0 {
                    next = 0.5 * x;
                }
                let done = (next - x).abs() <= 1e-15 * x;
                x = next;
                if done {
                    break;
                }
            }
            x.sqrt()
        }
    }
}

/// How a body's cells are made.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Plane(PlaneModel),
    Solid,
}

/// One integration point: its cell and its measure (`A t` of a triangle, `V` of a linear
/// tetrahedron, `w det J` at a point of a hexahedron's or a ten-node tetrahedron's rule).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Weight {
    cell: usize,
    measure: f64,
}

/// A point's view: its cell's nodes, the shape functions' gradients there (initial
/// configuration) and its measure.
#[derive(Debug, Clone, Copy)]
struct Point<'a> {
    nodes: &'a [usize],
    grad: &'a [[f64; 3]],
    measure: f64,
}

/// The hyperelastic cells of one body (module docs), integrated point by point: one point a
/// triangle or linear tetrahedron (constant gradients), the element's own rule for the
/// hexahedron (2 x 2 x 2 Gauss) and the ten-node tetrahedron (4 points straight, 15 curved),
/// the rules of the linear elements' stiffness, so that the cell-by-cell `K u` here is the
/// assembled one. Node `i` of a planar body has the dofs `2 i`, `2 i + 1` of the driver's
/// vector; of a solid body, `3 i .. 3 i + 3`.
#[derive(Debug, Clone)]
pub struct FiniteBody {
    law: Hyperelastic,
    lam: f64,
    mu: f64,
    kind: Kind,
    /// Nodes of a cell.
    nn: usize,
    /// The cells' nodes, `nn` a cell.
    nodes: Vec<usize>,
    /// The gradients at the points, `nn` a point.
    grads: Vec<[f64; 3]>,
    /// The points.
    weights: Vec<Weight>,
    dofs: usize,
}

/// What one cell gives at a displacement.
struct CellForce {
    /// First Piola-Kirchhoff stress.
    p: M3,
    /// The linear stress `D eps` of the same displacement gradient (as a 3x3 tensor).
    p_lin: M3,
    /// Stored energy and linear energy densities.
    w: f64,
    w_lin: f64,
    /// The largest principal Green strain's magnitude (the norm of `E`).
    strain: f64,
}

/// Why a mesh cannot be a [`FiniteBody`].
#[derive(Debug, thiserror::Error)]
pub enum FiniteError {
    /// A cell is not an element (inverted, degenerate) or the cells are not the element's.
    #[error(transparent)]
    Cell(#[from] CellError),
    /// No hyperelastic cell runs on these cells.
    #[error(
        "large deformation runs on triangles in 2D and on tet4, tet10 and hex8 in 3D, not on {0}"
    )]
    NoCell(&'static str),
}

impl FiniteBody {
    fn empty(law: Hyperelastic, elastic: &Elastic, kind: Kind, nn: usize, dofs: usize) -> Self {
        let (lam, mu) = lame(elastic);
        Self {
            law,
            lam,
            mu,
            kind,
            nn,
            nodes: Vec::new(),
            grads: Vec::new(),
            weights: Vec::new(),
            dofs,
        }
    }

    /// Adds a cell of `nodes` and its points `(gradients, measure)`.
    fn push_cell<'a>(
        &mut self,
        nodes: &[usize],
        points: impl IntoIterator<Item = (&'a [[f64; 3]], f64)>,
    ) {
        debug_assert_eq!(nodes.len(), self.nn);
        let cell = self.nodes.len() / self.nn;
        self.nodes.extend_from_slice(nodes);
        for (grad, measure) in points {
            debug_assert_eq!(grad.len(), self.nn);
            self.grads.extend_from_slice(grad);
            self.weights.push(Weight { cell, measure });
        }
    }

    /// A planar body of `triangles` (with their `geometry`), thickness `thickness` (m), on a
    /// driver's vector of `dofs` numbers.
    ///
    /// # Panics
    /// If `triangles` and `geometry` differ in length.
    pub fn planar(
        law: Hyperelastic,
        elastic: &Elastic,
        plane: PlaneModel,
        thickness: f64,
        triangles: &[[usize; 3]],
        geometry: &[Tri3Geometry],
        dofs: usize,
    ) -> Self {
        assert_eq!(triangles.len(), geometry.len());
        let mut b = Self::empty(law, elastic, Kind::Plane(plane), 3, dofs);
        for (t, g) in triangles.iter().zip(geometry) {
            let grad = g.grad.map(|r| [r[0], r[1], 0.0]);
            b.push_cell(t, [(&grad[..], g.area * thickness)]);
        }
        b
    }

    /// A solid body of linear tetrahedra `tets` (with their `geometry`) on a driver's
    /// vector of `dofs` numbers.
    ///
    /// # Panics
    /// If `tets` and `geometry` differ in length.
    pub fn solid(
        law: Hyperelastic,
        elastic: &Elastic,
        tets: &[[usize; 4]],
        geometry: &[Tet4Geometry],
        dofs: usize,
    ) -> Self {
        assert_eq!(tets.len(), geometry.len());
        let mut b = Self::empty(law, elastic, Kind::Solid, 4, dofs);
        for (t, g) in tets.iter().zip(geometry) {
            b.push_cell(t, [(&g.grad[..], g.volume)]);
        }
        b
    }

    /// A solid body of trilinear hexahedra `hexes` (Gmsh's order, with their `geometry`) on
    /// a driver's vector of `dofs` numbers: the 2 x 2 x 2 Gauss points of
    /// [`crate::element::hex8`].
    ///
    /// # Panics
    /// If `hexes` and `geometry` differ in length.
    pub fn hex8(
        law: Hyperelastic,
        elastic: &Elastic,
        hexes: &[[usize; 8]],
        geometry: &[Hex8Geometry],
        dofs: usize,
    ) -> Self {
        assert_eq!(hexes.len(), geometry.len());
        let mut b = Self::empty(law, elastic, Kind::Solid, 8, dofs);
        for (t, g) in hexes.iter().zip(geometry) {
            let pts = hex8::GAUSS.map(|xi| {
                let mut grad = [[0.0; 3]; 8];
                let det = jacobian(&hex8::shape(xi).1, &g.x, &mut grad);
                (grad, det)
            });
            b.push_cell(t, pts.iter().map(|(g, d)| (&g[..], *d)));
        }
        b
    }

    /// A solid body of ten-node tetrahedra `tets` (Gmsh's order, with their `geometry`) on
    /// a driver's vector of `dofs` numbers: the 4-point rule on a straight-sided cell, the
    /// 15-point rule on a curved one ([`crate::element::tet10`]'s stiffness rules).
    ///
    /// # Panics
    /// If `tets` and `geometry` differ in length.
    pub fn tet10(
        law: Hyperelastic,
        elastic: &Elastic,
        tets: &[[usize; 10]],
        geometry: &[Tet10Geometry],
        dofs: usize,
    ) -> Self {
        assert_eq!(tets.len(), geometry.len());
        let mut b = Self::empty(law, elastic, Kind::Solid, 10, dofs);
        let mut pts = Vec::with_capacity(15);
        for (t, g) in tets.iter().zip(geometry) {
            pts.clear();
            let mut add = |xi: &[f64; 3], w: f64| {
                let mut grad = [[0.0; 3]; 10];
                let det = jacobian(&tet10::shape(*xi).1, &g.x, &mut grad);
                pts.push((grad, w * det));
            };
            if g.curved {
                for (xi, w) in tet10::QUAD15.points.iter().zip(tet10::QUAD15.weights) {
                    add(xi, w);
                }
            } else {
                for (xi, w) in tet10::QUAD4.points.iter().zip(tet10::QUAD4.weights) {
                    add(xi, w);
                }
            }
            b.push_cell(t, pts.iter().map(|(g, d)| (&g[..], *d)));
        }
        b
    }

    /// The body of `mesh`'s cells (node `i` on the dofs `dim i ..`), on a driver's vector of
    /// `dofs` numbers: triangles (`plane`, `thickness` m) in 2D, tet4, tet10 or hex8 in 3D.
    ///
    /// # Errors
    /// [`FiniteError`] naming the first bad cell, or cells with no hyperelastic element.
    pub fn of_mesh(
        law: Hyperelastic,
        elastic: &Elastic,
        plane: PlaneModel,
        thickness: f64,
        mesh: &Mesh,
        dofs: usize,
    ) -> Result<Self, FiniteError> {
        use crate::element::continuum::{geometries, PlaneTri3, SolidHex8, SolidTet10, SolidTet4};
        let d = crate::element::solid::elasticity_3d(elastic);
        fn cells<const K: usize>(mesh: &Mesh) -> Vec<[usize; K]> {
            mesh.cells
                .connectivity()
                .chunks_exact(K)
                .map(|c| std::array::from_fn(|i| c[i]))
                .collect()
        }
        Ok(match mesh.cells.kind() {
            CellKind::Tri3 => {
                let el = PlaneTri3 {
                    d: plane.elasticity_matrix(elastic),
                    thickness,
                };
                let g = geometries(mesh, &el)?;
                Self::planar(law, elastic, plane, thickness, &cells(mesh), &g, dofs)
            }
            CellKind::Tet4 => {
                let g = geometries(mesh, &SolidTet4 { d })?;
                Self::solid(law, elastic, &cells(mesh), &g, dofs)
            }
            CellKind::Tet10 => {
                let g = geometries(mesh, &SolidTet10 { d })?;
                Self::tet10(law, elastic, &cells(mesh), &g, dofs)
            }
            CellKind::Hex8 => {
                let g = geometries(mesh, &SolidHex8 { d })?;
                Self::hex8(law, elastic, &cells(mesh), &g, dofs)
            }
            other => return Err(FiniteError::NoCell(other.describe())),
        })
    }

    /// Point `q`.
    fn point(&self, q: usize) -> Point<'_> {
        let w = self.weights[q];
        Point {
            nodes: &self.nodes[w.cell * self.nn..(w.cell + 1) * self.nn],
            grad: &self.grads[q * self.nn..(q + 1) * self.nn],
            measure: w.measure,
        }
    }

    /// Every point.
    fn points(&self) -> impl Iterator<Item = Point<'_>> + '_ {
        (0..self.weights.len()).map(|q| self.point(q))
    }

    /// Number of integration points.
    pub fn points_len(&self) -> usize {
        self.weights.len()
    }

    fn dim(&self) -> usize {
        match self.kind {
            Kind::Plane(_) => 2,
            Kind::Solid => 3,
        }
    }

    /// The displacement gradient `H = grad_X u` of cell `c` (zero out of the plane).
    fn gradient(&self, c: &Point, u: &[f64]) -> M3 {
        let d = self.dim();
        let mut h = [[0.0; 3]; 3];
        for a in 0..c.nodes.len() {
            for (i, row) in h.iter_mut().enumerate().take(d) {
                let ui = u[d * c.nodes[a] + i];
                for (j, v) in row.iter_mut().enumerate() {
                    *v += ui * c.grad[a][j];
                }
            }
        }
        h
    }

    /// Everything one cell gives at the displacement gradient `h`.
    fn cell_force(&self, h: &M3) -> CellForce {
        let (lam, mu) = (self.lam, self.mu);
        let mut f = *h;
        for (i, row) in f.iter_mut().enumerate() {
            row[i] += 1.0;
        }
        // Linear: eps = sym(H), D eps with the plane model's reduced lambda.
        let lam_lin = match self.kind {
            Kind::Plane(PlaneModel::Stress) => 2.0 * lam * mu / (lam + 2.0 * mu),
            _ => lam,
        };
        match self.kind {
            Kind::Plane(PlaneModel::Stress) => {
                f[2][2] = plane_stress_stretch(self.law, lam, mu, &f);
            }
            Kind::Plane(PlaneModel::Strain) | Kind::Solid => {}
        }
        let (w, p) = piola_3d(self.law, lam, mu, &f);
        let mut eps = [[0.0; 3]; 3];
        for (i, row) in eps.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = 0.5 * (h[i][j] + h[j][i]);
            }
        }
        let tr = eps[0][0] + eps[1][1] + eps[2][2];
        let mut p_lin = [[0.0; 3]; 3];
        let mut w_lin = 0.0;
        for (i, row) in p_lin.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = 2.0 * mu * eps[i][j] + if i == j { lam_lin * tr } else { 0.0 };
                w_lin += 0.5 * *v * eps[i][j];
            }
        }
        let c = right_cauchy_green(&f);
        let mut e2 = 0.0;
        for (i, row) in c.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                let e = 0.5 * (v - if i == j { 1.0 } else { 0.0 });
                e2 += e * e;
            }
        }
        CellForce {
            p,
            p_lin,
            w,
            w_lin,
            strain: e2.sqrt(),
        }
    }

    /// `y[dofs of c] += V_c s : grad N` (in-plane rows only for a planar body).
    fn scatter(&self, c: &Point, s: &M3, sign: f64, y: &mut [f64]) {
        let d = self.dim();
        for a in 0..c.nodes.len() {
            for (i, row) in s.iter().enumerate().take(d) {
                let g = &c.grad[a];
                y[d * c.nodes[a] + i] +=
                    sign * c.measure * (row[0] * g[0] + row[1] * g[1] + row[2] * g[2]);
            }
        }
    }

    /// The step's evaluation for Saint Venant-Kirchhoff triangles, in two dimensions only:
    /// in plane stress `S_33 = 0` gives `E_33 = -lambda tr E / (lambda + 2 mu)` and so the
    /// in-plane `S = 2 mu E + lambda' tr(E) I` with the plane-stress `lambda' = 2 lambda mu /
    /// (lambda + 2 mu)` (in plane strain `lambda' = lambda`), `P = F S`; the linear stress
    /// `2 mu eps + lambda' tr(eps) I` of the same cells beside it. Adds `f_int` and `K u -
    /// f_int` into the two vectors (the same forces as [`Self::cell_force`]'s, without its
    /// energies and strains).
    fn planar_svk_into(&self, plane: PlaneModel, u: &[f64], f_nl: &mut [f64], f_int: &mut [f64]) {
        let (lam, mu) = (self.lam, self.mu);
        let ls = match plane {
            PlaneModel::Stress => 2.0 * lam * mu / (lam + 2.0 * mu),
            PlaneModel::Strain => lam,
        };
        for c in self.points() {
            let mut h = [[0.0; 2]; 2];
            for a in 0..3 {
                let n = c.nodes[a];
                let (ux, uy) = (u[2 * n], u[2 * n + 1]);
                let g = &c.grad[a];
                h[0][0] += ux * g[0];
                h[0][1] += ux * g[1];
                h[1][0] += uy * g[0];
                h[1][1] += uy * g[1];
            }
            let f = [[1.0 + h[0][0], h[0][1]], [h[1][0], 1.0 + h[1][1]]];
            let e00 = 0.5 * (f[0][0] * f[0][0] + f[1][0] * f[1][0] - 1.0);
            let e11 = 0.5 * (f[0][1] * f[0][1] + f[1][1] * f[1][1] - 1.0);
            let e01 = 0.5 * (f[0][0] * f[0][1] + f[1][0] * f[1][1]);
            let tr = ls * (e00 + e11);
            let s = [
                [2.0 * mu * e00 + tr, 2.0 * mu * e01],
                [2.0 * mu * e01, 2.0 * mu * e11 + tr],
            ];
            let p = [
                [
                    f[0][0] * s[0][0] + f[0][1] * s[1][0],
                    f[0][0] * s[0][1] + f[0][1] * s[1][1],
                ],
                [
                    f[1][0] * s[0][0] + f[1][1] * s[1][0],
                    f[1][0] * s[0][1] + f[1][1] * s[1][1],
                ],
            ];
            let tl = ls * (h[0][0] + h[1][1]);
            let g01 = mu * (h[0][1] + h[1][0]);
            let pl = [
                [2.0 * mu * h[0][0] + tl, g01],
                [g01, 2.0 * mu * h[1][1] + tl],
            ];
            let m = c.measure;
            for a in 0..3 {
                let n = c.nodes[a];
                let g = &c.grad[a];
                for i in 0..2 {
                    let fi = m * (p[i][0] * g[0] + p[i][1] * g[1]);
                    let fl = m * (pl[i][0] * g[0] + pl[i][1] * g[1]);
                    f_int[2 * n + i] += fi;
                    f_nl[2 * n + i] += fl - fi;
                }
            }
        }
    }

    /// The nonlinear internal force `f_int(u)` into `out` (overwritten).
    pub fn internal_force_into(&self, u: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for c in self.points() {
            let r = self.cell_force(&self.gradient(&c, u));
            self.scatter(&c, &r.p, 1.0, out);
        }
    }

    /// The linear internal force `K u` of the same cells into `out` (overwritten).
    pub fn linear_force_into(&self, u: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for c in self.points() {
            let r = self.cell_force(&self.gradient(&c, u));
            self.scatter(&c, &r.p_lin, 1.0, out);
        }
    }

    /// The stored energy `W(u)` and the linear `u^T K u / 2`, J.
    pub fn energies(&self, u: &[f64]) -> (f64, f64) {
        let (mut w, mut w_lin) = (0.0, 0.0);
        for c in self.points() {
            let r = self.cell_force(&self.gradient(&c, u));
            w += c.measure * r.w;
            w_lin += c.measure * r.w_lin;
        }
        (w, w_lin)
    }

    /// The largest Green strain (Frobenius norm of `E` over the cells) and the largest
    /// linear strain (norm of `sym(grad u)`) at `u`.
    pub fn max_strains(&self, u: &[f64]) -> (f64, f64) {
        let (mut e, mut e_lin) = (0.0f64, 0.0f64);
        for c in self.points() {
            let h = self.gradient(&c, u);
            e = e.max(self.cell_force(&h).strain);
            let mut n2 = 0.0;
            for (i, row) in h.iter().enumerate() {
                for (j, v) in row.iter().enumerate() {
                    n2 += (0.5 * (v + h[j][i])).powi(2);
                }
            }
            e_lin = e_lin.max(n2.sqrt());
        }
        (e, e_lin)
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.nodes.len() / self.nn
    }

    /// Whether the body has no cell.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }
}

impl InternalForce for FiniteBody {
    fn state_len(&self) -> usize {
        2 * self.dofs
    }

    /// The prediction `2 f_nl(t_k) - f_nl(t_{k-1})` of the state's two pseudo-loads (module
    /// docs: the state).
    fn pseudo_load(&self, s: &[f64], f_nl: &mut [f64]) {
        let n = self.dofs;
        f_nl.fill(0.0);
        for ((f, a), b) in f_nl[..n].iter_mut().zip(&s[..n]).zip(&s[n..]) {
            *f = 2.0 * a - b;
        }
    }

    fn evaluate(
        &self,
        s0: &[f64],
        u: &[f64],
        s1: &mut [f64],
        f_nl: &mut [f64],
        f_int: &mut [f64],
    ) -> usize {
        f_nl.fill(0.0);
        f_int.fill(0.0);
        match (self.kind, self.law) {
            (Kind::Plane(plane), Hyperelastic::SaintVenantKirchhoff) => {
                self.planar_svk_into(plane, u, f_nl, f_int);
            }
            _ => {
                for c in self.points() {
                    let r = self.cell_force(&self.gradient(&c, u));
                    self.scatter(&c, &r.p, 1.0, f_int);
                    self.scatter(&c, &r.p_lin, 1.0, f_nl);
                    self.scatter(&c, &r.p, -1.0, f_nl);
                }
            }
        }
        let n = self.dofs;
        s1[..n].copy_from_slice(&f_nl[..n]);
        s1[n..].copy_from_slice(&s0[..n]);
        0
    }

    fn energy_correction(&self, _s: &[f64], u: &[f64]) -> f64 {
        let (w, w_lin) = self.energies(u);
        w - w_lin
    }

    /// The state is two nodal force vectors (`f_nl` at the last two steps), which a
    /// relabelling of the nodes carries: turned with the mesh by a symmetry of it, the
    /// force `K u - f_int(u)` turns with them (both `K u` and the objective `f_int`).
    fn nodal_state(&self) -> Option<usize> {
        Some(2)
    }
}

mod plastic;
pub use plastic::FinitePlastic;
mod statics;
pub use statics::{solve_static, StaticError, StaticStats, MAX_NEWTON};

#[cfg(test)]
mod tests;
