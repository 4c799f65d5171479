//! 3D Gmsh meshes: the unit cube and a disk meshed by Gmsh (tests/data, written by
//! validation/gmsh_meshes3d.py) read back against their geometry, and one deliberately
//! broken file per check, in ASCII and in binary, each refused with the Gmsh tag named.

use std::collections::{BTreeSet, HashMap};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use softway::mesh::gmsh::{
    parse_msh, parse_msh_3d, parse_msh_3d_tagged, parse_msh_any_tagged, pieces, read_msh,
    read_msh_3d, read_msh_3d_with, read_msh_any, GmshError, SolidOptions,
};
use softway::mesh::{CellKind, Cells, Mesh};

// ---------------------------------------------------------------------------------------
// Geometry computed here, independently of the reader.

fn sub(a: &[f64], b: &[f64]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn det3(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// Signed volume of the tetrahedron of the points `p`.
fn tet_volume(p: [&[f64]; 4]) -> f64 {
    det3(sub(p[1], p[0]), sub(p[2], p[0]), sub(p[3], p[0])) / 6.0
}

/// The corners of every cell (4 for tetrahedra, 8 for hexahedra).
fn corners(m: &Mesh) -> Vec<Vec<usize>> {
    let k = m.cells.kind().nodes();
    let c = if m.cells.kind() == CellKind::Hex8 {
        8
    } else {
        4
    };
    m.cells
        .connectivity()
        .chunks_exact(k)
        .map(|cell| cell[..c].to_vec())
        .collect()
}

/// The volume of a mesh of straight-sided cells: a tetrahedron by its corners, a hexahedron
/// split into six tetrahedra about its diagonal 0-6 (exact for plane faces).
fn volume(m: &Mesh) -> f64 {
    // The six tetrahedra of a hexahedron (Gmsh's order) around the diagonal 0-6.
    const HEX_TETS: [[usize; 4]; 6] = [
        [0, 1, 2, 6],
        [0, 2, 3, 6],
        [0, 3, 7, 6],
        [0, 7, 4, 6],
        [0, 4, 5, 6],
        [0, 5, 1, 6],
    ];
    corners(m)
        .iter()
        .map(|c| {
            if c.len() == 8 {
                HEX_TETS
                    .iter()
                    .map(|t| tet_volume(t.map(|k| m.point(c[k]))))
                    .sum::<f64>()
            } else {
                tet_volume([0, 1, 2, 3].map(|k| m.point(c[k])))
            }
        })
        .sum()
}

/// The nodes of `m` whose coordinates satisfy `f`, sorted.
fn nodes_where(m: &Mesh, f: impl Fn(&[f64]) -> bool) -> Vec<usize> {
    (0..m.n_nodes()).filter(|&i| f(m.point(i))).collect()
}

/// The ASCII and binary files of one mesh read alike: the same cells and node sets, the
/// coordinates to the ASCII file's 16 significant digits.
fn assert_same(ascii: &Mesh, binary: &Mesh, name: &str) {
    assert!(ascii.cells == binary.cells, "{name}: the cells differ");
    assert!(
        ascii.node_sets == binary.node_sets,
        "{name}: the node sets differ"
    );
    assert_eq!(ascii.coords.len(), binary.coords.len(), "{name}");
    for (a, b) in ascii.coords.iter().zip(&binary.coords) {
        assert!(
            (a - b).abs() <= 1e-15 * (1.0 + b.abs()),
            "{name}: {a} vs {b}"
        );
    }
}

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

// ---------------------------------------------------------------------------------------
// Meshes made by Gmsh.

/// The unit cube of Gmsh read back: volume 1, every cell positive, the groups where the
/// geometry puts them, ASCII and binary alike.
fn check_cube(name: &str, kind: CellKind) -> Mesh {
    let m = read_msh_3d(&data(&format!("{name}.msh"))).unwrap();
    let b = read_msh_3d(&data(&format!("{name}_bin.msh"))).unwrap();
    assert_same(&m, &b, name);
    assert_eq!(m.dim, 3);
    assert_eq!(m.cells.kind(), kind);
    assert!(m.cells.len() >= 50, "{name}: {} cells", m.cells.len());
    let v = volume(&m);
    assert!((v - 1.0).abs() < 1e-12, "{name}: volume {v}");
    for c in corners(&m) {
        let p: Vec<&[f64]> = c.iter().map(|&i| m.point(i)).collect();
        // Positive at corner 0 (a hexahedron's: along its edges 0-1, 0-3, 0-4).
        let j = if c.len() == 8 {
            det3(sub(p[1], p[0]), sub(p[3], p[0]), sub(p[4], p[0]))
        } else {
            det3(sub(p[1], p[0]), sub(p[2], p[0]), sub(p[3], p[0]))
        };
        assert!(j > 0.0, "{name}: cell {c:?} J = {j}");
    }
    let tol = 1e-12;
    assert_eq!(
        m.node_set("bottom").unwrap(),
        nodes_where(&m, |p| p[2].abs() < tol).as_slice()
    );
    assert_eq!(
        m.node_set("top").unwrap(),
        nodes_where(&m, |p| (p[2] - 1.0).abs() < tol).as_slice()
    );
    assert_eq!(
        m.node_set("corner").unwrap(),
        nodes_where(&m, |p| p.iter().all(|x| x.abs() < tol)).as_slice()
    );
    assert_eq!(m.node_set("body").unwrap().len(), m.n_nodes());
    assert_eq!(m.node_sets.len(), 4);
    // Every node in the cube.
    for p in m.points() {
        assert!(p.iter().all(|&x| (-tol..=1.0 + tol).contains(&x)), "{p:?}");
    }
    m
}

#[test]
fn unit_cube_in_tetrahedra_and_hexahedra() {
    let tet4 = check_cube("cube_tet4", CellKind::Tet4);
    let hex8 = check_cube("cube_hex8", CellKind::Hex8);
    // A transfinite 4 x 4 x 4 grid: 64 cells, 125 nodes.
    assert_eq!((hex8.cells.len(), hex8.n_nodes()), (64, 125));
    // The 10-node mesh is the 4-node one made quadratic: the same corners, the same cells.
    let tet10 = check_cube("cube_tet10", CellKind::Tet10);
    assert_eq!(tet10.cells.len(), tet4.cells.len());
    let corner_points = |m: &Mesh| -> BTreeSet<Vec<u64>> {
        corners(m)
            .iter()
            .map(|c| {
                let mut v: Vec<u64> = c
                    .iter()
                    .flat_map(|&i| m.point(i).iter().map(|x| (x * 1e9).round() as u64))
                    .collect();
                v.sort_unstable();
                v
            })
            .collect()
    };
    assert_eq!(corner_points(&tet4), corner_points(&tet10));
}

/// Gmsh's 10-node tetrahedra: node 4 + k at the middle of edge k in the order of
/// [`Cells::Tet10`] (0-1, 1-2, 2-0, 0-3, 2-3, 1-3), and [`CellKind::vtk_order`] giving VTK's
/// (0-1, 1-2, 2-0, 0-3, 1-3, 2-3: VTK's `vtkQuadraticTetra` documentation).
#[test]
fn quadratic_tetrahedra_node_order_by_geometry() {
    let m = read_msh_3d(&data("cube_tet10_bin.msh")).unwrap();
    let Cells::Tet10(cells) = &m.cells else {
        panic!("expected 10-node tetrahedra")
    };
    let at_middle = |c: &[usize], mid: usize, a: usize, b: usize| {
        let (pa, pb, pm) = (m.point(c[a]), m.point(c[b]), m.point(c[mid]));
        (0..3).all(|i| (pm[i] - 0.5 * (pa[i] + pb[i])).abs() < 1e-12)
    };
    let gmsh = [(0, 1), (1, 2), (2, 0), (0, 3), (2, 3), (1, 3)];
    let vtk = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];
    let order = CellKind::Tet10.vtk_order();
    for c in cells {
        for (k, &(a, b)) in gmsh.iter().enumerate() {
            assert!(at_middle(c, 4 + k, a, b), "cell {c:?} node {}", 4 + k);
        }
        let v: Vec<usize> = order.iter().map(|&k| c[k]).collect();
        for (k, &(a, b)) in vtk.iter().enumerate() {
            assert!(at_middle(&v, 4 + k, a, b), "VTK node {}", 4 + k);
        }
    }
}

/// A disk of radius 0.5 and thickness 0.1: curved faces. The 4-node mesh's volume is below
/// the cylinder's (its boundary nodes on the cylinder, its faces chords inside it) and within
/// the chords' loss; the 10-node mesh's mid-edge nodes on the tread lie on the cylinder too
/// (Gmsh curves the boundary edges), and pass the mid-edge check.
#[test]
fn disk_with_curved_tread() {
    let (r, h) = (0.5, 0.1);
    let exact = std::f64::consts::PI * r * r * h;
    for name in ["cylinder_tet4", "cylinder_tet10"] {
        let m = read_msh_3d(&data(&format!("{name}.msh"))).unwrap();
        let b = read_msh_3d(&data(&format!("{name}_bin.msh"))).unwrap();
        assert_same(&m, &b, name);
        let tread = m.node_set("tread").unwrap();
        assert!(tread.len() > 20);
        for &i in tread {
            let p = m.point(i);
            assert!((p[0].hypot(p[1]) - r).abs() < 1e-9 * r, "{name}: {p:?}");
        }
        assert_eq!(
            m.node_set("flank").unwrap(),
            nodes_where(&m, |p| p[2].abs() < 1e-12).as_slice()
        );
        let on_cylinder = nodes_where(&m, |p| (p[0].hypot(p[1]) - r).abs() < 1e-9 * r);
        assert_eq!(tread, on_cylinder.as_slice());
        let v = volume(&m);
        // Chords of the rim: a regular polygon of n sides has n/(2 pi) sin(2 pi/n) of the
        // circle's area; the mesh size 0.15 on r = 0.5 gives n near 21, a loss near 1.5 %.
        assert!(v < exact && v > 0.97 * exact, "{name}: {v} vs {exact}");
    }
}

#[test]
fn highest_dimension_reader() {
    // A 3D file gives the 3D mesh.
    let m = read_msh_any(&data("cube_hex8.msh")).unwrap();
    assert_eq!((m.dim, m.cells.kind()), (3, CellKind::Hex8));
    // A 2D file gives what the 2D reader gives.
    let s = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n\
             0 0 0\n1 0 0\n1 1 0\n0 1 0\n$EndNodes\n$Elements\n1 2 1 2\n2 1 2 2\n\
             1 1 2 3\n2 1 3 4\n$EndElements\n";
    let p = Path::new("square.msh");
    let (m2, tags) = parse_msh_any_tagged(s.as_bytes(), p).unwrap();
    assert_eq!(m2, parse_msh(s.as_bytes(), p).unwrap());
    assert_eq!((m2.dim, tags), (2, vec![1, 2, 3, 4]));
    // The 2D reader on a 3D file says what the file is.
    let e = read_msh(&data("cube_tet4.msh")).unwrap_err();
    assert!(e.to_string().contains("the file holds a 3D mesh"), "{e}");
    // The 3D reader on a 2D file: no volume cells.
    let e = parse_msh_3d(s.as_bytes(), p).unwrap_err();
    assert!(matches!(e, GmshError::NoCells { .. }), "{e}");
}

// ---------------------------------------------------------------------------------------
// Meshes written here: a grid of cubes split into tetrahedra or kept as hexahedra.

/// An element block: Gmsh type, entity dimension, elements (tag, node tags).
type Block = (i32, i32, Vec<(u64, Vec<u64>)>);

/// A MSH 4.1 file's content: nodes (tag, position) in one volume entity's block, and
/// element blocks (Gmsh type, entity dimension, elements of a tag and node tags).
#[derive(Clone)]
struct Msh {
    nodes: Vec<(u64, [f64; 3])>,
    blocks: Vec<Block>,
}

impl Msh {
    fn element_range(&self) -> (usize, u64, u64) {
        let tags: Vec<u64> = self
            .blocks
            .iter()
            .flat_map(|b| b.2.iter().map(|e| e.0))
            .collect();
        let (min, max) = (
            tags.iter().min().copied().unwrap_or(0),
            tags.iter().max().copied().unwrap_or(0),
        );
        (tags.len(), min, max)
    }

    fn node_range(&self) -> (u64, u64) {
        let min = self.nodes.iter().map(|n| n.0).min().unwrap_or(0);
        let max = self.nodes.iter().map(|n| n.0).max().unwrap_or(0);
        (min, max)
    }

    fn ascii(&self) -> Vec<u8> {
        let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
        let (min, max) = self.node_range();
        let _ = writeln!(s, "$Nodes\n1 {} {min} {max}", self.nodes.len());
        let _ = writeln!(s, "3 1 0 {}", self.nodes.len());
        for (t, _) in &self.nodes {
            let _ = writeln!(s, "{t}");
        }
        for (_, p) in &self.nodes {
            let _ = writeln!(s, "{:e} {:e} {:e}", p[0], p[1], p[2]);
        }
        let (n, min, max) = self.element_range();
        let _ = writeln!(
            s,
            "$EndNodes\n$Elements\n{} {n} {min} {max}",
            self.blocks.len()
        );
        for (ty, dim, els) in &self.blocks {
            let _ = writeln!(s, "{dim} 1 {ty} {}", els.len());
            for (t, nodes) in els {
                let nodes: Vec<String> = nodes.iter().map(u64::to_string).collect();
                let _ = writeln!(s, "{t} {}", nodes.join(" "));
            }
        }
        s.push_str("$EndElements\n");
        s.into_bytes()
    }

    /// Binary MSH 4.1, little endian, 8-byte `size_t`.
    fn binary(&self) -> Vec<u8> {
        let mut b: Vec<u8> = b"$MeshFormat\n4.1 1 8\n".to_vec();
        b.extend(1i32.to_le_bytes());
        b.extend(b"\n$EndMeshFormat\n$Nodes\n");
        let size = |b: &mut Vec<u8>, v: u64| b.extend(v.to_le_bytes());
        let int = |b: &mut Vec<u8>, v: i32| b.extend(v.to_le_bytes());
        let (min, max) = self.node_range();
        for v in [1, self.nodes.len() as u64, min, max] {
            size(&mut b, v);
        }
        for v in [3, 1, 0] {
            int(&mut b, v);
        }
        size(&mut b, self.nodes.len() as u64);
        for (t, _) in &self.nodes {
            size(&mut b, *t);
        }
        for (_, p) in &self.nodes {
            for x in p {
                b.extend(x.to_le_bytes());
            }
        }
        b.extend(b"\n$EndNodes\n$Elements\n");
        let (n, min, max) = self.element_range();
        for v in [self.blocks.len() as u64, n as u64, min, max] {
            size(&mut b, v);
        }
        for (ty, dim, els) in &self.blocks {
            for v in [*dim, 1, *ty] {
                int(&mut b, v);
            }
            size(&mut b, els.len() as u64);
            for (t, nodes) in els {
                size(&mut b, *t);
                for &v in nodes {
                    size(&mut b, v);
                }
            }
        }
        b.extend(b"\n$EndElements\n");
        b
    }

    /// The position of node `tag`.
    fn at(&self, tag: u64) -> [f64; 3] {
        self.nodes.iter().find(|n| n.0 == tag).unwrap().1
    }

    /// Cell `k` of block `b`.
    fn cell(&mut self, b: usize, k: usize) -> &mut (u64, Vec<u64>) {
        &mut self.blocks[b].2[k]
    }

    fn next_node_tag(&self) -> u64 {
        self.node_range().1 + 1
    }

    fn next_element_tag(&self) -> u64 {
        self.element_range().2 + 1
    }
}

/// Node tags of an `n x n x n` grid of cubes of side 1/n from `origin`, from `first`.
fn grid_tag(first: u64, n: usize, i: usize, j: usize, k: usize) -> u64 {
    first + (i + (n + 1) * (j + (n + 1) * k)) as u64
}

/// An `n x n x n` grid of unit-size cubes from `origin`: nodes tagged from `first_node`,
/// cells from `first_cell`; hexahedra, or each cube in the six tetrahedra around its
/// diagonal (Kuhn's split, conforming between cubes), positively oriented.
fn grid(n: usize, origin: [f64; 3], first_node: u64, first_cell: u64, kind: CellKind) -> Msh {
    let h = 1.0 / n as f64;
    let mut nodes = Vec::new();
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                let p = [i, j, k].map(|v| v as f64 * h);
                nodes.push((
                    grid_tag(first_node, n, i, j, k),
                    [origin[0] + p[0], origin[1] + p[1], origin[2] + p[2]],
                ));
            }
        }
    }
    let pos: HashMap<u64, [f64; 3]> = nodes.iter().copied().collect();
    let mut cells: Vec<Vec<u64>> = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let v = |a: usize, b: usize, c: usize| grid_tag(first_node, n, i + a, j + b, k + c);
                if kind == CellKind::Hex8 {
                    cells.push(vec![
                        v(0, 0, 0),
                        v(1, 0, 0),
                        v(1, 1, 0),
                        v(0, 1, 0),
                        v(0, 0, 1),
                        v(1, 0, 1),
                        v(1, 1, 1),
                        v(0, 1, 1),
                    ]);
                    continue;
                }
                for perm in [
                    [0, 1, 2],
                    [0, 2, 1],
                    [1, 0, 2],
                    [1, 2, 0],
                    [2, 0, 1],
                    [2, 1, 0],
                ] {
                    let mut at = [0usize; 3];
                    let mut tet = vec![v(0, 0, 0)];
                    for axis in perm {
                        at[axis] = 1;
                        tet.push(v(at[0], at[1], at[2]));
                    }
                    let p: Vec<[f64; 3]> = tet.iter().map(|t| pos[t]).collect();
                    if det3(sub(&p[1], &p[0]), sub(&p[2], &p[0]), sub(&p[3], &p[0])) < 0.0 {
                        tet.swap(1, 2);
                    }
                    cells.push(tet);
                }
            }
        }
    }
    let mut msh = Msh {
        nodes,
        blocks: vec![],
    };
    if kind == CellKind::Tet10 {
        // Mid-edge nodes, one per edge, in Gmsh's order.
        let mut mids: HashMap<(u64, u64), u64> = HashMap::new();
        let mut next = msh.next_node_tag();
        for c in &mut cells {
            let corners = [c[0], c[1], c[2], c[3]];
            for (a, b) in [(0, 1), (1, 2), (2, 0), (0, 3), (2, 3), (1, 3)] {
                let (ta, tb) = (corners[a], corners[b]);
                let key = (ta.min(tb), ta.max(tb));
                let tag = *mids.entry(key).or_insert_with(|| {
                    let (pa, pb) = (pos[&ta], pos[&tb]);
                    msh.nodes
                        .push((next, [0, 1, 2].map(|i| 0.5 * (pa[i] + pb[i]))));
                    next += 1;
                    next - 1
                });
                c.push(tag);
            }
        }
    }
    let els = cells
        .into_iter()
        .enumerate()
        .map(|(e, c)| (first_cell + e as u64, c))
        .collect();
    msh.blocks.push((kind.gmsh_type(), 3, els));
    msh
}

