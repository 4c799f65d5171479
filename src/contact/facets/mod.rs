//! Contact search in 3D: a body's contact nodes against another body's surface facets, the
//! same contract as the planar segment search ([`MasterSurface`], [`super::search`]).
//!
//! # Facets
//!
//! The surface of a 3D body is the set of its cells' faces that belong to exactly one
//! cell ([`surface_facets`]): the triangles of tetrahedra, the quadrilaterals of hexahedra,
//! each turned so that its normal points out of its cell (checked against the cell's
//! centre, whatever the mesh's node order), optionally only those whose nodes all lie in a
//! node set (the master region). A face shared by more than two cells is refused.
//!
//! **The 10-node tetrahedron's faces are taken by their corners.** Its face is a 6-node
//! quadratic triangle; with straight edges (the generated boxes, and any mesh whose
//! mid-edge nodes sit at their edges' middles) it is exactly the plane triangle of its
//! corners in the reference, so the facet's geometry is exact there. What the corner
//! facet leaves out is the mid-edge nodes' share of the master surface's motion: the
//! deformed face between corners is quadratic, the facet linear, a gap error of the order
//! of `h^2` times the displacement's curvature, the same order as the faceting of a
//! curved surface; and a contact force reaches the face's corners only (its consistent
//! nodal loads would go mostly to the mid-edge nodes). The mid-edge nodes can still be
//! slave nodes of the other side. Splitting each face into its four sub-triangles would
//! involve them at the same order of accuracy; the corners keep the rows at five nodes.
//!
//! # The closest point, the normal, the gap
//!
//! A node at `x` faces facet `f` at the parameters `(xi, eta)` of its closest point
//! `x_f = sum_i N_i(xi, eta) x_i` ([`closest`]: exact on a triangle, Newton's method on the
//! bilinear quadrilateral), within the reach (`|x - x_f| <= reach`). The facet's outward
//! unit normal there is `n` (a triangle's own; a quadrilateral's `x_xi x x_eta`), and
//! $$g = n \cdot (x - x_f).$$
//! A node over a vertex or an edge is at the same distance from several facets: the one
//! with the larger gap is taken, then the lower index (as [`super::search::Search::find`]).
//!
//! # The rows
//!
//! With `(f, xi, eta, n)` frozen for the step, the gap is linear in the displacements, as
//! in the plane ([`super::search`], The pair's row): `c` is `R_a^T n` on the slave node's
//! three dofs and `-N_i R_f^T n` on each facet node's three, the offset `-n . (o_a - o_f)`
//! holds the frames' origins, and `w = -n . (d_a - sum_i N_i d_i)` the frames' drift. The
//! tangential rows are the same construction along the two unit tangents of
//! [`super::pair::tangent_basis`]. A row acts on up to five nodes (a quadrilateral's four
//! and the slave node): [`crate::model::MAX_TERMS`] is 15.
//!
//! # The search structure
//!
//! Each step the facets are placed in the ground, boxed, and a bounding-volume hierarchy
//! is rebuilt over their boxes in place ([`bvh`]): no allocation once its buffers have
//! their size, which [`FacetSearch::new`] gives them. A query walks the boxes within the
//! reach, then within the closest distance found so far.

pub mod bvh;
pub mod closest;
#[cfg(test)]
mod tests;

use std::any::Any;

use super::interface::MasterSurface;
use super::obstacle::{dot, Vector};
use super::pair::tangent_basis;
use super::rows::Terms;
use super::search::{Motion, Placed, SearchedRow, Target};
use crate::mesh::{CellKind, Mesh};
use bvh::Bvh;
use closest::{
    closest_on_quad, closest_on_triangle, cross, quad_normal, quad_point, quad_weights, sub,
    triangle_point, unit,
};

/// A surface facet: a triangle or a bilinear quadrilateral of the master body's node
/// indices, counter-clockwise seen from outside (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Facet {
    /// A triangle: `x = x_0 + xi (x_1 - x_0) + eta (x_2 - x_0)`.
    Tri([usize; 3]),
    /// A bilinear quadrilateral on the unit square ([`closest`]).
    Quad([usize; 4]),
}

