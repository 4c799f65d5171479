//! Global assembly: the sparsity pattern is built once from the mesh connectivity, with a
//! map from every element-matrix entry to its slot in the value array; matrices sharing the
//! pattern (`M`, `K`, `C`, `A`) are then filled by scattering element matrices
//! (fenris `CsrAssembler::assemble_pattern` / `assemble_into_csr`).
//!
//! # The element loop
//!
//! A global matrix is the sum over the elements of their matrices scattered into the
//! pattern, `A = sum_e P_e^T A_e P_e` (`P_e` picks element `e`'s dofs). The element matrix
//! comes from an [`ElementMatrix`] operator, which fills a buffer the loop owns
//! (fenris `assemble_element_matrix_into(element_index, output)`); the loop
//! ([`Assembler::assemble`], [`Assembler::add_assembled`]) evaluates the elements in
//! parallel and scatters them in element order, so the result does not depend on the
//! number of threads.
//!
//! The operators of the 3-node triangle ([`crate::element::tri3`]) over a whole mesh:
//!
//! | operator | element matrix | global matrix |
//! |---|---|---|
//! | [`Tri3Mass`] | `rho t A / 12 (1 + delta_ij) delta_ab` (or lumped `rho t A / 3 I`) | `M` (also the damping `eta_z N^T N` of Eq. 22, with `eta_z` for `rho`) |
//! | [`Tri3Stiffness`] | `t A B^T D B` | `K` |
//! | [`Tri3GeometricStiffness`] | `delta_ab t A grad N_i . S_e grad N_j` | `K_sigma` of the element stresses `S_e` |
//!
//! # Dof layout and element families
//!
//! A model is a set of bodies and discrete elements whose nodes carry different dofs: a
//! triangle mesh's nodes `dim` translations, a 2D beam's nodes `(u, w, theta)` or
//! `(w, theta)` ([`crate::element::beam`]), a point mass or a hub its own
//! ([`crate::element::discrete`]). A [`DofLayout`] numbers the dofs node by node with a
//! count per node; an [`ElementFamily`] lists the dofs of elements of one kind (`ndof_e`
//! each, not `dim * npe`); [`Assembler::try_with_families`] builds one pattern for any
//! number of families, and the `*_family*` methods scatter family `f`'s element matrices,
//! `A = sum_f sum_{e in f} P_e^T A_e P_e`. A mesh alone ([`Assembler::new`]) is the one-family
//! case, [`ElementFamily::of_mesh`]: the same pattern, slots and values, bit for bit.

use crate::element::tri3::{self, Tri3Geometry};
use crate::linalg::Pattern;
use crate::material::Elastic;
use crate::mesh::Mesh;
use rayon::prelude::*;

/// An element operator: the `N x N` matrix of element `e`, written into the caller's buffer.
///
/// `N` is the number of dofs of an element (`dim * nodes per element`), the
/// [`Assembler::ndof_e`] of the mesh it is assembled on. The buffer is zero on entry;
/// the operator may overwrite it completely.
pub trait ElementMatrix<const N: usize>: Sync {
    /// Fills `out` with the matrix of element `e`.
    fn element_matrix_into(&self, e: usize, out: &mut [[f64; N]; N]);
}

/// Mass matrix of a triangle mesh, consistent or lumped ([`tri3::mass_into`]).
#[derive(Debug, Clone, Copy)]
pub struct Tri3Mass<'a> {
    /// Element geometry, one per triangle.
    pub geometry: &'a [Tri3Geometry],
    /// Mass per unit volume, kg/m^3 (or the damping `eta_z`, N s/m^4, Eq. 22).
    pub density: f64,
    /// Thickness, m.
    pub thickness: f64,
    /// Lumped (`true`) or consistent mass.
    pub lumped: bool,
}

impl ElementMatrix<6> for Tri3Mass<'_> {
    fn element_matrix_into(&self, e: usize, out: &mut [[f64; 6]; 6]) {
        tri3::mass_into(
            &self.geometry[e],
            self.density,
            self.thickness,
            self.lumped,
            out,
        );
    }
}

