//! Structured meshes of a box `[0, lx] x [0, ly] x [0, lz]` in 3D: hexahedra, or each
//! hexahedron cut into six tetrahedra along its main diagonal (Kuhn's subdivision, which
//! is conforming across neighbours because every cell is cut the same way), linear or with
//! mid-edge nodes ([`quadratic_tetrahedra`]).
//!
//! Node `(i, j, k)` is `i + (nx + 1) (j + (ny + 1) k)`; node sets `"x0"`, `"x1"`, `"y0"`,
//! `"y1"`, `"z0"`, `"z1"` (the faces) and `"all"`.

use std::collections::{BTreeMap, HashMap};

use super::{check_count, check_length, check_nodes, MeshError};
use crate::mesh::{CellKind, Cells, Mesh};

/// The six tetrahedra of the unit cube's corners (bits `x + 2 y + 4 z`): the paths from
/// corner 0 to corner 7 along the axes in each order, each turned positive.
const KUHN: [[usize; 4]; 6] = [
    [0, 1, 3, 7],
    [0, 3, 2, 7],
    [0, 2, 6, 7],
    [0, 6, 4, 7],
    [0, 4, 5, 7],
    [0, 5, 1, 7],
];

/// A structured annulus of hexahedra about the `z` axis: radii `bore..radius` in `nr`
/// rings, `nt` sectors round it, the thickness `t` in `nz` layers from `z = 0`. Node
/// `(i, j, k)` (ring boundary `i`, sector boundary `j`, layer boundary `k`) is
/// `i + (nr + 1) (j + nt k)`, at radius `bore + (radius - bore) i / nr` and angle
/// `2 pi j / nt`; `(r, theta, z)` is right-handed, so the cells have positive volume.
/// Node sets `"bore"` (`i = 0`), `"rim"` (`i = nr`, ordered by `j` then `k`) and `"all"`.
///
/// # Errors
/// [`MeshError`] for a length that is not finite and positive, a bore not inside the
/// radius, a count of zero (fewer than 3 sectors), or too many nodes.
pub fn annulus_hex8(
    bore: f64,
    radius: f64,
    thickness: f64,
    [nr, nt, nz]: [usize; 3],
) -> Result<Mesh, MeshError> {
    for (name, l) in [("bore", bore), ("radius", radius), ("thickness", thickness)] {
        check_length(name, l)?;
    }
    if bore >= radius {
        return Err(MeshError::OutOfRange {
            name: "bore (a share of the radius)",
            value: bore / radius,
            min: 0.0,
            max: 1.0,
        });
    }
    for (name, n) in [("rings", nr), ("layers", nz)] {
        check_count(name, n)?;
    }
    if nt < 3 {
        return Err(MeshError::CountBelow {
            name: "sectors",
            value: nt,
            min: 3,
        });
    }
    check_nodes(
        "sectors",
        nt,
        (nr + 1).checked_mul(nt).and_then(|n| n.checked_mul(nz + 1)),
    )?;
    let radii: Vec<f64> = (0..=nr)
        .map(|i| bore + (radius - bore) * i as f64 / nr as f64)
        .collect();
    let angles: Vec<f64> = (0..nt)
        .map(|j| 2.0 * std::f64::consts::PI * j as f64 / nt as f64)
        .collect();
    let zs: Vec<f64> = (0..=nz).map(|k| thickness * k as f64 / nz as f64).collect();
    swept_annulus_hex8(&radii, &angles, &zs)
}

