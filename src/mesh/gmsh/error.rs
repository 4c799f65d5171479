//! The errors of reading a Gmsh mesh: each names the file and what is wrong with it.

use super::*;

/// Errors when reading a Gmsh mesh. Every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum GmshError {
    /// The file could not be read (missing, no permission, ...).
    #[error("cannot read Gmsh mesh file {}: {source}", .path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The file is not MSH format version 4.1.
    #[error(
        "{}: unsupported Gmsh MSH format version {version} (only 4.1 is supported; \
         export with Mesh.MshFileVersion = 4.1, e.g. `gmsh -2 -format msh41`)",
        .path.display()
    )]
    UnsupportedVersion {
        /// The file.
        path: PathBuf,
        /// The version found in the `$MeshFormat` header.
        version: String,
    },
    /// The file is not valid MSH 4.1 (message from the `mshio` parser or from this reader).
    #[error("{}: invalid Gmsh MSH 4.1 file: {message}", .path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// What is wrong, and where.
        message: String,
    },
    /// The mesh holds no 3-node triangles.
    #[error(
        "{}: the mesh has no 3-node triangles (Gmsh element type 2); mesh the surfaces \
         in 2D (gmsh -2) with first-order triangles",
        .path.display()
    )]
    NoTriangles {
        /// The file.
        path: PathBuf,
    },
    /// A surface or volume element that is not a 3-node triangle (quads, second-order
    /// triangles, tetrahedra, ...).
    #[error(
        "{}: element {element} has unsupported type {element_type} on a {dim}D entity; \
         only 3-node triangles (type 2) are supported as cells",
        .path.display()
    )]
    UnsupportedElement {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of the (first) element of that type.
        element: u64,
        /// Gmsh element type number and name, e.g. `3 (Qua4)`.
        element_type: String,
        /// Dimension of the entity holding the element.
        dim: i32,
    },
    /// An element refers to a node tag that is not in the `$Nodes` section.
    #[error("{}: element {element} refers to node {node}, which is not in $Nodes", .path.display())]
    MissingNode {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of the element.
        element: u64,
        /// The missing Gmsh node tag.
        node: u64,
    },
    /// A section header announces more (or fewer) nodes or elements than its blocks hold.
    #[error(
        "{}: the {section} header announces {announced} {what}, its blocks hold {found}",
        .path.display()
    )]
    CountMismatch {
        /// The file.
        path: PathBuf,
        /// `$Nodes` or `$Elements`.
        section: &'static str,
        /// `nodes` or `elements`.
        what: &'static str,
        /// The count in the header.
        announced: u64,
        /// The count in the blocks.
        found: u64,
    },
    /// A node tag appears twice in `$Nodes`.
    #[error("{}: node {node} appears twice in $Nodes; node tags must be unique", .path.display())]
    DuplicateNode {
        /// The file.
        path: PathBuf,
        /// The Gmsh node tag.
        node: u64,
    },
    /// A node block repeats a node tag.
    #[error(
        "{}: the $Nodes block of entity (dim {dim}, tag {entity}) repeats a node tag: \
         {nodes} nodes, {tags} distinct tags; node tags must be unique",
        .path.display()
    )]
    DuplicateNodeInBlock {
        /// The file.
        path: PathBuf,
        /// The entity's dimension.
        dim: i32,
        /// The entity's tag.
        entity: i32,
        /// Nodes in the block.
        nodes: usize,
        /// Distinct tags among them.
        tags: usize,
    },
    /// Two nodes of different tags at the same position (an unmerged seam).
    #[error(
        "{}: nodes {first} and {second} are both at ({x}, {y}): the mesh is cut along a seam; \
         merge duplicate nodes (Gmsh: Coherence Mesh)",
        .path.display()
    )]
    CoincidentNodes {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of one node.
        first: u64,
        /// Gmsh tag of the other.
        second: u64,
        /// Their position, x.
        x: f64,
        /// Their position, y.
        y: f64,
    },
    /// A node used by no triangle (it would carry no stiffness and no mass).
    #[error(
        "{}: node {node}{group} belongs to no triangle; every node of the mesh must be a \
         triangle's vertex (remove it, or embed the point in the surface)",
        .path.display()
    )]
    UnusedNode {
        /// The file.
        path: PathBuf,
        /// Its Gmsh tag.
        node: u64,
        /// ` (group "name")` when a named group holds it, else empty.
        group: String,
    },
    /// A triangle has zero (or near-zero, relative to the mean triangle area) area.
    #[error(
        "{}: triangle {element} is degenerate: area {area:e} (mean triangle area {mean_area:e})",
        .path.display()
    )]
    DegenerateElement {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of the triangle.
        element: u64,
        /// Its signed area (counter-clockwise positive).
        area: f64,
        /// The mean absolute triangle area of the mesh.
        mean_area: f64,
    },
    /// A node off the plane `z = 0` (a 2D mesh's `z` would be dropped).
    #[error(
        "{}: node {node} is at z = {z:e}: a 2D mesh lies in the plane z = 0 (the nodes' x and y \
         reach {extent:e}; |z| up to 1e-9 of that is round-off); mesh the wheel in the xy plane",
        .path.display()
    )]
    NonPlanar {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of the node farthest off the plane.
        node: u64,
        /// Its z.
        z: f64,
        /// The largest |x| or |y| of the nodes.
        extent: f64,
    },
    /// A triangle listed twice (the same three nodes).
    #[error(
        "{}: triangles {first} and {second} have the same nodes {nodes:?}: an element listed \
         twice would count its mass and stiffness twice; remove the duplicate",
        .path.display()
    )]
    DuplicateElement {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of the first.
        first: u64,
        /// Gmsh tag of the repeat.
        second: u64,
        /// Their nodes' Gmsh tags.
        nodes: [u64; 3],
    },
    /// Two triangles on the same side of a shared edge: they overlap.
    #[error(
        "{}: triangles {first} and {second} overlap: both lie on the same side of their edge \
         from node {a} to node {b}; the triangles of a mesh must not cover an area twice",
        .path.display()
    )]
    OverlappingElements {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of one triangle.
        first: u64,
        /// Gmsh tag of the other.
        second: u64,
        /// Gmsh tag of the edge's first node.
        a: u64,
        /// Gmsh tag of the edge's second node.
        b: u64,
    },
    /// The triangles do not all have the same orientation.
    #[error(
        "{}: triangle {element} is inverted: {inverted} of {total} triangles are oriented \
         against the rest of the mesh",
        .path.display()
    )]
    InvertedElement {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of the first triangle oriented against the majority.
        element: u64,
        /// Number of triangles oriented against the majority.
        inverted: usize,
        /// Number of triangles.
        total: usize,
    },
}
