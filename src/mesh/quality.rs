//! Mesh quality: sizes, angles, aspect ratios, orientation, boundary and rotational symmetry
//! of a triangle mesh ([`quality`]).
//!
//! Definitions (per triangle with edges `l_1, l_2, l_3`, signed area `A`, longest edge
//! `L`):
//!
//! - **angles**: the three interior angles, in degrees, from the edge vectors (`atan2` of
//!   cross and dot products);
//! - **aspect ratio**: `R_c / (2 r_i)`, the circumradius `R_c = l_1 l_2 l_3 / (4 |A|)` over
//!   twice the inradius `r_i = 2 |A| / (l_1 + l_2 + l_3)`: 1 for the equilateral triangle,
//!   larger for any other, infinite for a degenerate one (a right isosceles triangle gives
//!   1.207, angles of 30-60-90 give 1.366);
//! - **degenerate**: `|A| <= 1e-12 L^2` (zero area up to rounding); **inverted**: `A < 0`
//!   and not degenerate (clockwise, while every cell of a [`Mesh`] must be
//!   counter-clockwise);
//! - **boundary edges**: edges of exactly one triangle; **non-manifold edges**: edges of
//!   more than two;
//! - **rim nodes**: the size of the node set `"rim"` if the mesh has one, else the number of
//!   nodes on boundary edges;
//! - **symmetry order**: the largest `k >= 1` such that turning every node by `2 pi / k`
//!   about the origin lands it within `1e-9 R` of a node (`R` the largest distance of a node
//!   from the origin), `k` tried among the divisors of the rim node count (a rotation that
//!   maps the mesh onto itself maps the rim onto itself, so its order divides the rim's).
//!   The hexagonal [`super::generators::disk_rings`] disks give 6, the
//!   [`super::generators::disk_graded`] disks 1. Only the nodes are compared; for the ring
//!   generators, whose triangles follow from the nodes, that is the mesh's symmetry.

use std::collections::HashMap;

use super::{CellKind, Cells, Mesh};

/// Relative tolerance of the symmetry test (of the largest distance from the origin).
pub const SYMMETRY_TOL: f64 = 1e-9;

/// Relative area below which a triangle counts as degenerate (of its longest edge squared).
pub const DEGENERATE_TOL: f64 = 1e-12;

/// The quality report of a mesh ([`quality`]; definitions in the [module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshQuality {
    /// Number of nodes.
    pub nodes: usize,
    /// Number of triangles (0 for a mesh of bars).
    pub triangles: usize,
    /// Smallest interior angle over all triangles, degrees (NaN without triangles).
    pub min_angle_deg: f64,
    /// Largest interior angle over all triangles, degrees (NaN without triangles).
    pub max_angle_deg: f64,
    /// Largest aspect ratio `R_c / (2 r_i)` (1 = equilateral; NaN without triangles,
    /// infinite with a degenerate one).
    pub max_aspect: f64,
    /// Mean aspect ratio over the triangles (NaN without triangles).
    pub mean_aspect: f64,
    /// Triangles of negative area (clockwise), degenerate ones excepted; solid cells with a
    /// negative corner Jacobian (a tetrahedron's volume, a hexahedron's at any corner).
    pub inverted: usize,
    /// Triangles of zero area: `|A| <= 1e-12 L^2` ([`DEGENERATE_TOL`]); solid cells with a
    /// corner Jacobian `|J| <= 1e-12 L^3`.
    pub degenerate: usize,
    /// Sum of the signed triangle areas, m^2.
    pub area: f64,
    /// Number of solid cells (tetrahedra, hexahedra; 0 below 3D).
    pub solids: usize,
    /// Sum of the solid cells' signed volumes, m^3 (NaN without solid cells): a tetrahedron's
    /// by its corners, a hexahedron's by 2 x 2 x 2 Gauss points (exact for the trilinear map).
    pub volume: f64,
    /// Edges of exactly one triangle.
    pub boundary_edges: usize,
    /// Edges of more than two triangles.
    pub non_manifold_edges: usize,
    /// Rim nodes: the `"rim"` node set's size, else the number of boundary nodes.
    pub rim_nodes: usize,
    /// Order of the rotational symmetry about the origin (1 = none but the identity).
    pub symmetry_order: usize,
}

