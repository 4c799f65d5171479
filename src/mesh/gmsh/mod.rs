//! Import of Gmsh `.msh` meshes (MSH format 4.1, ASCII or binary).
//!
//! [`read_msh`] reads a 2D triangle mesh: the 3-node triangles (Gmsh element type 2) become
//! the cells ([`Cells::Tri3`]), in the plane `z = 0` (a node off it beyond round-off, 1e-9 of
//! the mesh's extent, is an error naming it: its `z` would be dropped), and every *named*
//! physical group
//! (`$PhysicalNames`) becomes a node set of that name holding all nodes of the entities
//! tagged with it, whatever their dimension (points at the centre, curves on the rim,
//! surfaces). Points and lines are used only for these groups, never as cells.
//!
//! Nodes are renumbered compactly (`0..n`, in increasing Gmsh node tag order), so sparse
//! Gmsh node tags are fine. Every node must be a vertex of a triangle (a node of no triangle
//! would carry neither mass nor stiffness), node tags must be unique, no two nodes may share
//! a position (an unmerged seam), and the `$Nodes` and `$Elements` headers must announce
//! as many nodes and elements as their blocks hold: each is an error naming the node.
//!
//! Orientation: if all triangles are clockwise they are all reversed; a triangle of (near)
//! zero area, or a mesh with triangles of both orientations, is an error naming the Gmsh
//! element tag. So is a triangle listed twice (the same three nodes: its mass and stiffness
//! would count twice) and two triangles that overlap (on the same side of a shared edge).
//!
//! 3D meshes (4-node and 10-node tetrahedra, 8-node hexahedra) are read by
//! [`read_msh_3d`], and [`read_msh_any`] reads whichever a file holds (3D if it has volume
//! elements, else 2D as above); what they read and check is in [`solid`]. The 2D reader
//! refuses a 3D file, saying that it is one.
//!
//! Parsing goes through the [`mshio`] crate; the `$PhysicalNames` section (which `mshio`
//! skips) is read here. Export from Gmsh with `Mesh.MshFileVersion = 4.1` (the default in
//! Gmsh 4) and `-2` (2D mesh), for example `gmsh -2 -format msh41 disk.geo`.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

use mshio::{ElementType, MshFile, MshParserError};

use super::{Cells, Mesh};

mod bytes;
mod error;
pub mod solid;
mod solid_checks;
use bytes::*;
pub use error::GmshError;
pub use solid::{
    parse_msh_3d, parse_msh_3d_tagged, parse_msh_any_tagged, pieces, read_msh_3d,
    read_msh_3d_tagged, read_msh_3d_with, read_msh_any, read_msh_any_tagged, SolidOptions,
};

/// Reads a Gmsh MSH 4.1 file (ASCII or binary) as a 2D triangle mesh.
///
/// See the [module documentation](self) for what is read and how.
///
/// # Errors
/// A [`GmshError`] naming the file: [`GmshError::Io`] if it cannot be read,
/// [`GmshError::UnsupportedVersion`] for other MSH versions, [`GmshError::Parse`] for
/// malformed content, [`GmshError::NoTriangles`], [`GmshError::UnsupportedElement`],
/// [`GmshError::MissingNode`], [`GmshError::DegenerateElement`] and
/// [`GmshError::InvertedElement`] for unusable meshes.
pub fn read_msh(path: &Path) -> Result<Mesh, GmshError> {
    read_msh_tagged(path).map(|(mesh, _)| mesh)
}

/// [`read_msh`], with the Gmsh tag of every node (`tags[i]` is node `i`'s), for messages
/// that name a node as the user's file does.
///
/// # Errors
/// As [`read_msh`].
pub fn read_msh_tagged(path: &Path) -> Result<(Mesh, Vec<u64>), GmshError> {
    parse_msh_tagged(&read_bytes(path)?, path)
}

/// The bytes of the file `path`, refusing a device or a pipe (which could be read forever).
fn read_bytes(path: &Path) -> Result<Vec<u8>, GmshError> {
    let io = |source| GmshError::Io {
        path: path.to_path_buf(),
        source,
    };
    // A device (/dev/zero) or a pipe could be read forever.
    let meta = std::fs::metadata(path).map_err(io)?;
    if !meta.is_file() && !meta.is_dir() {
        return Err(io(std::io::Error::other(
            "not a regular file (a device or a pipe)",
        )));
    }
    std::fs::read(path).map_err(io)
}

/// Relative area below which a triangle counts as degenerate.
const DEGENERATE_RELATIVE_AREA: f64 = 1e-12;

/// Parses the bytes of a MSH 4.1 file (ASCII or binary) as [`read_msh`] does; `path` only
/// names the file in errors.
///
/// # Errors
/// The [`GmshError`]s of [`read_msh`] but [`GmshError::Io`].
pub fn parse_msh(bytes: &[u8], path: &Path) -> Result<Mesh, GmshError> {
    parse_msh_tagged(bytes, path).map(|(mesh, _)| mesh)
}

/// [`parse_msh`] with the node tags, as [`read_msh_tagged`].
///
/// # Errors
/// As [`parse_msh`].
pub fn parse_msh_tagged(bytes: &[u8], path: &Path) -> Result<(Mesh, Vec<u64>), GmshError> {
    let (msh, names) = parse_file(bytes, path)?;
    build_mesh(&msh, &names, path)
}

/// The parsed file and its physical names `(dim, tag) -> name`.
type Parsed = (MshFile<u64, i32, f64>, BTreeMap<(i32, i32), String>);

