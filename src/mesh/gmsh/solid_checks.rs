//! The checks of a 3D mesh read from a Gmsh file (the [`solid`](super::solid) module's
//! documentation says what each refuses and why): coincident nodes, corner Jacobians and
//! orientation, 10-node tetrahedra's mid-edge nodes, duplicate and overlapping cells, pieces.
//!
//! Nodes are compact indices here; `tags[i]` is node `i`'s Gmsh tag and `cell_tags[e]` cell
//! `e`'s, for the errors.

use super::*;
use crate::mesh::CellKind;

/// Distance, relative to the diagonal of the nodes' bounding box, within which two nodes
/// are at one position.
pub(super) const COINCIDENT_RELATIVE: f64 = 1e-9;

/// Corner Jacobian, relative to the cell's longest corner-to-corner distance cubed, at or
/// below which a cell is degenerate (as [`crate::mesh::quality::DEGENERATE_TOL`]).
const DEGENERATE_RELATIVE: f64 = crate::mesh::quality::DEGENERATE_TOL;

/// A hexahedron's corner `k` and its neighbours along its own `+xi`, `+eta`, `+zeta` (the
/// corner Jacobian is `det[x_a - x_k, x_b - x_k, x_c - x_k]`, positive for Gmsh's order).
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

/// A 10-node tetrahedron's mid-edge nodes (positions 4 to 9) and their edges' corners, in
/// Gmsh's order.
const TET10_EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (0, 3), (2, 3), (1, 3)];

/// The faces of a positively oriented tetrahedron, each turned outward (counter-clockwise
/// seen from outside).
const TET_FACES: [[usize; 3]; 4] = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];

/// The faces of a positively oriented hexahedron (Gmsh's order), each turned outward.
const HEX_FACES: [[usize; 4]; 6] = [
    [0, 3, 2, 1],
    [4, 5, 6, 7],
    [0, 1, 5, 4],
    [1, 2, 6, 5],
    [2, 3, 7, 6],
    [3, 0, 4, 7],
];

/// The node permutation that mirrors a cell (turns its orientation): new node `k` is old
/// node `perm[k]`.
fn mirror(kind: CellKind) -> &'static [usize] {
    match kind {
        CellKind::Tet4 => &[0, 2, 1, 3],
        // Corners 1 and 2 swapped: edges 0-1 and 2-0 swap, 1-2 stays, 2-3 and 1-3 swap.
        CellKind::Tet10 => &[0, 2, 1, 3, 6, 5, 4, 7, 9, 8],
        // Mirrored in xi = eta: 1 and 3, 5 and 7 swap.
        CellKind::Hex8 => &[0, 3, 2, 1, 4, 7, 6, 5],
        CellKind::Bar2 => &[1, 0],
        CellKind::Tri3 => &[0, 2, 1],
    }
}

/// One cell of `kind`, for messages (`"a 4-node tetrahedron"`).
fn one(kind: CellKind) -> &'static str {
    match kind {
        CellKind::Tet4 => "a 4-node tetrahedron",
        CellKind::Tet10 => "a 10-node tetrahedron",
        CellKind::Hex8 => "an 8-node hexahedron",
        CellKind::Bar2 => "a 2-node bar",
        CellKind::Tri3 => "a 3-node triangle",
    }
}