impl Facet {
    /// Its nodes.
    pub fn nodes(&self) -> &[usize] {
        match self {
            Facet::Tri(n) => n,
            Facet::Quad(n) => n,
        }
    }

    /// The weights `N_i(xi, eta)` of its nodes (the first [`Facet::nodes`]`.len()` used).
    pub fn weights(&self, xi: f64, eta: f64) -> [f64; 4] {
        match self {
            Facet::Tri(_) => [1.0 - xi - eta, xi, eta, 0.0],
            Facet::Quad(_) => quad_weights(xi, eta),
        }
    }

    /// The same facet seen from the other side.
    fn reversed(self) -> Facet {
        match self {
            Facet::Tri([a, b, c]) => Facet::Tri([a, c, b]),
            Facet::Quad([a, b, c, d]) => Facet::Quad([a, d, c, b]),
        }
    }
}

/// Why a surface or a facet search cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FacetError {
    /// The mesh's cells are not 3D solids.
    #[error("surface facets need a mesh of 3D solid cells (tetrahedra or hexahedra), not {0}")]
    Cells(&'static str),
    /// A node of the master region is not a node of the mesh.
    #[error("node {node} of the master region is not a node of the mesh (it has {nodes} nodes)")]
    Region {
        /// The node.
        node: usize,
        /// The mesh's node count.
        nodes: usize,
    },
    /// A face shared by more than two cells.
    #[error(
        "the face of nodes {nodes:?} belongs to {cells} cells (at most 2 in a conforming mesh)"
    )]
    NonManifold {
        /// Its nodes (sorted; `usize::MAX` past a triangle's three).
        nodes: [usize; 4],
        /// How many cells share it.
        cells: usize,
    },
    /// A facet naming a node the body does not have, repeating a node, or of zero area.
    #[error("master facet {facet} is {why}")]
    Facet {
        /// The facet.
        facet: usize,
        /// What is wrong.
        why: &'static str,
    },
    /// No facet at all.
    #[error("the master surface has no facet (an empty master region?)")]
    Empty,
    /// The reach is not finite and positive.
    #[error("the search reach must be finite and > 0 m, got {0}")]
    Reach(f64),
    /// The reference positions are not three per node.
    #[error("the master body's reference positions hold {0} values, not 3 per node")]
    Reference(usize),
}

/// The faces of the cells of `kind`, by local node indices (corners only; orientation
/// is fixed afterwards against the cell's centre).
fn faces(kind: CellKind) -> Result<&'static [Facet], FacetError> {
    const TET: [Facet; 4] = [
        Facet::Tri([0, 2, 1]),
        Facet::Tri([0, 1, 3]),
        Facet::Tri([1, 2, 3]),
        Facet::Tri([0, 3, 2]),
    ];
    const HEX: [Facet; 6] = [
        Facet::Quad([0, 3, 2, 1]),
        Facet::Quad([4, 5, 6, 7]),
        Facet::Quad([0, 1, 5, 4]),
        Facet::Quad([1, 2, 6, 5]),
        Facet::Quad([2, 3, 7, 6]),
        Facet::Quad([3, 0, 4, 7]),
    ];
    match kind {
        CellKind::Tet4 | CellKind::Tet10 => Ok(&TET),
        CellKind::Hex8 => Ok(&HEX),
        other => Err(FacetError::Cells(other.describe())),
    }
}

/// A point of a 3-per-node coordinate array.
fn point(coords: &[f64], i: usize) -> Vector {
    [coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]]
}

/// The area vector of `facet` with positions `x(i)` (a triangle's `(b - a) x (c - a) / 2`;
/// a quadrilateral's half cross product of its diagonals).
fn area_vector(facet: &Facet, x: impl Fn(usize) -> Vector) -> Vector {
    let v = match *facet {
        Facet::Tri([a, b, c]) => cross(sub(x(b), x(a)), sub(x(c), x(a))),
        Facet::Quad([a, b, c, d]) => cross(sub(x(c), x(a)), sub(x(d), x(b))),
    };
    v.map(|c| 0.5 * c)
}