/// Parses the bytes of a MSH 4.1 file: the header checked, the physical names read, the
/// `$Nodes` header repaired for `mshio`, then `mshio`'s parse (no panic escapes).
fn parse_file(bytes: &[u8], path: &Path) -> Result<Parsed, GmshError> {
    let parse_err = |message: String| GmshError::Parse {
        path: path.to_path_buf(),
        message,
    };

    let header = read_header(bytes).map_err(|e| match e {
        HeaderError::Version(version) => GmshError::UnsupportedVersion {
            path: path.to_path_buf(),
            version,
        },
        HeaderError::Invalid(message) => parse_err(message),
    })?;

    let names = read_physical_names(bytes).map_err(parse_err)?;

    // Counts of the $Nodes and $Elements sections, checked before mshio sees them (it
    // cannot handle empty sections), and the $Nodes header patched so that mshio keeps the
    // node tags (it drops them when they are contiguous, assuming they are in file order).
    let mut patched = None;
    if let Some(counts) = section_counts(bytes, "$Nodes", &header) {
        if counts.count == 0 {
            return Err(GmshError::NoTriangles {
                path: path.to_path_buf(),
            });
        }
        let mut copy = bytes.to_vec();
        if patch_max_tag(&mut copy, &counts, &header) {
            patched = Some(copy);
        }
    }
    if let Some(counts) = section_counts(bytes, "$Elements", &header) {
        if counts.count == 0 {
            return Err(GmshError::NoTriangles {
                path: path.to_path_buf(),
            });
        }
    }
    let input: &[u8] = patched.as_deref().unwrap_or(bytes);

    // mshio should not panic on the input checked above; catch it anyway so that a bad file
    // can never bring the program down.
    let parsed = std::panic::catch_unwind(|| {
        mshio::parse_msh_bytes(input).map_err(|e| describe_parse_error(&e, input, header.binary))
    });
    let msh = match parsed {
        Ok(Ok(msh)) => msh,
        Ok(Err(message)) => return Err(parse_err(message)),
        Err(_) => {
            return Err(parse_err(
                "internal error in the MSH parser (mshio panicked)".to_string(),
            ))
        }
    };
    Ok((msh, names))
}

/// Builds the mesh from the parsed file and the physical names `(dim, tag) -> name`.
fn build_mesh(
    msh: &MshFile<u64, i32, f64>,
    names: &BTreeMap<(i32, i32), String>,
    path: &Path,
) -> Result<(Mesh, Vec<u64>), GmshError> {
    check_counts(msh, path)?;
    let (coords, entity_nodes) = node_coordinates(msh, path)?;
    let physicals = entity_physicals(msh);
    let (mut groups, triangles) = groups_and_triangles(msh, names, &physicals, &coords, path)?;
    if triangles.is_empty() {
        return Err(GmshError::NoTriangles {
            path: path.to_path_buf(),
        });
    }
    check_planar(msh, path)?;
    // Nodes classified on a grouped entity (e.g. a physical point without a point element).
    for (&(dim, tag), list) in &entity_nodes {
        for name in group_names(&physicals, names, dim, tag) {
            groups.entry(name.clone()).or_default().extend(list);
        }
    }
    let used = check_nodes(&coords, &triangles, &groups, path)?;

    // Compact renumbering in increasing tag order.
    let index: HashMap<u64, usize> = used.iter().enumerate().map(|(i, &t)| (t, i)).collect();
    let xy: Vec<f64> = used
        .iter()
        .flat_map(|t| {
            let [x, y, _] = coords.get(t).copied().unwrap_or([f64::NAN; 3]);
            [x, y]
        })
        .collect();
    let idx = |t: &u64| index.get(t).copied().unwrap_or(0);
    let mut cells: Vec<[usize; 3]> = triangles
        .iter()
        .map(|(_, t)| [idx(&t[0]), idx(&t[1]), idx(&t[2])])
        .collect();

    orient(&mut cells, &xy, &triangles, path)?;
    check_overlaps(&cells, &triangles, &used, path)?;

    let node_sets = groups
        .into_iter()
        .map(|(name, set)| {
            let mut v: Vec<usize> = set.iter().map(idx).collect();
            v.sort_unstable();
            v.dedup();
            (name, v)
        })
        .collect();

    Ok((
        Mesh::new(2, xy, Cells::Tri3(cells), node_sets),
        used.into_iter().collect(),
    ))
}

/// The headers' counts of nodes and elements against the blocks'.
fn check_counts(msh: &MshFile<u64, i32, f64>, path: &Path) -> Result<(), GmshError> {
    let mismatch = |section, what, announced: u64, found: usize| {
        let found = found as u64;
        (announced != found).then(|| GmshError::CountMismatch {
            path: path.to_path_buf(),
            section,
            what,
            announced,
            found,
        })
    };
    if let Some(nodes) = &msh.data.nodes {
        let found = nodes.node_blocks.iter().map(|b| b.nodes.len()).sum();
        if let Some(e) = mismatch("$Nodes", "nodes", nodes.num_nodes, found) {
            return Err(e);
        }
    }
    if let Some(elements) = &msh.data.elements {
        let found = elements
            .element_blocks
            .iter()
            .map(|b| b.elements.len())
            .sum();
        if let Some(e) = mismatch("$Elements", "elements", elements.num_elements, found) {
            return Err(e);
        }
    }
    Ok(())
}

/// Node coordinates (x, y, z) by Gmsh tag.
type Coords = HashMap<u64, [f64; 3]>;

/// The Gmsh tags of the nodes of each entity's node block, by `(dim, tag)`.
type EntityNodes = HashMap<(i32, i32), Vec<u64>>;

/// The named groups: the Gmsh tags of their nodes by name.
type Groups = BTreeMap<String, BTreeSet<u64>>;

/// The triangles: each with its Gmsh element tag and its nodes' tags.
type Triangles = Vec<(u64, [u64; 3])>;