/// Elastic stiffness of a triangle mesh ([`tri3::stiffness_into`]).
#[derive(Debug, Clone, Copy)]
pub struct Tri3Stiffness<'a> {
    /// Element geometry, one per triangle.
    pub geometry: &'a [Tri3Geometry],
    /// Voigt elasticity matrix `D`, Pa.
    pub d: &'a [[f64; 3]; 3],
    /// Thickness, m.
    pub thickness: f64,
}

impl ElementMatrix<6> for Tri3Stiffness<'_> {
    fn element_matrix_into(&self, e: usize, out: &mut [[f64; 6]; 6]) {
        tri3::stiffness_into(&self.geometry[e], self.d, self.thickness, out);
    }
}

/// Geometric (initial-stress) stiffness of a triangle mesh under the element stresses
/// `stress[e] = [sxx, syy, txy]` (Pa), [`tri3::geometric_stiffness_into`].
#[derive(Debug, Clone, Copy)]
pub struct Tri3GeometricStiffness<'a> {
    /// Element geometry, one per triangle.
    pub geometry: &'a [Tri3Geometry],
    /// The prestress of each element, `[sxx, syy, txy]`, Pa.
    pub stress: &'a [[f64; 3]],
    /// Thickness, m.
    pub thickness: f64,
}

impl ElementMatrix<6> for Tri3GeometricStiffness<'_> {
    fn element_matrix_into(&self, e: usize, out: &mut [[f64; 6]; 6]) {
        tri3::geometric_stiffness_into(&self.geometry[e], self.stress[e], self.thickness, out);
    }
}

/// Assembles `M` (consistent or lumped) and `K` of a triangle mesh with the elasticity
/// matrix `d` and thickness `thickness` (m).
pub fn assemble_mass_stiffness(
    asm: &Assembler,
    geom: &[Tri3Geometry],
    d: &[[f64; 3]; 3],
    material: &Elastic,
    thickness: f64,
    lumped: bool,
) -> (Vec<f64>, Vec<f64>) {
    let m = asm.assemble(&Tri3Mass {
        geometry: geom,
        density: material.density,
        thickness,
        lumped,
    });
    let k = asm.assemble(&Tri3Stiffness {
        geometry: geom,
        d,
        thickness,
    });
    (m, k)
}

/// Invalid input to a [`DofLayout`], an [`ElementFamily`] or [`Assembler::try_with_families`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum AssemblyError {
    /// An element family with zero dofs per element.
    #[error("an element family must have at least one dof per element")]
    NoDofsPerElement,
    /// A dof list whose length is not a multiple of the dofs per element.
    #[error("{len} element dofs are not a whole number of elements of {ndof_e} dofs")]
    RaggedDofs {
        /// Length of the list.
        len: usize,
        /// Dofs per element.
        ndof_e: usize,
    },
    /// An element refers to a dof past the model's last.
    #[error("element {element} of family {family} refers to dof {dof}, the model has {n_dofs}")]
    DofOutOfRange {
        /// The family.
        family: usize,
        /// The element within the family.
        element: usize,
        /// The dof.
        dof: usize,
        /// Number of dofs of the model.
        n_dofs: usize,
    },
    /// A node past the layout's last.
    #[error("node {node} is not in the layout ({nodes} nodes)")]
    NodeOutOfRange {
        /// The node.
        node: usize,
        /// Number of nodes of the layout.
        nodes: usize,
    },
    /// A local dof past a node's dofs.
    #[error("node {node} has {dofs} dofs, local dof {local} asked for")]
    LocalDofOutOfRange {
        /// The node.
        node: usize,
        /// The local dof asked for.
        local: usize,
        /// Dofs of the node.
        dofs: usize,
    },
    /// Bodies of different dimensions joined in one model.
    #[error("bodies of {first}D and {other}D cannot be joined in one model")]
    MixedDimensions {
        /// The first body's dimension.
        first: usize,
        /// Another body's.
        other: usize,
    },
    /// The elements of one family have different numbers of dofs.
    #[error("element {element} has {got} dofs, the family's first has {expected}")]
    MixedElementDofs {
        /// The element.
        element: usize,
        /// Its dofs.
        got: usize,
        /// The first element's dofs.
        expected: usize,
    },
}

