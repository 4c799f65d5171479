//! Mesh generators for the paper's test problems.
//!
//! - [`bar`]: a straight 1D bar of two-node elements.
//! - [`disk_rings`]: the hexagonal-pattern disk (centre node plus `n` rings of `6k` nodes).
//! - [`disk_graded`]: a disk refined towards the rim, with a chosen number of rim nodes and
//!   no rotational symmetry (the hexagonal disk's six-fold symmetry shows in rolling results).
//! - [`rectangle`]: a structured triangle mesh of a rectangle.
//! - [`box_mesh`]: a structured box of hexahedra or tetrahedra (linear or quadratic) in 3D.
//! - [`box3d`]: the same boxes as flat arrays, for element checks without a [`Mesh`].
//! - [`wheel_of_revolution`]: a wheel of a real tread profile (S1002, conical) swept about
//!   its axle into hexahedra, graded toward the contact ([`revolution`]).
//! - [`rail_extruded`]: a UIC60 rail extruded into hexahedra at its 1:40 inclination,
//!   graded toward the contact ([`rail3d`]).
//!
//! Every generator checks its arguments and returns a [`MeshError`] naming the offending
//! parameter and the allowed range instead of panicking. All triangles are counter-clockwise
//! (positive area), and node sets are sorted with no repeats.

use std::collections::BTreeMap;

use super::{Cells, Mesh};
#[cfg(test)]
use disk::signed_area;

pub mod box3d;
mod disk;
pub mod graded;
pub mod rail3d;
pub mod revolution;
mod solid;

pub use disk::{disk_graded, disk_symmetric_rim, DiskOptions};
pub use rail3d::{rail_extruded, RailSpec};
pub use revolution::{wheel_of_revolution, TreadProfile, WheelSpec, WheelWeb};
pub use solid::{annulus_hex8, box_mesh, quadratic_tetrahedra, swept_annulus_hex8, tetrahedra};

/// Largest number of nodes a generator will build (a guard against accidental huge meshes
/// that would exhaust memory).
pub const MAX_NODES: usize = 50_000_000;

/// Invalid arguments to a mesh generator.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// A length is zero, negative, infinite or NaN.
    #[error("mesh parameter `{name}` must be a finite number > 0 (in m), got {value}")]
    InvalidLength {
        /// Name of the parameter.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// An element or ring count is zero.
    #[error("mesh parameter `{name}` must be an integer >= 1, got {value}")]
    InvalidCount {
        /// Name of the parameter.
        name: &'static str,
        /// The value given.
        value: usize,
    },
    /// A count is below the smallest value the generator accepts.
    #[error("mesh parameter `{name}` must be an integer >= {min}, got {value}")]
    CountBelow {
        /// Name of the parameter.
        name: &'static str,
        /// The value given.
        value: usize,
        /// The smallest value allowed.
        min: usize,
    },
    /// A dimensionless number is outside its allowed range (or NaN).
    #[error("mesh parameter `{name}` must be a number in [{min}, {max}], got {value}")]
    OutOfRange {
        /// Name of the parameter.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The smallest value allowed.
        min: f64,
        /// The largest value allowed.
        max: f64,
    },
    /// The requested mesh would have more than [`MAX_NODES`] nodes.
    #[error(
        "mesh too large: `{name}` = {value} would give more than {max} nodes; \
         use a smaller `{name}`"
    )]
    TooLarge {
        /// Name of the parameter that makes the mesh too large.
        name: &'static str,
        /// The value given.
        value: usize,
        /// The node limit ([`MAX_NODES`]).
        max: usize,
    },
    /// The mesh cannot be built as asked (the message says why).
    #[error("{0}")]
    Invalid(String),
}

fn check_length(name: &'static str, value: f64) -> Result<(), MeshError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(MeshError::InvalidLength { name, value })
    }
}

fn check_count(name: &'static str, value: usize) -> Result<(), MeshError> {
    if value >= 1 {
        Ok(())
    } else {
        Err(MeshError::InvalidCount { name, value })
    }
}