/// Node coordinates by tag (each tag once), and the nodes of each entity's node block.
fn node_coordinates(
    msh: &MshFile<u64, i32, f64>,
    path: &Path,
) -> Result<(Coords, EntityNodes), GmshError> {
    let mut coords: Coords = HashMap::new();
    let mut entity_nodes: HashMap<(i32, i32), Vec<u64>> = HashMap::new();
    if let Some(nodes) = &msh.data.nodes {
        let mut next_tag = nodes.min_node_tag;
        for block in &nodes.node_blocks {
            let list = entity_nodes
                .entry((block.entity_dim, block.entity_tag))
                .or_default();
            match &block.node_tags {
                Some(tags) => {
                    if tags.len() < block.nodes.len() {
                        // mshio keeps the tags in a map: a repeated tag shrinks it.
                        return Err(GmshError::DuplicateNodeInBlock {
                            path: path.to_path_buf(),
                            dim: block.entity_dim,
                            entity: block.entity_tag,
                            nodes: block.nodes.len(),
                            tags: tags.len(),
                        });
                    }
                    for (&tag, &i) in tags {
                        if let Some(n) = block.nodes.get(i) {
                            if coords.insert(tag, [n.x, n.y, n.z]).is_some() {
                                return Err(GmshError::DuplicateNode {
                                    path: path.to_path_buf(),
                                    node: tag,
                                });
                            }
                            list.push(tag);
                        }
                    }
                }
                None => {
                    // Contiguous tags, in file order.
                    for n in &block.nodes {
                        if coords.insert(next_tag, [n.x, n.y, n.z]).is_some() {
                            return Err(GmshError::DuplicateNode {
                                path: path.to_path_buf(),
                                node: next_tag,
                            });
                        }
                        list.push(next_tag);
                        next_tag = next_tag.saturating_add(1);
                    }
                }
            }
        }
    }
    Ok((coords, entity_nodes))
}

/// The physical tags of each entity `(dim, tag)`.
fn entity_physicals(msh: &MshFile<u64, i32, f64>) -> HashMap<(i32, i32), Vec<i32>> {
    let mut entity_physicals: HashMap<(i32, i32), Vec<i32>> = HashMap::new();
    if let Some(entities) = &msh.data.entities {
        for p in &entities.points {
            entity_physicals.insert((0, p.tag), p.physical_tags.clone());
        }
        for c in &entities.curves {
            entity_physicals.insert((1, c.tag), c.physical_tags.clone());
        }
        for s in &entities.surfaces {
            entity_physicals.insert((2, s.tag), s.physical_tags.clone());
        }
        for v in &entities.volumes {
            entity_physicals.insert((3, v.tag), v.physical_tags.clone());
        }
    }
    entity_physicals
}

/// The names of the physical groups of the entity `(dim, tag)`.
fn group_names<'a>(
    entity_physicals: &HashMap<(i32, i32), Vec<i32>>,
    names: &'a BTreeMap<(i32, i32), String>,
    dim: i32,
    tag: i32,
) -> Vec<&'a String> {
    entity_physicals
        .get(&(dim, tag))
        .map(|phys| {
            phys.iter()
                .filter_map(|&p| names.get(&(dim, p)).or_else(|| names.get(&(dim, -p))))
                .collect()
        })
        .unwrap_or_default()
}

