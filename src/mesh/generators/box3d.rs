//! Structured meshes of the box `[0, lx] x [0, ly] x [0, lz]` for the 3D solids, as flat
//! arrays (not a [`super::Mesh`]): [`box_mesh`]'s boxes: `coords` (`x, y, z` per node) and the cells' node lists.
//!
//! The grid node `(i, j, k)` (`i = 0..=nx` along `x`, ...) has the index
//! `i + (nx + 1) (j + (ny + 1) k)`.
//!
//! - [`box_hex8`]: one hexahedron per grid cell, Gmsh's node order.
//! - [`box_tet4`]: each grid cell cut into six tetrahedra around its diagonal from the
//!   corner `(i, j, k)` to `(i + 1, j + 1, k + 1)` (Kuhn's / Freudenthal's triangulation:
//!   the same cut in every cell, so neighbouring cells meet face to face), all positively
//!   oriented.
//! - [`box_tet10`]: the same tetrahedra with a node at the middle of every edge (numbered
//!   after the grid nodes, in the order the edges are first met), Gmsh's ten-node order.

use super::{box_mesh, MeshError};
use crate::mesh::CellKind;

/// Nodes and cells of a box mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxMesh<const N: usize> {
    /// Coordinates, `[x0, y0, z0, x1, ...]`, m.
    pub coords: Vec<f64>,
    /// The cells' nodes.
    pub cells: Vec<[usize; N]>,
}

impl<const N: usize> BoxMesh<N> {
    /// The number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.coords.len() / 3
    }

    /// The coordinates of node `i`.
    pub fn point(&self, i: usize) -> [f64; 3] {
        [
            self.coords[3 * i],
            self.coords[3 * i + 1],
            self.coords[3 * i + 2],
        ]
    }

    /// The node coordinates of cell `c`.
    pub fn cell_points(&self, c: usize) -> [[f64; 3]; N] {
        self.cells[c].map(|i| self.point(i))
    }
}

/// The box of [`box_mesh`] of `kind` as flat arrays, its cells of `N` nodes.
fn flat<const N: usize>(
    kind: CellKind,
    size: [f64; 3],
    n: [usize; 3],
) -> Result<BoxMesh<N>, MeshError> {
    let m = box_mesh(kind, size, n)?;
    let (cells, rest) = m.cells.connectivity().as_chunks::<N>();
    debug_assert!(rest.is_empty());
    Ok(BoxMesh {
        cells: cells.to_vec(),
        coords: m.coords,
    })
}

/// A box of `nx * ny * nz` equal hexahedra (module docs; [`box_mesh`]'s).
///
/// # Errors
/// [`MeshError`] for a size that is not finite and positive, a zero count, or too many
/// nodes.
pub fn box_hex8(size: [f64; 3], n: [usize; 3]) -> Result<BoxMesh<8>, MeshError> {
    flat(CellKind::Hex8, size, n)
}

/// A box of `6 nx ny nz` four-node tetrahedra (module docs; [`box_mesh`]'s).
///
/// # Errors
/// As [`box_hex8`].
pub fn box_tet4(size: [f64; 3], n: [usize; 3]) -> Result<BoxMesh<4>, MeshError> {
    flat(CellKind::Tet4, size, n)
}

/// A box of `6 nx ny nz` ten-node tetrahedra with straight edges (module docs;
/// [`box_mesh`]'s).
///
/// # Errors
/// As [`box_hex8`].
pub fn box_tet10(size: [f64; 3], n: [usize; 3]) -> Result<BoxMesh<10>, MeshError> {
    flat(CellKind::Tet10, size, n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::tet10::EDGES;
    use crate::element::{hex8, tet10, tet4};
    use std::collections::HashMap;

    #[test]
    fn the_cells_tile_the_box_with_positive_volumes() {
        let (size, n) = ([2.0, 0.5, 0.7], [3, 2, 4]);
        let h = box_hex8(size, n).unwrap();
        let t4 = box_tet4(size, n).unwrap();
        let t10 = box_tet10(size, n).unwrap();
        assert_eq!(h.n_nodes(), 4 * 3 * 5);
        assert_eq!((h.cells.len(), t4.cells.len()), (24, 144));
        let v = 2.0 * 0.5 * 0.7;
        let vh: f64 = (0..h.cells.len())
            .map(|c| hex8::geometry(&h.cell_points(c)).unwrap().volume)
            .sum();
        let v4: f64 = (0..t4.cells.len())
            .map(|c| tet4::geometry(&t4.cell_points(c)).unwrap().volume)
            .sum();
        let v10: f64 = (0..t10.cells.len())
            .map(|c| {
                let g = tet10::geometry(&t10.cell_points(c)).unwrap();
                assert!(!g.curved);
                g.volume
            })
            .sum();
        for got in [vh, v4, v10] {
            assert!((got - v).abs() < 1e-13, "{got} vs {v}");
        }
        // Conformity of the tetrahedra: every triangular face is shared by two cells or
        // lies on the boundary of the box.
        let mut faces: HashMap<[usize; 3], usize> = HashMap::new();
        for t in &t4.cells {
            for skip in 0..4 {
                let mut f = [0; 3];
                let mut m = 0;
                for (l, &node) in t.iter().enumerate() {
                    if l != skip {
                        f[m] = node;
                        m += 1;
                    }
                }
                f.sort_unstable();
                *faces.entry(f).or_insert(0) += 1;
            }
        }
        for (f, count) in faces {
            let on_boundary = (0..3).any(|q| {
                let vals = f.map(|i| t4.point(i)[q]);
                vals.iter().all(|&x| x == 0.0) || vals.iter().all(|&x| x == size[q])
            });
            assert!(count == 2 || (count == 1 && on_boundary), "{f:?} {count}");
        }
        // Mid-edge nodes: one per distinct edge (Euler: E = V + F_cells - ..., counted
        // here directly).
        let mut edges = std::collections::HashSet::new();
        for t in &t4.cells {
            for [a, b] in EDGES {
                edges.insert((t[a].min(t[b]), t[a].max(t[b])));
            }
        }
        assert_eq!(t10.n_nodes(), h.n_nodes() + edges.len());
    }

    #[test]
    fn bad_arguments_are_errors() {
        assert!(matches!(
            box_hex8([0.0, 1.0, 1.0], [1, 1, 1]),
            Err(MeshError::InvalidLength { name: "lx", .. })
        ));
        assert!(matches!(
            box_tet4([1.0, 1.0, 1.0], [1, 0, 1]),
            Err(MeshError::InvalidCount { name: "ny", .. })
        ));
        assert!(matches!(
            box_tet10([1.0, 1.0, 1.0], [100_000, 100_000, 100_000]),
            Err(MeshError::TooLarge { .. })
        ));
    }
}