/// The dofs of the nodes of a model: node `i` owns the consecutive dofs
/// `first(i) .. first(i) + count(i)`, in the order the nodes were pushed. The number of dofs
/// per node is given per node (per family of nodes), not fixed to the dimension: a triangle
/// mesh's nodes carry `dim` translations, a 2D beam's nodes `(u, w, theta)` or `(w, theta)`,
/// a point node or a hub its own translations (and rotation).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DofLayout {
    /// `first[i]` is node `i`'s first dof; `first[n_nodes]` is the number of dofs.
    first: Vec<usize>,
}

impl Default for DofLayout {
    fn default() -> Self {
        Self::new()
    }
}

impl DofLayout {
    /// An empty layout.
    pub fn new() -> Self {
        Self { first: vec![0] }
    }

    /// `n_nodes` nodes of `per_node` dofs each: node `i`'s dof `c` is `per_node * i + c` (the
    /// layout of a mesh, `per_node = dim`).
    pub fn uniform(n_nodes: usize, per_node: usize) -> Self {
        let mut l = Self::new();
        l.push_nodes(n_nodes, per_node);
        l
    }

    /// Appends `count` nodes of `per_node` dofs each; returns their node numbers.
    pub fn push_nodes(&mut self, count: usize, per_node: usize) -> std::ops::Range<usize> {
        let first_node = self.n_nodes();
        let mut next = self.n_dofs();
        for _ in 0..count {
            next += per_node;
            self.first.push(next);
        }
        first_node..first_node + count
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.first.len() - 1
    }

    /// Number of dofs.
    pub fn n_dofs(&self) -> usize {
        self.first[self.first.len() - 1]
    }

    /// The dofs of `node`.
    ///
    /// # Errors
    /// [`AssemblyError::NodeOutOfRange`].
    pub fn dofs(&self, node: usize) -> Result<std::ops::Range<usize>, AssemblyError> {
        if node >= self.n_nodes() {
            return Err(AssemblyError::NodeOutOfRange {
                node,
                nodes: self.n_nodes(),
            });
        }
        Ok(self.first[node]..self.first[node + 1])
    }

    /// The global number of `node`'s local dof `local`.
    ///
    /// # Errors
    /// [`AssemblyError::NodeOutOfRange`], [`AssemblyError::LocalDofOutOfRange`].
    pub fn dof(&self, node: usize, local: usize) -> Result<usize, AssemblyError> {
        let r = self.dofs(node)?;
        if local >= r.len() {
            return Err(AssemblyError::LocalDofOutOfRange {
                node,
                local,
                dofs: r.len(),
            });
        }
        Ok(r.start + local)
    }
}

/// A family of elements with the same number of dofs each (`ndof_e`): the global dofs of
/// element `e` are `dofs[e * ndof_e .. (e + 1) * ndof_e]`, in the order of the rows and
/// columns of its element matrix.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ElementFamily {
    ndof_e: usize,
    dofs: Vec<usize>,
}

impl ElementFamily {
    /// A family of elements of `ndof_e` dofs from their dof lists, concatenated.
    ///
    /// # Errors
    /// [`AssemblyError::NoDofsPerElement`], [`AssemblyError::RaggedDofs`].
    pub fn try_new(ndof_e: usize, dofs: Vec<usize>) -> Result<Self, AssemblyError> {
        if ndof_e == 0 {
            return Err(AssemblyError::NoDofsPerElement);
        }
        if dofs.len() % ndof_e != 0 {
            return Err(AssemblyError::RaggedDofs {
                len: dofs.len(),
                ndof_e,
            });
        }
        Ok(Self { ndof_e, dofs })
    }

