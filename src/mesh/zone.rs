//! A wheel mesh refined in one sector of its rim, and the relocation of that sector: the
//! paper's "relocation of the condensed mesh together with the moving load" (§2, Fig. 4b).
//!
//! **The mesh.** The annulus between the hub (`hub_radius`, clamped) and the rim is cut into
//! `sectors` equal sectors and geometric rings (`r_{k+1} = q r_k`, cells about square), the
//! root cells of a quadtree in `(ln r, theta)`. A cell is split into four while it is larger
//! than the size wanted at its centre,
//! `s(x) = min(s_c + g (R - r), s_f + g dist(x, zone))`, with `s_c = 2 pi R / rim_nodes` the
//! pitch of the rim outside the zone, `s_f = 2 pi R / zone_rim_nodes` its pitch inside,
//! `dist(x, zone)` the distance to the zone's arc of the rim and `g` the grading. With
//! `depth = Some(l)` the zone is refined in depth as well: the size wanted near the zone is
//! `min(s_f + g d, s_f (1 + (d / l)^2))` (`d = dist(x, zone)`), so that the elements at a
//! depth `d ~ l` below the contact are about twice the zone's pitch, not `g d`: they shrink
//! with it, and a ladder of zone pitches converges at every depth the contact's stresses
//! reach (the graded rule's elements at depth `a` are `g a` whatever the pitch, an error
//! that does not go with the pitch). About `(pi w / 4 + pi l) l / s_f^2` cells more, `w` the
//! zone's arc length. A leaf cell
//! whose sides carry only its four corners is two triangles, its diagonal alternating from
//! cell to cell like a chequerboard (`diagonal_flipped`): one diagonal everywhere makes
//! the mesh chiral, and a wheel rolling one way then grows a creep force different from the
//! same wheel rolling the other way (on the creep scenario's 9,216-node zone the free-rolling
//! creepage moved by 3.5 % with the diagonal's direction). A cell with nodes of finer
//! neighbours on its sides is a fan from a node at its centre. Every node
//! sits on the lattice of the finest level, `(j, i)`: radius `r_h q^(j / 2^L)`, angle
//! `theta_c + 2 pi i / (sectors 2^L)`, with the zone centred on `theta_c = -pi/2` (the base
//! below the wheel at `t = 0`).
//!
//! **Relocation.** Outside the zone the mesh is the same after a turn by one sector (the
//! sizes depend on the radius only there), so turning the frame of the mesh by one sector
//! `Delta` with the contact keeps every node there on a node: the material at node `(j, i)`
//! after the turn is the material that was at `(j, i + 2^L)`, its vectors turned by
//! `-Delta` ([`ZoneMesh::sources`]). Only where the zone moves, ahead of it and behind it, the
//! new nodes take the values interpolated in the triangles of the old mesh ([`Source::Triangle`])
//! and the nodes left behind are dropped. The mesh, its matrices and their factorization stay
//! the same: a relocation is a relabelling of the state, not a new model.

use std::collections::HashMap;
use std::f64::consts::PI;

use super::generators::MeshError;
use super::{Cells, Mesh};

/// The parameters of [`disk_zone`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ZoneOptions {
    /// Rim radius `R`, m.
    pub radius: f64,
    /// Hub radius (the inner boundary, clamped by the wheel's hub), m.
    pub hub_radius: f64,
    /// Sectors of the root cells: the zone is relocated by `2 pi / sectors` at a time.
    pub sectors: usize,
    /// Rim nodes a full rim would have at the pitch outside the zone (a multiple of
    /// `sectors`, times a power of two).
    pub rim_nodes: usize,
    /// Rim nodes a full rim would have at the pitch inside the zone (`rim_nodes` times a
    /// power of two).
    pub zone_rim_nodes: usize,
    /// Angular width of the zone's arc of the rim, rad.
    pub zone_width: f64,
    /// Growth of the cell size with the distance from the rim and from the zone (`g`).
    pub grading: f64,
    /// The zone refined in depth as well (m; `None`: not): within the distance `l` of the
    /// zone's arc the cells keep the zone's pitch's scale, `s_f (1 + (d / l)^2)`, so that the
    /// elements at a depth `d ~ l` shrink with the zone's pitch (module docs). For creep
    /// studies, `l` about the contact's half-width `a`.
    pub depth: Option<f64>,
}

