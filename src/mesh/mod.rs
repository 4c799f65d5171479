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

/// A finite element mesh in 1D or 2D.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Spatial dimension: 1 (bars, `y` unused and zero) or 2 (triangles).
    pub dim: usize,
    /// Reference coordinates of the nodes, in m. In 1D only `[0]` is used.
    pub points: Vec<[f64; 2]>,
    /// The cells.
    pub cells: Cells,
    /// Named node sets (sorted node indices, no repeats).
    pub node_sets: BTreeMap<String, Vec<usize>>,
}

impl Mesh {
    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.points.len()
    }

    /// Number of degrees of freedom (`dim` per node; node `i`, component `c` is `dim*i + c`).
    pub fn n_dofs(&self) -> usize {
        self.dim * self.points.len()
    }

    /// The node set of that name, if any.
    pub fn node_set(&self, name: &str) -> Option<&[usize]> {
        self.node_sets.get(name).map(|v| v.as_slice())
    }

    /// Reference coordinates as a flat vector of length [`Mesh::n_dofs`].
    pub fn reference_positions(&self) -> Vec<f64> {
        let mut x = Vec::with_capacity(self.n_dofs());
        for p in &self.points {
            x.extend_from_slice(&p[..self.dim]);
        }
        x
    }

    /// Node indices of each cell, as slices.
    pub fn cell_nodes(&self, e: usize) -> &[usize] {
        match &self.cells {
            Cells::Bar2(c) => &c[e],
            Cells::Tri3(c) => &c[e],
        }
    }
}
