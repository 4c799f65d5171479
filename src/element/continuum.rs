//! The contract of a continuum element: what the generic layers (assembly, a body of any
//! dimension, stresses for output) need of an element kind, whatever its dimension and
//! node count (MFEM's `FiniteElement` with its `BilinearFormIntegrator`s, fenris's element
//! and operator traits, in one small trait).
//!
//! A kind implements [`Continuum<N>`] (`N = dim * nodes` dofs per cell) over the cells of
//! its [`CellKind`]: the geometry of a cell from its nodes' coordinates (computed once per
//! mesh, refusing an inverted or degenerate cell), its mass and stiffness into a buffer
//! the caller owns, and its stress from the cell's displacements. Its value carries what
//! the kernel needs beyond the cell (the elasticity matrix, the thickness of a plane
//! element). The operators [`ContinuumMass`] and [`ContinuumStiffness`] turn it into
//! [`ElementMatrix`] operators on a mesh's [`Assembler`]; [`assemble_continuum`] builds a
//! mesh's mass and stiffness; [`CellStresses`] is the object-safe view a body keeps for
//! its output.
//!
//! Implemented here for the plane triangle ([`PlaneTri3`], [`super::tri3`]) and the solids
//! ([`SolidTet4`], [`SolidTet10`], [`SolidHex8`] over [`super::tet4`], [`super::tet10`],
//! [`super::hex8`]); a body of any of them ([`crate::bodies::solid`]) goes through the same
//! assembly, contact rows and output.

use crate::assembly::{Assembler, ElementMatrix};
use crate::mesh::{CellKind, Mesh};

use super::tri3::{self, Tri3Geometry};

/// A cell that cannot be an element: the mesh's cell index, its nodes and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CellError {
    /// The cell is inverted or degenerate (the kernel's message).
    #[error("cell {cell} (nodes {nodes:?}): {message}")]
    Geometry {
        /// The cell.
        cell: usize,
        /// Its nodes.
        nodes: Vec<usize>,
        /// What the kernel found.
        message: String,
    },
    /// The mesh's cells or dimension are not the element's.
    #[error("the element takes a {dim}D mesh of {expected}, not a {got_dim}D mesh of {got}")]
    WrongCells {
        /// The element's cells.
        expected: &'static str,
        /// Its dimension.
        dim: usize,
        /// The mesh's cells.
        got: &'static str,
        /// The mesh's dimension.
        got_dim: usize,
    },
}

/// A continuum element kind with `N` dofs per cell (module docs).
pub trait Continuum<const N: usize>: Sync {
    /// What a cell's kernels need of its shape, computed once ([`Continuum::geometry`]).
    type Geometry: Send + Sync + Clone + std::fmt::Debug;

    /// The cells the element runs on (`N = kind.dim() * kind.nodes()`).
    const KIND: CellKind;

    /// Stress components per cell (Voigt: `[sxx, syy, txy]` in the plane,
    /// `[sxx, syy, szz, tyz, txz, txy]` in 3D).
    const STRESSES: usize;

    /// The geometry of a cell whose nodes are at `x` (flat, `dim` per node, in the cell's
    /// node order).
    ///
    /// # Errors
    /// A message saying why the cell is inverted or degenerate.
    fn geometry(&self, x: &[f64]) -> Result<Self::Geometry, String>;

    /// The cell's mass matrix at `density` (consistent or `lumped`) into `out`; `density`
    /// may also be the damping `eta_z` of the paper's Eq. 22, which has the mass's shape.
    fn mass_into(&self, g: &Self::Geometry, density: f64, lumped: bool, out: &mut [[f64; N]; N]);

    /// The cell's elastic stiffness matrix into `out`.
    fn stiffness_into(&self, g: &Self::Geometry, out: &mut [[f64; N]; N]);

