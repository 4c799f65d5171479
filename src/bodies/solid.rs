//! A body of continuum cells in any dimension: its mesh's cells assembled through the element
//! contract ([`crate::element::Continuum`]) into a [`Body`] the joined model, the contact
//! rows and the driver take as they take the wheel, with the cells' stresses for output.
//!
//! [`solid`] picks the element from the mesh's cells ([`CellKind`]): the plane triangle
//! ([`PlaneTri3`]) in 2D, the solids in 3D. This is the one place that lists which element
//! runs on which cells; a new element is one line here beside its implementation of the
//! contract.

use crate::contact::search::Motion;
use crate::element::continuum::{
    assemble_continuum_shaped, CellError, Cells, PlaneTri3, SolidHex8, SolidTet10, SolidTet4,
};
use crate::element::{CellStresses, Continuum};
use crate::material::{Elastic, PlaneModel};
use crate::mesh::{CellKind, Mesh};
use crate::model::LinearModel;

use super::Body;

/// What a continuum body is made of.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolidSpec {
    /// The material.
    pub material: Elastic,
    /// The plane hypothesis of a 2D body (ignored in 3D).
    pub plane: PlaneModel,
    /// The out-of-plane thickness of a 2D body, m (ignored in 3D).
    pub thickness: f64,
    /// Lumped (`true`) or consistent mass.
    pub lumped: bool,
}

/// Why a mesh cannot be a continuum body.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolidError {
    /// A cell is inverted or degenerate, or the cells are not the element's.
    #[error(transparent)]
    Cell(#[from] CellError),
    /// No element runs on the mesh's cells.
    #[error(
        "no continuum element runs on {0} (a body needs triangles in 2D or solid cells in 3D)"
    )]
    NoElement(&'static str),
}

/// A continuum body: the [`Body`] and its cells' stresses.
#[derive(Debug)]
pub struct Solid {
    /// The body (its frame [`Motion`], no supports, load or initial state: set them).
    pub body: Body,
    /// Its cells' stresses under its displacements ([`CellStresses`]).
    pub stresses: Box<dyn CellStresses>,
}

/// The body `name` of `mesh`'s cells with `spec`, in the frame `motion` (module docs).
///
/// # Errors
/// [`SolidError`] naming the first bad cell, or cells without an element.
pub fn solid(
    name: &str,
    mesh: Mesh,
    spec: &SolidSpec,
    motion: Motion,
) -> Result<Solid, SolidError> {
    solid_shaped(name, None, mesh, spec, motion)
}

/// The body `name` of a mesh closed on itself (a rail whose ends are joined), each cell
/// shaped by the same cell of `open`, the mesh it was closed from
/// ([`crate::element::continuum::assemble_continuum_shaped`]).
///
/// # Errors
/// As [`solid`], or a cell of `open` that is not `closed`'s.
pub fn solid_closed(
    name: &str,
    open: &Mesh,
    closed: Mesh,
    spec: &SolidSpec,
    motion: Motion,
) -> Result<Solid, SolidError> {
    solid_shaped(name, Some(open), closed, spec, motion)
}

/// [`solid`], the cells shaped by `shape`'s when there is one.
fn solid_shaped(
    name: &str,
    shape: Option<&Mesh>,
    mesh: Mesh,
    spec: &SolidSpec,
    motion: Motion,
) -> Result<Solid, SolidError> {
    match mesh.cells.kind() {
        CellKind::Tri3 => {
            let el = PlaneTri3 {
                d: spec.plane.elasticity_matrix(&spec.material),
                thickness: spec.thickness,
            };
            build(name, shape, mesh, el, spec, motion)
        }
        CellKind::Tet4 => build(name, shape, mesh, SolidTet4 { d: d3(spec) }, spec, motion),
        CellKind::Tet10 => build(name, shape, mesh, SolidTet10 { d: d3(spec) }, spec, motion),
        CellKind::Hex8 => build(name, shape, mesh, SolidHex8 { d: d3(spec) }, spec, motion),
        other => Err(SolidError::NoElement(other.describe())),
    }
}

/// The solids' elasticity matrix.
fn d3(spec: &SolidSpec) -> [[f64; 6]; 6] {
    crate::element::solid::elasticity_3d(&spec.material)
}

/// The body of `mesh` with the element `el`.
fn build<E, const N: usize>(
    name: &str,
    shape: Option<&Mesh>,
    mesh: Mesh,
    el: E,
    spec: &SolidSpec,
    motion: Motion,
) -> Result<Solid, SolidError>
where
    E: Continuum<N> + Send + std::fmt::Debug + 'static,
{
    let a = assemble_continuum_shaped(
        shape.unwrap_or(&mesh),
        &mesh,
        &el,
        spec.material.density,
        spec.lumped,
    )?;
    let stresses = Box::new(Cells {
        element: el,
        geometry: a.geometry,
        connectivity: mesh.cells.connectivity().to_vec(),
        dim: mesh.dim,
    });
    let model = LinearModel {
        c: a.assembler.zeros(),
        assembler: a.assembler,
        m: a.m,
        k: a.k.clone(),
    };
    Ok(Solid {
        body: Body::on_mesh(name, mesh, model, a.k, motion),
        stresses,
    })
}