/// Interior angles (degrees), aspect ratio `R_c / (2 r_i)`, signed area and longest edge of
/// the triangle `p`.
fn triangle_measures(p: [&[f64]; 3]) -> ([f64; 3], f64, f64, f64) {
    let sub = |a: &[f64], b: &[f64]| [a[0] - b[0], a[1] - b[1]];
    let mut angles = [0.0; 3];
    let mut len = [0.0; 3];
    for v in 0..3 {
        let e1 = sub(p[(v + 1) % 3], p[v]);
        let e2 = sub(p[(v + 2) % 3], p[v]);
        let cross = e1[0] * e2[1] - e1[1] * e2[0];
        let dot = e1[0] * e2[0] + e1[1] * e2[1];
        angles[v] = cross.abs().atan2(dot).to_degrees();
        // The edge opposite vertex v + 2.
        len[v] = e1[0].hypot(e1[1]);
    }
    let e1 = sub(p[1], p[0]);
    let e2 = sub(p[2], p[0]);
    let area = 0.5 * (e1[0] * e2[1] - e1[1] * e2[0]);
    let longest = len[0].max(len[1]).max(len[2]);
    let aspect = if area.abs() <= DEGENERATE_TOL * longest * longest {
        f64::INFINITY
    } else {
        // R_c / (2 r_i) = (l1 l2 l3 / 4|A|) / (4 |A| / (l1 + l2 + l3)).
        len[0] * len[1] * len[2] * (len[0] + len[1] + len[2]) / (16.0 * area * area)
    };
    (angles, aspect, area, longest)
}

/// Divisors of `n` (`n >= 1`), largest first.
fn divisors_descending(n: usize) -> Vec<usize> {
    let mut small = Vec::new();
    let mut large = Vec::new();
    let mut k = 1;
    while k <= n / k {
        if n % k == 0 {
            small.push(k);
            if k != n / k {
                large.push(n / k);
            }
        }
        k += 1;
    }
    large.extend(small.into_iter().rev());
    large
}