/// An annulus of hexahedra about the `z` axis swept through the ring radii `radii`
/// (increasing, from the bore to the rim) and the angular stations `angles` (increasing,
/// within one turn: the last sector closes back to the first station) and the layers'
/// boundaries `zs` along the axle (increasing). Node `(i, j, k)` (radius `i`, station `j`,
/// layer boundary `k`) is `i + (nr + 1) (j + nt k)` with `nr + 1 = radii.len()`,
/// `nt = angles.len()`; node sets `"bore"`, `"rim"` (ordered by `j` then `k`) and `"all"`,
/// as [`annulus_hex8`], which is this mesh at equal rings and stations. The moving refined
/// zone's wheel ([`crate::mesh::zone3d`]) has its stations fine under the base.
///
/// # Errors
/// [`MeshError`] for radii or stations that are not finite and increasing (at least two
/// radii from a positive bore, three stations within one turn, two layer boundaries), or
/// too many nodes.
pub fn swept_annulus_hex8(radii: &[f64], angles: &[f64], zs: &[f64]) -> Result<Mesh, MeshError> {
    let increasing =
        |v: &[f64]| v.windows(2).all(|w| w[1] > w[0]) && v.iter().all(|x| x.is_finite());
    if zs.len() < 2 || !increasing(zs) {
        return Err(MeshError::CountBelow {
            name: "layer boundaries along the axle (increasing)",
            value: zs.len(),
            min: 2,
        });
    }
    let nz = zs.len() - 1;
    if radii.len() < 2 || !increasing(radii) || radii[0] <= 0.0 {
        return Err(MeshError::CountBelow {
            name: "ring radii (increasing, from a bore > 0)",
            value: radii.len(),
            min: 2,
        });
    }
    let turn = 2.0 * std::f64::consts::PI;
    if angles.len() < 3 || !increasing(angles) || angles[angles.len() - 1] - angles[0] >= turn {
        return Err(MeshError::CountBelow {
            name: "angular stations (increasing, within one turn)",
            value: angles.len(),
            min: 3,
        });
    }
    let (nr, nt) = (radii.len() - 1, angles.len());
    check_nodes(
        "sectors",
        nt,
        (nr + 1).checked_mul(nt).and_then(|n| n.checked_mul(nz + 1)),
    )?;
    let id = |i: usize, j: usize, k: usize| i + (nr + 1) * ((j % nt) + nt * k);
    let mut coords = Vec::with_capacity(3 * (nr + 1) * nt * (nz + 1));
    for &z in zs {
        for &th in angles {
            for &r in radii {
                coords.extend([r * th.cos(), r * th.sin(), z]);
            }
        }
    }
    let mut hexes = Vec::with_capacity(nr * nt * nz);
    for k in 0..nz {
        for j in 0..nt {
            for i in 0..nr {
                hexes.push([
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ]);
            }
        }
    }
    let ring = |i: usize| -> Vec<usize> {
        (0..=nz)
            .flat_map(|k| (0..nt).map(move |j| (j, k)))
            .map(|(j, k)| id(i, j, k))
            .collect()
    };
    let mut sets = BTreeMap::new();
    sets.insert("bore".to_string(), ring(0));
    sets.insert("rim".to_string(), ring(nr));
    sets.insert("all".to_string(), (0..coords.len() / 3).collect());
    Ok(Mesh::new(3, coords, Cells::Hex8(hexes), sets))
}

/// A box of `nx x ny x nz` cells of `kind` ([`CellKind::Hex8`], [`CellKind::Tet4`] or
/// [`CellKind::Tet10`]).
///
/// # Errors
/// [`MeshError`] for a length that is not finite and positive, a zero count, too many
/// nodes, or a kind that is not a solid ([`MeshError::OutOfRange`] naming `kind`).
pub fn box_mesh(kind: CellKind, lengths: [f64; 3], counts: [usize; 3]) -> Result<Mesh, MeshError> {
    for (name, l) in ["lx", "ly", "lz"].into_iter().zip(lengths) {
        check_length(name, l)?;
    }
    for (name, n) in ["nx", "ny", "nz"].into_iter().zip(counts) {
        check_count(name, n)?;
    }
    if kind.dim() != 3 {
        return Err(MeshError::OutOfRange {
            name: "kind (a solid: tetrahedra or hexahedra)",
            value: kind.dim() as f64,
            min: 3.0,
            max: 3.0,
        });
    }
    let [nx, ny, nz] = counts;
    let nodes = (nx + 1)
        .checked_mul(ny + 1)
        .and_then(|a| a.checked_mul(nz + 1));
    // Room for the 10-node tetrahedra's mid-edge nodes (fewer than 7 per grid node).
    let room = if kind == CellKind::Tet10 { 8 } else { 1 };
    check_nodes(
        "nx * ny * nz",
        nx.max(ny).max(nz),
        nodes.and_then(|n| n.checked_mul(room)),
    )?;
    let n_nodes = nodes.unwrap_or(0);
    let coord = |i: usize, n: usize, l: f64| if i == n { l } else { l * i as f64 / n as f64 };
    let id = |i: usize, j: usize, k: usize| i + (nx + 1) * (j + (ny + 1) * k);
    let mut coords = Vec::with_capacity(3 * n_nodes);
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                coords.extend([
                    coord(i, nx, lengths[0]),
                    coord(j, ny, lengths[1]),
                    coord(k, nz, lengths[2]),
                ]);
            }
        }
    }
    let mut hexes = Vec::with_capacity(nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                hexes.push([
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ]);
            }
        }
    }
    let mut sets = BTreeMap::new();
    let face = |axis: usize, at: usize| -> Vec<usize> {
        let mut v: Vec<usize> = (0..=nz)
            .flat_map(|k| (0..=ny).flat_map(move |j| (0..=nx).map(move |i| (i, j, k))))
            .filter(|&(i, j, k)| [i, j, k][axis] == at)
            .map(|(i, j, k)| id(i, j, k))
            .collect();
        v.sort_unstable();
        v
    };
    for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
        sets.insert(format!("{name}0"), face(axis, 0));
        sets.insert(format!("{name}1"), face(axis, counts[axis]));
    }
    sets.insert("all".to_string(), (0..n_nodes).collect());
    let mesh = Mesh::new(3, coords, Cells::Hex8(hexes), sets);
    Ok(match kind {
        CellKind::Hex8 => mesh,
        CellKind::Tet4 => tetrahedra(&mesh),
        _ => quadratic_tetrahedra(&tetrahedra(&mesh)),
    })
}