const KINDS: [CellKind; 3] = [CellKind::Tet4, CellKind::Tet10, CellKind::Hex8];

/// The file in both encodings, read with the 3D reader.
fn both(msh: &Msh) -> [Result<(Mesh, Vec<u64>), GmshError>; 2] {
    [
        parse_msh_3d_tagged(&msh.ascii(), Path::new("grid.msh")),
        parse_msh_3d_tagged(&msh.binary(), Path::new("grid_bin.msh")),
    ]
}

/// Both encodings refused, with the error `check` accepts, whose message holds `words`.
fn refused(msh: &Msh, check: impl Fn(&GmshError) -> bool, words: &[String]) {
    for r in both(msh) {
        let Err(e) = r else {
            panic!("the broken mesh was read")
        };
        assert!(check(&e), "{e:?}");
        let text = e.to_string();
        for w in words {
            assert!(text.contains(w.as_str()), "{text:?} lacks {w:?}");
        }
    }
}

#[test]
fn written_grids_read_back() {
    for kind in KINDS {
        let msh = grid(2, [0.0; 3], 1, 1, kind);
        for r in both(&msh) {
            let (m, tags) = r.unwrap();
            assert_eq!(m.cells.kind(), kind);
            assert_eq!(m.n_nodes(), msh.nodes.len());
            assert_eq!(tags, (1..=msh.nodes.len() as u64).collect::<Vec<_>>());
            assert!((volume(&m) - 1.0).abs() < 1e-12, "{kind:?}");
            assert!(pieces(&m).iter().all(|&p| p == 0));
        }
    }
}