/// The point of node `i` of the flat coordinates (NaN beyond them).
fn point(xyz: &[f64], i: usize) -> [f64; 3] {
    match xyz.get(3 * i..3 * i + 3) {
        Some(&[x, y, z]) => [x, y, z],
        _ => [f64::NAN; 3],
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// `det [a b c]` of three 3-vectors.
fn det3(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// No two nodes within [`COINCIDENT_RELATIVE`] of the bounding box's diagonal: nodes hashed
/// on a grid of that spacing, each compared with the earlier nodes of the 27 cells around
/// it.
pub(super) fn check_coincident(xyz: &[f64], tags: &[u64], path: &Path) -> Result<(), GmshError> {
    let n = xyz.len() / 3;
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for i in 0..n {
        let p = point(xyz, i);
        for c in 0..3 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    let extent = norm(sub(hi, lo));
    if !extent.is_finite() {
        // NaN or infinite coordinates: left to the Jacobians (a NaN one is degenerate).
        return Ok(());
    }
    let tol = COINCIDENT_RELATIVE * extent;
    let spacing = if tol > 0.0 { tol } else { 1.0 };
    let key = |p: [f64; 3]| p.map(|v| (v / spacing).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::with_capacity(n);
    for i in 0..n {
        let p = point(xyz, i);
        let k = key(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let near = grid.get(&[k[0] + dx, k[1] + dy, k[2] + dz]);
                    for &j in near.into_iter().flatten() {
                        let d = norm(sub(p, point(xyz, j)));
                        if d <= tol {
                            let q = point(xyz, j);
                            return Err(GmshError::CoincidentSolidNodes {
                                path: path.to_path_buf(),
                                first: tags[j],
                                second: tags[i],
                                x: q[0],
                                y: q[1],
                                z: q[2],
                                distance: d,
                                tolerance: tol,
                            });
                        }
                    }
                }
            }
        }
        grid.entry(k).or_default().push(i);
    }
    Ok(())
}

/// The corner Jacobians of cell `c` (one for a tetrahedron, whose corners all share it;
/// eight for a hexahedron), each with its corner's position in the cell, and the cell's
/// longest corner-to-corner distance.
fn corner_jacobians(kind: CellKind, c: &[usize], xyz: &[f64]) -> (Vec<(usize, f64)>, f64) {
    let x = |k: usize| point(xyz, c[k]);
    let corners = if kind == CellKind::Hex8 { 8 } else { 4 };
    let mut longest = 0.0f64;
    for a in 0..corners {
        for b in a + 1..corners {
            longest = longest.max(norm(sub(x(a), x(b))));
        }
    }
    let jacobians = if kind == CellKind::Hex8 {
        HEX_CORNERS
            .iter()
            .map(|&[o, a, b, d]| (o, det3(sub(x(a), x(o)), sub(x(b), x(o)), sub(x(d), x(o)))))
            .collect()
    } else {
        let o = x(0);
        vec![(0, det3(sub(x(1), o), sub(x(2), o), sub(x(3), o)))]
    };
    (jacobians, longest)
}

/// The cells' checks in order: corner Jacobians (degenerate, tangled, inverted; a mesh of
/// only negatively oriented cells is mirrored cell by cell in `flat`), mid-edge nodes,
/// duplicate cells, overlapping cells.
pub(super) fn check_cells(
    kind: CellKind,
    flat: &mut [usize],
    xyz: &[f64],
    tags: &[u64],
    cell_tags: &[u64],
    path: &Path,
) -> Result<(), GmshError> {
    orient(kind, flat, xyz, tags, cell_tags, path)?;
    if kind == CellKind::Tet10 {
        check_mid_edges(flat, xyz, tags, cell_tags, path)?;
    }
    check_duplicates_and_overlaps(kind, flat, tags, cell_tags, path)
}

/// Corner Jacobians: each cell not degenerate and not tangled, all of one sign; all
/// negative: every cell mirrored.
fn orient(
    kind: CellKind,
    flat: &mut [usize],
    xyz: &[f64],
    tags: &[u64],
    cell_tags: &[u64],
    path: &Path,
) -> Result<(), GmshError> {
    let k = kind.nodes();
    // Each cell's sign: true if positively oriented.
    let mut positive = Vec::with_capacity(cell_tags.len());
    for (e, c) in flat.chunks_exact(k).enumerate() {
        let (jacobians, longest) = corner_jacobians(kind, c, xyz);
        let scale = longest.powi(3);
        let floor = DEGENERATE_RELATIVE * scale;
        // NaN Jacobians (from NaN coordinates) count as degenerate.
        if let Some(&(corner, jacobian)) = jacobians
            .iter()
            .find(|(_, j)| j.is_nan() || j.abs() <= floor)
        {
            return Err(GmshError::DegenerateCell {
                path: path.to_path_buf(),
                element: cell_tags[e],
                kind: one(kind),
                node: tags[c[corner]],
                jacobian,
                scale,
            });
        }
        let plus = jacobians.iter().filter(|(_, j)| *j > 0.0).count();
        if plus != 0 && plus != jacobians.len() {
            let (corner, jacobian) = jacobians
                .iter()
                .copied()
                .find(|(_, j)| *j < 0.0)
                .unwrap_or((0, f64::NAN));
            return Err(GmshError::InvertedCell {
                path: path.to_path_buf(),
                element: cell_tags[e],
                kind: one(kind),
                reason: format!(
                    "its corner Jacobians differ in sign ({plus} of {} positive; {jacobian:e} \
                     at node {}): the cell is tangled (folded through itself)",
                    jacobians.len(),
                    tags[c[corner]]
                ),
            });
        }
        positive.push(plus > 0);
    }
    let plus = positive.iter().filter(|&&p| p).count();
    let minus = positive.len() - plus;
    if minus == 0 {
        return Ok(());
    }
    if plus == 0 {
        let perm = mirror(kind);
        let mut old = vec![0; k];
        for c in flat.chunks_exact_mut(k) {
            old.copy_from_slice(c);
            for (slot, &p) in c.iter_mut().zip(perm) {
                *slot = old[p];
            }
        }
        return Ok(());
    }
    let majority = plus >= minus;
    let first = positive.iter().position(|&p| p != majority).unwrap_or(0);
    Err(GmshError::InvertedCell {
        path: path.to_path_buf(),
        element: cell_tags[first],
        kind: one(kind),
        reason: format!(
            "{} of {} cells are oriented against the rest of the mesh (their corner Jacobians \
             are {} where the others' are {})",
            plus.min(minus),
            positive.len(),
            if majority { "negative" } else { "positive" },
            if majority { "positive" } else { "negative" },
        ),
    })
}

/// Every 10-node tetrahedron's mid-edge nodes within a quarter of their edge's length from
/// the edge's middle.
fn check_mid_edges(
    flat: &[usize],
    xyz: &[f64],
    tags: &[u64],
    cell_tags: &[u64],
    path: &Path,
) -> Result<(), GmshError> {
    for (e, c) in flat.chunks_exact(10).enumerate() {
        for (m, &(a, b)) in TET10_EDGES.iter().enumerate() {
            let (xa, xb, xm) = (point(xyz, c[a]), point(xyz, c[b]), point(xyz, c[4 + m]));
            let middle = [0, 1, 2].map(|i| 0.5 * (xa[i] + xb[i]));
            let distance = norm(sub(xm, middle));
            let length = norm(sub(xb, xa));
            // So that NaN fails.
            let near = distance < 0.25 * length;
            if !near {
                return Err(GmshError::MidEdgeNode {
                    path: path.to_path_buf(),
                    element: cell_tags[e],
                    node: tags[c[4 + m]],
                    position: 4 + m,
                    a: tags[c[a]],
                    b: tags[c[b]],
                    distance,
                    length,
                });
            }
        }
    }
    Ok(())
}

/// No cell listed twice (the same corners) and no two cells on the same side of a face
/// (each outward face met once at most). The cells are positively oriented.
fn check_duplicates_and_overlaps(
    kind: CellKind,
    flat: &[usize],
    tags: &[u64],
    cell_tags: &[u64],
    path: &Path,
) -> Result<(), GmshError> {
    let k = kind.nodes();
    let corners = if kind == CellKind::Hex8 { 8 } else { 4 };
    let n_cells = flat.len() / k;
    let mut same: HashMap<[usize; 8], usize> = HashMap::with_capacity(n_cells);
    for (e, c) in flat.chunks_exact(k).enumerate() {
        let mut key = [usize::MAX; 8];
        key[..corners].copy_from_slice(&c[..corners]);
        key.sort_unstable();
        if let Some(&first) = same.get(&key) {
            return Err(GmshError::DuplicateCell {
                path: path.to_path_buf(),
                first: cell_tags[first],
                second: cell_tags[e],
                nodes: key[..corners].iter().map(|&i| tags[i]).collect(),
            });
        }
        same.insert(key, e);
    }
    let faces: Vec<&[usize]> = if kind == CellKind::Hex8 {
        HEX_FACES.iter().map(|f| &f[..]).collect()
    } else {
        TET_FACES.iter().map(|f| &f[..]).collect()
    };
    let mut seen: HashMap<[usize; 4], usize> = HashMap::with_capacity(faces.len() * n_cells);
    for (e, c) in flat.chunks_exact(k).enumerate() {
        for face in &faces {
            // The face's nodes from its smallest, in its own (outward) cyclic order.
            let nodes: Vec<usize> = face.iter().map(|&v| c[v]).collect();
            let start = (0..nodes.len()).min_by_key(|&i| nodes[i]).unwrap_or(0);
            let mut key = [usize::MAX; 4];
            for (i, slot) in key.iter_mut().take(nodes.len()).enumerate() {
                *slot = nodes[(start + i) % nodes.len()];
            }
            if let Some(&first) = seen.get(&key) {
                return Err(GmshError::OverlappingCells {
                    path: path.to_path_buf(),
                    first: cell_tags[first],
                    second: cell_tags[e],
                    face: nodes.iter().map(|&i| tags[i]).collect(),
                });
            }
            seen.insert(key, e);
        }
    }
    Ok(())
}

/// The piece of every node of `n` (cells of `k` nodes, flat): numbered in order of their
/// first node.
pub(super) fn piece_numbers(n: usize, flat: &[usize], k: usize) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for c in flat.chunks_exact(k.max(1)) {
        for &v in &c[1..] {
            if v < n && c[0] < n {
                let (a, b) = (root(&mut parent, c[0]), root(&mut parent, v));
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    // Roots are each piece's smallest node: number them in node order.
    let mut number = vec![usize::MAX; n];
    let mut next = 0;
    let mut piece = vec![0; n];
    for i in 0..n {
        let r = root(&mut parent, i);
        if number[r] == usize::MAX {
            number[r] = next;
            next += 1;
        }
        piece[i] = number[r];
    }
    piece
}

/// The cells joined through their nodes reach every node; else an error naming the
/// smallest node tag of the second piece.
pub(super) fn check_connected(
    n: usize,
    flat: &[usize],
    k: usize,
    tags: &[u64],
    path: &Path,
) -> Result<(), GmshError> {
    let piece = piece_numbers(n, flat, k);
    let pieces = piece.iter().max().map_or(0, |&p| p + 1);
    if pieces <= 1 {
        return Ok(());
    }
    // Nodes are in increasing tag order: the second piece's first node has its smallest tag.
    let second = piece.iter().position(|&p| p == 1).unwrap_or(0);
    Err(GmshError::Disconnected {
        path: path.to_path_buf(),
        pieces,
        first: tags[0],
        node: tags[second],
        size: piece.iter().filter(|&&p| p == 1).count(),
    })
}