/// The surface facets of a 3D solid mesh (module docs): the faces of exactly one cell,
/// outward, sorted by their nodes; with `region`, only those whose nodes all lie in it.
///
/// # Errors
/// [`FacetError::Cells`] for a mesh of other cells, [`FacetError::Region`] for a region
/// node beyond the mesh, [`FacetError::NonManifold`] for a face of three cells or more.
pub fn surface_facets(mesh: &Mesh, region: Option<&[usize]>) -> Result<Vec<Facet>, FacetError> {
    let kind = mesh.cells.kind();
    let local = faces(kind)?;
    if mesh.dim != 3 {
        return Err(FacetError::Cells(kind.describe()));
    }
    let n_nodes = mesh.n_nodes();
    let mut inside = vec![region.is_none(); n_nodes];
    for &node in region.unwrap_or(&[]) {
        *inside.get_mut(node).ok_or(FacetError::Region {
            node,
            nodes: n_nodes,
        })? = true;
    }
    let corners = if kind == CellKind::Hex8 { 8 } else { 4 };
    let mut all: Vec<([usize; 4], Facet)> = Vec::with_capacity(mesh.cells.len() * local.len());
    for e in 0..mesh.cells.len() {
        let cell = &mesh.cell_nodes(e)[..corners];
        let centre = cell.iter().fold([0.0; 3], |acc, &i| {
            let p = point(&mesh.coords, i);
            std::array::from_fn(|d| acc[d] + p[d] / corners as f64)
        });
        for face in local {
            let facet = match *face {
                Facet::Tri(f) => Facet::Tri(f.map(|i| cell[i])),
                Facet::Quad(f) => Facet::Quad(f.map(|i| cell[i])),
            };
            let nodes = facet.nodes();
            let mid = nodes.iter().fold([0.0; 3], |acc, &i| {
                let p = point(&mesh.coords, i);
                std::array::from_fn(|d| acc[d] + p[d] / nodes.len() as f64)
            });
            let outward = dot(
                area_vector(&facet, |i| point(&mesh.coords, i)),
                sub(mid, centre),
            ) >= 0.0;
            let mut key = [usize::MAX; 4];
            key[..nodes.len()].copy_from_slice(nodes);
            key.sort_unstable();
            all.push((key, if outward { facet } else { facet.reversed() }));
        }
    }
    all.sort_unstable_by_key(|(key, _)| *key);
    let mut out = Vec::new();
    for group in all.chunk_by(|a, b| a.0 == b.0) {
        match group.len() {
            1 => {
                let facet = group[0].1;
                if facet.nodes().iter().all(|&i| inside[i]) {
                    out.push(facet);
                }
            }
            2 => {}
            cells => {
                return Err(FacetError::NonManifold {
                    nodes: group[0].0,
                    cells,
                })
            }
        }
    }
    Ok(out)
}

/// The facets of a master body placed in the ground and the hierarchy over them (module
/// docs).
#[derive(Debug, Clone)]
pub struct FacetSearch {
    master: Placed,
    /// The master body's reference positions, three per node.
    reference: Vec<f64>,
    facets: Vec<Facet>,
    /// The facets' nodes, sorted, without repeats.
    surface_nodes: Vec<usize>,
    reach: f64,
    /// Distances within this are ties (the facets' size times `1e-12`), m.
    tie: f64,
    /// Every master node's ground position at the last update (the surface nodes' only).
    placed: Vec<Vector>,
    /// The facets' boxes at the last update.
    boxes: Vec<(Vector, Vector)>,
    bvh: Bvh,
    /// A turning of the master's material that its mesh does not follow
    /// ([`FacetSearch::with_spin`]).
    spin: Option<MaterialSpin>,
}