    /// The cell's stress ([`Continuum::STRESSES`] components, its mean over the cell) under
    /// the cell's displacements `u` (node after node, `dim` each) into `out`.
    fn stress_into(&self, g: &Self::Geometry, u: &[f64; N], out: &mut [f64]);
}

/// The geometry of every cell of `mesh` for the element `el`.
///
/// # Errors
/// [`CellError::WrongCells`] when the mesh is not of the element's cells and dimension,
/// [`CellError::Geometry`] naming the first cell that is inverted or degenerate.
pub fn geometries<E: Continuum<N>, const N: usize>(
    mesh: &Mesh,
    el: &E,
) -> Result<Vec<E::Geometry>, CellError> {
    let kind = mesh.cells.kind();
    if kind != E::KIND || mesh.dim != E::KIND.dim() {
        return Err(CellError::WrongCells {
            expected: E::KIND.describe(),
            dim: E::KIND.dim(),
            got: kind.describe(),
            got_dim: mesh.dim,
        });
    }
    let mut x = Vec::with_capacity(N);
    let per = kind.nodes();
    mesh.cells
        .connectivity()
        .chunks_exact(per)
        .enumerate()
        .map(|(cell, nodes)| {
            x.clear();
            for &i in nodes {
                x.extend_from_slice(mesh.point(i));
            }
            el.geometry(&x).map_err(|message| CellError::Geometry {
                cell,
                nodes: nodes.to_vec(),
                message,
            })
        })
        .collect()
}

/// The mass (or the mass-shaped damping) of the cells of `geometry` as an [`ElementMatrix`].
#[derive(Debug, Clone, Copy)]
pub struct ContinuumMass<'a, E: Continuum<N>, const N: usize> {
    /// The element.
    pub element: &'a E,
    /// One geometry per cell.
    pub geometry: &'a [E::Geometry],
    /// Mass per unit volume, kg/m^3 (or the damping `eta_z`).
    pub density: f64,
    /// Lumped (`true`) or consistent.
    pub lumped: bool,
}

impl<E: Continuum<N>, const N: usize> ElementMatrix<N> for ContinuumMass<'_, E, N> {
    fn element_matrix_into(&self, e: usize, out: &mut [[f64; N]; N]) {
        self.element
            .mass_into(&self.geometry[e], self.density, self.lumped, out);
    }
}

/// The elastic stiffness of the cells of `geometry` as an [`ElementMatrix`].
#[derive(Debug, Clone, Copy)]
pub struct ContinuumStiffness<'a, E: Continuum<N>, const N: usize> {
    /// The element.
    pub element: &'a E,
    /// One geometry per cell.
    pub geometry: &'a [E::Geometry],
}

impl<E: Continuum<N>, const N: usize> ElementMatrix<N> for ContinuumStiffness<'_, E, N> {
    fn element_matrix_into(&self, e: usize, out: &mut [[f64; N]; N]) {
        self.element.stiffness_into(&self.geometry[e], out);
    }
}

/// A mesh of one continuum element, assembled: its pattern, geometry, mass and stiffness.
#[derive(Debug, Clone)]
pub struct Assembled<G> {
    /// The mesh's pattern ([`Assembler::new`]).
    pub assembler: Assembler,
    /// One geometry per cell.
    pub geometry: Vec<G>,
    /// The mass matrix, on the pattern.
    pub m: Vec<f64>,
    /// The stiffness matrix, on the pattern.
    pub k: Vec<f64>,
}

/// The mass (at `density`, consistent or `lumped`) and stiffness of `mesh` with the element
/// `el`.
///
/// # Errors
/// [`CellError`] from [`geometries`].
pub fn assemble_continuum<E: Continuum<N>, const N: usize>(
    mesh: &Mesh,
    el: &E,
    density: f64,
    lumped: bool,
) -> Result<Assembled<E::Geometry>, CellError> {
    assemble_continuum_shaped(mesh, mesh, el, density, lumped)
}