    /// The cells of `mesh`, `dim` dofs per node: node `a`'s component `c` is dof
    /// `dim * a + c` (the layout [`DofLayout::uniform`]`(n_points, dim)`).
    pub fn of_mesh(mesh: &Mesh) -> Self {
        let dim = mesh.dim;
        let n_el = mesh.cells.len();
        let npe = if n_el > 0 {
            mesh.cell_nodes(0).len()
        } else {
            0
        };
        let ndof_e = dim * npe;
        let mut dofs = Vec::with_capacity(n_el * ndof_e);
        for e in 0..n_el {
            for &node in mesh.cell_nodes(e) {
                for c in 0..dim {
                    dofs.push(dim * node + c);
                }
            }
        }
        Self { ndof_e, dofs }
    }

    /// Elements on nodes of `layout`: element `e` takes every dof of each of its nodes, node
    /// after node (a 2D beam on `(w, theta)` nodes: `[w_a, theta_a, w_b, theta_b]`). An
    /// empty `elements` gives an empty family.
    ///
    /// # Errors
    /// [`AssemblyError::NodeOutOfRange`], [`AssemblyError::MixedElementDofs`] when the
    /// elements do not all have the same number of dofs, [`AssemblyError::NoDofsPerElement`].
    pub fn on_nodes<const K: usize>(
        layout: &DofLayout,
        elements: &[[usize; K]],
    ) -> Result<Self, AssemblyError> {
        let mut dofs = Vec::new();
        let mut ndof_e = 0;
        for (e, nodes) in elements.iter().enumerate() {
            let before = dofs.len();
            for &node in nodes {
                dofs.extend(layout.dofs(node)?);
            }
            let got = dofs.len() - before;
            if e == 0 {
                ndof_e = got;
            } else if got != ndof_e {
                return Err(AssemblyError::MixedElementDofs {
                    element: e,
                    got,
                    expected: ndof_e,
                });
            }
        }
        if elements.is_empty() {
            // No element to tell: an empty family of one dof per node.
            ndof_e = K.max(1);
        }
        Self::try_new(ndof_e, dofs)
    }

    /// Dofs per element.
    pub fn ndof_e(&self) -> usize {
        self.ndof_e
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.dofs.len() / self.ndof_e.max(1)
    }

    /// True without elements.
    pub fn is_empty(&self) -> bool {
        self.dofs.is_empty()
    }

    /// Global dofs of element `e`.
    pub fn element_dofs(&self, e: usize) -> &[usize] {
        &self.dofs[e * self.ndof_e..(e + 1) * self.ndof_e]
    }
}

/// An element family and its map from element-matrix entries to value slots.
#[derive(Debug, Clone)]
struct FamilyMap {
    family: ElementFamily,
    /// For element `e`, local entry `(a, b)` (row-major) lands at
    /// `values[slots[e * ndof_e^2 + a * ndof_e + b]]`.
    slots: Vec<usize>,
}

/// The sparsity pattern of a model and the element-to-value maps of its element families.
///
/// [`Assembler::new`] holds one family, the cells of a mesh; [`Assembler::try_with_families`]
/// holds any number of families with their own dofs per element (triangles, beams, discrete
/// springs and masses) on one pattern. The methods without a family index act on family 0.
#[derive(Debug, Clone)]
pub struct Assembler {
    /// The pattern (square, `n_dofs x n_dofs`, every coupling of two dofs of one element).
    pub pattern: Pattern,
    /// Degrees of freedom per element of family 0 (for a mesh: `dim * nodes per element`).
    pub ndof_e: usize,
    families: Vec<FamilyMap>,
}

impl Assembler {
    /// Builds the pattern of `mesh`, plus the diagonal of every dof (so that a dof touched by
    /// no element still has a slot for a Dirichlet 1).
    pub fn new(mesh: &Mesh) -> Self {
        Self::build(mesh.n_dofs(), vec![ElementFamily::of_mesh(mesh)])
    }