#[test]
fn inverted_cell_named() {
    for kind in KINDS {
        let mut msh = grid(2, [0.0; 3], 1, 1, kind);
        let c = msh.cell(0, 5);
        let tag = c.0;
        // Mirrored: corners 1 and 2 swapped (a hexahedron's 1 and 3, 5 and 7).
        let perm: &[usize] = match kind {
            CellKind::Tet4 => &[0, 2, 1, 3],
            CellKind::Tet10 => &[0, 2, 1, 3, 6, 5, 4, 7, 9, 8],
            _ => &[0, 3, 2, 1, 4, 7, 6, 5],
        };
        c.1 = perm.iter().map(|&k| c.1[k]).collect();
        refused(
            &msh,
            |e| matches!(e, GmshError::InvertedCell { element, .. } if *element == tag),
            &[format!("cell {tag} "), "is inverted".into(), "1 of".into()],
        );
    }
}

#[test]
fn tangled_hexahedron_named() {
    let mut msh = grid(2, [0.0; 3], 1, 1, CellKind::Hex8);
    // Cell 3's first two corners swapped: its bottom face a bow tie, its corner Jacobians
    // negative at the swapped corners and positive elsewhere.
    let c = msh.cell(0, 3);
    let tag = c.0;
    c.1.swap(0, 1);
    refused(
        &msh,
        |e| matches!(e, GmshError::InvertedCell { element, .. } if *element == tag),
        &[format!("cell {tag} "), "tangled".into()],
    );
}