/// A rigid turning of the master body's material about the axis `axis` (unit) through
/// `pivot` at `rate` (rad/s, right-handed about `axis`), which the body's mesh and frame do
/// not follow: Kalker's spin creepage as a rigid slip. Its velocity
/// `rate axis x (x - pivot)` enters the tangential rows' surface velocity alone
/// ([`FacetSearch::with_spin`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialSpin {
    /// The axis, unit.
    pub axis: Vector,
    /// A point of the axis in the ground, m.
    pub pivot: Vector,
    /// The rate, rad/s.
    pub rate: f64,
}

impl MaterialSpin {
    /// The turning's velocity at the ground point `x`, m/s.
    pub fn velocity(&self, x: Vector) -> Vector {
        let r = sub(x, self.pivot);
        cross(self.axis, r).map(|c| self.rate * c)
    }
}

impl FacetSearch {
    /// A search against `facets` (outward, [`surface_facets`]) of the master body with
    /// reference positions `reference` (three per node, its own) placed by `master`,
    /// finding facets within `reach` (m) of a node.
    ///
    /// # Errors
    /// [`FacetError`] for reference positions that are not three per node, no facet, a
    /// facet naming a node the body does not have, repeating a node or of zero area, or a
    /// reach that is not finite and positive.
    pub fn new(
        master: Placed,
        reference: Vec<f64>,
        facets: Vec<Facet>,
        reach: f64,
    ) -> Result<Self, FacetError> {
        if reference.len() % 3 != 0 {
            return Err(FacetError::Reference(reference.len()));
        }
        if !(reach.is_finite() && reach > 0.0) {
            return Err(FacetError::Reach(reach));
        }
        if facets.is_empty() {
            return Err(FacetError::Empty);
        }
        let n_nodes = reference.len() / 3;
        let mut size: f64 = 0.0;
        for (k, f) in facets.iter().enumerate() {
            let nodes = f.nodes();
            let bad = |why| Err(FacetError::Facet { facet: k, why });
            if nodes.iter().any(|&i| i >= n_nodes) {
                return bad("naming a node the master body does not have");
            }
            if (1..nodes.len()).any(|i| nodes[..i].contains(&nodes[i])) {
                return bad("repeating a node");
            }
            let a = area_vector(f, |i| point(&reference, i));
            let a2 = dot(a, a);
            if a2.is_nan() || a2 <= 0.0 {
                return bad("of zero area");
            }
            for (i, &p) in nodes.iter().enumerate() {
                let q = nodes[(i + 1) % nodes.len()];
                let e = sub(point(&reference, q), point(&reference, p));
                size = size.max(dot(e, e).sqrt());
            }
        }
        let mut surface_nodes: Vec<usize> = facets
            .iter()
            .flat_map(|f| f.nodes().iter().copied())
            .collect();
        surface_nodes.sort_unstable();
        surface_nodes.dedup();
        Ok(Self {
            placed: vec![[0.0; 3]; n_nodes],
            boxes: Vec::with_capacity(facets.len()),
            bvh: Bvh::with_capacity(facets.len()),
            master,
            reference,
            surface_nodes,
            reach,
            tie: 1e-12 * size.max(reach),
            facets,
            spin: None,
        })
    }

    /// With the master's material turning by `spin` under its mesh: the tangential rows
    /// ([`MasterSurface::tangent_row`]) see the facet point's material move by
    /// [`MaterialSpin::velocity`] beside its frame's drift, so the slip they hold carries
    /// the spin's rigid slip (Kalker's `phi (-y, x)`, as the rigid base's
    /// [`crate::contact::RotatingBase::spin`]); the normal rows and the geometry do not.
    /// For a small spin over the patch's passage (the elastic rail's, whose frame
    /// translates) it is Kalker's steady theory's rigid slip; it is not a turning body.
    pub fn with_spin(mut self, spin: Option<MaterialSpin>) -> Self {
        self.spin = spin;
        self
    }

    /// The search against the surface of the 3D solid `mesh` ([`surface_facets`], within
    /// `region` when given), placed by `master`, within `reach` (m).
    ///
    /// # Errors
    /// Those of [`surface_facets`] and [`FacetSearch::new`].
    pub fn on_mesh(
        mesh: &Mesh,
        region: Option<&[usize]>,
        master: Placed,
        reach: f64,
    ) -> Result<Self, FacetError> {
        let facets = surface_facets(mesh, region)?;
        Self::new(master, mesh.coords.clone(), facets, reach)
    }