/// Where the state of a node after a relocation comes from (module docs, Relocation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Source {
    /// The same material point was a node: its values, turned.
    Node(usize),
    /// Interpolated in a triangle of the old mesh (barycentric weights; slightly outside
    /// the triangle for a point on the rim's arc beyond a chord).
    Triangle {
        /// The triangle's nodes.
        nodes: [usize; 3],
        /// Their weights (summing to 1).
        weights: [f64; 3],
    },
}

/// A mesh with a refined zone and its relocation map.
#[derive(Debug, Clone)]
pub struct ZoneMesh {
    /// The mesh (node sets `"rim"`, `"hub"`).
    pub mesh: Mesh,
    /// The angle of one relocation, `2 pi / sectors`, rad.
    pub step: f64,
    /// The angle of the zone's centre, rad.
    pub centre: f64,
    /// Per node, where its state comes from at a relocation (module docs).
    pub sources: Vec<Source>,
    /// Nodes that are on a node of the old mesh at a relocation.
    pub exact_nodes: usize,
}

fn pow2_ratio(a: usize, b: usize) -> Option<u32> {
    (b > 0 && a % b == 0 && (a / b).is_power_of_two()).then(|| (a / b).trailing_zeros())
}

/// Builds the mesh of [`ZoneOptions`] (module docs).
///
/// # Errors
/// [`MeshError`] naming the parameter: lengths not finite and positive, a hub not inside the
/// rim, fewer than 8 sectors, rim node counts that are not the sectors (or `rim_nodes`) times
/// a power of two, a zone wider than half the rim or narrower than two sectors, a grading
/// outside `[0.05, 2]`, a mesh beyond the node limit.
pub fn disk_zone(o: &ZoneOptions) -> Result<ZoneMesh, MeshError> {
    let (fine, step) = check_options(o)?;
    let lat = Lattice::of(o, fine, step);
    let leaves = quadtree_leaves(o, &lat)?;
    let (keys, polys) = leaf_nodes(&lat, &leaves);
    let index: HashMap<Key, usize> = keys.iter().enumerate().map(|(n, &k)| (k, n)).collect();
    let coords: Vec<f64> = keys.iter().flat_map(|&(j, i)| lat.point(j, i)).collect();
    let (tris, leaf_tris) = triangulate(&lat, &leaves, &polys, &index, &coords);
    let mesh = zone_mesh(&lat, &keys, coords, tris);
    let (sources, exact) = relocation_sources(&lat, &leaves, &leaf_tris, &keys, &index, &mesh);
    Ok(ZoneMesh {
        mesh,
        step,
        centre: lat.centre,
        sources,
        exact_nodes: exact,
    })
}

