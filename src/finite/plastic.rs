//! J2 plasticity at finite strain ([`FinitePlastic`]): the total Lagrangian cells of
//! [`FiniteBody`] (triangles in 2D; tet4, tet10 and hex8 in 3D) with the additive split of the Green-Lagrange strain,
//! `S = D (E - E_p)`, and the J2 return mapping of [`crate::plasticity`] on the second
//! Piola-Kirchhoff stress `S`.
//!
//! # Why this form
//!
//! The Green strain `E` and the stress `S` are unchanged by a rigid rotation of the body
//! (`F -> Q F` leaves `C = F^T F` alone), so the plastic law written between them is
//! objective by construction: no rate to integrate, no objective rate to choose (the
//! hypoelastic forms with a Jaumann or Green-Naghdi rate need one, and a multiplicative
//! `F = F_e F_p` a new return mapping). It is the paper's Eq. 13, `S` from `E`, with the
//! plastic strain subtracted, and at small strains it is the small-strain J2 of
//! [`crate::plasticity::PlasticBody`] (the same return mapping on the same numbers, `E`
//! then `sym(grad u)`). Its limit: the additive split of `E` is accurate while the elastic
//! strains stay small (steel: below 0.5 %) however large the rotations and moderate the
//! plastic strains; at plastic strains of tens of percent a multiplicative split would be
//! the next step.
//!
//! # The force and its state
//!
//! Per triangle: `F = I + H`, `E = (F^T F - I) / 2`, `S` from the return mapping at the
//! engineering strain `[E_xx, E_yy, 2 E_xy]` (plane strain or plane stress as the small-strain
//! law), `P = F S`, `f_int = sum V P grad N`; the force handed to the iteration is
//! `f_nl = K u - f_int` (the linear `K u` of the same triangles). The state is the
//! triangles' plastic states ([`crate::plasticity::STATE_LEN`] each, in the small-strain
//! body's layout: its readers work on this prefix) followed by the last two steps'
//! `f_nl`, whose extrapolation predicts the next step's ([`FiniteBody`]'s prediction).
//!
//! In 3D, per integration point of the solid cells: the Voigt Green strain `[E_xx, E_yy,
//! E_zz, 2 E_yz, 2 E_xz, 2 E_xy]` into the 3D return of [`crate::element::j2_solid`]
//! (the same radial return carried onto the six components), `S` back, `P = F S`; the
//! points' states are [`PointState3d::LEN`] numbers each (total and plastic strain,
//! backstress, equivalent plastic strain).

use super::{FiniteBody, Kind, M3};
use crate::element::j2_solid::{j2_stress_3d, PointState3d};
use crate::model::InternalForce;
use crate::plasticity::{J2Material, PointState, STATE_LEN};

/// The J2 body at finite strain, planar or solid (module docs).
#[derive(Debug, Clone)]
pub struct FinitePlastic {
    body: FiniteBody,
    material: J2Material,
}

/// One solid point's stresses at a displacement: `S` and `P`, the Voigt Green strain, the
/// linear `D sym(H)`, the return's result.
struct Point3 {
    s: [f64; 6],
    e: [f64; 6],
    p: M3,
    p_lin: M3,
    h: M3,
    state: PointState3d,
    plastic: bool,
}

/// One triangle's stresses at a displacement: `P` and the linear `D sym(H)` (in-plane,
/// 2x2), and the return mapping's result.
struct Cell2 {
    s: [[f64; 2]; 2],
    e: [f64; 3],
    p: [[f64; 2]; 2],
    p_lin: [[f64; 2]; 2],
    state: PointState,
    plastic: bool,
}

impl FinitePlastic {
    /// The J2 `material` on the hyperelastic body `body`'s cells (its law is not used: the
    /// elastic part is `material`'s Saint Venant-Kirchhoff `S = D (E - E_p)`; `body`'s
    /// elastic constants are `material`'s).
    pub fn new(body: FiniteBody, material: J2Material) -> Self {
        Self { body, material }
    }

    fn plane(&self) -> crate::material::PlaneModel {
        match self.body.kind {
            Kind::Plane(p) => p,
            Kind::Solid => unreachable!("the planar paths run on planar bodies"),
        }
    }

    /// Numbers of one point's plastic state.
    fn point_len(&self) -> usize {
        match self.body.kind {
            Kind::Plane(_) => STATE_LEN,
            Kind::Solid => PointState3d::LEN,
        }
    }

    fn cells_len(&self) -> usize {
        self.body.points_len() * self.point_len()
    }