/// The named groups (possibly empty) with the nodes of their elements, and the triangles
/// with their Gmsh tags; an element on a node without coordinates, or a surface element
/// other than a 3-node triangle, is an error.
fn groups_and_triangles(
    msh: &MshFile<u64, i32, f64>,
    names: &BTreeMap<(i32, i32), String>,
    physicals: &HashMap<(i32, i32), Vec<i32>>,
    coords: &Coords,
    path: &Path,
) -> Result<(Groups, Triangles), GmshError> {
    let missing = |element: u64, node: u64| GmshError::MissingNode {
        path: path.to_path_buf(),
        element,
        node,
    };
    let mut groups: BTreeMap<String, BTreeSet<u64>> = names
        .values()
        .map(|name| (name.clone(), BTreeSet::new()))
        .collect();
    let mut triangles: Vec<(u64, [u64; 3])> = Vec::new();
    if let Some(elements) = &msh.data.elements {
        for block in &elements.element_blocks {
            let (dim, tag) = (block.entity_dim, block.entity_tag);
            if block.element_type == ElementType::Tri3 {
                for el in &block.elements {
                    if let [a, b, c] = el.nodes[..] {
                        for n in [a, b, c] {
                            if !coords.contains_key(&n) {
                                return Err(missing(el.element_tag, n));
                            }
                        }
                        triangles.push((el.element_tag, [a, b, c]));
                    }
                }
            } else if dim >= 2 {
                if let Some(el) = block.elements.first() {
                    let et = block.element_type;
                    return Err(GmshError::UnsupportedElement {
                        path: path.to_path_buf(),
                        element: el.element_tag,
                        element_type: format!("{} ({et:?})", et as i32),
                        dim,
                        hint: if dim == 3 || solid::cell_kind(et).is_some() {
                            "; the file holds a 3D mesh (volume elements), and a 2D model \
                             takes triangles in the plane z = 0"
                                .to_string()
                        } else {
                            String::new()
                        },
                    });
                }
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
    }
    Ok((groups, triangles))
}

/// The nodes of the triangles, in increasing tag order; every node must be a triangle's
/// vertex and no two at one position.
fn check_nodes(
    coords: &Coords,
    triangles: &[(u64, [u64; 3])],
    groups: &Groups,
    path: &Path,
) -> Result<BTreeSet<u64>, GmshError> {
    let used: BTreeSet<u64> = triangles.iter().flat_map(|(_, t)| *t).collect();
    if let Some(&node) = coords.keys().filter(|t| !used.contains(t)).min() {
        let group = groups
            .iter()
            .find(|(_, set)| set.contains(&node))
            .map(|(name, _)| format!(" (group \"{name}\")"))
            .unwrap_or_default();
        return Err(GmshError::UnusedNode {
            path: path.to_path_buf(),
            node,
            group,
        });
    }
    let mut by_position: Vec<(u64, [f64; 2])> = used
        .iter()
        .map(|t| {
            let [x, y, _] = coords.get(t).copied().unwrap_or([f64::NAN; 3]);
            (*t, [x, y])
        })
        .collect();
    by_position.sort_by(|a, b| a.1[0].total_cmp(&b.1[0]).then(a.1[1].total_cmp(&b.1[1])));
    if let Some(w) = by_position.windows(2).find(|w| w[0].1 == w[1].1) {
        let (a, b) = (w[0].0.min(w[1].0), w[0].0.max(w[1].0));
        return Err(GmshError::CoincidentNodes {
            path: path.to_path_buf(),
            first: a,
            second: b,
            x: w[0].1[0],
            y: w[0].1[1],
        });
    }
    Ok(used)
}

/// Relative `|z|` (to the largest `|x|`, `|y|`) beyond which a node is off the plane.
const PLANAR_RELATIVE_Z: f64 = 1e-9;

/// Every node in the plane `z = 0`, to [`PLANAR_RELATIVE_Z`] of the nodes' extent in x and
/// y.
fn check_planar(msh: &MshFile<u64, i32, f64>, path: &Path) -> Result<(), GmshError> {
    let Some(nodes) = &msh.data.nodes else {
        return Ok(());
    };
    let mut extent = 0.0f64;
    // (|z|, block, index in the block) of the node farthest off the plane.
    let mut worst: Option<(f64, usize, usize)> = None;
    for (b, block) in nodes.node_blocks.iter().enumerate() {
        for (i, n) in block.nodes.iter().enumerate() {
            extent = extent.max(n.x.abs()).max(n.y.abs());
            // A NaN z counts as off the plane (f64::max skips NaN x and y).
            let z = if n.z.is_nan() {
                f64::INFINITY
            } else {
                n.z.abs()
            };
            if worst.is_none_or(|w| z > w.0) {
                worst = Some((z, b, i));
            }
        }
    }
    let Some((z, b, i)) = worst.filter(|w| w.0 > PLANAR_RELATIVE_Z * extent) else {
        return Ok(());
    };
    // The node's tag: its block's tag map, else the contiguous tags in file order.
    let block = &nodes.node_blocks[b];
    let tag = match &block.node_tags {
        Some(tags) => tags.iter().find(|(_, &k)| k == i).map(|(&t, _)| t),
        None => {
            let before: usize = nodes.node_blocks[..b].iter().map(|x| x.nodes.len()).sum();
            Some(nodes.min_node_tag + (before + i) as u64)
        }
    };
    Err(GmshError::NonPlanar {
        path: path.to_path_buf(),
        node: tag.unwrap_or(0),
        z: if z.is_finite() {
            block.nodes[i].z
        } else {
            f64::NAN
        },
        extent,
    })
}

/// No triangle listed twice and no two triangles overlapping: once all counter-clockwise,
/// every directed edge belongs to one triangle at most. `used` are the node tags in compact
/// order (for messages).
fn check_overlaps(
    cells: &[[usize; 3]],
    triangles: &[(u64, [u64; 3])],
    used: &BTreeSet<u64>,
    path: &Path,
) -> Result<(), GmshError> {
    let mut same: HashMap<[usize; 3], usize> = HashMap::with_capacity(cells.len());
    for (k, c) in cells.iter().enumerate() {
        let mut key = *c;
        key.sort_unstable();
        if let Some(&first) = same.get(&key) {
            let mut nodes = triangles[first].1;
            nodes.sort_unstable();
            return Err(GmshError::DuplicateElement {
                path: path.to_path_buf(),
                first: triangles[first].0,
                second: triangles[k].0,
                nodes,
            });
        }
        same.insert(key, k);
    }
    let tags: Vec<u64> = used.iter().copied().collect();
    let mut edges: HashMap<(usize, usize), usize> = HashMap::with_capacity(3 * cells.len());
    for (k, c) in cells.iter().enumerate() {
        for (a, b) in [(c[0], c[1]), (c[1], c[2]), (c[2], c[0])] {
            if let Some(&first) = edges.get(&(a, b)) {
                return Err(GmshError::OverlappingElements {
                    path: path.to_path_buf(),
                    first: triangles[first].0,
                    second: triangles[k].0,
                    a: tags.get(a).copied().unwrap_or(a as u64),
                    b: tags.get(b).copied().unwrap_or(b as u64),
                });
            }
            edges.insert((a, b), k);
        }
    }
    Ok(())
}

/// Checks the triangle areas and makes all triangles counter-clockwise (see the module
/// documentation); `xy` holds the nodes' flat planar coordinates. `triangles` gives the
/// Gmsh tag of each cell, for errors.
fn orient(
    cells: &mut [[usize; 3]],
    xy: &[f64],
    triangles: &[(u64, [u64; 3])],
    path: &Path,
) -> Result<(), GmshError> {
    let area = |t: &[usize; 3]| {
        let p = |i: usize| match xy.get(2 * t[i]..2 * t[i] + 2) {
            Some(&[x, y]) => [x, y],
            _ => [f64::NAN; 2],
        };
        let (a, b, c) = (p(0), p(1), p(2));
        0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
    };
    let areas: Vec<f64> = cells.iter().map(area).collect();
    let mean_area = areas.iter().map(|a| a.abs()).sum::<f64>() / areas.len().max(1) as f64;
    let tol = DEGENERATE_RELATIVE_AREA * mean_area;
    for (k, &a) in areas.iter().enumerate() {
        // NaN areas (from NaN coordinates) count as degenerate.
        if a.is_nan() || a.abs() <= tol {
            return Err(GmshError::DegenerateElement {
                path: path.to_path_buf(),
                element: triangles[k].0,
                area: a,
                mean_area,
            });
        }
    }
    let positive = areas.iter().filter(|&&a| a > 0.0).count();
    let negative = areas.len() - positive;
    if negative == 0 {
        return Ok(());
    }
    if positive == 0 {
        for c in cells.iter_mut() {
            c.swap(1, 2);
        }
        return Ok(());
    }
    // Mixed: the minority orientation is inverted.
    let majority_positive = positive >= negative;
    let first = areas
        .iter()
        .position(|&a| (a > 0.0) != majority_positive)
        .unwrap_or(0);
    Err(GmshError::InvertedElement {
        path: path.to_path_buf(),
        element: triangles[first].0,
        inverted: positive.min(negative),
        total: areas.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A temporary directory removed on drop.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(name: &str) -> Self {
            let dir = std::env::temp_dir()
                .join(format!("softway-gmsh-test-{}-{name}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).unwrap();
            TempDir(dir)
        }
        fn write(&self, file: &str, content: &[u8]) -> PathBuf {
            let p = self.0.join(file);
            std::fs::write(&p, content).unwrap();
            p
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    /// Node coordinates of the unit square test mesh: 4 corners and the centre.
    const XY: [[f64; 2]; 5] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]];

    /// The unit square, split into 4 triangles around its centre, as ASCII MSH 4.1.
    ///
    /// `tags[i]` is the Gmsh tag of node `XY[i]`; `tris` are the triangles (element tags
    /// 3, 4, ...) as indices into `XY`. Physical groups: "corner" (point 1, physical 1),
    /// "bottom" (curve 1, physical 1), "body" (surface 1, physical 2), and an unnamed
    /// physical group 7 on curve 3.
    fn square_ascii(tags: [u64; 5], tris: &[[usize; 3]]) -> String {
        let mut s = String::from(
            "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
             $PhysicalNames\n3\n0 1 \"corner\"\n1 1 \"bottom\"\n2 2 \"body\"\n$EndPhysicalNames\n\
             $Entities\n4 4 1 0\n\
             1 0 0 0 1 1\n2 1 0 0 0\n3 1 1 0 0\n4 0 1 0 0\n\
             1 0 0 0 1 0 0 1 1 2 1 -2\n\
             2 1 0 0 1 1 0 0 2 2 -3\n\
             3 0 1 0 1 1 0 1 7 2 3 -4\n\
             4 0 0 0 0 1 0 0 2 4 -1\n\
             1 0 0 0 1 1 0 1 2 4 1 2 3 4\n\
             $EndEntities\n",
        );
        let (min, max) = (tags.iter().min().unwrap(), tags.iter().max().unwrap());
        s += &format!("$Nodes\n9 5 {min} {max}\n");
        for p in 0..4 {
            let [x, y] = XY[p];
            s += &format!("0 {} 0 1\n{}\n{x} {y} 0\n", p + 1, tags[p]);
        }
        for c in 1..=4 {
            s += &format!("1 {c} 0 0\n");
        }
        s += &format!("2 1 0 1\n{}\n0.5 0.5 0\n$EndNodes\n", tags[4]);
        let n_el = 3 + tris.len();
        s += &format!("$Elements\n4 {n_el} 1 {n_el}\n");
        s += &format!("0 1 15 1\n1 {}\n", tags[0]);
        s += &format!("1 1 1 1\n2 {} {}\n", tags[0], tags[1]);
        s += &format!("1 3 1 1\n{} {} {}\n", n_el, tags[2], tags[3]);
        s += &format!("2 1 2 {}\n", tris.len());
        for (k, t) in tris.iter().enumerate() {
            s += &format!("{} {} {} {}\n", k + 3, tags[t[0]], tags[t[1]], tags[t[2]]);
        }
        s += "$EndElements\n";
        s
    }

    /// The same mesh as [`square_ascii`] (without the unnamed group), in binary MSH 4.1.
    fn square_binary(tags: [u64; 5], tris: &[[usize; 3]], little: bool) -> Vec<u8> {
        let mut b: Vec<u8> = Vec::new();
        let int = |b: &mut Vec<u8>, v: i32| {
            b.extend(if little {
                v.to_le_bytes()
            } else {
                v.to_be_bytes()
            })
        };
        let size = |b: &mut Vec<u8>, v: u64| {
            b.extend(if little {
                v.to_le_bytes()
            } else {
                v.to_be_bytes()
            })
        };
        let dbl = |b: &mut Vec<u8>, v: f64| {
            b.extend(if little {
                v.to_le_bytes()
            } else {
                v.to_be_bytes()
            })
        };
        b.extend(b"$MeshFormat\n4.1 1 8\n");
        int(&mut b, 1);
        b.extend(b"\n$EndMeshFormat\n");
        b.extend(b"$PhysicalNames\n3\n0 1 \"corner\"\n1 1 \"bottom\"\n2 2 \"body\"\n");
        b.extend(b"$EndPhysicalNames\n$Entities\n");
        for n in [4, 4, 1, 0] {
            size(&mut b, n);
        }
        for (p, xy) in XY.iter().take(4).enumerate() {
            int(&mut b, p as i32 + 1);
            dbl(&mut b, xy[0]);
            dbl(&mut b, xy[1]);
            dbl(&mut b, 0.0);
            if p == 0 {
                size(&mut b, 1);
                int(&mut b, 1);
            } else {
                size(&mut b, 0);
            }
        }
        for c in 0..4usize {
            int(&mut b, c as i32 + 1);
            for v in [0.0, 0.0, 0.0, 1.0, 1.0, 0.0] {
                dbl(&mut b, v);
            }
            if c == 0 {
                size(&mut b, 1);
                int(&mut b, 1);
            } else {
                size(&mut b, 0);
            }
            size(&mut b, 2);
            int(&mut b, c as i32 + 1);
            int(&mut b, -(((c + 1) % 4) as i32 + 1));
        }
        int(&mut b, 1);
        for v in [0.0, 0.0, 0.0, 1.0, 1.0, 0.0] {
            dbl(&mut b, v);
        }
        size(&mut b, 1);
        int(&mut b, 2);
        size(&mut b, 4);
        for c in 1..=4 {
            int(&mut b, c);
        }
        b.extend(b"\n$EndEntities\n$Nodes\n");
        let (min, max) = (*tags.iter().min().unwrap(), *tags.iter().max().unwrap());
        for v in [5, 5, min, max] {
            size(&mut b, v);
        }
        let block = |b: &mut Vec<u8>, dim: i32, tag: i32, nodes: &[usize]| {
            int(b, dim);
            int(b, tag);
            int(b, 0);
            size(b, nodes.len() as u64);
            for &n in nodes {
                size(b, tags[n]);
            }
            for &n in nodes {
                dbl(b, XY[n][0]);
                dbl(b, XY[n][1]);
                dbl(b, 0.0);
            }
        };
        for p in 0..4 {
            block(&mut b, 0, p as i32 + 1, &[p]);
        }
        block(&mut b, 2, 1, &[4]);
        b.extend(b"\n$EndNodes\n$Elements\n");
        let n_el = 2 + tris.len() as u64;
        for v in [3, n_el, 1, n_el] {
            size(&mut b, v);
        }
        for v in [0, 1, 15] {
            int(&mut b, v);
        }
        size(&mut b, 1);
        size(&mut b, 1);
        size(&mut b, tags[0]);
        for v in [1, 1, 1] {
            int(&mut b, v);
        }
        size(&mut b, 1);
        for v in [2, tags[0], tags[1]] {
            size(&mut b, v);
        }
        for v in [2, 1, 2] {
            int(&mut b, v);
        }
        size(&mut b, tris.len() as u64);
        for (k, t) in tris.iter().enumerate() {
            for v in [k as u64 + 3, tags[t[0]], tags[t[1]], tags[t[2]]] {
                size(&mut b, v);
            }
        }
        b.extend(b"\n$EndElements\n");
        b
    }

    const CCW: [[usize; 3]; 4] = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
    const TAGS: [u64; 5] = [1, 2, 3, 4, 5];

    fn signed_area(m: &Mesh, t: [usize; 3]) -> f64 {
        let [a, b, c] = t.map(|i| m.point(i));
        0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
    }

    fn tris(m: &Mesh) -> Vec<[usize; 3]> {
        match &m.cells {
            Cells::Tri3(t) => t.clone(),
            _ => panic!("expected triangles"),
        }
    }

    /// The index of the node at `xy`.
    fn node_at(m: &Mesh, xy: [f64; 2]) -> usize {
        m.points().position(|p| p == xy).expect("node")
    }

    /// Checks the square mesh read back: counts, coordinates, sets, orientation.
    fn check_square(m: &Mesh) {
        assert_eq!(m.dim, 2);
        assert_eq!(m.n_nodes(), 5);
        assert_eq!(m.cells.len(), 4);
        for p in XY {
            node_at(m, p);
        }
        let mut total = 0.0;
        for t in tris(m) {
            let a = signed_area(m, t);
            assert!(a > 0.0, "triangle {t:?} area {a}");
            total += a;
            assert!(t.contains(&node_at(m, [0.5, 0.5])));
        }
        assert!((total - 1.0).abs() < 1e-14);
        let set = |name: &str, xy: &[[f64; 2]]| {
            let mut expect: Vec<usize> = xy.iter().map(|&p| node_at(m, p)).collect();
            expect.sort_unstable();
            assert_eq!(m.node_set(name), Some(expect.as_slice()), "set {name}");
        };
        set("bottom", &[[0.0, 0.0], [1.0, 0.0]]);
        set("corner", &[[0.0, 0.0]]);
        set("body", &XY);
        assert_eq!(m.node_sets.len(), 3, "{:?}", m.node_sets.keys());
    }

    #[test]
    fn ascii_square_counts_sets_orientation() {
        let dir = TempDir::new("ascii");
        let p = dir.write("square.msh", square_ascii(TAGS, &CCW).as_bytes());
        let m = read_msh(&p).unwrap();
        check_square(&m);
        // Tags 1..5 in increasing order: the node order is kept.
        assert_eq!(m.coords, XY.concat());
        assert_eq!(tris(&m), CCW.to_vec());
        assert_eq!(m.node_set("bottom"), Some(&[0, 1][..]));
    }

    #[test]
    fn two_triangles_and_eight_triangles() {
        let dir = TempDir::new("two-eight");
        // Two triangles: the centre node is used only by the "body" group's node block; a
        // node of no triangle carries no mass nor stiffness: an error naming it.
        let two = [[0, 1, 2], [0, 2, 3]];
        let p = dir.write("two.msh", square_ascii(TAGS, &two).as_bytes());
        let e = read_msh(&p).unwrap_err();
        assert!(matches!(e, GmshError::UnusedNode { .. }), "{e}");

        // Eight triangles on a 3 x 3 node grid, one node block, no named boundary groups.
        let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
        s += "$PhysicalNames\n1\n2 1 \"body\"\n$EndPhysicalNames\n";
        s += "$Entities\n0 0 1 0\n1 0 0 0 1 1 0 1 1 0\n$EndEntities\n";
        s += "$Nodes\n1 9 1 9\n2 1 0 9\n";
        for k in 1..=9 {
            s += &format!("{k}\n");
        }
        for j in 0..3 {
            for i in 0..3 {
                s += &format!("{} {} 0\n", i as f64 / 2.0, j as f64 / 2.0);
            }
        }
        s += "$EndNodes\n$Elements\n1 8 1 8\n2 1 2 8\n";
        let mut e = 1;
        for j in 0..2 {
            for i in 0..2 {
                let n = |i: usize, j: usize| 1 + i + 3 * j;
                s += &format!("{e} {} {} {}\n", n(i, j), n(i + 1, j), n(i + 1, j + 1));
                s += &format!(
                    "{} {} {} {}\n",
                    e + 1,
                    n(i, j),
                    n(i + 1, j + 1),
                    n(i, j + 1)
                );
                e += 2;
            }
        }
        s += "$EndElements\n";
        let p = dir.write("eight.msh", s.as_bytes());
        let m = read_msh(&p).unwrap();
        assert_eq!((m.n_nodes(), m.cells.len()), (9, 8));
        assert_eq!(m.node_set("body").unwrap(), &(0..9).collect::<Vec<_>>()[..]);
        let total: f64 = tris(&m).into_iter().map(|t| signed_area(&m, t)).sum();
        assert!((total - 1.0).abs() < 1e-14);
    }

    #[test]
    fn sparse_and_permuted_tags() {
        let dir = TempDir::new("tags");
        // Sparse tags.
        let p = dir.write(
            "sparse.msh",
            square_ascii([101, 7, 33, 2000, 5], &CCW).as_bytes(),
        );
        let m = read_msh(&p).unwrap();
        check_square(&m);
        // Renumbered by increasing tag: 5 (centre), 7, 33, 101, 2000.
        assert_eq!(m.point(0), [0.5, 0.5]);
        assert_eq!(m.point(4), [0.0, 1.0]);
        // Contiguous tags 1..=5, but not in file order: mshio would drop them.
        let p = dir.write(
            "permuted.msh",
            square_ascii([5, 4, 3, 2, 1], &CCW).as_bytes(),
        );
        let m = read_msh(&p).unwrap();
        check_square(&m);
        assert_eq!(
            m.coords,
            [[0.5, 0.5], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]].concat()
        );
    }

    /// Regression (issue 12): a repeated node tag, a node of no triangle, two nodes at one
    /// place and a header announcing more nodes than its blocks hold were read silently
    /// (the later node won, the lone node made a singular model, the seam cut the mesh).
    #[test]
    fn duplicate_unused_coincident_nodes_and_false_counts_are_errors() {
        let bytes = square_ascii([1, 2, 3, 4, 1], &CCW);
        let e = parse_msh(bytes.as_bytes(), Path::new("dup.msh")).unwrap_err();
        assert!(matches!(e, GmshError::DuplicateNode { node: 1, .. }), "{e}");
        let two = [[0, 1, 2], [0, 2, 3]];
        let e = parse_msh(
            square_ascii([1, 2, 3, 4, 5], &two).as_bytes(),
            Path::new("u.msh"),
        )
        .unwrap_err();
        assert!(matches!(e, GmshError::UnusedNode { node: 5, .. }), "{e}");
        assert!(e.to_string().contains("node 5 (group \"body\")"), "{e}");
        let moved = square_ascii([1, 2, 3, 4, 5], &CCW).replace("0.5 0.5 0\n", "1 1 0\n");
        let e = parse_msh(moved.as_bytes(), Path::new("c.msh")).unwrap_err();
        assert!(
            matches!(
                e,
                GmshError::CoincidentNodes {
                    first: 3,
                    second: 5,
                    ..
                }
            ),
            "{e}"
        );
        let claims =
            square_ascii([1, 2, 3, 4, 5], &CCW).replace("$Nodes\n9 5 1 5", "$Nodes\n9 6 1 5");
        let e = parse_msh(claims.as_bytes(), Path::new("n.msh")).unwrap_err();
        assert!(
            matches!(
                e,
                GmshError::CountMismatch {
                    announced: 6,
                    found: 5,
                    ..
                }
            ),
            "{e}"
        );
    }

    #[test]
    fn clockwise_mesh_is_reversed() {
        let dir = TempDir::new("cw");
        let cw: Vec<[usize; 3]> = CCW.iter().map(|t| [t[0], t[2], t[1]]).collect();
        let p = dir.write("cw.msh", square_ascii(TAGS, &cw).as_bytes());
        let m = read_msh(&p).unwrap();
        check_square(&m);
        assert_eq!(tris(&m), CCW.to_vec());
    }

    #[test]
    fn zero_area_triangle_is_an_error() {
        let dir = TempDir::new("zero");
        let mut t = CCW.to_vec();
        t[3] = [0, 2, 4]; // (0,0), (1,1), (0.5,0.5): collinear; element tag 6
        let p = dir.write("zero.msh", square_ascii(TAGS, &t).as_bytes());
        let e = read_msh(&p).unwrap_err();
        assert!(
            matches!(e, GmshError::DegenerateElement { element: 6, .. }),
            "{e:?}"
        );
        let msg = e.to_string();
        assert!(
            msg.contains("zero.msh") && msg.contains("triangle 6"),
            "{msg}"
        );
    }

    #[test]
    fn inverted_triangle_is_an_error() {
        let dir = TempDir::new("inverted");
        let mut t = CCW.to_vec();
        t[2] = [2, 4, 3]; // element tag 5, clockwise
        let p = dir.write("inv.msh", square_ascii(TAGS, &t).as_bytes());
        let e = read_msh(&p).unwrap_err();
        assert!(
            matches!(
                e,
                GmshError::InvertedElement {
                    element: 5,
                    inverted: 1,
                    total: 4,
                    ..
                }
            ),
            "{e:?}"
        );
        assert!(e.to_string().contains("inv.msh"));
        // Mostly clockwise: the one counter-clockwise triangle is the inverted one.
        let t = vec![[0, 4, 1], [1, 2, 4], [2, 4, 3], [3, 4, 0]];
        let p = dir.write("inv2.msh", square_ascii(TAGS, &t).as_bytes());
        let e = read_msh(&p).unwrap_err();
        assert!(
            matches!(e, GmshError::InvertedElement { element: 4, .. }),
            "{e:?}"
        );
    }

    #[test]
    fn missing_file_names_the_path() {
        let dir = TempDir::new("missing");
        let p = dir.0.join("nope.msh");
        let e = read_msh(&p).unwrap_err();
        assert!(matches!(e, GmshError::Io { .. }), "{e:?}");
        assert!(e.to_string().contains("nope.msh"), "{e}");
    }

    #[test]
    fn garbage_and_bad_headers() {
        let dir = TempDir::new("garbage");
        let cases: &[(&str, &[u8])] = &[
            ("garbage.msh", b"hello, this is not a mesh\n\x00\xff"),
            ("empty.msh", b""),
            ("bad-type.msh", b"$MeshFormat\n4.1 7 8\n$EndMeshFormat\n"),
            ("bad-size.msh", b"$MeshFormat\n4.1 0 99999999999999\n$EndMeshFormat\n"),
            ("short.msh", b"$MeshFormat\n4.1 0\n$EndMeshFormat\n"),
            ("bin-short.msh", b"$MeshFormat\n4.1 1 8\n"),
            (
                "bad-body.msh",
                b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n2 1 0 2\n1\n2\n0 0 0\nx y z\n$EndNodes\n",
            ),
            (
                "bad-names.msh",
                b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 1 \"a\"\n$EndPhysicalNames\n",
            ),
            (
                "unclosed-names.msh",
                b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n1 1 \"a\"\n",
            ),
        ];
        for (name, content) in cases {
            let p = dir.write(name, content);
            let e = read_msh(&p).unwrap_err();
            assert!(matches!(e, GmshError::Parse { .. }), "{name}: {e:?}");
            let msg = e.to_string();
            assert!(msg.contains(name), "{msg}");
            assert!(!msg.contains("panicked"), "{msg}");
        }
        // The parser's message says where.
        let e = read_msh(&dir.0.join("bad-body.msh")).unwrap_err();
        assert!(e.to_string().contains("line 10"), "{e}");
    }

    #[test]
    fn unsupported_version() {
        let dir = TempDir::new("version");
        let p = dir.write("old.msh", b"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
        let e = read_msh(&p).unwrap_err();
        assert!(
            matches!(&e, GmshError::UnsupportedVersion { version, .. } if version == "2.2"),
            "{e:?}"
        );
        assert!(e.to_string().contains("old.msh"));
    }

    #[test]
    fn no_triangles_and_unsupported_elements() {
        let dir = TempDir::new("notri");
        let head = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
                    $Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n$EndNodes\n";
        // Lines only.
        let s = format!("{head}$Elements\n1 1 1 1\n1 1 1 1\n1 1 2\n$EndElements\n");
        let e = read_msh(&dir.write("lines.msh", s.as_bytes())).unwrap_err();
        assert!(matches!(e, GmshError::NoTriangles { .. }), "{e:?}");
        assert!(e.to_string().contains("lines.msh"));
        // No $Elements at all, and an empty $Elements section.
        let e = read_msh(&dir.write("none.msh", head.as_bytes())).unwrap_err();
        assert!(matches!(e, GmshError::NoTriangles { .. }), "{e:?}");
        let s = format!("{head}$Elements\n0 0 0 0\n$EndElements\n");
        let e = read_msh(&dir.write("zero-el.msh", s.as_bytes())).unwrap_err();
        assert!(matches!(e, GmshError::NoTriangles { .. }), "{e:?}");
        let s = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n0 0 1 1\n$EndNodes\n";
        let e = read_msh(&dir.write("zero-nodes.msh", s.as_bytes())).unwrap_err();
        assert!(matches!(e, GmshError::NoTriangles { .. }), "{e:?}");
        // A quad.
        let s = format!("{head}$Elements\n1 1 7 7\n2 1 3 1\n7 1 2 3 4\n$EndElements\n");
        let e = read_msh(&dir.write("quad.msh", s.as_bytes())).unwrap_err();
        assert!(
            matches!(&e, GmshError::UnsupportedElement { element: 7, dim: 2, element_type, .. }
                if element_type == "3 (Qua4)"),
            "{e:?}"
        );
        // A triangle on a missing node.
        let s = format!("{head}$Elements\n1 1 3 3\n2 1 2 1\n3 1 2 99\n$EndElements\n");
        let e = read_msh(&dir.write("missing-node.msh", s.as_bytes())).unwrap_err();
        assert!(
            matches!(
                e,
                GmshError::MissingNode {
                    element: 3,
                    node: 99,
                    ..
                }
            ),
            "{e:?}"
        );
        // No $Entities and no names: a mesh without node sets is fine.
        let s = format!("{head}$Elements\n1 2 1 2\n2 1 2 2\n1 1 2 3\n2 1 3 4\n$EndElements\n");
        let m = read_msh(&dir.write("plain.msh", s.as_bytes())).unwrap();
        assert_eq!((m.n_nodes(), m.cells.len()), (4, 2));
        assert!(m.node_sets.is_empty());
    }

    #[test]
    fn binary_little_and_big_endian() {
        let dir = TempDir::new("binary");
        for little in [true, false] {
            let bytes = square_binary(TAGS, &CCW, little);
            let m = read_msh(&dir.write("bin.msh", &bytes)).unwrap();
            check_square(&m);
            assert_eq!(m.coords, XY.concat());
            // Sparse and permuted tags, clockwise triangles.
            let cw: Vec<[usize; 3]> = CCW.iter().map(|t| [t[0], t[2], t[1]]).collect();
            let bytes = square_binary([5, 4, 3, 2, 1], &cw, little);
            let m = read_msh(&dir.write("bin2.msh", &bytes)).unwrap();
            check_square(&m);
            assert_eq!(m.point(0), [0.5, 0.5]);
            let bytes = square_binary([10, 40, 20, 90, 3], &CCW, little);
            check_square(&read_msh(&dir.write("bin3.msh", &bytes)).unwrap());
        }
    }

    #[test]
    fn truncated_files_give_errors_not_panics() {
        let ascii = square_ascii([101, 7, 33, 2000, 5], &CCW).into_bytes();
        let binary = square_binary(TAGS, &CCW, true);
        let p = Path::new("truncated.msh");
        for bytes in [&ascii, &binary] {
            for len in 0..bytes.len() {
                if let Err(GmshError::Parse { message, .. }) = parse_msh(&bytes[..len], p) {
                    assert!(!message.contains("panicked"), "length {len}: {message}");
                }
            }
            assert!(parse_msh(bytes, p).is_ok());
        }
    }
}