/// Checks the options; returns the finest level of the quadtree (the zone's rim pitch) and
/// the angle of one sector.
fn check_options(o: &ZoneOptions) -> Result<(u32, f64), MeshError> {
    for (name, v) in [("radius", o.radius), ("hub_radius", o.hub_radius)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(MeshError::InvalidLength { name, value: v });
        }
    }
    if o.hub_radius >= o.radius {
        return Err(MeshError::OutOfRange {
            name: "hub_radius",
            value: o.hub_radius,
            min: 0.0,
            max: o.radius,
        });
    }
    if o.sectors < 8 {
        return Err(MeshError::CountBelow {
            name: "sectors",
            value: o.sectors,
            min: 8,
        });
    }
    let coarse = pow2_ratio(o.rim_nodes, o.sectors).ok_or(MeshError::OutOfRange {
        name: "rim_nodes (a multiple of the sectors by a power of two)",
        value: o.rim_nodes as f64,
        min: o.sectors as f64,
        max: f64::INFINITY,
    })?;
    let fine = coarse
        + pow2_ratio(o.zone_rim_nodes, o.rim_nodes).ok_or(MeshError::OutOfRange {
            name: "zone_rim_nodes (rim_nodes times a power of two)",
            value: o.zone_rim_nodes as f64,
            min: o.rim_nodes as f64,
            max: f64::INFINITY,
        })?;
    let step = 2.0 * PI / o.sectors as f64;
    if !(o.zone_width >= 2.0 * step && o.zone_width <= PI) {
        return Err(MeshError::OutOfRange {
            name: "zone_width (rad)",
            value: o.zone_width,
            min: 2.0 * step,
            max: PI,
        });
    }
    if !(0.05..=2.0).contains(&o.grading) {
        return Err(MeshError::OutOfRange {
            name: "grading",
            value: o.grading,
            min: 0.05,
            max: 2.0,
        });
    }
    if let Some(l) = o.depth {
        if !(l.is_finite() && l > 0.0 && l < o.radius - o.hub_radius) {
            return Err(MeshError::OutOfRange {
                name: "depth (the zone's refinement in depth, m)",
                value: l,
                min: 0.0,
                max: o.radius - o.hub_radius,
            });
        }
    }
    if o.zone_rim_nodes > super::generators::MAX_NODES / 8 {
        return Err(MeshError::TooLarge {
            name: "zone_rim_nodes",
            value: o.zone_rim_nodes,
            max: super::generators::MAX_NODES,
        });
    }
    Ok((fine, step))
}

/// The leaves of the quadtree: every root cell split while it is larger than the size
/// wanted at its centre (module docs), sorted by level, ring and sector.
fn quadtree_leaves(o: &ZoneOptions, lat: &Lattice) -> Result<Vec<Cell>, MeshError> {
    let fine = lat.levels;
    let s_c = 2.0 * PI * o.radius / o.rim_nodes as f64;
    let s_f = 2.0 * PI * o.radius / o.zone_rim_nodes as f64;
    let size = |r: f64, th: f64| -> f64 {
        let coarse = s_c + o.grading * (o.radius - r);
        let d = wrap(th - lat.centre);
        let half = 0.5 * o.zone_width;
        let dist = if d.abs() <= half {
            o.radius - r
        } else {
            let e = lat.centre + half * d.signum();
            let (ex, ey) = (o.radius * e.cos(), o.radius * e.sin());
            ((r * th.cos() - ex).powi(2) + (r * th.sin() - ey).powi(2)).sqrt()
        };
        let zone = s_f + o.grading * dist;
        let zone = match o.depth {
            Some(l) => zone.min(s_f * (1.0 + (dist / l).powi(2))),
            None => zone,
        };
        coarse.min(zone)
    };
    let mut leaves: Vec<Cell> = Vec::new();
    let mut stack: Vec<Cell> = Vec::new();
    for ir in 0..lat.rows {
        for it in 0..o.sectors {
            stack.push(Cell { level: 0, ir, it });
        }
    }
    while let Some(c) = stack.pop() {
        let (j0, j1, i0, i1) = lat.span(c);
        let (r1, dth) = (lat.r(j1), lat.theta(i1) - lat.theta(i0));
        let rc = lat.r_frac((j0 + j1) as f64 / 2.0);
        let thc = lat.theta_frac((i0 + i1) as f64 / 2.0);
        if c.level < fine && r1 * dth > 1.05 * size(rc, thc) {
            for (dr, dt) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                stack.push(Cell {
                    level: c.level + 1,
                    ir: 2 * c.ir + dr,
                    it: 2 * c.it + dt,
                });
            }
        } else {
            leaves.push(c);
        }
        if leaves.len() + stack.len() > super::generators::MAX_NODES {
            return Err(MeshError::TooLarge {
                name: "zone_rim_nodes",
                value: o.zone_rim_nodes,
                max: super::generators::MAX_NODES,
            });
        }
    }
    leaves.sort_by_key(|c| (c.level, c.ir, c.it));
    Ok(leaves)
}