/// Each hexahedron of a mesh of [`Cells::Hex8`] cut into Kuhn's six tetrahedra (module
/// docs); any other mesh unchanged.
pub fn tetrahedra(mesh: &Mesh) -> Mesh {
    let Cells::Hex8(hexes) = &mesh.cells else {
        return mesh.clone();
    };
    // Hex8's local order (0-1-2-3 bottom, 4-5-6-7 top) by the corner bits x + 2 y + 4 z.
    const BY_BITS: [usize; 8] = [0, 1, 3, 2, 4, 5, 7, 6];
    let tets = hexes
        .iter()
        .flat_map(|h| KUHN.map(|t| t.map(|b| h[BY_BITS[b]])))
        .collect();
    let mut m = Mesh::new(
        3,
        mesh.coords.clone(),
        Cells::Tet4(tets),
        mesh.node_sets.clone(),
    );
    orient_tetrahedra(&mut m);
    m
}

/// Swaps two corners of every negatively oriented 4-node tetrahedron of `mesh`.
fn orient_tetrahedra(mesh: &mut Mesh) {
    let coords = mesh.coords.clone();
    let x = |i: usize| [coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]];
    if let Cells::Tet4(tets) = &mut mesh.cells {
        for t in tets.iter_mut() {
            let [a, b, c, d] = t.map(x);
            let e = |p: [f64; 3]| [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
            let (u, v, w) = (e(b), e(c), e(d));
            let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                + u[2] * (v[0] * w[1] - v[1] * w[0]);
            if det < 0.0 {
                t.swap(2, 3);
            }
        }
    }
}

