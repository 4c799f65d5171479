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
         only 3-node triangles (type 2) are supported as cells{hint}",
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
        /// Empty, or what the file is when it holds a 3D mesh (`; the file holds a 3D
        /// mesh ...`).
        hint: String,
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
    /// A 3D read found no volume cells (4-node, 10-node tetrahedra or 8-node hexahedra).
    #[error(
        "{}: the mesh has no volume cells: softway's 3D cells are 4-node tetrahedra (Gmsh \
         type 4), 10-node tetrahedra (11) and 8-node hexahedra (5); mesh the volumes (gmsh -3) \
         and, when the file has physical groups, put the volumes in one too (Gmsh saves only \
         the elements of physical groups unless Mesh.SaveAll = 1)",
        .path.display()
    )]
    NoCells {
        /// The file.
        path: PathBuf,
    },
    /// A volume element of a type softway has no cell for (prisms, pyramids, 20-node
    /// hexahedra, ...).
    #[error(
        "{}: element {element} has unsupported type {element_type} on a {dim}D entity; the 3D \
         cells are 4-node tetrahedra (type 4), 10-node tetrahedra (11) and 8-node hexahedra (5)",
        .path.display()
    )]
    UnsupportedCell {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of the (first) element of that type.
        element: u64,
        /// Gmsh element type number and name, e.g. `6 (Pri6)`.
        element_type: String,
        /// Dimension of the entity holding the element.
        dim: i32,
    },
    /// Volume cells of two kinds in one mesh.
    #[error(
        "{}: the volume cells are of two kinds: element {first} is one of the {first_kind} and \
         element {second} one of the {second_kind}; a mesh holds one kind of cell (mesh every \
         volume with the same element type and order)",
        .path.display()
    )]
    MixedCells {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of the first cell of the first kind.
        first: u64,
        /// The first kind, e.g. `4-node tetrahedra`.
        first_kind: &'static str,
        /// Gmsh tag of the first cell of the other kind.
        second: u64,
        /// The other kind.
        second_kind: &'static str,
    },
    /// A node of no volume cell (it would carry no stiffness and no mass).
    #[error(
        "{}: node {node}{group} belongs to no volume cell; every node of a 3D mesh must be a \
         node of a tetrahedron or hexahedron (remove it, or embed the point in the volume)",
        .path.display()
    )]
    UnusedSolidNode {
        /// The file.
        path: PathBuf,
        /// Its Gmsh tag.
        node: u64,
        /// ` (group "name")` when a named group holds it, else empty.
        group: String,
    },
    /// Two nodes of different tags at one position, to a tolerance relative to the mesh's
    /// extent (an unmerged seam).
    #[error(
        "{}: nodes {first} and {second} are {distance:e} apart at ({x}, {y}, {z}), within \
         {tolerance:e} (1e-9 of the mesh's extent): the mesh is cut along a seam; merge \
         duplicate nodes (Gmsh: Coherence Mesh)",
        .path.display()
    )]
    CoincidentSolidNodes {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of one node.
        first: u64,
        /// Gmsh tag of the other.
        second: u64,
        /// The first node's x.
        x: f64,
        /// Its y.
        y: f64,
        /// Its z.
        z: f64,
        /// Their distance.
        distance: f64,
        /// The tolerance: 1e-9 of the diagonal of the nodes' bounding box.
        tolerance: f64,
    },
    /// A cell of zero volume: a corner Jacobian zero up to round-off.
    #[error(
        "{}: cell {element} ({kind}) is degenerate: its corner Jacobian at node {node} is \
         {jacobian:e}, zero against its longest edge cubed {scale:e} (flat or with coincident \
         corners)",
        .path.display()
    )]
    DegenerateCell {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of the cell.
        element: u64,
        /// Its kind, e.g. `a 4-node tetrahedron`.
        kind: &'static str,
        /// Gmsh tag of the corner.
        node: u64,
        /// The corner Jacobian (six times a tetrahedron's volume).
        jacobian: f64,
        /// The cell's longest corner-to-corner distance, cubed.
        scale: f64,
    },
    /// A cell oriented against the rest of the mesh, or a hexahedron whose corner Jacobians
    /// differ in sign (tangled).
    #[error(
        "{}: cell {element} ({kind}) is inverted: {reason}",
        .path.display()
    )]
    InvertedCell {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of the cell.
        element: u64,
        /// Its kind.
        kind: &'static str,
        /// Why: against the majority (`k of n cells ...`) or tangled (`corner Jacobians of
        /// both signs ...`).
        reason: String,
    },
    /// A cell listed twice (the same corners).
    #[error(
        "{}: cells {first} and {second} have the same corners {nodes:?}: a cell listed twice \
         would count its mass and stiffness twice; remove the duplicate",
        .path.display()
    )]
    DuplicateCell {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of the first.
        first: u64,
        /// Gmsh tag of the repeat.
        second: u64,
        /// Their corners' Gmsh tags, sorted.
        nodes: Vec<u64>,
    },
    /// Two cells on the same side of a shared face (so also any face of more than two cells).
    #[error(
        "{}: cells {first} and {second} overlap: both lie on the same side of their face with \
         nodes {face:?}; a face belongs to two cells at most, one on each side",
        .path.display()
    )]
    OverlappingCells {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of one cell.
        first: u64,
        /// Gmsh tag of the other.
        second: u64,
        /// The face's corners' Gmsh tags.
        face: Vec<u64>,
    },
    /// The mesh is in several pieces (no face, edge or node joins them).
    #[error(
        "{}: the mesh is in {pieces} pieces: node {node} is in a piece of {size} nodes with no \
         node in common with the piece of node {first}; join them (Gmsh: Coherence Mesh, or \
         fragment the volumes), or read the file as several bodies",
        .path.display()
    )]
    Disconnected {
        /// The file.
        path: PathBuf,
        /// Number of pieces.
        pieces: usize,
        /// The smallest Gmsh node tag of the mesh (in the first piece).
        first: u64,
        /// The smallest Gmsh node tag of the second piece.
        node: u64,
        /// The second piece's node count.
        size: usize,
    },
    /// A 10-node tetrahedron's mid-edge node far from its edge's middle (a wrong node order).
    #[error(
        "{}: cell {element} (a 10-node tetrahedron): its mid-edge node {node} (position {position} \
         in the cell) is {distance:e} from the middle of its edge from node {a} to node {b} \
         (length {length:e}); beyond a quarter of the edge the quadratic map folds: check the \
         node order (Gmsh's: edges 0-1, 1-2, 2-0, 0-3, 2-3, 1-3; VTK swaps the last two)",
        .path.display()
    )]
    MidEdgeNode {
        /// The file.
        path: PathBuf,
        /// Gmsh tag of the cell.
        element: u64,
        /// Gmsh tag of the mid-edge node.
        node: u64,
        /// Its position among the cell's ten nodes (4 to 9).
        position: usize,
        /// Gmsh tag of the edge's first corner.
        a: u64,
        /// Gmsh tag of its second corner.
        b: u64,
        /// The node's distance from the edge's middle.
        distance: f64,
        /// The edge's length.
        length: f64,
    },
}