fn check_nodes(name: &'static str, value: usize, nodes: Option<usize>) -> Result<usize, MeshError> {
    match nodes {
        Some(n) if n <= MAX_NODES => Ok(n),
        _ => Err(MeshError::TooLarge {
            name,
            value,
            max: MAX_NODES,
        }),
    }
}

/// A straight 1D bar from `x = 0` to `x = length` with `n_elements` equal two-node elements.
///
/// Nodes are numbered from left to right (`n_elements + 1` nodes, one coordinate `x` each). Node sets:
/// `"left"` (node 0), `"right"` (the last node) and `"all"`.
///
/// # Errors
/// [`MeshError::InvalidLength`] unless `length` is finite and positive,
/// [`MeshError::InvalidCount`] if `n_elements` is zero, [`MeshError::TooLarge`] past
/// [`MAX_NODES`] nodes.
pub fn bar(length: f64, n_elements: usize) -> Result<Mesh, MeshError> {
    check_length("length", length)?;
    check_count("n_elements", n_elements)?;
    let n_nodes = check_nodes("n_elements", n_elements, n_elements.checked_add(1))?;

    let coords = (0..n_nodes)
        .map(|i| {
            // The last node sits exactly at `length`.
            if i == n_elements {
                length
            } else {
                length * i as f64 / n_elements as f64
            }
        })
        .collect();
    let cells = (0..n_elements).map(|e| [e, e + 1]).collect();

    let mut node_sets = BTreeMap::new();
    node_sets.insert("left".to_string(), vec![0]);
    node_sets.insert("right".to_string(), vec![n_elements]);
    node_sets.insert("all".to_string(), (0..n_nodes).collect());

    Ok(Mesh::new(1, coords, Cells::Bar2(cells), node_sets))
}

/// Index of the first node of ring `k` (ring 0 is the centre node): `1 + 3k(k-1)` for `k >= 1`.
fn ring_start(k: usize) -> usize {
    if k == 0 {
        0
    } else {
        1 + 3 * k * (k - 1)
    }
}

/// The hexagonal-pattern disk of the paper: a centre node and `n_rings` rings.
///
/// Ring `k` (`1..=n_rings`) holds `6k` nodes at equal angles `2 pi i / (6k)` (`i = 0..6k`,
/// starting on the positive `x` axis, counter-clockwise) on the circle of radius
/// `k * radius / n_rings`. Between rings `k - 1` and `k` each of the six sectors of the
/// hexagon pattern holds `2k - 1` triangles, so the mesh has `1 + 3n(n+1)` nodes and `6n^2`
/// counter-clockwise triangles (`n = 12`: 469 nodes, 864 triangles).
///
/// Nodes are numbered ring by ring (centre first), by angle within a ring. Node sets:
/// `"centre"` (`[0]`), `"rim"` (the outer ring, ordered by angle) and `"all"`.
///
/// # Errors
/// [`MeshError::InvalidLength`] unless `radius` is finite and positive,
/// [`MeshError::InvalidCount`] if `n_rings` is zero, [`MeshError::TooLarge`] past
/// [`MAX_NODES`] nodes.
pub fn disk_rings(radius: f64, n_rings: usize) -> Result<Mesh, MeshError> {
    check_length("radius", radius)?;
    check_count("n_rings", n_rings)?;
    let n = n_rings;
    // 1 + 3 n (n + 1), checked.
    let n_nodes = n
        .checked_add(1)
        .and_then(|m| m.checked_mul(n))
        .and_then(|m| m.checked_mul(3))
        .and_then(|m| m.checked_add(1));
    let n_nodes = check_nodes("n_rings", n, n_nodes)?;

    let mut coords = Vec::with_capacity(2 * n_nodes);
    coords.extend([0.0, 0.0]);
    for k in 1..=n {
        let r = if k == n {
            radius
        } else {
            radius * k as f64 / n as f64
        };
        let m = 6 * k;
        for i in 0..m {
            let theta = std::f64::consts::TAU * i as f64 / m as f64;
            coords.extend([r * theta.cos(), r * theta.sin()]);
        }
    }

    let mut tris = Vec::with_capacity(6 * n * n);
    for k in 1..=n {
        let outer_start = ring_start(k);
        let outer_len = 6 * k;
        let inner_start = ring_start(k - 1);
        let inner_len = 6 * (k - 1);
        // Node j (0..=k) of side s on the outer ring, node j (0..=k-1) on the inner ring.
        let outer = |s: usize, j: usize| outer_start + (k * s + j) % outer_len;
        let inner = |s: usize, j: usize| {
            if k == 1 {
                0
            } else {
                inner_start + ((k - 1) * s + j) % inner_len
            }
        };
        for s in 0..6 {
            // Triangles with an edge on the outer ring ...
            for j in 0..k {
                tris.push([inner(s, j), outer(s, j), outer(s, j + 1)]);
            }
            // ... and with an edge on the inner ring.
            for j in 0..k - 1 {
                tris.push([inner(s, j), outer(s, j + 1), inner(s, j + 1)]);
            }
        }
    }

    let mut node_sets = BTreeMap::new();
    node_sets.insert("centre".to_string(), vec![0]);
    node_sets.insert("rim".to_string(), (ring_start(n)..n_nodes).collect());
    node_sets.insert("all".to_string(), (0..n_nodes).collect());

    Ok(Mesh::new(2, coords, Cells::Tri3(tris), node_sets))
}