/// A mesh of 4-node tetrahedra with a node added at the middle of every edge, shared by the
/// cells around it: 10-node tetrahedra in Gmsh's order ([`Cells::Tet10`]); the new nodes
/// join no node set but `"all"`. Any other mesh unchanged.
pub fn quadratic_tetrahedra(mesh: &Mesh) -> Mesh {
    let Cells::Tet4(tets) = &mesh.cells else {
        return mesh.clone();
    };
    const EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [2, 3], [1, 3]];
    let mut coords = mesh.coords.clone();
    let mut mid: HashMap<(usize, usize), usize> = HashMap::new();
    let mut cells = Vec::with_capacity(tets.len());
    for t in tets {
        let mut c = [0; 10];
        c[..4].copy_from_slice(t);
        for (k, [a, b]) in EDGES.into_iter().enumerate() {
            let (a, b) = (t[a], t[b]);
            c[4 + k] = *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let n = coords.len() / 3;
                for d in 0..3 {
                    coords.push(0.5 * (mesh.coords[3 * a + d] + mesh.coords[3 * b + d]));
                }
                n
            });
        }
        cells.push(c);
    }
    // A mid-edge node lies on a face (a named set of the linear mesh's nodes, all on one
    // plane) when both its edge's ends do.
    let mut sets = mesh.node_sets.clone();
    for (name, set) in sets.iter_mut() {
        if name == "all" {
            *set = (0..coords.len() / 3).collect();
            continue;
        }
        let ends = set.clone();
        let has = |i: usize| ends.binary_search(&i).is_ok();
        set.extend(
            mid.iter()
                .filter(|((a, b), _)| has(*a) && has(*b))
                .map(|(_, &m)| m),
        );
        set.sort_unstable();
    }
    Mesh::new(3, coords, Cells::Tet10(cells), sets)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::quality;

    /// Every node on a face of the box is in the face's set, the mid-edge nodes of the
    /// ten-node tetrahedra included, and no other node is.
    #[test]
    fn the_face_sets_hold_every_node_on_their_face() {
        let (l, n) = ([0.3, 0.2, 0.1], [3, 2, 2]);
        for kind in [CellKind::Hex8, CellKind::Tet4, CellKind::Tet10] {
            let m = box_mesh(kind, l, n).unwrap();
            for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
                for (end, at) in [(0, 0.0), (1, l[axis])] {
                    let set = &m.node_sets[&format!("{name}{end}")];
                    let on: Vec<usize> = (0..m.n_nodes())
                        .filter(|&i| (m.point(i)[axis] - at).abs() < 1e-12)
                        .collect();
                    assert_eq!(set, &on, "{kind:?} {name}{end}");
                }
            }
            assert_eq!(m.node_sets["all"].len(), m.n_nodes());
        }
    }

    /// Every kind fills the box's volume exactly with positively oriented cells, and the
    /// tetrahedra share their faces (each interior face twice, opposite in orientation).
    #[test]
    fn boxes_fill_their_volume_with_positive_conforming_cells() {
        let (l, n) = ([0.3, 0.2, 0.1], [3, 2, 2]);
        for kind in [CellKind::Hex8, CellKind::Tet4, CellKind::Tet10] {
            let m = box_mesh(kind, l, n).unwrap();
            let q = quality(&m);
            let cells = 12 * if kind == CellKind::Hex8 { 1 } else { 6 };
            assert_eq!(
                (q.solids, q.inverted, q.degenerate),
                (cells, 0, 0),
                "{kind:?}"
            );
            assert!((q.volume - 0.006).abs() < 1e-15, "{kind:?}: {}", q.volume);
        }
        // Conforming: every triangular face of the tetrahedra is met once (on the boundary:
        // 2 per boundary square) or twice (inside).
        let m = box_mesh(CellKind::Tet4, l, n).unwrap();
        let mut faces: HashMap<[usize; 3], usize> = HashMap::new();
        for t in m.cells.connectivity().chunks_exact(4) {
            for skip in 0..4 {
                let mut f: Vec<usize> = (0..4).filter(|&k| k != skip).map(|k| t[k]).collect();
                f.sort_unstable();
                *faces.entry([f[0], f[1], f[2]]).or_insert(0) += 1;
            }
        }
        let boundary = faces.values().filter(|&&c| c == 1).count();
        assert!(faces.values().all(|&c| c == 1 || c == 2));
        assert_eq!(boundary, 2 * 2 * (3 * 2 + 3 * 2 + 2 * 2));
        // The 10-node mesh: one node per edge, at its middle.
        let q = box_mesh(CellKind::Tet10, l, n).unwrap();
        for c in q.cells.connectivity().chunks_exact(10) {
            let p = |i: usize| q.point(i);
            let (a, b, m) = (p(c[2]), p(c[3]), p(c[8]));
            assert!((0..3).all(|d| (0.5 * (a[d] + b[d]) - m[d]).abs() < 1e-15));
        }
    }

    /// A bad argument is named.
    #[test]
    fn bad_box_arguments_are_named() {
        let e = box_mesh(CellKind::Hex8, [1.0, -1.0, 1.0], [1, 1, 1]).unwrap_err();
        assert!(e.to_string().contains("`ly`"), "{e}");
        let e = box_mesh(CellKind::Tet4, [1.0; 3], [1, 0, 1]).unwrap_err();
        assert!(e.to_string().contains("`ny`"), "{e}");
        let e = box_mesh(CellKind::Tri3, [1.0; 3], [1, 1, 1]).unwrap_err();
        assert!(e.to_string().contains("kind"), "{e}");
    }
}