    /// The facets.
    pub fn facets(&self) -> &[Facet] {
        &self.facets
    }

    /// The reach, m.
    pub fn reach(&self) -> f64 {
        self.reach
    }

    /// The master body's placement.
    pub fn master(&self) -> Placed {
        self.master
    }

    /// Places the facets in the ground at time `t` with the model's displacements `u` and
    /// rebuilds the hierarchy over them. Allocates nothing.
    pub fn update(&mut self, t: f64, u: &[f64]) {
        for &i in &self.surface_nodes {
            let local = self.master.local(3, &self.reference, u, i);
            self.placed[i] = self.master.motion.place(t, local);
        }
        self.boxes.clear();
        for f in &self.facets {
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for &i in f.nodes() {
                for d in 0..3 {
                    lo[d] = lo[d].min(self.placed[i][d]);
                    hi[d] = hi[d].max(self.placed[i][d]);
                }
            }
            self.boxes.push((lo, hi));
        }
        self.bvh.build(&self.boxes);
    }

    /// The closest facet to the ground point `x` within the reach, with the parameters of
    /// the closest point, the normal and the gap (module docs); `None` when none is within
    /// reach.
    pub fn find(&self, x: Vector) -> Option<Target> {
        let mut best: Option<(f64, Target)> = None;
        let reach2 = self.reach * self.reach;
        self.bvh.visit(x, reach2, |k| {
            self.consider(k, x, &mut best);
            best.map_or(reach2, |(d, _)| (d + self.tie).powi(2).min(reach2))
        });
        best.map(|(_, t)| t)
    }

    /// [`FacetSearch::find`] by trying every facet (for the tests of the hierarchy).
    #[cfg(test)]
    fn find_brute(&self, x: Vector) -> Option<Target> {
        let mut best = None;
        for k in 0..self.facets.len() {
            self.consider(k, x, &mut best);
        }
        best.map(|(_, t)| t)
    }

    /// Keeps facet `k` in `best` (its distance and target) when it is within reach and
    /// closer, or as close with a larger gap, or the same gap and a lower index.
    fn consider(&self, k: usize, x: Vector, best: &mut Option<(f64, Target)>) {
        let (dist, t) = self.project(k, x);
        if dist > self.reach {
            return;
        }
        let better = match best {
            None => true,
            Some((bd, bt)) => {
                dist < *bd - self.tie
                    || (dist <= *bd + self.tie
                        && (t.gap > bt.gap || (t.gap == bt.gap && k < bt.segment)))
            }
        };
        if better {
            *best = Some((dist, t));
        }
    }

    /// The distance from `x` to facet `k` as placed at the last update, and the target.
    fn project(&self, k: usize, x: Vector) -> (f64, Target) {
        let (xi, eta, at, normal) = match self.facets[k] {
            Facet::Tri(n) => {
                let p = n.map(|i| self.placed[i]);
                let (xi, eta) = closest_on_triangle(x, p[0], p[1], p[2]);
                let normal = unit(cross(sub(p[1], p[0]), sub(p[2], p[0])));
                (xi, eta, triangle_point(&p, xi, eta), normal)
            }
            Facet::Quad(n) => {
                let p = n.map(|i| self.placed[i]);
                let (xi, eta) = closest_on_quad(x, &p);
                (xi, eta, quad_point(&p, xi, eta), quad_normal(&p, xi, eta))
            }
        };
        let r = sub(x, at);
        let target = Target {
            segment: k,
            xi,
            eta,
            normal,
            gap: dot(normal, r),
        };
        (dot(r, r).sqrt(), target)
    }