/// A mesh whose cells are all mirrored is turned cell by cell: the volume positive, the
/// 10-node cells' mid-edge nodes still at their edges' middles.
#[test]
fn mirrored_mesh_is_reversed() {
    for kind in KINDS {
        let mut msh = grid(2, [0.0; 3], 1, 1, kind);
        // Mirror the geometry in the plane x = 0: every cell negatively oriented.
        for n in &mut msh.nodes {
            n.1[0] = -n.1[0];
        }
        for r in both(&msh) {
            let (m, _) = r.unwrap();
            let v = volume(&m);
            assert!((v - 1.0).abs() < 1e-12, "{kind:?}: {v}");
            if let Cells::Tet10(cells) = &m.cells {
                for c in cells {
                    for (k, (a, b)) in [(0, 1), (1, 2), (2, 0), (0, 3), (2, 3), (1, 3)]
                        .into_iter()
                        .enumerate()
                    {
                        let (pa, pb, pm) = (m.point(c[a]), m.point(c[b]), m.point(c[4 + k]));
                        for i in 0..3 {
                            assert!((pm[i] - 0.5 * (pa[i] + pb[i])).abs() < 1e-12);
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn degenerate_cell_named() {
    for kind in KINDS {
        let mut msh = grid(2, [0.0; 3], 1, 1, kind);
        let tag = msh.next_element_tag();
        // A cell on four nodes of one plane (the bottom face's corners), or a hexahedron
        // whose top is its bottom.
        let (a, b, c, d) = (
            grid_tag(1, 2, 0, 0, 0),
            grid_tag(1, 2, 1, 0, 0),
            grid_tag(1, 2, 1, 1, 0),
            grid_tag(1, 2, 0, 1, 0),
        );
        let nodes = match kind {
            CellKind::Hex8 => vec![a, b, c, d, a, b, c, d],
            CellKind::Tet4 => vec![a, b, c, d],
            _ => {
                // Mid-edge nodes at the middles: the grid's where it has one, else new.
                let mut v = vec![a, b, c, d];
                for (p, q) in [(0, 1), (1, 2), (2, 0), (0, 3), (2, 3), (1, 3)] {
                    let (pp, pq) = (msh.at(v[p]), msh.at(v[q]));
                    let mid = [0, 1, 2].map(|i| 0.5 * (pp[i] + pq[i]));
                    let tag = match msh.nodes.iter().find(|n| n.1 == mid) {
                        Some(n) => n.0,
                        None => {
                            let t = msh.next_node_tag();
                            msh.nodes.push((t, mid));
                            t
                        }
                    };
                    v.push(tag);
                }
                v
            }
        };
        msh.blocks[0].2.push((tag, nodes));
        refused(
            &msh,
            |e| matches!(e, GmshError::DegenerateCell { element, .. } if *element == tag),
            &[format!("cell {tag} "), "degenerate".into()],
        );
    }
}

#[test]
fn duplicate_cell_named() {
    for kind in KINDS {
        let mut msh = grid(2, [0.0; 3], 1, 1, kind);
        let (first, nodes) = msh.cell(0, 7).clone();
        let tag = msh.next_element_tag();
        msh.blocks[0].2.push((tag, nodes));
        refused(
            &msh,
            |e| {
                matches!(e, GmshError::DuplicateCell { first: f, second, .. }
                    if *f == first && *second == tag)
            },
            &[format!("cells {first} and {tag} ")],
        );
    }
}

#[test]
fn coincident_nodes_named() {
    for kind in KINDS {
        for offset in [0.0, 1e-12] {
            let mut msh = grid(2, [0.0; 3], 1, 1, kind);
            // An unmerged copy of the grid's centre node, used by one cell.
            let centre = grid_tag(1, 2, 1, 1, 1);
            let copy = msh.next_node_tag();
            let mut p = msh.at(centre);
            p[2] += offset;
            msh.nodes.push((copy, p));
            let cell = msh.blocks[0]
                .2
                .iter_mut()
                .find(|c| c.1.contains(&centre))
                .unwrap();
            for n in cell.1.iter_mut().filter(|n| **n == centre) {
                *n = copy;
            }
            refused(
                &msh,
                |e| {
                    matches!(e, GmshError::CoincidentSolidNodes { first, second, .. }
                        if *first == centre && *second == copy)
                },
                &[format!("nodes {centre} and {copy} ")],
            );
        }
    }
}

#[test]
fn unused_node_named() {
    for kind in KINDS {
        let mut msh = grid(2, [0.0; 3], 1, 1, kind);
        let lone = msh.next_node_tag();
        msh.nodes.push((lone, [5.0, 5.0, 5.0]));
        refused(
            &msh,
            |e| matches!(e, GmshError::UnusedSolidNode { node, .. } if *node == lone),
            &[format!("node {lone} ")],
        );
    }
}

/// A cell on an existing cell's face, on its side (inside it): the face then belongs to
/// three cells, two of them on one side.
#[test]
fn overlapping_cells_named() {
    for kind in KINDS {
        let mut msh = grid(2, [0.0; 3], 1, 1, kind);
        let (host, nodes) = msh.cell(0, 0).clone();
        let tag = msh.next_element_tag();
        let first = msh.next_node_tag();
        // The host's corners and their centre.
        let corners = if kind == CellKind::Hex8 { 8 } else { 4 };
        let pts: Vec<[f64; 3]> = nodes[..corners].iter().map(|&t| msh.at(t)).collect();
        let centre = [0, 1, 2].map(|i| pts.iter().map(|p| p[i]).sum::<f64>() / corners as f64);
        let toward = |p: [f64; 3]| [0, 1, 2].map(|i| 0.5 * (p[i] + centre[i]));
        let new = match kind {
            CellKind::Hex8 => {
                // The bottom face kept, the top brought halfway to the centre.
                for k in 0..4 {
                    msh.nodes.push((first + k, toward(pts[4 + k as usize])));
                }
                let mut v = nodes[..4].to_vec();
                v.extend(first..first + 4);
                v
            }
            _ => {
                // Face 0-1-2 kept, corner 3 halfway to the centre.
                msh.nodes.push((first, toward(pts[3])));
                let mut v = vec![nodes[0], nodes[1], nodes[2], first];
                if kind == CellKind::Tet10 {
                    // Mid-edge nodes: the kept face's, and new ones on the new edges.
                    v.extend_from_slice(&nodes[4..7]);
                    let apex = msh.at(first);
                    for (k, c) in [(1u64, 0usize), (2, 2), (3, 1)] {
                        let p = msh.at(nodes[c]);
                        msh.nodes
                            .push((first + k, [0, 1, 2].map(|i| 0.5 * (p[i] + apex[i]))));
                        v.push(first + k);
                    }
                }
                v
            }
        };
        msh.blocks[0].2.push((tag, new));
        refused(
            &msh,
            |e| {
                matches!(e, GmshError::OverlappingCells { first, second, .. }
                    if *first == host && *second == tag)
            },
            &[format!("cells {host} and {tag} overlap")],
        );
    }
}

#[test]
fn disconnected_mesh_names_a_node_of_the_second_piece() {
    for kind in KINDS {
        let a = grid(1, [0.0; 3], 1, 1, kind);
        // A second cube beside the first, 2 away, tagged after it.
        let b = grid(
            1,
            [2.0, 0.0, 0.0],
            a.next_node_tag() + 100,
            a.next_element_tag(),
            kind,
        );
        let mut msh = a.clone();
        msh.nodes.extend(b.nodes.iter().copied());
        msh.blocks[0].2.extend(b.blocks[0].2.iter().cloned());
        let second = a.next_node_tag() + 100;
        refused(
            &msh,
            |e| {
                matches!(e, GmshError::Disconnected { pieces: 2, node, size, .. }
                    if *node == second && *size == b.nodes.len())
            },
            &[format!("node {second} ")],
        );
        // Asked for several bodies: read, in two pieces of the cubes' nodes.
        let dir = std::env::temp_dir().join(format!("softway-gmsh3d-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(format!("two-{kind:?}.msh"));
        std::fs::write(&p, msh.binary()).unwrap();
        let options = SolidOptions {
            several_bodies: true,
        };
        let (m, _) = read_msh_3d_with(&p, options).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        let piece = pieces(&m);
        for (i, p) in m.points().enumerate() {
            assert_eq!(piece[i], usize::from(p[0] > 1.5), "node {i} at {p:?}");
        }
        assert!((volume(&m) - 2.0).abs() < 1e-12);
    }
}

#[test]
fn mismatched_headers() {
    let msh = grid(1, [0.0; 3], 1, 1, CellKind::Tet4);
    let (n_nodes, n_cells) = (msh.nodes.len(), 6);
    // ASCII: the $Nodes and $Elements headers announce one more.
    let text = String::from_utf8(msh.ascii()).unwrap();
    let nodes = text.replace(
        &format!("$Nodes\n1 {n_nodes} "),
        &format!("$Nodes\n1 {} ", n_nodes + 1),
    );
    let elements = text.replace(
        &format!("$Elements\n1 {n_cells} "),
        &format!("$Elements\n1 {} ", n_cells + 1),
    );
    // Binary: the count is the second size_t after the section's line.
    let patch = |section: &[u8], count: usize| {
        let mut b = msh.binary();
        let at = b.windows(section.len()).position(|w| w == section).unwrap() + section.len() + 8;
        b[at..at + 8].copy_from_slice(&(count as u64 + 1).to_le_bytes());
        b
    };
    let cases = [
        (nodes.into_bytes(), "$Nodes", n_nodes),
        (elements.into_bytes(), "$Elements", n_cells),
        (patch(b"$Nodes\n", n_nodes), "$Nodes", n_nodes),
        (patch(b"$Elements\n", n_cells), "$Elements", n_cells),
    ];
    for (bytes, section, found) in cases {
        let e = parse_msh_3d(&bytes, Path::new("h.msh")).unwrap_err();
        assert!(
            matches!(&e, GmshError::CountMismatch { section: s, announced, found: f, .. }
                if *s == section && *announced == found as u64 + 1 && *f == found as u64),
            "{e:?}"
        );
    }
}

/// A 10-node tetrahedron in VTK's order (its last two mid-edge nodes swapped) in a mesh of
/// Gmsh's: refused, naming the cell and the node; also in Gmsh's own file.
#[test]
fn mid_edge_node_off_its_edge_named() {
    let mut msh = grid(2, [0.0; 3], 1, 1, CellKind::Tet10);
    let c = msh.cell(0, 4);
    let (tag, node) = (c.0, c.1[9]);
    c.1.swap(8, 9);
    refused(
        &msh,
        |e| {
            matches!(e, GmshError::MidEdgeNode { element, node: n, position: 8, .. }
                if *element == tag && *n == node)
        },
        &[format!("cell {tag} "), format!("node {node} ")],
    );
    // Gmsh's cube: the first 10-node tetrahedron's last two nodes swapped.
    let text = std::fs::read_to_string(data("cube_tet10.msh")).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let elements = lines.iter().position(|l| l == "$Elements").unwrap();
    // The first line after the header of the block of 10-node tetrahedra (type 11).
    let line_no = elements
        + lines[elements..]
            .iter()
            .position(|l| {
                let f: Vec<&str> = l.split_whitespace().collect();
                f.len() == 4 && f[0] == "3" && f[2] == "11"
            })
            .unwrap()
        + 1;
    let mut fields: Vec<u64> = lines[line_no]
        .split_whitespace()
        .map(|f| f.parse().unwrap())
        .collect();
    let (tag, node) = (fields[0], fields[10]);
    fields.swap(9, 10);
    lines[line_no] = fields
        .iter()
        .map(u64::to_string)
        .collect::<Vec<_>>()
        .join(" ");
    let swapped = lines.join("\n") + "\n";
    let e = parse_msh_3d(swapped.as_bytes(), Path::new("swapped.msh")).unwrap_err();
    assert!(
        matches!(e, GmshError::MidEdgeNode { element, node: n, .. } if element == tag && n == node),
        "{e:?}"
    );
}

#[test]
fn mixed_and_unsupported_cells_named() {
    // Tetrahedra and hexahedra in one file (a second cube beside the first, joined).
    let tets = grid(1, [0.0; 3], 1, 1, CellKind::Tet4);
    let mut msh = tets.clone();
    let hexes = grid(1, [0.0; 3], 1, 100, CellKind::Hex8);
    msh.blocks.push(hexes.blocks[0].clone());
    refused(
        &msh,
        |e| {
            matches!(e, GmshError::MixedCells { first: 1, second: 100, first_kind, second_kind, .. }
                if *first_kind == "4-node tetrahedra" && *second_kind == "8-node hexahedra")
        },
        &["element 1 ".into(), "element 100 ".into()],
    );
    // A prism (Gmsh type 6).
    let mut msh = tets.clone();
    msh.blocks.push((6, 3, vec![(50, vec![1, 2, 3, 5, 6, 7])]));
    refused(
        &msh,
        |e| matches!(e, GmshError::UnsupportedCell { element: 50, .. }),
        &["element 50 ".into(), "6 (Pri6)".into()],
    );
    // A tetrahedron on a node that is not in $Nodes.
    let mut msh = tets.clone();
    msh.cell(0, 2).1[3] = 999;
    refused(
        &msh,
        |e| {
            matches!(
                e,
                GmshError::MissingNode {
                    element: 3,
                    node: 999,
                    ..
                }
            )
        },
        &["element 3 ".into(), "node 999".into()],
    );
    // Triangles only: no volume cells.
    let mut msh = tets;
    msh.blocks = vec![(2, 2, vec![(1, vec![1, 2, 3])])];
    msh.nodes.truncate(3);
    refused(&msh, |e| matches!(e, GmshError::NoCells { .. }), &[]);
}

/// Groups of every dimension on written files: a point, a surface's triangles and the
/// volume, by name.
#[test]
fn groups_of_every_dimension() {
    let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    s += "$PhysicalNames\n3\n0 1 \"tip\"\n2 2 \"base\"\n3 3 \"solid\"\n$EndPhysicalNames\n";
    // One point (tag 1, physical 1), one surface (tag 1, physical 2), one volume (tag 1,
    // physical 3); no curves.
    s +=
        "$Entities\n1 0 1 1\n1 0 0 1 1 1\n1 0 0 0 1 1 0 1 2 0\n1 0 0 0 1 1 1 1 3 0\n$EndEntities\n";
    s += "$Nodes\n2 5 1 5\n0 1 0 1\n5\n0 0 1\n3 1 0 4\n1\n2\n3\n4\n";
    s += "0 0 0\n1 0 0\n0 1 0\n0 0 -1\n$EndNodes\n";
    // Two tetrahedra over and under the triangle 1-2-3; the base triangle; the tip point.
    s += "$Elements\n3 4 1 4\n0 1 15 1\n1 5\n2 1 2 1\n2 1 2 3\n3 1 4 2\n3 1 2 3 5\n4 1 3 2 4\n";
    s += "$EndElements\n";
    let (m, tags) = parse_msh_3d_tagged(s.as_bytes(), Path::new("g.msh")).unwrap();
    assert_eq!(tags, vec![1, 2, 3, 4, 5]);
    assert_eq!(m.node_set("tip"), Some(&[4][..]));
    assert_eq!(m.node_set("base"), Some(&[0, 1, 2][..]));
    assert_eq!(m.node_set("solid"), Some(&[0, 1, 2, 3, 4][..]));
    assert!((volume(&m) - 2.0 / 6.0).abs() < 1e-15);
}

/// The mesh report ([`softway::mesh::quality()`]) on Gmsh's 3D meshes: every cell counted
/// as a solid, the unit cube's volume, no inverted or degenerate cell.
#[test]
fn quality_report_of_gmsh_solids() {
    for name in ["cube_tet4", "cube_tet10_bin", "cube_hex8_bin"] {
        let m = read_msh_3d(&data(&format!("{name}.msh"))).unwrap();
        let q = softway::mesh::quality(&m);
        assert_eq!((q.nodes, q.solids), (m.n_nodes(), m.cells.len()), "{name}");
        assert!((q.volume - 1.0).abs() < 1e-12, "{name}: {}", q.volume);
        assert_eq!((q.inverted, q.degenerate), (0, 0), "{name}");
    }
}

/// Every truncation of a 3D file, ASCII or binary, is an error (or, cut in its last line
/// break, the mesh), never a panic.
#[test]
fn truncated_solid_files_give_errors_not_panics() {
    for kind in KINDS {
        let msh = grid(1, [0.0; 3], 1, 1, kind);
        for bytes in [msh.ascii(), msh.binary()] {
            for len in 0..bytes.len() {
                let r = std::panic::catch_unwind(|| {
                    let _ = parse_msh_3d(&bytes[..len], Path::new("cut.msh"));
                });
                assert!(r.is_ok(), "{kind:?}: panicked at length {len}");
            }
            assert!(parse_msh_3d(&bytes, Path::new("whole.msh")).is_ok());
        }
    }
}