/// Nodes of the planar `mesh` within distance `radius` of `centre` (its `x` and `y`, e.g.
/// for a hub clamp), sorted.
///
/// A node counts as inside when its distance is at most `radius + tol`, with the tolerance
/// `tol = 1e-9 * max(radius, size of the mesh)` so that nodes placed on the circle by the
/// generators (with rounding) are included. A negative or NaN `radius` gives no nodes.
///
/// # Panics
/// If the mesh or `centre` has fewer than two coordinates.
pub fn nodes_within(mesh: &Mesh, centre: &[f64], radius: f64) -> Vec<usize> {
    if radius.is_nan() || radius < 0.0 {
        return Vec::new();
    }
    let extent = mesh
        .points()
        .map(|p| p[0].abs().max(p[1].abs()))
        .filter(|v| v.is_finite())
        .fold(0.0_f64, f64::max);
    let limit = radius + 1e-9 * radius.max(extent);
    mesh.points()
        .enumerate()
        .filter(|(_, p)| {
            let dx = p[0] - centre[0];
            let dy = p[1] - centre[1];
            dx.hypot(dy) <= limit
        })
        .map(|(i, _)| i)
        .collect()
}

/// A structured triangle mesh of the rectangle `[0, lx] x [0, ly]`.
///
/// The rectangle is split into `nx` by `ny` quads, each cut into two counter-clockwise
/// triangles along alternating diagonals (the "union jack" pattern: the diagonal direction
/// flips from one quad to the next, so the mesh has no preferred direction). Node `(i, j)` (`i = 0..=nx` along `x`, `j = 0..=ny`
/// along `y`) has index `i + j (nx + 1)`. Node sets: `"left"` (`x = 0`), `"right"`
/// (`x = lx`), `"bottom"` (`y = 0`), `"top"` (`y = ly`) and `"all"`.
///
/// # Errors
/// [`MeshError::InvalidLength`] unless `lx` and `ly` are finite and positive,
/// [`MeshError::InvalidCount`] if `nx` or `ny` is zero, [`MeshError::TooLarge`] past
/// [`MAX_NODES`] nodes.
pub fn rectangle(lx: f64, ly: f64, nx: usize, ny: usize) -> Result<Mesh, MeshError> {
    check_length("lx", lx)?;
    check_length("ly", ly)?;
    check_count("nx", nx)?;
    check_count("ny", ny)?;
    let row = check_nodes("nx", nx, nx.checked_add(1))?;
    let n_nodes = ny.checked_add(1).and_then(|c| c.checked_mul(row));
    let n_nodes = check_nodes("ny", ny, n_nodes)?;

    let coord = |i: usize, n: usize, l: f64| {
        if i == n {
            l
        } else {
            l * i as f64 / n as f64
        }
    };
    let mut coords = Vec::with_capacity(2 * n_nodes);
    for j in 0..=ny {
        let y = coord(j, ny, ly);
        for i in 0..=nx {
            coords.extend([coord(i, nx, lx), y]);
        }
    }

    let id = |i: usize, j: usize| i + j * row;
    let mut tris = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (n00, n10, n01, n11) = (id(i, j), id(i + 1, j), id(i, j + 1), id(i + 1, j + 1));
            if (i + j) % 2 == 0 {
                // Diagonal from (i, j) to (i + 1, j + 1).
                tris.push([n00, n10, n11]);
                tris.push([n00, n11, n01]);
            } else {
                // Diagonal from (i + 1, j) to (i, j + 1).
                tris.push([n00, n10, n01]);
                tris.push([n10, n11, n01]);
            }
        }
    }

    let mut node_sets = BTreeMap::new();
    node_sets.insert("left".to_string(), (0..=ny).map(|j| id(0, j)).collect());
    node_sets.insert("right".to_string(), (0..=ny).map(|j| id(nx, j)).collect());
    node_sets.insert("bottom".to_string(), (0..=nx).map(|i| id(i, 0)).collect());
    node_sets.insert("top".to_string(), (0..=nx).map(|i| id(i, ny)).collect());
    node_sets.insert("all".to_string(), (0..n_nodes).collect());

    Ok(Mesh::new(2, coords, Cells::Tri3(tris), node_sets))
}