/// [`assemble_continuum`] on `mesh`'s nodes and cells with each cell's geometry taken from
/// the same cell of `shape`: a mesh closed on itself (a rail whose ends are joined), whose
/// cells across the seam name the first station's nodes, is shaped by the open mesh it was
/// closed from (the same cells in the same order, the last station not yet merged).
///
/// # Errors
/// As [`assemble_continuum`], or [`CellError::WrongCells`] when `shape` has another count
/// or kind of cells.
pub fn assemble_continuum_shaped<E: Continuum<N>, const N: usize>(
    shape: &Mesh,
    mesh: &Mesh,
    el: &E,
    density: f64,
    lumped: bool,
) -> Result<Assembled<E::Geometry>, CellError> {
    if shape.cells.len() != mesh.cells.len() || shape.cells.kind() != mesh.cells.kind() {
        return Err(CellError::WrongCells {
            expected: mesh.cells.kind().describe(),
            dim: mesh.dim,
            got: shape.cells.kind().describe(),
            got_dim: shape.dim,
        });
    }
    let geometry = geometries(shape, el)?;
    let assembler = Assembler::new(mesh);
    let m = assembler.assemble(&ContinuumMass {
        element: el,
        geometry: &geometry,
        density,
        lumped,
    });
    let k = assembler.assemble(&ContinuumStiffness {
        element: el,
        geometry: &geometry,
    });
    Ok(Assembled {
        assembler,
        geometry,
        m,
        k,
    })
}

/// The stresses of a body's cells, whatever their element (object safe: a body keeps one
/// behind a `Box<dyn CellStresses>`).
pub trait CellStresses: Send + Sync + std::fmt::Debug {
    /// Stress components per cell ([`Continuum::STRESSES`]).
    fn components(&self) -> usize;

    /// Every cell's stress under the body's displacements `u` into `out`
    /// ([`CellStresses::components`] per cell, cell after cell). No allocation.
    ///
    /// # Panics
    /// If `out` is not `components() * cells` long.
    fn stresses_into(&self, u: &[f64], out: &mut [f64]);
}

/// A mesh's cells with their element and geometry: its [`CellStresses`].
#[derive(Debug, Clone)]
pub struct Cells<E: Continuum<N>, const N: usize> {
    /// The element.
    pub element: E,
    /// One geometry per cell.
    pub geometry: Vec<E::Geometry>,
    /// The cells' nodes, flat.
    pub connectivity: Vec<usize>,
    /// The mesh's dimension.
    pub dim: usize,
}

impl<E, const N: usize> CellStresses for Cells<E, N>
where
    E: Continuum<N> + Send + std::fmt::Debug,
{
    fn components(&self) -> usize {
        E::STRESSES
    }

    fn stresses_into(&self, u: &[f64], out: &mut [f64]) {
        let per = E::KIND.nodes();
        assert_eq!(out.len(), E::STRESSES * self.geometry.len());
        let mut ue = [0.0; N];
        for ((nodes, g), s) in self
            .connectivity
            .chunks_exact(per)
            .zip(&self.geometry)
            .zip(out.chunks_exact_mut(E::STRESSES))
        {
            for (a, &node) in nodes.iter().enumerate() {
                ue[self.dim * a..self.dim * (a + 1)]
                    .copy_from_slice(&u[self.dim * node..self.dim * (node + 1)]);
            }
            self.element.stress_into(g, &ue, s);
        }
    }
}

/// The 3-node triangle in the plane ([`super::tri3`]) with its elasticity matrix (plane
/// stress or plane strain: [`crate::material::PlaneModel::elasticity_matrix`]) and its
/// thickness.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneTri3 {
    /// The Voigt elasticity matrix, Pa.
    pub d: [[f64; 3]; 3],
    /// The out-of-plane thickness, m.
    pub thickness: f64,
}

impl Continuum<6> for PlaneTri3 {
    type Geometry = Tri3Geometry;
    const KIND: CellKind = CellKind::Tri3;
    const STRESSES: usize = 3;