/// The nodes, sorted: the leaves' corners, then the centres of the cells with hanging
/// nodes; and each leaf's polygon (its nodes round its sides, counter-clockwise from
/// `(j0, i0)`).
fn leaf_nodes(lat: &Lattice, leaves: &[Cell]) -> (Vec<Key>, Vec<Vec<Key>>) {
    let mut corner: HashMap<(usize, usize), usize> = HashMap::new();
    for &c in leaves {
        let (j0, j1, i0, i1) = lat.span(c);
        for (j, i) in [(j0, i0), (j0, i1), (j1, i0), (j1, i1)] {
            corner.entry(lat.key(j, i)).or_insert(0);
        }
    }
    let polygon = |c: Cell| -> Vec<(usize, usize)> {
        let (j0, j1, i0, i1) = lat.span(c);
        let mut p = Vec::new();
        for i in i0..i1 {
            if corner.contains_key(&lat.key(j0, i)) {
                p.push(lat.key(j0, i));
            }
        }
        for j in j0..j1 {
            if corner.contains_key(&lat.key(j, i1)) {
                p.push(lat.key(j, i1));
            }
        }
        for i in (i0 + 1..=i1).rev() {
            if corner.contains_key(&lat.key(j1, i)) {
                p.push(lat.key(j1, i));
            }
        }
        for j in (j0 + 1..=j1).rev() {
            if corner.contains_key(&lat.key(j, i0)) {
                p.push(lat.key(j, i0));
            }
        }
        p
    };
    let mut keys: Vec<(usize, usize)> = corner.keys().copied().collect();
    let polys: Vec<Vec<(usize, usize)>> = leaves.iter().map(|&c| polygon(c)).collect();
    for (c, p) in leaves.iter().zip(&polys) {
        if p.len() > 4 {
            let (j0, j1, i0, i1) = lat.span(*c);
            keys.push(lat.key((j0 + j1) / 2, (i0 + i1) / 2));
        }
    }
    keys.sort_unstable();
    keys.dedup();
    (keys, polys)
}

