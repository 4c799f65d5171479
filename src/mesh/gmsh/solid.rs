//! Import of 3D Gmsh meshes: 4-node and 10-node tetrahedra and 8-node hexahedra.
//!
//! [`read_msh_3d`] reads the volume cells of a MSH 4.1 file (ASCII or binary): Gmsh element
//! types 4 ([`Cells::Tet4`]), 11 ([`Cells::Tet10`]) and 5 ([`Cells::Hex8`]), in Gmsh's node
//! order (which [`Cells`] keeps). [`read_msh_any`] reads the mesh of the highest dimension
//! in the file: the 3D mesh when the file holds volume elements, else exactly what
//! [`read_msh`] gives.
//!
//! As in 2D, nodes are renumbered compactly in increasing Gmsh tag order, and every *named*
//! physical group, of any dimension, becomes a node set of that name: the nodes of the
//! group's elements and the nodes classified on its entities (a surface named `"tread"` for
//! contact, `"hub"` for a support, a volume `"wheel"`, a point). Points, lines and surface
//! elements (triangles, quadrangles, second-order ones) serve these groups only.
//!
//! One kind of cell per mesh: a file whose volumes hold two kinds (tetrahedra and
//! hexahedra, or first- and second-order tetrahedra) is refused ([`GmshError::MixedCells`]).
//! A [`Mesh`] holds one kind of cell, and Gmsh joins tetrahedra to hexahedra only through
//! pyramids, which softway has no element for; 4-node and 10-node tetrahedra side by side
//! would not be conforming (the mid-edge nodes of the shared faces hang).
//!
//! The checks, each an error naming the file and the Gmsh element or node tag:
//!
//! - the `$Nodes` and `$Elements` headers announce as many nodes and elements as their
//!   blocks hold, and node tags are unique ([`GmshError::CountMismatch`],
//!   [`GmshError::DuplicateNode`]);
//! - every node is a node of a volume cell ([`GmshError::UnusedSolidNode`]: it would carry
//!   neither mass nor stiffness);
//! - no two nodes within `1e-9` of the diagonal of the nodes' bounding box
//!   ([`GmshError::CoincidentSolidNodes`]: an unmerged seam, which cuts the body);
//! - corner Jacobians (a tetrahedron's `det[x1 - x0, x2 - x0, x3 - x0]`, six times its
//!   volume; a hexahedron's at each of its eight corners, along its three edges there): zero
//!   against the cell's longest corner-to-corner distance cubed (`|J| <= 1e-12 L^3`, as
//!   [`quality`](crate::mesh::quality())) is a degenerate cell
//!   ([`GmshError::DegenerateCell`]); a hexahedron whose corner Jacobians differ in sign is
//!   tangled, and a cell oriented against the majority is inverted
//!   ([`GmshError::InvertedCell`]). A mesh whose cells are *all* negatively oriented (a
//!   mirror image, e.g. a left wheel made from a right one with a reflection, or a
//!   left-handed frame) is reversed cell by cell, as a clockwise 2D mesh is: the geometry is
//!   sound and only the node order is mirrored, so refusing it would only make the user
//!   redo it by hand;
//! - each 10-node tetrahedron's mid-edge nodes within a quarter of their edge's length from
//!   the edge's middle ([`GmshError::MidEdgeNode`]): a quadratic edge `x(s)` with its middle
//!   node moved by `d` along it has `dx/ds = L/2 - 2 s d` on `s` in `[-1, 1]`, which vanishes
//!   at an end when `|d| = L/4` (the quarter-point element); a node order mixed up (VTK's,
//!   whose last two mid-edge nodes are Gmsh's swapped) puts the node at another edge's
//!   middle, far beyond that. Curved boundary edges (Gmsh places their middle node on the
//!   geometry) sag by `L^2 / (8 R)`, well inside;
//! - no cell listed twice (the same corners: [`GmshError::DuplicateCell`]), and no two
//!   cells on the same side of a shared face ([`GmshError::OverlappingCells`]): once every
//!   cell is positively oriented, each face of a cell turned outward is met at most once
//!   (an inner face is met once in each direction), which also refuses a face shared by
//!   more than two cells;
//! - one piece: the cells joined through their shared nodes reach every node
//!   ([`GmshError::Disconnected`], naming a node of the second piece), unless the caller
//!   asked for several bodies ([`SolidOptions::several_bodies`]; [`pieces`] then tells
//!   them apart).