/// The largest divisor `k` of `rim` such that turning every point (flat planar coordinates
/// `xy`, two per point) by `2 pi / k` about the origin lands it within `SYMMETRY_TOL * R` of
/// a point (1 if none but the identity).
fn symmetry_order(xy: &[f64], rim: usize) -> usize {
    let extent = xy
        .chunks_exact(2)
        .map(|p| p[0].hypot(p[1]))
        .filter(|r| r.is_finite())
        .fold(0.0_f64, f64::max);
    if rim <= 1 || extent == 0.0 {
        return 1;
    }
    let tol = SYMMETRY_TOL * extent;
    // Points hashed on a grid of cells of side 2 tol: a match lies in the 3 x 3 block of
    // cells around the turned point.
    let cell = 2.0 * tol;
    let key = |x: f64, y: f64| ((x / cell).floor() as i64, (y / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (i, p) in xy.chunks_exact(2).enumerate() {
        grid.entry(key(p[0], p[1])).or_default().push(i);
    }
    let has_point_near = |qx: f64, qy: f64| {
        let (cx, cy) = key(qx, qy);
        (cx - 1..=cx + 1).any(|x| {
            (cy - 1..=cy + 1).any(|y| {
                grid.get(&(x, y)).is_some_and(|v| {
                    v.iter()
                        .any(|&i| (xy[2 * i] - qx).hypot(xy[2 * i + 1] - qy) <= tol)
                })
            })
        })
    };
    for k in divisors_descending(rim) {
        if k == 1 {
            return 1;
        }
        let (s, c) = (std::f64::consts::TAU / k as f64).sin_cos();
        let maps_onto_itself = xy
            .chunks_exact(2)
            .all(|p| has_point_near(c * p[0] - s * p[1], s * p[0] + c * p[1]));
        if maps_onto_itself {
            return k;
        }
    }
    1
}

/// The quality report of `mesh` (definitions in the [module docs](self)).
///
/// A mesh of bars ([`Cells::Bar2`]) has no triangles: its angles and aspect ratios are NaN,
/// its edge counts 0, its rim the `"rim"` node set (if any).
pub fn quality(mesh: &Mesh) -> MeshQuality {
    let tris: &[[usize; 3]] = match &mesh.cells {
        Cells::Tri3(t) => t,
        _ => &[],
    };
    let mut q = MeshQuality {
        nodes: mesh.n_nodes(),
        triangles: tris.len(),
        min_angle_deg: f64::NAN,
        max_angle_deg: f64::NAN,
        max_aspect: f64::NAN,
        mean_aspect: f64::NAN,
        inverted: 0,
        degenerate: 0,
        area: 0.0,
        solids: 0,
        volume: f64::NAN,
        boundary_edges: 0,
        non_manifold_edges: 0,
        rim_nodes: 0,
        symmetry_order: 1,
    };
    let mut edges: HashMap<(usize, usize), usize> = HashMap::new();
    let mut aspect_sum = 0.0;
    for t in tris {
        let (angles, aspect, area, longest) = triangle_measures(t.map(|i| mesh.point(i)));
        for a in angles {
            // f64::min / max skip the NaN start.
            q.min_angle_deg = q.min_angle_deg.min(a);
            q.max_angle_deg = q.max_angle_deg.max(a);
        }
        q.max_aspect = q.max_aspect.max(aspect);
        aspect_sum += aspect;
        q.area += area;
        if area.abs() <= DEGENERATE_TOL * longest * longest {
            q.degenerate += 1;
        } else if area < 0.0 {
            q.inverted += 1;
        }
        for v in 0..3 {
            let (a, b) = (t[v], t[(v + 1) % 3]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    if !tris.is_empty() {
        q.mean_aspect = aspect_sum / tris.len() as f64;
    }
    if mesh.cells.kind().dim() == 3 && mesh.dim == 3 {
        solid_measures(mesh, &mut q);
    }
    let mut boundary_nodes = std::collections::BTreeSet::new();
    for (&(a, b), &count) in &edges {
        if count == 1 {
            q.boundary_edges += 1;
            boundary_nodes.insert(a);
            boundary_nodes.insert(b);
        } else if count > 2 {
            q.non_manifold_edges += 1;
        }
    }
    q.rim_nodes = match mesh.node_set("rim") {
        Some(rim) => rim.len(),
        None => boundary_nodes.len(),
    };
    // The symmetry is planar: a 1D mesh lies on the x axis.
    let planar: Vec<f64> = mesh
        .points()
        .flat_map(|p| [p[0], p.get(1).copied().unwrap_or(0.0)])
        .collect();
    q.symmetry_order = symmetry_order(&planar, q.rim_nodes);
    q
}

/// `det [a b c]` of three 3-vectors.
fn det3(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// The corner Jacobians, the volume and the longest edge of the solid cells of a 3D mesh
/// into `q` ([`MeshQuality::solids`], [`MeshQuality::volume`], `inverted`, `degenerate`).
fn solid_measures(mesh: &Mesh, q: &mut MeshQuality) {
    let kind = mesh.cells.kind();
    let x = |i: usize| -> [f64; 3] {
        let p = mesh.point(i);
        [p[0], p[1], p[2]]
    };
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let len = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    // A hexahedron's corner k, its three neighbours along +xi, +eta, +zeta in its own frame.
    const HEX_CORNERS: [[usize; 4]; 8] = [
        [0, 1, 3, 4],
        [1, 2, 0, 5],
        [2, 3, 1, 6],
        [3, 0, 2, 7],
        [4, 7, 5, 0],
        [5, 4, 6, 1],
        [6, 5, 7, 2],
        [7, 6, 4, 3],
    ];
    q.volume = 0.0;
    for c in mesh.cells.connectivity().chunks_exact(kind.nodes()) {
        let (corner_dets, volume, longest): (Vec<f64>, f64, f64) = if kind == CellKind::Hex8 {
            let dets = HEX_CORNERS
                .iter()
                .map(|&[o, a, b, d]| {
                    let o = x(c[o]);
                    det3(sub(x(c[a]), o), sub(x(c[b]), o), sub(x(c[d]), o))
                })
                .collect();
            let longest = (0..8)
                .flat_map(|i| (0..8).map(move |j| (i, j)))
                .map(|(i, j)| len(sub(x(c[i]), x(c[j]))))
                .fold(0.0, f64::max);
            (dets, hex_volume(c, &x), longest)
        } else {
            let o = x(c[0]);
            let d = det3(sub(x(c[1]), o), sub(x(c[2]), o), sub(x(c[3]), o));
            let longest = (0..4)
                .flat_map(|i| (0..4).map(move |j| (i, j)))
                .map(|(i, j)| len(sub(x(c[i]), x(c[j]))))
                .fold(0.0, f64::max);
            (vec![d], d / 6.0, longest)
        };
        q.solids += 1;
        q.volume += volume;
        let floor = DEGENERATE_TOL * longest.powi(3);
        if corner_dets.iter().any(|d| d.abs() <= floor) {
            q.degenerate += 1;
        } else if corner_dets.iter().any(|&d| d < 0.0) {
            q.inverted += 1;
        }
    }
}

/// The volume of the trilinear hexahedron `c` by 2 x 2 x 2 Gauss points (the element's
/// own shape functions, [`crate::element::hex8`]), signed: an inverted cell's is negative.
fn hex_volume(c: &[usize], x: &impl Fn(usize) -> [f64; 3]) -> f64 {
    use crate::element::hex8::{shape, GAUSS};
    GAUSS
        .iter()
        .map(|&g| {
            let (_, dn) = shape(g);
            let mut jac = [[0.0; 3]; 3];
            for (k, dnk) in dn.iter().enumerate() {
                let xk = x(c[k]);
                for (a, row) in jac.iter_mut().enumerate() {
                    for (i, xi) in xk.iter().enumerate() {
                        row[i] += dnk[a] * xi;
                    }
                }
            }
            det3(jac[0], jac[1], jac[2])
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generators::{bar, disk_rings, rectangle};

    fn one_triangle(p: [[f64; 2]; 3]) -> Mesh {
        Mesh::new(
            2,
            p.concat(),
            Cells::Tri3(vec![[0, 1, 2]]),
            Default::default(),
        )
    }

    #[test]
    fn equilateral_right_and_degenerate_triangles() {
        let h = 3.0_f64.sqrt() / 2.0;
        let q = quality(&one_triangle([[0.0, 0.0], [1.0, 0.0], [0.5, h]]));
        assert!((q.min_angle_deg - 60.0).abs() < 1e-12 && (q.max_angle_deg - 60.0).abs() < 1e-12);
        assert!((q.max_aspect - 1.0).abs() < 1e-12, "{}", q.max_aspect);
        assert!((q.area - 0.5 * h).abs() < 1e-15);
        assert_eq!((q.inverted, q.degenerate, q.boundary_edges), (0, 0, 3));
        assert_eq!(q.rim_nodes, 3);
        // Turned by 120 degrees about the origin the triangle does not land on itself.
        assert_eq!(q.symmetry_order, 1);

        let q = quality(&one_triangle([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]));
        assert!((q.max_angle_deg - 90.0).abs() < 1e-12);
        assert!((q.min_angle_deg - 45.0).abs() < 1e-12);
        assert!((q.max_aspect - (1.0 + 2.0_f64.sqrt()) / 2.0).abs() < 1e-12);

        // Clockwise: inverted, same shape.
        let q = quality(&one_triangle([[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]]));
        assert_eq!((q.inverted, q.degenerate), (1, 0));
        assert!(q.area < 0.0);

        let q = quality(&one_triangle([[0.0, 0.0], [1.0, 0.0], [2.0, 1e-14]]));
        assert_eq!((q.inverted, q.degenerate), (0, 1));
        assert!(q.max_aspect.is_infinite());
        assert!(q.min_angle_deg < 1e-9 && q.max_angle_deg > 180.0 - 1e-9);
    }

    #[test]
    fn triangle_centred_at_origin_has_order_3() {
        let p = |deg: f64| [deg.to_radians().cos(), deg.to_radians().sin()];
        let q = quality(&one_triangle([p(10.0), p(130.0), p(250.0)]));
        assert_eq!(q.symmetry_order, 3);
        assert!((q.max_aspect - 1.0).abs() < 1e-12);
    }

    #[test]
    fn hexagonal_disks_have_order_6() {
        for n in [1, 2, 5, 8, 12] {
            let m = disk_rings(0.1, n).unwrap();
            let q = quality(&m);
            assert_eq!(q.symmetry_order, 6, "n = {n}");
            assert_eq!(q.rim_nodes, 6 * n);
            assert_eq!(q.boundary_edges, 6 * n);
            assert_eq!((q.inverted, q.degenerate, q.non_manifold_edges), (0, 0, 0));
        }
        // Turning one interior node breaks the symmetry.
        let mut m = disk_rings(0.1, 8).unwrap();
        m.coords[2 * 3] += 1e-6;
        assert_eq!(quality(&m).symmetry_order, 1);
    }

    #[test]
    fn rectangle_and_bar() {
        let q = quality(&rectangle(2.0, 1.0, 4, 2).unwrap());
        assert_eq!((q.nodes, q.triangles), (15, 16));
        assert_eq!(q.boundary_edges, 12);
        assert_eq!(q.rim_nodes, 12);
        assert!((q.area - 2.0).abs() < 1e-12);
        // A rectangle with a corner at the origin: no rotation about the origin.
        assert_eq!(q.symmetry_order, 1);
        let q = quality(&bar(1.0, 3).unwrap());
        assert_eq!((q.nodes, q.triangles, q.rim_nodes), (4, 0, 0));
        assert!(q.min_angle_deg.is_nan() && q.max_aspect.is_nan());
        assert_eq!(q.symmetry_order, 1);
    }

    #[test]
    fn divisors() {
        assert_eq!(divisors_descending(12), vec![12, 6, 4, 3, 2, 1]);
        assert_eq!(divisors_descending(1), vec![1]);
        assert_eq!(divisors_descending(49), vec![49, 7, 1]);
        assert_eq!(divisors_descending(1440).len(), 36);
    }
}