    fn geometry(&self, x: &[f64]) -> Result<Tri3Geometry, String> {
        tri3::geometry(&[[x[0], x[1]], [x[2], x[3]], [x[4], x[5]]]).map_err(|e| e.to_string())
    }

    fn mass_into(&self, g: &Tri3Geometry, density: f64, lumped: bool, out: &mut [[f64; 6]; 6]) {
        tri3::mass_into(g, density, self.thickness, lumped, out);
    }

    fn stiffness_into(&self, g: &Tri3Geometry, out: &mut [[f64; 6]; 6]) {
        tri3::stiffness_into(g, &self.d, self.thickness, out);
    }

    fn stress_into(&self, g: &Tri3Geometry, u: &[f64; 6], out: &mut [f64]) {
        out.copy_from_slice(&tri3::stress(g, &self.d, u));
    }
}

/// The solid elements' points: `NN` nodes of three coordinates from a flat slice.
fn points<const NN: usize>(x: &[f64]) -> [[f64; 3]; NN] {
    std::array::from_fn(|i| [x[3 * i], x[3 * i + 1], x[3 * i + 2]])
}

/// The 4-node tetrahedron ([`super::tet4`]) with its 6 x 6 elasticity matrix
/// ([`super::solid::elasticity_3d`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolidTet4 {
    /// The Voigt elasticity matrix, Pa.
    pub d: [[f64; 6]; 6],
}

impl Continuum<12> for SolidTet4 {
    type Geometry = super::tet4::Tet4Geometry;
    const KIND: CellKind = CellKind::Tet4;
    const STRESSES: usize = 6;

    fn geometry(&self, x: &[f64]) -> Result<Self::Geometry, String> {
        super::tet4::geometry(&points(x)).map_err(|e| e.to_string())
    }

    fn mass_into(&self, g: &Self::Geometry, density: f64, lumped: bool, out: &mut [[f64; 12]; 12]) {
        super::tet4::mass_into(g, density, lumped, out);
    }

    fn stiffness_into(&self, g: &Self::Geometry, out: &mut [[f64; 12]; 12]) {
        super::tet4::stiffness_into(g, &self.d, out);
    }

    fn stress_into(&self, g: &Self::Geometry, u: &[f64; 12], out: &mut [f64]) {
        out.copy_from_slice(&super::tet4::stress(g, &self.d, u));
    }
}

/// The 10-node tetrahedron ([`super::tet10`]); its stress is the centroid's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolidTet10 {
    /// The Voigt elasticity matrix, Pa.
    pub d: [[f64; 6]; 6],
}

impl Continuum<30> for SolidTet10 {
    type Geometry = super::tet10::Tet10Geometry;
    const KIND: CellKind = CellKind::Tet10;
    const STRESSES: usize = 6;

    fn geometry(&self, x: &[f64]) -> Result<Self::Geometry, String> {
        super::tet10::geometry(&points(x)).map_err(|e| e.to_string())
    }

    fn mass_into(&self, g: &Self::Geometry, density: f64, lumped: bool, out: &mut [[f64; 30]; 30]) {
        super::tet10::mass_into(g, density, lumped, out);
    }

    fn stiffness_into(&self, g: &Self::Geometry, out: &mut [[f64; 30]; 30]) {
        super::tet10::stiffness_into(g, &self.d, out);
    }

    fn stress_into(&self, g: &Self::Geometry, u: &[f64; 30], out: &mut [f64]) {
        out.copy_from_slice(&super::tet10::stress_at(g, &self.d, [0.25; 3], u));
    }
}

/// The 8-node hexahedron ([`super::hex8`]); its stress is the centroid's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolidHex8 {
    /// The Voigt elasticity matrix, Pa.
    pub d: [[f64; 6]; 6],
}

impl Continuum<24> for SolidHex8 {
    type Geometry = super::hex8::Hex8Geometry;
    const KIND: CellKind = CellKind::Hex8;
    const STRESSES: usize = 6;