use super::solid_checks::{check_cells, check_coincident, check_connected, piece_numbers};
use super::*;
use crate::mesh::CellKind;

/// What [`read_msh_3d_with`] accepts beyond the default.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SolidOptions {
    /// Accept a mesh in several pieces (several bodies in one file, e.g. a wheel and a rail
    /// meshed apart); [`pieces`] numbers them. Default: refused
    /// ([`GmshError::Disconnected`]).
    pub several_bodies: bool,
}

/// Reads a Gmsh MSH 4.1 file (ASCII or binary) as a 3D mesh of 4-node or 10-node
/// tetrahedra or 8-node hexahedra, in one piece.
///
/// See the [module documentation](self) for what is read and checked.
///
/// # Errors
/// A [`GmshError`] naming the file: [`GmshError::Io`], [`GmshError::UnsupportedVersion`],
/// [`GmshError::Parse`] as [`read_msh`]; [`GmshError::NoCells`],
/// [`GmshError::UnsupportedCell`], [`GmshError::MixedCells`], [`GmshError::MissingNode`]
/// and the checks' errors of the module documentation.
pub fn read_msh_3d(path: &Path) -> Result<Mesh, GmshError> {
    read_msh_3d_tagged(path).map(|(mesh, _)| mesh)
}

/// [`read_msh_3d`], with the Gmsh tag of every node (`tags[i]` is node `i`'s).
///
/// # Errors
/// As [`read_msh_3d`].
pub fn read_msh_3d_tagged(path: &Path) -> Result<(Mesh, Vec<u64>), GmshError> {
    read_msh_3d_with(path, SolidOptions::default())
}

/// [`read_msh_3d_tagged`] with [`SolidOptions`] (several bodies in one file).
///
/// # Errors
/// As [`read_msh_3d`].
pub fn read_msh_3d_with(path: &Path, options: SolidOptions) -> Result<(Mesh, Vec<u64>), GmshError> {
    parse_msh_3d_with(&read_bytes(path)?, path, options)
}

/// Parses the bytes of a MSH 4.1 file as [`read_msh_3d`] does; `path` only names the file in
/// errors.
///
/// # Errors
/// The [`GmshError`]s of [`read_msh_3d`] but [`GmshError::Io`].
pub fn parse_msh_3d(bytes: &[u8], path: &Path) -> Result<Mesh, GmshError> {
    parse_msh_3d_tagged(bytes, path).map(|(mesh, _)| mesh)
}

/// [`parse_msh_3d`] with the node tags, as [`read_msh_3d_tagged`].
///
/// # Errors
/// As [`parse_msh_3d`].
pub fn parse_msh_3d_tagged(bytes: &[u8], path: &Path) -> Result<(Mesh, Vec<u64>), GmshError> {
    parse_msh_3d_with(bytes, path, SolidOptions::default())
}

/// [`parse_msh_3d_tagged`] with [`SolidOptions`].
fn parse_msh_3d_with(
    bytes: &[u8],
    path: &Path,
    options: SolidOptions,
) -> Result<(Mesh, Vec<u64>), GmshError> {
    let (msh, names) = parse_file(bytes, path).map_err(|e| match e {
        // An empty $Nodes or $Elements section.
        GmshError::NoTriangles { path } => GmshError::NoCells { path },
        e => e,
    })?;
    build_solid(&msh, &names, path, options)
}

