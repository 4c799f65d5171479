//! Meshes: nodes, cells and named node sets.
//!
//! A [`Mesh`] holds the reference (undeformed) coordinates of its nodes, its cells of one
//! kind ([`Cells::Bar2`] in 1D, [`Cells::Tri3`] in 2D) and named node sets that scenarios
//! refer to (`"head"`, `"rim"`, `"centre"`, Gmsh physical groups, ...).
//!
//! Generators build the paper's meshes and graded disks ([`generators`]); [`gmsh`] imports
//! Gmsh `.msh` files; [`quality`](mod@quality) reports a mesh's angles, aspect ratios, boundary and
//! rotational symmetry.

use std::collections::BTreeMap;

pub mod generators;
pub mod gmsh;
pub mod quality;
pub mod zone;

pub use quality::{quality, MeshQuality};

/// The cells of a mesh: one kind of element for the whole mesh.
#[derive(Debug, Clone, PartialEq)]
pub enum Cells {
    /// Two-node bar elements (1D, axial).
    Bar2(Vec<[usize; 2]>),
    /// Three-node triangles (2D), counter-clockwise.
    Tri3(Vec<[usize; 3]>),
}

impl Cells {
    /// Number of cells.
    pub fn len(&self) -> usize {
        match self {
            Cells::Bar2(c) => c.len(),
            Cells::Tri3(c) => c.len(),
        }
    }

    /// True when there are no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
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
        match &self.cells {
            Cells::Bar2(c) => &c[e],
            Cells::Tri3(c) => &c[e],
        }
    }
}