    fn geometry(&self, x: &[f64]) -> Result<Self::Geometry, String> {
        super::hex8::geometry(&points(x)).map_err(|e| e.to_string())
    }

    fn mass_into(&self, g: &Self::Geometry, density: f64, lumped: bool, out: &mut [[f64; 24]; 24]) {
        super::hex8::mass_into(g, density, lumped, out);
    }

    fn stiffness_into(&self, g: &Self::Geometry, out: &mut [[f64; 24]; 24]) {
        super::hex8::stiffness_into(g, &self.d, out);
    }

    fn stress_into(&self, g: &Self::Geometry, u: &[f64; 24], out: &mut [f64]) {
        out.copy_from_slice(&super::hex8::stress_at(g, &self.d, [0.0; 3], u));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assembly::assemble_mass_stiffness;
    use crate::material::{Elastic, PlaneModel};
    use crate::mesh::generators::{box_mesh, disk_graded, DiskOptions};

    const STEEL: Elastic = Elastic {
        young: 210e9,
        poisson: 0.3,
        density: 7850.0,
    };

    /// Through the contract, the plane triangle gives the triangle assembly's matrices bit
    /// for bit (the same kernels in the same order) and its stresses.
    #[test]
    fn the_plane_triangle_through_the_contract_is_the_triangle_assembly() {
        let mesh = disk_graded(0.1, 48, DiskOptions::default()).unwrap();
        let d = PlaneModel::Stress.elasticity_matrix(&STEEL);
        let el = PlaneTri3 { d, thickness: 0.02 };
        for lumped in [false, true] {
            let a = assemble_continuum(&mesh, &el, STEEL.density, lumped).unwrap();
            let (m, k) =
                assemble_mass_stiffness(&a.assembler, &a.geometry, &d, &STEEL, 0.02, lumped);
            assert_eq!((a.m, a.k), (m, k));
        }
        // A uniform strain gives every cell its stress D e.
        let e = [1e-4, -2e-4, 3e-4];
        let u: Vec<f64> = mesh
            .points()
            .flat_map(|p| {
                [
                    e[0] * p[0] + 0.5 * e[2] * p[1],
                    e[1] * p[1] + 0.5 * e[2] * p[0],
                ]
            })
            .collect();
        let a = assemble_continuum(&mesh, &el, STEEL.density, false).unwrap();
        let cells = Cells {
            element: el,
            geometry: a.geometry,
            connectivity: mesh.cells.connectivity().to_vec(),
            dim: 2,
        };
        let mut s = vec![0.0; 3 * mesh.cells.len()];
        cells.stresses_into(&u, &mut s);
        for c in s.chunks_exact(3) {
            for r in 0..3 {
                let exact: f64 = (0..3).map(|k| d[r][k] * e[k]).sum();
                assert!((c[r] - exact).abs() < 1e-6 * exact.abs().max(1e3), "{c:?}");
            }
        }
    }

    /// A mesh of other cells, and an inverted cell, are refused by name.
    #[test]
    fn wrong_cells_and_inverted_cells_are_named() {
        let el = PlaneTri3 {
            d: [[0.0; 3]; 3],
            thickness: 1.0,
        };
        let solid = box_mesh(CellKind::Tet4, [1.0; 3], [1, 1, 1]).unwrap();
        let e = geometries(&solid, &el).unwrap_err();
        assert!(
            e.to_string().contains("not a 3D mesh of 4-node tetrahedra"),
            "{e}"
        );
        let mut flat = crate::mesh::generators::rectangle(1.0, 1.0, 1, 1).unwrap();
        flat.cells.connectivity_mut().swap(0, 1);
        let e = geometries(&flat, &el).unwrap_err();
        assert!(
            matches!(&e, CellError::Geometry { cell: 0, .. }) && e.to_string().contains("inverted"),
            "{e}"
        );
    }
}