/// Reads the mesh of the highest dimension in a MSH 4.1 file: the 3D mesh of
/// [`read_msh_3d`] when the file holds volume elements, else the 2D mesh of [`read_msh`]
/// (exactly as [`read_msh`] reads it).
///
/// # Errors
/// Those of [`read_msh_3d`] for a file with volume elements, else those of [`read_msh`].
pub fn read_msh_any(path: &Path) -> Result<Mesh, GmshError> {
    read_msh_any_tagged(path).map(|(mesh, _)| mesh)
}

/// [`read_msh_any`], with the Gmsh tag of every node.
///
/// # Errors
/// As [`read_msh_any`].
pub fn read_msh_any_tagged(path: &Path) -> Result<(Mesh, Vec<u64>), GmshError> {
    parse_msh_any_tagged(&read_bytes(path)?, path)
}

/// [`read_msh_any_tagged`] on the bytes of a file; `path` only names it in errors.
///
/// # Errors
/// As [`read_msh_any`] but [`GmshError::Io`].
pub fn parse_msh_any_tagged(bytes: &[u8], path: &Path) -> Result<(Mesh, Vec<u64>), GmshError> {
    let (msh, names) = parse_file(bytes, path)?;
    let solid = msh.data.elements.as_ref().is_some_and(|e| {
        e.element_blocks
            .iter()
            .any(|b| b.entity_dim == 3 || cell_kind(b.element_type).is_some())
    });
    if solid {
        build_solid(&msh, &names, path, SolidOptions::default())
    } else {
        build_mesh(&msh, &names, path)
    }
}

/// The piece of every node of `mesh` (the cells joined through shared nodes): `0` for the
/// piece of node 0, `1` for the piece of the first node not in it, and so on. A mesh in one
/// piece gives all zeros; read several bodies with [`SolidOptions::several_bodies`] and
/// tell them apart with this.
pub fn pieces(mesh: &Mesh) -> Vec<usize> {
    piece_numbers(
        mesh.n_nodes(),
        mesh.cells.connectivity(),
        mesh.cells.kind().nodes(),
    )
}

/// softway's cell kind of a Gmsh volume element type, if it has one.
pub(super) fn cell_kind(et: ElementType) -> Option<CellKind> {
    match et {
        ElementType::Tet4 => Some(CellKind::Tet4),
        ElementType::Tet10 => Some(CellKind::Tet10),
        ElementType::Hex8 => Some(CellKind::Hex8),
        _ => None,
    }
}

/// The volume cells of a file: their kind, Gmsh tags and nodes' Gmsh tags (flat).
struct SolidCells {
    kind: CellKind,
    tags: Vec<u64>,
    nodes: Vec<u64>,
}

/// Builds the 3D mesh from the parsed file and the physical names `(dim, tag) -> name`.
fn build_solid(
    msh: &MshFile<u64, i32, f64>,
    names: &BTreeMap<(i32, i32), String>,
    path: &Path,
    options: SolidOptions,
) -> Result<(Mesh, Vec<u64>), GmshError> {
    check_counts(msh, path)?;
    let (coords, entity_nodes) = node_coordinates(msh, path)?;
    let physicals = entity_physicals(msh);
    let (mut groups, cells) = groups_and_cells(msh, names, &physicals, &coords, path)?;
    for (&(dim, tag), list) in &entity_nodes {
        for name in group_names(&physicals, names, dim, tag) {
            groups.entry(name.clone()).or_default().extend(list);
        }
    }

    // Every node a node of a cell.
    let used: BTreeSet<u64> = cells.nodes.iter().copied().collect();
    if let Some(&node) = coords.keys().filter(|t| !used.contains(t)).min() {
        let group = groups
            .iter()
            .find(|(_, set)| set.contains(&node))
            .map(|(name, _)| format!(" (group \"{name}\")"))
            .unwrap_or_default();
        return Err(GmshError::UnusedSolidNode {
            path: path.to_path_buf(),
            node,
            group,
        });
    }

    // Compact renumbering in increasing tag order.
    let tags: Vec<u64> = used.into_iter().collect();
    let index: HashMap<u64, usize> = tags.iter().enumerate().map(|(i, &t)| (t, i)).collect();
    let idx = |t: &u64| index.get(t).copied().unwrap_or(0);
    let xyz: Vec<f64> = tags
        .iter()
        .flat_map(|t| coords.get(t).copied().unwrap_or([f64::NAN; 3]))
        .collect();
    let mut flat: Vec<usize> = cells.nodes.iter().map(idx).collect();

    check_coincident(&xyz, &tags, path)?;
    check_cells(cells.kind, &mut flat, &xyz, &tags, &cells.tags, path)?;
    if !options.several_bodies {
        check_connected(tags.len(), &flat, cells.kind.nodes(), &tags, path)?;
    }

    let node_sets = groups
        .into_iter()
        .map(|(name, set)| {
            let mut v: Vec<usize> = set.iter().map(idx).collect();
            v.sort_unstable();
            v.dedup();
            (name, v)
        })
        .collect();
    let mesh = Mesh::new(3, xyz, Cells::from_flat(cells.kind, &flat), node_sets);
    Ok((mesh, tags))
}