    /// Builds the pattern of `n_dofs` dofs coupled by the elements of `families` (family `f`
    /// keeps index `f`), plus the diagonal of every dof. With the single family
    /// [`ElementFamily::of_mesh`] this is [`Assembler::new`], entry for entry.
    ///
    /// # Errors
    /// [`AssemblyError::DofOutOfRange`] when an element refers to a dof `>= n_dofs`.
    pub fn try_with_families(
        n_dofs: usize,
        families: Vec<ElementFamily>,
    ) -> Result<Self, AssemblyError> {
        for (f, fam) in families.iter().enumerate() {
            if let Some(p) = fam.dofs.iter().position(|&d| d >= n_dofs) {
                return Err(AssemblyError::DofOutOfRange {
                    family: f,
                    element: p / fam.ndof_e.max(1),
                    dof: fam.dofs[p],
                    n_dofs,
                });
            }
        }
        Ok(Self::build(n_dofs, families))
    }

    /// The pattern (the union of the diagonal and every element's couplings, sorted) and the
    /// slot maps; dofs checked by the caller.
    fn build(n: usize, families: Vec<ElementFamily>) -> Self {
        // Column lists of rows.
        let mut cols: Vec<Vec<usize>> = (0..n).map(|j| vec![j]).collect();
        for fam in &families {
            for e in 0..fam.len() {
                let d = fam.element_dofs(e);
                for &j in d {
                    cols[j].extend_from_slice(d);
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for c in &mut cols {
            c.sort_unstable();
            c.dedup();
            row_idx.extend_from_slice(c);
            col_ptr.push(row_idx.len());
        }
        let maps: Vec<FamilyMap> = families
            .into_iter()
            .map(|family| {
                let m = family.ndof_e;
                let mut slots = Vec::with_capacity(family.len() * m * m);
                for e in 0..family.len() {
                    let d = family.element_dofs(e);
                    for &i in d {
                        for &j in d {
                            let rows = &row_idx[col_ptr[j]..col_ptr[j + 1]];
                            let k = rows
                                .binary_search(&i)
                                .expect("pattern holds element entries");
                            slots.push(col_ptr[j] + k);
                        }
                    }
                }
                FamilyMap { family, slots }
            })
            .collect();
        // SAFETY of new_checked: indices sorted, in range, no duplicates by construction.
        let pattern = Pattern::new_checked(n, n, col_ptr, None, row_idx);
        Self {
            pattern,
            ndof_e: maps.first().map_or(0, |f| f.family.ndof_e),
            families: maps,
        }
    }

    /// The slot map of family `f` (tests).
    #[cfg(test)]
    fn slots(&self, f: usize) -> &[usize] {
        &self.families[f].slots
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.pattern.row_idx().len()
    }

    /// Number of element families.
    pub fn n_families(&self) -> usize {
        self.families.len()
    }

    /// Element family `f`.
    ///
    /// # Panics
    /// If `f >= n_families()`.
    pub fn family(&self, f: usize) -> &ElementFamily {
        &self.families[f].family
    }

    /// Global dofs of element `e` of family 0.
    pub fn element_dofs(&self, e: usize) -> &[usize] {
        self.families[0].family.element_dofs(e)
    }

    /// Index in the value array of global entry `(i, j)`, if stored.
    pub fn slot(&self, i: usize, j: usize) -> Option<usize> {
        let cp = self.pattern.col_ptr();
        let rows = &self.pattern.row_idx()[cp[j]..cp[j + 1]];
        rows.binary_search(&i).ok().map(|k| cp[j] + k)
    }

    /// A zero value array for this pattern.
    pub fn zeros(&self) -> Vec<f64> {
        vec![0.0; self.nnz()]
    }

    /// Adds the element matrices of family 0 produced by `kernel(e, out)` (row-major,
    /// `ndof_e^2`, `out` zeroed before each call) into `values`, one element after another.
    pub fn assemble_serial_into<F>(&self, values: &mut [f64], kernel: F)
    where
        F: FnMut(usize, &mut [f64]),
    {
        if !self.families.is_empty() {
            self.assemble_family_serial_into(0, values, kernel);
        }
    }

    /// [`Assembler::assemble_serial_into`] on family `f`.
    ///
    /// # Panics
    /// If `f >= n_families()`.
    pub fn assemble_family_serial_into<F>(&self, f: usize, values: &mut [f64], mut kernel: F)
    where
        F: FnMut(usize, &mut [f64]),
    {
        let map = &self.families[f];
        let m = map.family.ndof_e * map.family.ndof_e;
        let mut buf = vec![0.0; m];
        for e in 0..map.family.len() {
            buf.fill(0.0);
            kernel(e, &mut buf);
            for (k, &s) in map.slots[e * m..(e + 1) * m].iter().enumerate() {
                values[s] += buf[k];
            }
        }
    }

    /// As [`Assembler::assemble_serial_into`], with the element kernels evaluated in
    /// parallel (rayon) in chunks, each chunk into its own buffer, then scattered in element
    /// order, so the result is bitwise the serial one.
    pub fn assemble_par_into<F>(&self, values: &mut [f64], kernel: F)
    where
        F: Fn(usize, &mut [f64]) + Sync,
    {
        if !self.families.is_empty() {
            self.assemble_family_par_into(0, values, kernel);
        }
    }

    /// [`Assembler::assemble_par_into`] on family `f`.
    ///
    /// # Panics
    /// If `f >= n_families()`.
    pub fn assemble_family_par_into<F>(&self, f: usize, values: &mut [f64], kernel: F)
    where
        F: Fn(usize, &mut [f64]) + Sync,
    {
        let map = &self.families[f];
        let m = map.family.ndof_e * map.family.ndof_e;
        let n_el = map.family.len();
        const CHUNK: usize = 256;
        let locals: Vec<Vec<f64>> = (0..n_el.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let lo = c * CHUNK;
                let hi = (lo + CHUNK).min(n_el);
                let mut buf = vec![0.0; (hi - lo) * m];
                for e in lo..hi {
                    kernel(e, &mut buf[(e - lo) * m..(e - lo + 1) * m]);
                }
                buf
            })
            .collect();
        for (c, buf) in locals.iter().enumerate() {
            let lo = c * CHUNK;
            for (k, v) in buf.iter().enumerate() {
                values[map.slots[lo * m + k]] += v;
            }
        }
    }

    /// The global matrix of the operator `op` on family 0 (values on this pattern).
    ///
    /// # Panics
    /// If `N` is not family 0's [`Assembler::ndof_e`].
    pub fn assemble<const N: usize>(&self, op: &impl ElementMatrix<N>) -> Vec<f64> {
        let mut values = self.zeros();
        self.add_assembled(op, &mut values);
        values
    }

    /// Adds the global matrix of the operator `op` on family 0 into `values`: the element
    /// loop of the module docs, in parallel, scattered in element order (bitwise the serial
    /// sum).
    ///
    /// # Panics
    /// If `N` is not family 0's [`Assembler::ndof_e`].
    pub fn add_assembled<const N: usize>(&self, op: &impl ElementMatrix<N>, values: &mut [f64]) {
        if self.families.is_empty() {
            return;
        }
        self.add_assembled_family(0, op, values);
    }

    /// [`Assembler::add_assembled`] on family `f`.
    ///
    /// # Panics
    /// If `f >= n_families()`, or if the family has elements and `N` is not its
    /// [`ElementFamily::ndof_e`].
    pub fn add_assembled_family<const N: usize>(
        &self,
        f: usize,
        op: &impl ElementMatrix<N>,
        values: &mut [f64],
    ) {
        let fam = &self.families[f].family;
        if fam.is_empty() {
            return;
        }
        assert_eq!(N, fam.ndof_e, "element operator of the wrong size");
        self.assemble_family_par_into(f, values, |e, out| {
            let mut b = [[0.0; N]; N];
            op.element_matrix_into(e, &mut b);
            out.copy_from_slice(b.as_flattened());
        });
    }

    /// Dense copy (tests, small eigenproblems).
    pub fn to_dense(&self, values: &[f64]) -> faer::Mat<f64> {
        let n = self.pattern.nrows();
        let mut a = faer::Mat::zeros(n, n);
        let cp = self.pattern.col_ptr();
        let ri = self.pattern.row_idx();
        for j in 0..n {
            for p in cp[j]..cp[j + 1] {
                a[(ri[p], j)] += values[p];
            }
        }
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generators::disk_rings;

    #[test]
    fn operator_loop_is_bitwise_the_serial_sum_and_mass_sums_to_the_mass() {
        let mesh = disk_rings(0.1, 6).unwrap();
        let crate::mesh::Cells::Tri3(tris) = &mesh.cells else {
            panic!("disk of triangles")
        };
        let geom: Vec<Tri3Geometry> = tris
            .iter()
            .map(|t| tri3::geometry(&tri3::corners(&mesh, *t)).unwrap())
            .collect();
        let asm = Assembler::new(&mesh);
        let mat = Elastic {
            young: 2.05e11,
            poisson: 0.3,
            density: 7830.0,
        };
        let d = crate::material::PlaneModel::Stress.elasticity_matrix(&mat);
        let (m, k) = assemble_mass_stiffness(&asm, &geom, &d, &mat, 0.01, false);
        let mut k_ser = asm.zeros();
        asm.assemble_serial_into(&mut k_ser, |e, out| {
            let mut b = [[0.0; 6]; 6];
            tri3::stiffness_into(&geom[e], &d, 0.01, &mut b);
            out.copy_from_slice(b.as_flattened());
        });
        assert_eq!(k, k_ser);
        // Mass: 1^T M 1 over both components is twice the mass rho t A.
        let area: f64 = geom.iter().map(|g| g.area).sum();
        let total: f64 = m.iter().sum::<f64>() / 2.0;
        let exact = 7830.0 * 0.01 * area;
        assert!((total - exact).abs() < 1e-12 * exact, "{total} vs {exact}");
        // Geometric stiffness of a uniform hydrostatic stress p: u^T K_sigma u = p t
        // sum_a int |grad u_a|^2, which is p t |Omega| for u = (x, 0).
        let p = 3.0e6;
        let stress = vec![[p, p, 0.0]; geom.len()];
        let ks = asm.assemble(&Tri3GeometricStiffness {
            geometry: &geom,
            stress: &stress,
            thickness: 0.01,
        });
        let u: Vec<f64> = mesh.points().flat_map(|q| [q[0], 0.0]).collect();
        let mut ku = vec![0.0; u.len()];
        crate::linalg::spmv_into(&asm.pattern, &ks, &u, &mut ku);
        let q: f64 = ku.iter().zip(&u).map(|(a, b)| a * b).sum();
        assert!((q - p * 0.01 * area).abs() < 1e-10 * p * 0.01 * area, "{q}");
    }

    #[test]
    fn families_on_a_layout_give_the_mesh_matrices_bit_for_bit() {
        let mesh = disk_rings(0.1, 4).unwrap();
        let crate::mesh::Cells::Tri3(tris) = &mesh.cells else {
            panic!("disk of triangles")
        };
        let geom: Vec<Tri3Geometry> = tris
            .iter()
            .map(|t| tri3::geometry(&tri3::corners(&mesh, *t)).unwrap())
            .collect();
        let mat = Elastic {
            young: 2.05e11,
            poisson: 0.3,
            density: 7830.0,
        };
        let d = crate::material::PlaneModel::Stress.elasticity_matrix(&mat);
        let old = Assembler::new(&mesh);
        let layout = DofLayout::uniform(mesh.n_nodes(), 2);
        let fam = ElementFamily::on_nodes(&layout, tris).unwrap();
        assert_eq!(fam, ElementFamily::of_mesh(&mesh));
        let new = Assembler::try_with_families(layout.n_dofs(), vec![fam.clone()]).unwrap();
        assert_eq!(old.pattern.col_ptr(), new.pattern.col_ptr());
        assert_eq!(old.pattern.row_idx(), new.pattern.row_idx());
        assert_eq!(old.slots(0), new.slots(0));
        let (m0, k0) = assemble_mass_stiffness(&old, &geom, &d, &mat, 0.01, false);
        let (m1, k1) = assemble_mass_stiffness(&new, &geom, &d, &mat, 0.01, false);
        assert_eq!((m0.clone(), k0.clone()), (m1, k1));

        // The same triangles with a beam of (w, theta) nodes and a spring from the rim to
        // the beam on one pattern: the triangles' entries keep their values, bit for bit.
        let mut layout = layout;
        let beam_nodes = layout.push_nodes(3, 2);
        let beam = ElementFamily::on_nodes(
            &layout,
            &[
                [beam_nodes.start, beam_nodes.start + 1],
                [beam_nodes.start + 1, beam_nodes.start + 2],
            ],
        )
        .unwrap();
        assert_eq!(beam.ndof_e(), 4);
        let rim = layout.dof(mesh.n_nodes() - 1, 1).unwrap();
        let spring =
            ElementFamily::try_new(2, vec![rim, layout.dof(beam_nodes.start, 0).unwrap()]).unwrap();
        let mixed = Assembler::try_with_families(layout.n_dofs(), vec![fam, beam, spring]).unwrap();
        assert_eq!(mixed.n_families(), 3);
        // The beam: two 4x4 blocks sharing a 2x2 one; the spring: two off-diagonal entries.
        assert_eq!(mixed.nnz(), old.nnz() + 2 * 16 - 4 + 2);
        let k2 = mixed.assemble(&Tri3Stiffness {
            geometry: &geom,
            d: &d,
            thickness: 0.01,
        });
        let n0 = old.pattern.nrows();
        let (cp, ri) = (old.pattern.col_ptr(), old.pattern.row_idx());
        for j in 0..n0 {
            for p in cp[j]..cp[j + 1] {
                assert_eq!(k2[mixed.slot(ri[p], j).unwrap()].to_bits(), k0[p].to_bits());
            }
        }
        let outside: f64 = (n0..layout.n_dofs())
            .flat_map(|j| (0..layout.n_dofs()).map(move |i| (i, j)))
            .filter_map(|(i, j)| mixed.slot(i, j))
            .map(|s| k2[s].abs())
            .sum();
        assert_eq!(outside, 0.0);
        assert_eq!(
            Assembler::try_with_families(4, vec![ElementFamily::try_new(2, vec![0, 4]).unwrap()])
                .unwrap_err(),
            AssemblyError::DofOutOfRange {
                family: 0,
                element: 0,
                dof: 4,
                n_dofs: 4
            }
        );
    }

    #[test]
    fn layout_numbers_nodes_of_any_dof_count() {
        let mut l = DofLayout::uniform(2, 2);
        let beam = l.push_nodes(2, 3);
        let point = l.push_nodes(1, 1);
        assert_eq!((beam, point.clone()), (2..4, 4..5));
        assert_eq!(l.n_dofs(), 2 * 2 + 2 * 3 + 1);
        assert_eq!(l.dofs(3), Ok(7..10));
        assert_eq!(l.dof(4, 0), Ok(10));
        assert_eq!(
            l.dof(4, 1),
            Err(AssemblyError::LocalDofOutOfRange {
                node: 4,
                local: 1,
                dofs: 1
            })
        );
        assert!(matches!(
            l.dofs(5),
            Err(AssemblyError::NodeOutOfRange { .. })
        ));
        assert!(matches!(
            ElementFamily::on_nodes(&l, &[[0, 1], [2, 3]]),
            Err(AssemblyError::MixedElementDofs {
                element: 1,
                got: 6,
                expected: 4
            })
        ));
        assert_eq!(
            ElementFamily::try_new(0, vec![]),
            Err(AssemblyError::NoDofsPerElement)
        );
        assert!(matches!(
            ElementFamily::try_new(3, vec![0; 4]),
            Err(AssemblyError::RaggedDofs { .. })
        ));
    }
}