    /// The row of slave node `node` against `target` along the unit direction `n` at time
    /// `t` in the configuration `u` (module docs, The rows); with `spin`, the master's
    /// material velocity at the facet point gains [`MaterialSpin::velocity`] (a tangential
    /// row's, [`FacetSearch::with_spin`]: linear in the point, so summed over the facet's
    /// nodes with their weights as the frame's drift is).
    #[allow(clippy::too_many_arguments)]
    fn row(
        &self,
        target: &Target,
        n: Vector,
        slave: Placed,
        node: usize,
        x_ref: &[f64],
        t: f64,
        u: &[f64],
        spin: Option<&MaterialSpin>,
    ) -> SearchedRow {
        let facet = self.facets[target.segment];
        let weights = facet.weights(target.xi, target.eta);
        let mut terms = Terms::default();
        let ca = slave.motion.rotate_back(t, n);
        let da = slave.first_dof + 3 * node;
        for (c, &v) in ca.iter().enumerate() {
            terms.push(da + c, v);
        }
        let cm = self.master.motion.rotate_back(t, n);
        let mut drift_f = [0.0; 3];
        for (&m, &wgt) in facet.nodes().iter().zip(&weights) {
            let d = self.master.first_dof + 3 * m;
            for (c, &v) in cm.iter().enumerate() {
                terms.push(d + c, -wgt * v);
            }
            let local = self.master.local(3, &self.reference, u, m);
            let mut dm = self.master.motion.drift(t, local);
            if let Some(spin) = spin {
                let v = spin.velocity(self.master.motion.place(t, local));
                dm = std::array::from_fn(|c| dm[c] + v[c]);
            }
            for c in 0..3 {
                drift_f[c] += wgt * dm[c];
            }
        }
        // g = n.(x_a - x_f) = c.(X + u) + n.(o_a - o_f): o = -n.(o_a - o_f).
        let (oa, om) = (
            slave.motion.place(t, [0.0; 3]),
            self.master.motion.place(t, [0.0; 3]),
        );
        let offset = -dot(n, sub(oa, om));
        let la: Vector = std::array::from_fn(|c| x_ref[c] + u[da + c]);
        let drift_a = slave.motion.drift(t, la);
        SearchedRow {
            terms,
            offset,
            w: -dot(n, sub(drift_a, drift_f)),
        }
    }
}

/// The facet search as a master surface ([`MasterSurface`]): three dofs per node.
impl MasterSurface for FacetSearch {
    fn dim(&self) -> usize {
        3
    }

    fn shift_frame(&mut self, d: Vector) -> bool {
        match &mut self.master.motion {
            Motion::Translating { origin, .. } | Motion::Pressed { origin, .. } => {
                for (o, dc) in origin.iter_mut().zip(d) {
                    *o += dc;
                }
                true
            }
            _ => false,
        }
    }

    fn reach(&self) -> f64 {
        self.reach
    }

    fn master(&self) -> Placed {
        self.master
    }

    fn master_dofs(&self) -> Vec<usize> {
        let first = self.master.first_dof;
        self.surface_nodes
            .iter()
            .flat_map(|&i| (0..3).map(move |c| first + 3 * i + c))
            .collect()
    }

    fn update(&mut self, t: f64, u: &[f64]) {
        FacetSearch::update(self, t, u);
    }

    fn find(&self, x: Vector) -> Option<Target> {
        FacetSearch::find(self, x)
    }

    fn normal_row(
        &self,
        target: &Target,
        slave: Placed,
        node: usize,
        x_ref: &[f64],
        t: f64,
        u: &[f64],
    ) -> SearchedRow {
        self.row(target, target.normal, slave, node, x_ref, t, u, None)
    }

    fn tangent_row(
        &self,
        target: &Target,
        k: usize,
        slave: Placed,
        node: usize,
        x_ref: &[f64],
        t: f64,
        u: &[f64],
    ) -> Option<SearchedRow> {
        (k < 2).then(|| {
            let tangent = tangent_basis(3, target.normal)[k];
            let spin = self.spin.as_ref();
            self.row(target, tangent, slave, node, x_ref, t, u, spin)
        })
    }

    fn clone_box(&self) -> Box<dyn MasterSurface> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
