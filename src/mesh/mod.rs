//! Meshes: nodes, cells and named node sets.
//!
//! A [`Mesh`] holds the reference (undeformed) coordinates of its nodes, its cells of one
//! kind ([`Cells::Bar2`] in 1D, [`Cells::Tri3`] in 2D, [`Cells::Tet4`], [`Cells::Tet10`] or
//! [`Cells::Hex8`] in 3D) and named node sets that scenarios refer to (`"head"`, `"rim"`,
//! `"centre"`, Gmsh physical groups, ...). The dimension is the mesh's parameter
//! ([`Mesh::dim`]); what a cell kind is (its dimension, node count, VTK and Gmsh codes) is
//! [`CellKind`]'s, so the layers above (assembly, output, checks) ask the cells rather than
//! assume triangles.
//!
//! Generators build the paper's meshes and graded disks ([`generators`]); [`gmsh`] imports
//! Gmsh `.msh` files; [`quality`](mod@quality) reports a mesh's angles, aspect ratios, boundary and
//! rotational symmetry.

use std::collections::BTreeMap;

pub mod generators;
pub mod gmsh;
pub mod profiles;
pub mod quality;
pub mod zone;
pub mod zone3d;

pub use quality::{quality, MeshQuality};

/// The cells of a mesh: one kind of element for the whole mesh.
///
/// Node orders are Gmsh's (which VTK's linear cells share; [`CellKind::vtk_order`] maps the
/// 10-node tetrahedron's).
#[derive(Debug, Clone, PartialEq)]
pub enum Cells {
    /// Two-node bar elements (1D, axial).
    Bar2(Vec<[usize; 2]>),
    /// Three-node triangles (2D), counter-clockwise.
    Tri3(Vec<[usize; 3]>),
    /// Four-node tetrahedra (3D), positively oriented: `(x1 - x0) . ((x2 - x0) x (x3 - x0)) > 0`.
    Tet4(Vec<[usize; 4]>),
    /// Ten-node tetrahedra (3D): the corners as [`Cells::Tet4`], then the mid-edge nodes of
    /// the edges 0-1, 1-2, 2-0, 0-3, 2-3, 1-3 (Gmsh's order).
    Tet10(Vec<[usize; 10]>),
    /// Eight-node hexahedra (3D): the bottom face 0-1-2-3 counter-clockwise seen from the
    /// top, then the top face 4-5-6-7 above it (Gmsh's and VTK's order).
    Hex8(Vec<[usize; 8]>),
}

/// What a kind of cell is: its dimension, nodes and codes in the file formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CellKind {
    /// [`Cells::Bar2`].
    Bar2,
    /// [`Cells::Tri3`].
    Tri3,
    /// [`Cells::Tet4`].
    Tet4,
    /// [`Cells::Tet10`].
    Tet10,
    /// [`Cells::Hex8`].
    Hex8,
}

impl CellKind {
    /// Every kind, in order of dimension.
    pub const ALL: [CellKind; 5] = [
        CellKind::Bar2,
        CellKind::Tri3,
        CellKind::Tet4,
        CellKind::Tet10,
        CellKind::Hex8,
    ];

    /// The dimension of the cell (and of a mesh of such cells).
    pub fn dim(self) -> usize {
        match self {
            CellKind::Bar2 => 1,
            CellKind::Tri3 => 2,
            CellKind::Tet4 | CellKind::Tet10 | CellKind::Hex8 => 3,
        }
    }

    /// Nodes per cell.
    pub fn nodes(self) -> usize {
        match self {
            CellKind::Bar2 => 2,
            CellKind::Tri3 => 3,
            CellKind::Tet4 => 4,
            CellKind::Tet10 => 10,
            CellKind::Hex8 => 8,
        }
    }

    /// Gmsh's element type number (`.msh` 4.1, "elementType").
    pub fn gmsh_type(self) -> i32 {
        match self {
            CellKind::Bar2 => 1,
            CellKind::Tri3 => 2,
            CellKind::Tet4 => 4,
            CellKind::Tet10 => 11,
            CellKind::Hex8 => 5,
        }
    }

    /// The kind of Gmsh's element type `t`, if softway has it.
    pub fn from_gmsh_type(t: i32) -> Option<CellKind> {
        CellKind::ALL.into_iter().find(|k| k.gmsh_type() == t)
    }

    /// VTK's node `k` of a cell is the mesh's node `vtk_order()[k]` of it. Gmsh and VTK
    /// agree but for the 10-node tetrahedron, whose last two mid-edge nodes (edges 2-3 and
    /// 1-3 in Gmsh, 1-3 and 2-3 in VTK) swap.
    pub fn vtk_order(self) -> &'static [usize] {
        match self {
            CellKind::Bar2 => &[0, 1],
            CellKind::Tri3 => &[0, 1, 2],
            CellKind::Tet4 => &[0, 1, 2, 3],
            CellKind::Tet10 => &[0, 1, 2, 3, 4, 5, 6, 7, 9, 8],
            CellKind::Hex8 => &[0, 1, 2, 3, 4, 5, 6, 7],
        }
    }

    /// A short name for messages (`"3-node triangles"`).
    pub fn describe(self) -> &'static str {
        match self {
            CellKind::Bar2 => "2-node bars",
            CellKind::Tri3 => "3-node triangles",
            CellKind::Tet4 => "4-node tetrahedra",
            CellKind::Tet10 => "10-node tetrahedra",
            CellKind::Hex8 => "8-node hexahedra",
        }
    }
}