/// A block `[0, length] x [0, depth]` for a body that another rolls along: the triangles of
/// [`rectangle`] with columns of width close to `dx` and rows that grow geometrically by
/// `ratio` from `dx` at the top (`y = depth`, the contact surface) down to the bottom (the
/// last rows scaled so that they end at `y = 0`). Node sets as [`rectangle`]'s.
///
/// # Errors
/// [`MeshError`] for a length, depth or `dx` that is not finite and positive, a `ratio`
/// outside `[1, 2]`, or too many nodes.
pub fn block_graded(length: f64, depth: f64, dx: f64, ratio: f64) -> Result<Mesh, MeshError> {
    check_length("length", length)?;
    check_length("depth", depth)?;
    check_length("dx", dx)?;
    if !(1.0..=2.0).contains(&ratio) {
        return Err(MeshError::OutOfRange {
            name: "ratio",
            value: ratio,
            min: 1.0,
            max: 2.0,
        });
    }
    let nx = (length / dx).ceil().max(1.0);
    if nx > MAX_NODES as f64 {
        return Err(MeshError::TooLarge {
            name: "length / dx",
            value: usize::MAX,
            max: MAX_NODES,
        });
    }
    let mut rows = Vec::new();
    let (mut h, mut sum) = (dx, 0.0);
    while sum < depth && rows.len() < 10_000 {
        rows.push(h);
        sum += h;
        h *= ratio;
    }
    // The last row ends past the bottom: shrink the rows below the first half so that the
    // top keeps its `dx`.
    let over = sum - depth;
    let scale_from = rows.len() / 2;
    let below: f64 = rows[scale_from..].iter().sum();
    let s = ((below - over) / below).max(0.1);
    for r in &mut rows[scale_from..] {
        *r *= s;
    }
    let ny = rows.len();
    let mut mesh = rectangle(length, depth, nx as usize, ny)?;
    let row = nx as usize + 1;
    let mut y = depth;
    let mut ys = vec![depth; ny + 1];
    for (k, r) in rows.iter().enumerate() {
        y -= r;
        ys[ny - 1 - k] = if k + 1 == ny { 0.0 } else { y.max(0.0) };
    }
    for (i, p) in mesh.coords.chunks_exact_mut(2).enumerate() {
        p[1] = ys[i / row];
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_graded_block_has_its_fine_rows_on_top_and_covers_its_depth() {
        let m = block_graded(0.3, 0.05, 2e-3, 1.25).unwrap();
        let top = &m.node_sets["top"];
        let bottom = &m.node_sets["bottom"];
        assert!(top.iter().all(|&i| m.point(i)[1] == 0.05));
        assert!(bottom.iter().all(|&i| m.point(i)[1] == 0.0));
        let row = top.len();
        let (y0, y1) = (
            m.point(m.n_nodes() - 1)[1],
            m.point(m.n_nodes() - 1 - row)[1],
        );
        assert!(((y0 - y1) - 2e-3).abs() < 1e-12, "top row {}", y0 - y1);
        assert!(((m.point(1)[0] - m.point(0)[0]) - 2e-3).abs() < 1e-12);
        let Cells::Tri3(tris) = &m.cells else {
            panic!("triangles")
        };
        assert!(tris.iter().all(|&t| signed_area(&m.coords, t) > 0.0));
        let area: f64 = tris.iter().map(|&t| signed_area(&m.coords, t)).sum();
        assert!(
            area > 0.0 && (area - 0.3 * 0.05).abs() < 1e-12 * 0.015,
            "area {area}"
        );
    }

    fn tris(mesh: &Mesh) -> &[[usize; 3]] {
        match &mesh.cells {
            Cells::Tri3(t) => t,
            _ => panic!("expected triangles"),
        }
    }

    /// Every edge is shared by at most two triangles, with opposite directions (a consistently
    /// oriented manifold), and every node is used by some triangle.
    fn check_conforming(mesh: &Mesh) {
        let mut edges = std::collections::HashMap::new();
        let mut used = vec![false; mesh.n_nodes()];
        for t in tris(mesh) {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                assert!(a < mesh.n_nodes() && b < mesh.n_nodes());
                assert_ne!(a, b);
                used[a] = true;
                *edges.entry((a, b)).or_insert(0) += 1;
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(count, 1, "directed edge {a}->{b} used twice");
        }
        assert!(used.iter().all(|&u| u), "unused node");
    }

    fn check_sets_sorted(mesh: &Mesh) {
        for (name, set) in &mesh.node_sets {
            assert!(set.windows(2).all(|w| w[0] < w[1]), "set {name} not sorted");
            assert!(
                set.iter().all(|&i| i < mesh.n_nodes()),
                "set {name} out of range"
            );
        }
    }

    #[test]
    fn bar_nodes_cells_sets() {
        let m = bar(2.0, 4).unwrap();
        assert_eq!(m.dim, 1);
        assert_eq!(m.n_nodes(), 5);
        assert_eq!(m.cells, Cells::Bar2(vec![[0, 1], [1, 2], [2, 3], [3, 4]]));
        let xs: Vec<f64> = m.points().map(|p| p[0]).collect();
        assert_eq!(xs, vec![0.0, 0.5, 1.0, 1.5, 2.0]);
        assert_eq!(m.coords, xs);
        assert_eq!(m.node_set("left"), Some(&[0][..]));
        assert_eq!(m.node_set("right"), Some(&[4][..]));
        assert_eq!(m.node_set("all").unwrap().len(), 5);
        assert_eq!(m.reference_positions(), xs);
        check_sets_sorted(&m);

        let m = bar(0.3, 7).unwrap();
        assert_eq!(m.point(7)[0], 0.3);
    }

    #[test]
    fn bar_rejects_bad_arguments() {
        for l in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = bar(l, 3).unwrap_err();
            assert!(matches!(e, MeshError::InvalidLength { name: "length", .. }));
            assert!(e.to_string().contains("`length`"), "{e}");
            assert!(e.to_string().contains("> 0"), "{e}");
        }
        let e = bar(1.0, 0).unwrap_err();
        assert_eq!(
            e,
            MeshError::InvalidCount {
                name: "n_elements",
                value: 0
            }
        );
        assert!(e.to_string().contains(">= 1"));
        assert!(matches!(
            bar(1.0, usize::MAX).unwrap_err(),
            MeshError::TooLarge { .. }
        ));
    }

    #[test]
    fn disk_counts_for_1_to_12_rings() {
        for n in 1..=12 {
            let m = disk_rings(1.0, n).unwrap();
            assert_eq!(m.dim, 2);
            assert_eq!(m.n_nodes(), 1 + 3 * n * (n + 1), "n = {n}");
            assert_eq!(m.cells.len(), 6 * n * n, "n = {n}");
            assert_eq!(m.node_set("rim").unwrap().len(), 6 * n);
            assert_eq!(m.node_set("centre"), Some(&[0][..]));
            assert_eq!(m.node_set("all").unwrap().len(), m.n_nodes());
            check_conforming(&m);
            check_sets_sorted(&m);
        }
        let m = disk_rings(0.5, 12).unwrap();
        assert_eq!((m.n_nodes(), m.cells.len()), (469, 864));
    }

    #[test]
    fn disk_triangles_positive_and_area_converges() {
        let radius = 0.7;
        let exact = std::f64::consts::PI * radius * radius;
        let mut prev_err = f64::INFINITY;
        for n in 1..=12 {
            let m = disk_rings(radius, n).unwrap();
            let mut total = 0.0;
            let mut min_area = f64::INFINITY;
            for &t in tris(&m) {
                let a = signed_area(&m.coords, t);
                assert!(a > 0.0, "n = {n}: triangle {t:?} has area {a}");
                min_area = min_area.min(a);
                total += a;
            }
            // Well-shaped: no sliver much smaller than the average triangle.
            let mean = total / m.cells.len() as f64;
            assert!(min_area > 0.3 * mean, "n = {n}: min {min_area} mean {mean}");
            // The mesh is the inscribed 6n-gon: area = (6n/2) R^2 sin(2 pi / 6n).
            let m6 = 6.0 * n as f64;
            let polygon = 0.5 * m6 * radius * radius * (std::f64::consts::TAU / m6).sin();
            assert!((total - polygon).abs() < 1e-12 * exact, "n = {n}");
            let err = exact - total;
            assert!(err > 0.0 && err < prev_err, "n = {n}: error {err}");
            prev_err = err;
        }
        assert!(prev_err / exact < 2e-3);
    }

    #[test]
    fn disk_rim_on_circle_ordered_by_angle() {
        let r = 2.5;
        let m = disk_rings(r, 5).unwrap();
        let rim = m.node_set("rim").unwrap();
        let mut last = -1.0;
        for &i in rim {
            let p = m.point(i);
            assert!((p[0].hypot(p[1]) - r).abs() < 1e-12);
            let mut ang = p[1].atan2(p[0]);
            if ang < 0.0 {
                ang += std::f64::consts::TAU;
            }
            assert!(ang > last);
            last = ang;
        }
        // Ring k nodes sit on radius k r / n.
        for k in 1..=5 {
            for i in ring_start(k)..ring_start(k) + 6 * k {
                let p = m.point(i);
                assert!((p[0].hypot(p[1]) - r * k as f64 / 5.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn disk_rejects_bad_arguments() {
        assert!(matches!(
            disk_rings(-1.0, 3),
            Err(MeshError::InvalidLength { name: "radius", .. })
        ));
        assert!(matches!(
            disk_rings(1.0, 0),
            Err(MeshError::InvalidCount {
                name: "n_rings",
                ..
            })
        ));
        assert!(matches!(
            disk_rings(1.0, usize::MAX / 2),
            Err(MeshError::TooLarge {
                name: "n_rings",
                ..
            })
        ));
        assert!(matches!(
            disk_rings(1.0, 10_000),
            Err(MeshError::TooLarge { .. })
        ));
    }

    #[test]
    fn nodes_within_hub() {
        let m = disk_rings(1.0, 12).unwrap();
        // Radius 2/12: centre, ring 1 and ring 2 (rounded positions included).
        let hub = nodes_within(&m, &[0.0, 0.0], 2.0 / 12.0);
        assert_eq!(hub, (0..1 + 6 + 12).collect::<Vec<_>>());
        assert_eq!(nodes_within(&m, &[0.0, 0.0], 0.0), vec![0]);
        assert!(nodes_within(&m, &[0.0, 0.0], -1.0).is_empty());
        assert!(nodes_within(&m, &[0.0, 0.0], f64::NAN).is_empty());
        assert_eq!(nodes_within(&m, &[0.0, 0.0], 10.0).len(), m.n_nodes());
        // Off-centre: the rim node on the positive x axis.
        let rim0 = m.node_set("rim").unwrap()[0];
        assert_eq!(nodes_within(&m, &[1.0, 0.0], 1e-3), vec![rim0]);
    }

    #[test]
    fn rectangle_nodes_cells_sets() {
        let (lx, ly, nx, ny) = (2.0, 1.0, 4, 3);
        let m = rectangle(lx, ly, nx, ny).unwrap();
        assert_eq!(m.dim, 2);
        assert_eq!(m.n_nodes(), 5 * 4);
        assert_eq!(m.cells.len(), 2 * 4 * 3);
        let mut total = 0.0;
        for &t in tris(&m) {
            let a = signed_area(&m.coords, t);
            assert!((a - 0.5 * (lx / nx as f64) * (ly / ny as f64)).abs() < 1e-14);
            total += a;
        }
        assert!((total - lx * ly).abs() < 1e-12);
        check_conforming(&m);
        check_sets_sorted(&m);
        let on = |name: &str, f: &dyn Fn(&[f64]) -> bool| {
            let set = m.node_set(name).unwrap();
            let expect: Vec<usize> = (0..m.n_nodes()).filter(|&i| f(m.point(i))).collect();
            assert_eq!(set, expect.as_slice(), "{name}");
        };
        on("left", &|p| p[0] == 0.0);
        on("right", &|p| p[0] == lx);
        on("bottom", &|p| p[1] == 0.0);
        on("top", &|p| p[1] == ly);
        on("all", &|_| true);
        // Alternating diagonals: both diagonal directions occur.
        let diag_up = tris(&m)
            .iter()
            .filter(|t| t.contains(&0) && t.contains(&6))
            .count();
        let diag_down = tris(&m)
            .iter()
            .filter(|t| t.contains(&2) && t.contains(&6))
            .count();
        assert_eq!((diag_up, diag_down), (2, 2));
    }

    #[test]
    fn rectangle_single_cell_and_bad_arguments() {
        let m = rectangle(1.0, 1.0, 1, 1).unwrap();
        assert_eq!((m.n_nodes(), m.cells.len()), (4, 2));
        assert!(matches!(
            rectangle(0.0, 1.0, 1, 1),
            Err(MeshError::InvalidLength { name: "lx", .. })
        ));
        assert!(matches!(
            rectangle(1.0, f64::NAN, 1, 1),
            Err(MeshError::InvalidLength { name: "ly", .. })
        ));
        assert!(matches!(
            rectangle(1.0, 1.0, 0, 1),
            Err(MeshError::InvalidCount { name: "nx", .. })
        ));
        assert!(matches!(
            rectangle(1.0, 1.0, 1, 0),
            Err(MeshError::InvalidCount { name: "ny", .. })
        ));
        assert!(matches!(
            rectangle(1.0, 1.0, 100_000, 100_000),
            Err(MeshError::TooLarge { name: "ny", .. })
        ));
        assert!(matches!(
            rectangle(1.0, 1.0, usize::MAX, 1),
            Err(MeshError::TooLarge { name: "nx", .. })
        ));
    }
}