    /// Solid point `q`'s stresses at `u` from the plastic state `st0`.
    fn point3(&self, q: usize, u: &[f64], st0: &PointState3d) -> Point3 {
        let c = self.body.point(q);
        let h = self.body.gradient(&c, u);
        let mut f = h;
        for (i, row) in f.iter_mut().enumerate() {
            row[i] += 1.0;
        }
        let mut c2 = [[0.0; 3]; 3];
        for (i, row) in c2.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = (0..3).map(|k| f[k][i] * f[k][j]).sum();
            }
        }
        let e = [
            0.5 * (c2[0][0] - 1.0),
            0.5 * (c2[1][1] - 1.0),
            0.5 * (c2[2][2] - 1.0),
            c2[1][2],
            c2[0][2],
            c2[0][1],
        ];
        let (state, s, plastic) = j2_stress_3d(&self.material, &e, st0);
        let st = [[s[0], s[5], s[4]], [s[5], s[1], s[3]], [s[4], s[3], s[2]]];
        let mut p = [[0.0; 3]; 3];
        for (i, row) in p.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = (0..3).map(|k| f[i][k] * st[k][j]).sum();
            }
        }
        let (lam, mu) = (self.body.lam, self.body.mu);
        let tr = h[0][0] + h[1][1] + h[2][2];
        let mut p_lin = [[0.0; 3]; 3];
        for (i, row) in p_lin.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = mu * (h[i][j] + h[j][i]) + if i == j { lam * tr } else { 0.0 };
            }
        }
        Point3 {
            s,
            e,
            p,
            p_lin,
            h,
            state,
            plastic,
        }
    }

    /// The second Piola-Kirchhoff stress (Voigt `[xx, yy, zz, yz, xz, xy]`, Pa) and the
    /// state of a solid body's point `q` at `u` from the state `st0` (for checks and
    /// outputs).
    ///
    /// # Panics
    /// If the body is planar.
    pub fn stress_3d(&self, q: usize, u: &[f64], st0: &PointState3d) -> ([f64; 6], PointState3d) {
        assert!(
            matches!(self.body.kind, Kind::Solid),
            "a solid body's point"
        );
        let r = self.point3(q, u, st0);
        (r.s, r.state)
    }

    /// Triangle `k`'s stresses at `u` from the plastic state `st0`.
    fn cell(&self, k: usize, u: &[f64], st0: &PointState) -> Cell2 {
        let c = self.body.point(k);
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
        let r = self
            .material
            .update(self.plane(), [e00, e11, 2.0 * e01], st0);
        let s = [[r.stress[0], r.stress[2]], [r.stress[2], r.stress[1]]];
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
        let (lam, mu) = (self.body.lam, self.body.mu);
        let ls = match self.plane() {
            crate::material::PlaneModel::Stress => 2.0 * lam * mu / (lam + 2.0 * mu),
            crate::material::PlaneModel::Strain => lam,
        };
        let tl = ls * (h[0][0] + h[1][1]);
        let g01 = mu * (h[0][1] + h[1][0]);
        Cell2 {
            s,
            e: [e00, e11, e01],
            p,
            p_lin: [
                [2.0 * mu * h[0][0] + tl, g01],
                [g01, 2.0 * mu * h[1][1] + tl],
            ],
            state: r.state,
            plastic: r.plastic,
        }
    }

    /// The second Piola-Kirchhoff stress `[S_xx, S_yy, S_xy]` and the state of triangle `k`
    /// at `u` from the state `st0` (for checks and outputs).
    pub fn stress(&self, k: usize, u: &[f64], st0: &PointState) -> ([f64; 3], PointState) {
        let r = self.cell(k, u, st0);
        ([r.s[0][0], r.s[1][1], r.s[0][1]], r.state)
    }

    /// Integration points (one a triangle), each with its plastic state.
    pub fn len(&self) -> usize {
        self.body.points_len()
    }

    /// Whether the body has no point.
    pub fn is_empty(&self) -> bool {
        self.body.points_len() == 0
    }
}

impl InternalForce for FinitePlastic {
    fn state_len(&self) -> usize {
        self.cells_len() + 2 * self.body.dofs
    }