impl Cells {
    /// The kind of the cells.
    pub fn kind(&self) -> CellKind {
        match self {
            Cells::Bar2(_) => CellKind::Bar2,
            Cells::Tri3(_) => CellKind::Tri3,
            Cells::Tet4(_) => CellKind::Tet4,
            Cells::Tet10(_) => CellKind::Tet10,
            Cells::Hex8(_) => CellKind::Hex8,
        }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.connectivity().len() / self.kind().nodes()
    }

    /// True when there are no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The nodes of every cell, cell after cell ([`CellKind::nodes`] each).
    pub fn connectivity(&self) -> &[usize] {
        match self {
            Cells::Bar2(c) => c.as_flattened(),
            Cells::Tri3(c) => c.as_flattened(),
            Cells::Tet4(c) => c.as_flattened(),
            Cells::Tet10(c) => c.as_flattened(),
            Cells::Hex8(c) => c.as_flattened(),
        }
    }

    /// The nodes of every cell, mutable (to renumber them).
    pub fn connectivity_mut(&mut self) -> &mut [usize] {
        match self {
            Cells::Bar2(c) => c.as_flattened_mut(),
            Cells::Tri3(c) => c.as_flattened_mut(),
            Cells::Tet4(c) => c.as_flattened_mut(),
            Cells::Tet10(c) => c.as_flattened_mut(),
            Cells::Hex8(c) => c.as_flattened_mut(),
        }
    }

    /// Cells of `kind` from a flat connectivity ([`CellKind::nodes`] per cell).
    ///
    /// # Panics
    /// If `flat.len()` is not a whole number of cells.
    pub fn from_flat(kind: CellKind, flat: &[usize]) -> Cells {
        fn chunks<const K: usize>(flat: &[usize]) -> Vec<[usize; K]> {
            let (cells, rest) = flat.as_chunks::<K>();
            assert!(
                rest.is_empty(),
                "{} nodes are not whole cells of {K}",
                flat.len()
            );
            cells.to_vec()
        }
        match kind {
            CellKind::Bar2 => Cells::Bar2(chunks(flat)),
            CellKind::Tri3 => Cells::Tri3(chunks(flat)),
            CellKind::Tet4 => Cells::Tet4(chunks(flat)),
            CellKind::Tet10 => Cells::Tet10(chunks(flat)),
            CellKind::Hex8 => Cells::Hex8(chunks(flat)),
        }
    }
}

/// A finite element mesh; its dimension is a parameter.
///
/// The reference coordinates are flat with the dimension as stride: node `i` is
/// `coords[dim * i..dim * (i + 1)]` ([`Mesh::point`]), which is also the layout of the
/// degrees of freedom (node `i`, component `c` is `dim * i + c`).
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Spatial dimension: 1 (bars) or 2 (triangles); the stride of [`Mesh::coords`].
    pub dim: usize,
    /// Reference coordinates of the nodes, in m, `dim` per node (node by node).
    pub coords: Vec<f64>,
    /// The cells.
    pub cells: Cells,
    /// Named node sets (sorted node indices, no repeats).
    pub node_sets: BTreeMap<String, Vec<usize>>,
}

impl Mesh {
    /// A mesh of dimension `dim` with the flat coordinates `coords` (`dim` per node).
    ///
    /// # Panics
    /// If `dim` is zero or `coords.len()` is not a multiple of `dim`.
    pub fn new(
        dim: usize,
        coords: Vec<f64>,
        cells: Cells,
        node_sets: BTreeMap<String, Vec<usize>>,
    ) -> Mesh {
        assert!(
            dim >= 1 && coords.len() % dim == 0,
            "{} coordinates are not a whole number of nodes of dimension {dim}",
            coords.len()
        );
        Mesh {
            dim,
            coords,
            cells,
            node_sets,
        }
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.coords.len() / self.dim
    }

    /// Number of degrees of freedom (`dim` per node; node `i`, component `c` is `dim*i + c`).
    pub fn n_dofs(&self) -> usize {
        self.dim * self.n_nodes()
    }

    /// Reference coordinates of node `i` (`dim` of them), in m.
    ///
    /// # Panics
    /// If `i >= n_nodes()`.
    pub fn point(&self, i: usize) -> &[f64] {
        &self.coords[self.dim * i..self.dim * (i + 1)]
    }

    /// Reference coordinates of every node, in node order (`dim` each).
    pub fn points(&self) -> impl ExactSizeIterator<Item = &[f64]> + '_ {
        self.coords.chunks_exact(self.dim)
    }

    /// The node set of that name, if any.
    pub fn node_set(&self, name: &str) -> Option<&[usize]> {
        self.node_sets.get(name).map(|v| v.as_slice())
    }

    /// Reference coordinates as a flat vector of length [`Mesh::n_dofs`] (the coordinates).
    pub fn reference_positions(&self) -> Vec<f64> {
        self.coords.clone()
    }

    /// Node indices of each cell, as slices.
    pub fn cell_nodes(&self, e: usize) -> &[usize] {
        let k = self.cells.kind().nodes();
        &self.cells.connectivity()[k * e..k * (e + 1)]
    }
}