/// The named groups (possibly empty) with the nodes of their elements, and the volume
/// cells; an element on a node without coordinates, a volume element softway has no cell
/// for, or cells of two kinds are errors.
fn groups_and_cells(
    msh: &MshFile<u64, i32, f64>,
    names: &BTreeMap<(i32, i32), String>,
    physicals: &HashMap<(i32, i32), Vec<i32>>,
    coords: &Coords,
    path: &Path,
) -> Result<(Groups, SolidCells), GmshError> {
    let missing = |element: u64, node: u64| GmshError::MissingNode {
        path: path.to_path_buf(),
        element,
        node,
    };
    let mut groups: Groups = names
        .values()
        .map(|name| (name.clone(), BTreeSet::new()))
        .collect();
    // The kind of the cells and the tag of its first cell.
    let mut first: Option<(CellKind, u64)> = None;
    let (mut tags, mut nodes) = (Vec::new(), Vec::new());
    let Some(elements) = &msh.data.elements else {
        return Err(GmshError::NoCells {
            path: path.to_path_buf(),
        });
    };
    for block in &elements.element_blocks {
        let (dim, tag, et) = (block.entity_dim, block.entity_tag, block.element_type);
        let Some(el0) = block.elements.first() else {
            continue;
        };
        let kind = cell_kind(et);
        if let Some(kind) = kind {
            match first {
                None => first = Some((kind, el0.element_tag)),
                Some((k, t)) if k != kind => {
                    return Err(GmshError::MixedCells {
                        path: path.to_path_buf(),
                        first: t,
                        first_kind: k.describe(),
                        second: el0.element_tag,
                        second_kind: kind.describe(),
                    })
                }
                Some(_) => {}
            }
            for el in &block.elements {
                for &n in &el.nodes {
                    if !coords.contains_key(&n) {
                        return Err(missing(el.element_tag, n));
                    }
                }
                tags.push(el.element_tag);
                nodes.extend_from_slice(&el.nodes);
            }
        } else if dim == 3 {
            return Err(GmshError::UnsupportedCell {
                path: path.to_path_buf(),
                element: el0.element_tag,
                element_type: format!("{} ({et:?})", et as i32),
                dim,
            });
        }
        for name in group_names(physicals, names, dim, tag) {
            let set = groups.entry(name.clone()).or_default();
            for el in &block.elements {
                for &n in &el.nodes {
                    if !coords.contains_key(&n) {
                        return Err(missing(el.element_tag, n));
                    }
                    set.insert(n);
                }
            }
        }
    }
    let Some((kind, _)) = first else {
        return Err(GmshError::NoCells {
            path: path.to_path_buf(),
        });
    };
    Ok((groups, SolidCells { kind, tags, nodes }))
}