    /// The prediction `2 f_nl(t_k) - f_nl(t_{k-1})` of the state's two pseudo-loads.
    fn pseudo_load(&self, s: &[f64], f_nl: &mut [f64]) {
        let (m, n) = (self.cells_len(), self.body.dofs);
        f_nl.fill(0.0);
        for ((f, a), b) in f_nl[..n]
            .iter_mut()
            .zip(&s[m..m + n])
            .zip(&s[m + n..m + 2 * n])
        {
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
        let mut flowed = 0;
        if matches!(self.body.kind, Kind::Solid) {
            let l = PointState3d::LEN;
            for q in 0..self.body.points_len() {
                let st0 = PointState3d::read(&s0[q * l..(q + 1) * l]);
                let r = self.point3(q, u, &st0);
                r.state.write(&mut s1[q * l..(q + 1) * l]);
                flowed += usize::from(r.plastic);
                let c = self.body.point(q);
                self.body.scatter(&c, &r.p, 1.0, f_int);
                self.body.scatter(&c, &r.p_lin, 1.0, f_nl);
                self.body.scatter(&c, &r.p, -1.0, f_nl);
            }
        } else {
            for k in 0..self.body.points_len() {
                let st0 = PointState::read(&s0[k * STATE_LEN..(k + 1) * STATE_LEN]);
                let r = self.cell(k, u, &st0);
                r.state.write(&mut s1[k * STATE_LEN..(k + 1) * STATE_LEN]);
                flowed += usize::from(r.plastic);
                let c = self.body.point(k);
                for a in 0..3 {
                    let (node, g) = (c.nodes[a], &c.grad[a]);
                    for i in 0..2 {
                        let fi = c.measure * (r.p[i][0] * g[0] + r.p[i][1] * g[1]);
                        let fl = c.measure * (r.p_lin[i][0] * g[0] + r.p_lin[i][1] * g[1]);
                        f_int[2 * node + i] += fi;
                        f_nl[2 * node + i] += fl - fi;
                    }
                }
            }
        }
        let (m, n) = (self.cells_len(), self.body.dofs);
        s1[m..m + n].copy_from_slice(&f_nl[..n]);
        s1[m + n..m + 2 * n].copy_from_slice(&s0[m..m + n]);
        flowed
    }

    /// `sum V [psi(E - E_p) - (D eps) : eps / 2]`, `psi` the elastic energy of the strain
    /// `E - E_p` (`lambda tr^2 / 2 + mu |.|^2`, with the out-of-plane strain the state holds in
    /// plane stress) and `eps = sym(H)` the linear reading.
    fn energy_correction(&self, s: &[f64], u: &[f64]) -> f64 {
        let (lam, mu) = (self.body.lam, self.body.mu);
        let mut corr = 0.0;
        if matches!(self.body.kind, Kind::Solid) {
            let l = PointState3d::LEN;
            for q in 0..self.body.points_len() {
                let st = PointState3d::read(&s[q * l..(q + 1) * l]);
                let r = self.point3(q, u, &st);
                // E - E_p in tensor components.
                let ee: [f64; 6] = std::array::from_fn(|k| {
                    let v = r.e[k] - st.plastic[k];
                    if k < 3 {
                        v
                    } else {
                        0.5 * v
                    }
                });
                let tr = ee[0] + ee[1] + ee[2];
                let stored = 0.5 * lam * tr * tr
                    + mu * (ee[0] * ee[0]
                        + ee[1] * ee[1]
                        + ee[2] * ee[2]
                        + 2.0 * (ee[3] * ee[3] + ee[4] * ee[4] + ee[5] * ee[5]));
                let mut linear = 0.0;
                for i in 0..3 {
                    for j in 0..3 {
                        linear += 0.5 * r.p_lin[i][j] * 0.5 * (r.h[i][j] + r.h[j][i]);
                    }
                }
                corr += self.body.point(q).measure * (stored - linear);
            }
            return corr;
        }
        for k in 0..self.body.points_len() {
            let st = PointState::read(&s[k * STATE_LEN..(k + 1) * STATE_LEN]);
            let r = self.cell(k, u, &st);
            let ezz = match self.plane() {
                crate::material::PlaneModel::Strain => 0.0,
                crate::material::PlaneModel::Stress => st.ezz,
            };
            let ee = [
                r.e[0] - st.eps_p[0],
                r.e[1] - st.eps_p[1],
                ezz - st.eps_p[2],
                r.e[2] - st.eps_p[3],
            ];
            let tr = ee[0] + ee[1] + ee[2];
            let stored = 0.5 * lam * tr * tr
                + mu * (ee[0] * ee[0] + ee[1] * ee[1] + ee[2] * ee[2] + 2.0 * ee[3] * ee[3]);
            let c = self.body.point(k);
            let mut h = [[0.0; 2]; 2];
            for a in 0..3 {
                let g = &c.grad[a];
                for (i, row) in h.iter_mut().enumerate() {
                    row[0] += u[2 * c.nodes[a] + i] * g[0];
                    row[1] += u[2 * c.nodes[a] + i] * g[1];
                }
            }
            let eps = [h[0][0], h[1][1], 0.5 * (h[0][1] + h[1][0])];
            let linear = 0.5
                * (r.p_lin[0][0] * eps[0] + r.p_lin[1][1] * eps[1] + 2.0 * r.p_lin[0][1] * eps[2]);
            corr += c.measure * (stored - linear);
        }
        corr
    }
}