/// The triangles of the nodes at the flat planar coordinates `coords`, counter-clockwise: a
/// leaf of four nodes is two triangles, one with hanging nodes a fan from its centre; and
/// each leaf's range of triangles.
fn triangulate(
    lat: &Lattice,
    leaves: &[Cell],
    polys: &[Vec<Key>],
    index: &HashMap<Key, usize>,
    coords: &[f64],
) -> (Vec<[usize; 3]>, Vec<(usize, usize)>) {
    let xy = |i: usize| &coords[2 * i..2 * i + 2];
    let area = |t: [usize; 3]| {
        let (a, b, c) = (xy(t[0]), xy(t[1]), xy(t[2]));
        (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
    };
    let ccw = |t: [usize; 3]| if area(t) < 0.0 { [t[0], t[2], t[1]] } else { t };
    let mut tris: Vec<[usize; 3]> = Vec::new();
    let mut leaf_tris: Vec<(usize, usize)> = Vec::with_capacity(leaves.len());
    for (c, p) in leaves.iter().zip(polys) {
        let first = tris.len();
        let ids: Vec<usize> = p.iter().map(|k| index[k]).collect();
        if ids.len() == 4 {
            // Corners in the order (j0,i0), (j0,i1), (j1,i1), (j1,i0): the diagonal from
            // (j0,i0) to (j1,i1), or from (j0,i1) to (j1,i0).
            if diagonal_flipped(*c) {
                tris.push(ccw([ids[0], ids[1], ids[3]]));
                tris.push(ccw([ids[1], ids[2], ids[3]]));
            } else {
                tris.push(ccw([ids[0], ids[1], ids[2]]));
                tris.push(ccw([ids[0], ids[2], ids[3]]));
            }
        } else {
            let (j0, j1, i0, i1) = lat.span(*c);
            let m = index[&lat.key((j0 + j1) / 2, (i0 + i1) / 2)];
            for k in 0..ids.len() {
                tris.push(ccw([m, ids[k], ids[(k + 1) % ids.len()]]));
            }
        }
        leaf_tris.push((first, tris.len()));
    }
    (tris, leaf_tris)
}

/// Whether the leaf `c` of four nodes is cut along its other diagonal: a chequerboard in
/// the cells of one level, `(ring + sector) mod 2`, so that neither diagonal prevails (module
/// docs). The root cells alternate by ring alone: a relocation turns the mesh by one root
/// sector, which would swap the chequerboard's colours there, while it moves a cell of
/// level `l >= 1` by `2^l` of its own sectors, which keeps them; the mesh outside the zone is
/// then the same after a relocation, triangles included.
fn diagonal_flipped(c: Cell) -> bool {
    if c.level == 0 {
        c.ir % 2 == 1
    } else {
        (c.ir + c.it) % 2 == 1
    }
}

/// The mesh of the nodes `keys` at the flat planar coordinates `coords` and the triangles
/// `tris`, with the node sets `"rim"` and `"hub"`.
fn zone_mesh(lat: &Lattice, keys: &[Key], coords: Vec<f64>, tris: Vec<[usize; 3]>) -> Mesh {
    let rim: Vec<usize> = (0..keys.len()).filter(|&n| keys[n].0 == lat.nr()).collect();
    let hub: Vec<usize> = (0..keys.len()).filter(|&n| keys[n].0 == 0).collect();
    let mut node_sets = std::collections::BTreeMap::new();
    node_sets.insert("rim".to_string(), rim);
    node_sets.insert("hub".to_string(), hub);
    Mesh::new(2, coords, Cells::Tri3(tris), node_sets)
}

/// Relocation sources: per node, the node one sector ahead, else its triangle in the old
/// mesh; and the count of the former.
fn relocation_sources(
    lat: &Lattice,
    leaves: &[Cell],
    leaf_tris: &[(usize, usize)],
    keys: &[Key],
    index: &HashMap<Key, usize>,
    mesh: &Mesh,
) -> (Vec<Source>, usize) {
    let fine = lat.levels;
    let rows = lat.rows;
    let leaf_of: HashMap<Cell, usize> = leaves.iter().enumerate().map(|(n, &c)| (c, n)).collect();
    let shift = 1usize << fine;
    let Cells::Tri3(tris) = &mesh.cells else {
        unreachable!("built with triangles")
    };
    let mut sources = Vec::with_capacity(keys.len());
    let mut exact = 0;
    for &(j, i) in keys {
        let from = lat.key(j, i + shift);
        if let Some(&n) = index.get(&from) {
            sources.push(Source::Node(n));
            exact += 1;
            continue;
        }
        let x = lat.point(from.0, from.1);
        let leaf = (0..=fine)
            .find_map(|level| {
                let up = fine - level;
                let ir = (from.0 >> up).min((rows << level) - 1);
                leaf_of.get(&Cell {
                    level,
                    ir,
                    it: from.1 >> up,
                })
            })
            .copied()
            .expect("every lattice point lies in a leaf");
        let (a, b) = leaf_tris[leaf];
        let best = (a..b)
            .map(|t| {
                let w = barycentric(mesh, tris[t], &x);
                (w[0].min(w[1]).min(w[2]), t, w)
            })
            .max_by(|p, q| p.0.total_cmp(&q.0))
            .expect("a leaf has triangles");
        sources.push(Source::Triangle {
            nodes: tris[best.1],
            weights: best.2,
        });
    }
    (sources, exact)
}

/// Barycentric coordinates of the planar point `x` in triangle `t` of `mesh`.
fn barycentric(mesh: &Mesh, t: [usize; 3], x: &[f64]) -> [f64; 3] {
    let (a, b, c) = (mesh.point(t[0]), mesh.point(t[1]), mesh.point(t[2]));
    let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    let l1 = ((x[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (x[1] - a[1])) / det;
    let l2 = ((b[0] - a[0]) * (x[1] - a[1]) - (x[0] - a[0]) * (b[1] - a[1])) / det;
    [1.0 - l1 - l2, l1, l2]
}

/// An angle wrapped to `(-pi, pi]`.
fn wrap(a: f64) -> f64 {
    let mut a = a % (2.0 * PI);
    if a > PI {
        a -= 2.0 * PI;
    } else if a <= -PI {
        a += 2.0 * PI;
    }
    a
}

/// A node of the lattice of the finest level, `(j, i)` (module docs).
type Key = (usize, usize);

/// A quadtree cell: `level` 0 is a root cell (one ring, one sector).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct Cell {
    level: u32,
    ir: usize,
    it: usize,
}

/// The lattice of the finest level (module docs).
#[derive(Debug, Clone, Copy)]
struct Lattice {
    levels: u32,
    rows: usize,
    sectors: usize,
    hub: f64,
    radius: f64,
    q_ln: f64,
    centre: f64,
}

impl Lattice {
    /// The lattice of the options `o` with `levels` levels below the root cells of angle
    /// `step`: rings about square, the zone centred below the wheel.
    fn of(o: &ZoneOptions, levels: u32, step: f64) -> Self {
        let rows = ((o.radius / o.hub_radius).ln() / (1.0 + step).ln())
            .round()
            .max(1.0) as usize;
        Lattice {
            levels,
            rows,
            sectors: o.sectors,
            hub: o.hub_radius,
            radius: o.radius,
            q_ln: (o.radius / o.hub_radius).ln() / rows as f64,
            centre: -PI / 2.0,
        }
    }
    /// The key of the lattice point `(j, i)`: its angle index taken round the rim.
    fn key(&self, j: usize, i: usize) -> Key {
        (j, i % self.nt())
    }
    fn m(&self) -> usize {
        1 << self.levels
    }
    fn nt(&self) -> usize {
        self.sectors * self.m()
    }
    fn nr(&self) -> usize {
        self.rows * self.m()
    }
    /// The lattice span `(j0, j1, i0, i1)` of a cell.
    fn span(&self, c: Cell) -> (usize, usize, usize, usize) {
        let s = 1usize << (self.levels - c.level);
        (c.ir * s, (c.ir + 1) * s, c.it * s, (c.it + 1) * s)
    }
    fn r_frac(&self, j: f64) -> f64 {
        if j >= self.nr() as f64 {
            self.radius
        } else {
            self.hub * (self.q_ln * j / self.m() as f64).exp()
        }
    }
    fn r(&self, j: usize) -> f64 {
        self.r_frac(j as f64)
    }
    fn theta_frac(&self, i: f64) -> f64 {
        self.centre + 2.0 * PI * i / self.nt() as f64
    }
    fn theta(&self, i: usize) -> f64 {
        self.theta_frac(i as f64)
    }
    fn point(&self, j: usize, i: usize) -> [f64; 2] {
        let (r, th) = (self.r(j), self.theta(i % self.nt()));
        [r * th.cos(), r * th.sin()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::quality;

    fn options() -> ZoneOptions {
        ZoneOptions {
            radius: 0.1,
            hub_radius: 0.01,
            sectors: 72,
            rim_nodes: 144,
            zone_rim_nodes: 1152,
            zone_width: 20f64.to_radians(),
            grading: 0.3,
            depth: None,
        }
    }

    /// The rim holds the coarse pitch outside the zone and the fine one inside, every
    /// triangle is counter-clockwise with a fair angle, and the relocation map keeps every
    /// node outside the moving zone on a node.
    #[test]
    fn zone_mesh_has_its_pitches_and_a_relocation_map() {
        let z = disk_zone(&options()).unwrap();
        let q = quality(&z.mesh);
        eprintln!(
            "{} nodes, {} triangles, min angle {:.1} deg, max aspect {:.2}, exact {} of {}",
            z.mesh.n_nodes(),
            z.mesh.cells.len(),
            q.min_angle_deg,
            q.max_aspect,
            z.exact_nodes,
            z.sources.len()
        );
        assert!(q.min_angle_deg > 18.0, "{q:?}");
        let rim = z.mesh.node_set("rim").unwrap();
        let angles: Vec<f64> = rim
            .iter()
            .map(|&n| {
                let p = z.mesh.point(n);
                wrap(p[1].atan2(p[0]) - z.centre)
            })
            .collect();
        let fine = 2.0 * PI / 1152.0;
        let coarse = 2.0 * PI / 144.0;
        let mut sorted = angles.clone();
        sorted.sort_by(f64::total_cmp);
        for w in sorted.windows(2) {
            let d = w[1] - w[0];
            let mid = 0.5 * (w[0] + w[1]);
            if mid.abs() < 10f64.to_radians() {
                assert!((d - fine).abs() < 1e-9, "pitch {d} at {mid}");
            }
            if mid.abs() > 60f64.to_radians() {
                assert!((d - coarse).abs() < 1e-9, "pitch {d} at {mid}");
            }
        }
        // Far from the zone every node maps onto a node; the interpolated ones are few.
        assert!(z.exact_nodes > z.sources.len() * 8 / 10);
        for (n, s) in z.sources.iter().enumerate() {
            let p = z.mesh.point(n);
            let a = wrap(p[1].atan2(p[0]) - z.centre);
            if a.abs() > 90f64.to_radians() {
                assert!(matches!(s, Source::Node(_)), "node {n} at {a}");
            }
            if let Source::Node(m) = *s {
                // The source is the same point one sector ahead.
                let (c, s_) = (z.step.cos(), z.step.sin());
                let q = z.mesh.point(m);
                let turned = [c * p[0] - s_ * p[1], s_ * p[0] + c * p[1]];
                assert!(
                    (turned[0] - q[0]).abs() < 1e-12 && (turned[1] - q[1]).abs() < 1e-12,
                    "node {n}"
                );
            }
            if let Source::Triangle { weights, .. } = *s {
                assert!((weights.iter().sum::<f64>() - 1.0).abs() < 1e-12);
                assert!(weights.iter().all(|&w| w > -0.05), "{weights:?}");
            }
        }
    }

    /// No diagonal prevails (module docs): of the zone's cells cut in two, as many along one
    /// diagonal as along the other; and far from the zone a relocation carries every
    /// triangle onto a triangle (the chequerboard keeps its colours under a turn by one
    /// sector: with `(ring + sector) mod 2` on the root cells too it would not).
    #[test]
    fn the_zone_has_no_preferred_diagonal_and_turns_onto_itself() {
        let z = disk_zone(&options()).unwrap();
        let Cells::Tri3(tris) = &z.mesh.cells else {
            unreachable!()
        };
        let angle = |n: usize| {
            let p = z.mesh.point(n);
            wrap(p[1].atan2(p[0]) - z.centre)
        };
        // A triangle of a cell cut in two has a right-angle-like corner at one end of the
        // cell's ring side; its hypotenuse, the diagonal, rises or falls in angle with the
        // radius. Count the hypotenuses' directions in the zone, each once.
        let radius = |n: usize| {
            let p = z.mesh.point(n);
            p[0].hypot(p[1])
        };
        let mut rising = std::collections::BTreeSet::new();
        let mut falling = std::collections::BTreeSet::new();
        for t in tris {
            if t.iter().any(|&n| angle(n).abs() > 5f64.to_radians()) {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let (dr, dth) = (radius(b) - radius(a), angle(b) - angle(a));
                if dr.abs() > 1e-12 && dth.abs() > 1e-12 {
                    let key = (a.min(b), a.max(b));
                    if dr * dth > 0.0 {
                        rising.insert(key);
                    } else {
                        falling.insert(key);
                    }
                }
            }
        }
        eprintln!(
            "zone diagonals: {} rising, {} falling",
            rising.len(),
            falling.len()
        );
        assert!(rising.len() > 100, "{}", rising.len());
        let (r, f) = (rising.len() as f64, falling.len() as f64);
        assert!((r - f).abs() < 0.05 * (r + f), "{r} rising, {f} falling");
        // Far from the zone, every triangle's image under the relocation's node map is a
        // triangle of the mesh.
        let set: std::collections::HashSet<[usize; 3]> = tris
            .iter()
            .map(|t| {
                let mut s = *t;
                s.sort_unstable();
                s
            })
            .collect();
        let mut far = 0;
        for t in tris {
            if t.iter().any(|&n| angle(n).abs() < 90f64.to_radians()) {
                continue;
            }
            let mut image = [0; 3];
            for k in 0..3 {
                let Source::Node(m) = z.sources[t[k]] else {
                    panic!("node {} far from the zone is interpolated", t[k])
                };
                image[k] = m;
            }
            image.sort_unstable();
            assert!(set.contains(&image), "triangle {t:?} turns onto {image:?}");
            far += 1;
        }
        assert!(far > 1000, "{far}");
    }

    /// A linear field is carried exactly by the relocation (interpolation is exact for it).
    #[test]
    fn relocation_carries_a_linear_field_exactly() {
        let z = disk_zone(&options()).unwrap();
        let f = |p: &[f64]| 3.0 * p[0] - 2.0 * p[1] + 0.5;
        let old: Vec<f64> = z.mesh.points().map(f).collect();
        let (c, s) = (z.step.cos(), z.step.sin());
        for (n, src) in z.sources.iter().enumerate() {
            let v = match *src {
                Source::Node(m) => old[m],
                Source::Triangle { nodes, weights } => {
                    (0..3).map(|k| weights[k] * old[nodes[k]]).sum()
                }
            };
            let p = z.mesh.point(n);
            let expect = f(&[c * p[0] - s * p[1], s * p[0] + c * p[1]]);
            assert!((v - expect).abs() < 1e-12, "node {n}: {v} vs {expect}");
        }
    }

    /// Refined in depth (`depth = Some(l)`), the elements at depth `l` under the zone's
    /// centre shrink with the zone's pitch (about twice it); graded by `g` alone they stay
    /// about `g l` whatever the pitch.
    #[test]
    fn a_zone_refined_in_depth_follows_its_pitch_at_depth() {
        let l = 1e-3;
        let largest_at_depth = |zone_rim_nodes: usize, depth: Option<f64>| {
            let o = ZoneOptions {
                radius: 0.1,
                hub_radius: 0.04,
                sectors: 288,
                rim_nodes: 288,
                zone_rim_nodes,
                zone_width: 4f64.to_radians(),
                grading: 0.3,
                depth,
            };
            let z = disk_zone(&o).unwrap();
            let Cells::Tri3(tris) = &z.mesh.cells else {
                unreachable!()
            };
            let mut largest: f64 = 0.0;
            for t in tris {
                let p: Vec<&[f64]> = t.iter().map(|&n| z.mesh.point(n)).collect();
                let c = [
                    (p[0][0] + p[1][0] + p[2][0]) / 3.0,
                    (p[0][1] + p[1][1] + p[2][1]) / 3.0,
                ];
                // Below the zone's centre (the contact at -y), between 0.8 l and 1.2 l deep.
                let d = 0.1 - c[0].hypot(c[1]);
                if c[0].abs() < 0.5 * l && (0.8 * l..1.2 * l).contains(&d) {
                    for k in 0..3 {
                        let (a, b) = (p[k], p[(k + 1) % 3]);
                        largest = largest.max((a[0] - b[0]).hypot(a[1] - b[1]));
                    }
                }
            }
            (largest, 2.0 * PI * 0.1 / zone_rim_nodes as f64)
        };
        for n in [2304, 4608] {
            let (e, s_f) = largest_at_depth(n, Some(l));
            eprintln!("zone {n}: largest edge at depth l {e:.3e} m, pitch {s_f:.3e} m");
            assert!(e < 3.5 * s_f, "{e} vs pitch {s_f}");
            let (e, _) = largest_at_depth(n, None);
            assert!(e > 0.15 * l, "graded alone: {e}");
        }
    }

    #[test]
    fn bad_options_are_refused() {
        let o = options();
        for bad in [
            ZoneOptions {
                rim_nodes: 100,
                ..o
            },
            ZoneOptions {
                zone_rim_nodes: 1000,
                ..o
            },
            ZoneOptions {
                hub_radius: 0.2,
                ..o
            },
            ZoneOptions { sectors: 4, ..o },
            ZoneOptions {
                depth: Some(-1e-3),
                ..o
            },
            ZoneOptions {
                zone_width: 0.01,
                ..o
            },
        ] {
            assert!(disk_zone(&bad).is_err(), "{bad:?}");
        }
    }
}
