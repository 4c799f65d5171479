//! ParaView output: XML unstructured grids (`.vtu`) and time-series collections (`.pvd`).
//!
//! [`write_vtu`] writes one mesh with point and cell fields (through [`vtkio`], XML format,
//! base64-encoded binary data); [`PvdWriter`] collects `(time, file)` entries and writes the
//! `.pvd` collection that ParaView opens as one time series. Both write atomically: to a
//! temporary file in the target's folder, then renamed over the target, so a crash or a
//! concurrent reader never sees a half-written file.
//!
//! Points are written in 3D (`z = 0`; `y = 0` in 1D). Two-component vectors (and the 1D
//! displacement) are padded with zeros to three components, as ParaView expects for
//! vectors (e.g. for "Warp By Vector").

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells as VtkCells, DataArrayBase, DataSet,
    ElementType, IOBuffer, UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};

use crate::mesh::{CellKind, Mesh};

/// A named field of nodal or cell values to write.
#[derive(Debug, Clone, Copy)]
pub struct Field<'a> {
    /// Name shown in ParaView.
    pub name: &'a str,
    /// Components per node or cell: 1 (scalar), 2 or 3 (vector; 2-vectors are written padded
    /// to 3 for ParaView).
    pub components: usize,
    /// The values, `components` per node (or cell), node-major: `values[components*i + c]`.
    pub values: &'a [f64],
}

/// Errors when writing VTK files. Every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum VtkError {
    /// A field has an unsupported number of components.
    #[error(
        "{}: field \"{name}\" has {components} components; only 1, 2 or 3 are supported",
        .path.display()
    )]
    InvalidComponents {
        /// The file.
        path: PathBuf,
        /// The field.
        name: String,
        /// Its number of components.
        components: usize,
    },
    /// A field (or the displacement) has the wrong number of values.
    #[error(
        "{}: field \"{name}\" has {len} values, expected {expected} \
         ({count} {location} x {components} components)",
        .path.display()
    )]
    FieldLength {
        /// The file.
        path: PathBuf,
        /// The field.
        name: String,
        /// Number of values given.
        len: usize,
        /// Number of values expected.
        expected: usize,
        /// Number of nodes or cells.
        count: usize,
        /// `"nodes"` or `"cells"`.
        location: &'static str,
        /// Components per node or cell.
        components: usize,
    },
    /// Two point fields or two cell fields have the same name.
    #[error("{}: two {location} fields are named \"{name}\"", .path.display())]
    DuplicateField {
        /// The file.
        path: PathBuf,
        /// The repeated name.
        name: String,
        /// `"point"` or `"cell"`.
        location: &'static str,
    },
    /// The mesh is inconsistent (dimension, or a cell refers to a missing node).
    #[error("{}: invalid mesh: {message}", .path.display())]
    InvalidMesh {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A time in a `.pvd` collection is not finite.
    #[error("{}: time {time} of \"{file}\" is not a finite number", .path.display())]
    InvalidTime {
        /// The `.pvd` file.
        path: PathBuf,
        /// The time.
        time: f64,
        /// The data file of that entry.
        file: String,
    },
    /// Writing the file failed.
    #[error("cannot write {}: {source}", .path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// vtkio could not encode the data.
    #[error("cannot write {}: VTK encoding failed: {message}", .path.display())]
    Encode {
        /// The file.
        path: PathBuf,
        /// vtkio's message.
        message: String,
    },
}

/// Writes `mesh` and its fields as an XML unstructured grid (`.vtu`) for ParaView.
///
/// Cells are VTK lines (1D bars), triangles (2D), tetrahedra (linear or quadratic) or
/// hexahedra (3D), by [`CellKind`]. `displacement`, when given, holds `mesh.dim`
/// values per node (node-major, as [`Mesh::reference_positions`]) and is written as the
/// point vector field `"displacement"` (padded to 3 components); the points themselves stay
/// at their reference positions (use ParaView's "Warp By Vector" to deform). Point fields
/// have one value tuple per node, cell fields one per cell, in mesh order.
///
/// The file is written atomically (temporary file in the same folder, then renamed).
///
/// # Errors
/// [`VtkError::InvalidComponents`], [`VtkError::FieldLength`] or
/// [`VtkError::DuplicateField`] for bad fields, [`VtkError::InvalidMesh`] for an
/// inconsistent mesh, [`VtkError::Io`] or [`VtkError::Encode`] if writing fails.
pub fn write_vtu(
    path: &Path,
    mesh: &Mesh,
    displacement: Option<&[f64]>,
    point_fields: &[Field],
    cell_fields: &[Field],
) -> Result<(), VtkError> {
    let vtk = build_vtu(path, mesh, displacement, point_fields, cell_fields)?;
    write_atomically(path, |file| {
        vtk.write_xml(&mut *file).map_err(|e| match e {
            vtkio::Error::IO(source) => VtkError::Io {
                path: path.to_path_buf(),
                source,
            },
            other => VtkError::Encode {
                path: path.to_path_buf(),
                message: other.to_string(),
            },
        })
    })
}

/// VTK's type of a cell kind.
fn vtk_cell_type(kind: CellKind) -> CellType {
    match kind {
        CellKind::Bar2 => CellType::Line,
        CellKind::Tri3 => CellType::Triangle,
        CellKind::Tet4 => CellType::Tetra,
        CellKind::Tet10 => CellType::QuadraticTetra,
        CellKind::Hex8 => CellType::Hexahedron,
    }
}

/// Checks the input and builds the vtkio model.
fn build_vtu(
    path: &Path,
    mesh: &Mesh,
    displacement: Option<&[f64]>,
    point_fields: &[Field],
    cell_fields: &[Field],
) -> Result<Vtk, VtkError> {
    let invalid = |message: String| VtkError::InvalidMesh {
        path: path.to_path_buf(),
        message,
    };
    let n_cells = mesh.cells.len();
    let kind = mesh.cells.kind();
    let nodes_per_cell = kind.nodes();
    let cell_type = vtk_cell_type(kind);
    // VTK's node order of each cell (Gmsh's but for the 10-node tetrahedron).
    let flat: Vec<u64> = mesh
        .cells
        .connectivity()
        .chunks_exact(nodes_per_cell)
        .flat_map(|c| kind.vtk_order().iter().map(|&k| c[k] as u64))
        .collect();
    if kind.dim() != mesh.dim {
        return Err(invalid(format!(
            "dimension {} does not match its {}",
            mesh.dim,
            kind.describe()
        )));
    }
    if mesh.coords.len() % mesh.dim != 0 {
        return Err(invalid(format!(
            "{} coordinates are not a whole number of nodes of dimension {}",
            mesh.coords.len(),
            mesh.dim
        )));
    }
    let n_nodes = mesh.n_nodes();
    if let Some(pos) = flat.iter().position(|&i| i >= n_nodes as u64) {
        return Err(invalid(format!(
            "cell {} refers to node {}, but the mesh has {n_nodes} nodes",
            pos / nodes_per_cell,
            flat[pos]
        )));
    }

    let check = |f: &Field, count: usize, location: &'static str| -> Result<(), VtkError> {
        if !(1..=3).contains(&f.components) {
            return Err(VtkError::InvalidComponents {
                path: path.to_path_buf(),
                name: f.name.to_string(),
                components: f.components,
            });
        }
        let expected = count * f.components;
        if f.values.len() != expected {
            return Err(VtkError::FieldLength {
                path: path.to_path_buf(),
                name: f.name.to_string(),
                len: f.values.len(),
                expected,
                count,
                location,
                components: f.components,
            });
        }
        Ok(())
    };

    let disp_field = displacement.map(|values| Field {
        name: "displacement",
        components: mesh.dim,
        values,
    });
    let all_point_fields: Vec<&Field> = disp_field.iter().chain(point_fields).collect();
    for (fields, count, location, kind) in [
        (all_point_fields, n_nodes, "nodes", "point"),
        (cell_fields.iter().collect(), n_cells, "cells", "cell"),
    ] {
        for (k, f) in fields.iter().enumerate() {
            check(f, count, location)?;
            if fields[..k].iter().any(|g| g.name == f.name) {
                return Err(VtkError::DuplicateField {
                    path: path.to_path_buf(),
                    name: f.name.to_string(),
                    location: kind,
                });
            }
        }
    }

    // Three components whatever the dimension: the missing ones are zero.
    let points: Vec<f64> = mesh
        .points()
        .flat_map(|p| std::array::from_fn::<f64, 3, _>(|c| p.get(c).copied().unwrap_or(0.0)))
        .collect();
    let offsets: Vec<u64> = (1..=n_cells as u64)
        .map(|k| k * nodes_per_cell as u64)
        .collect();

    let piece = UnstructuredGridPiece {
        points: IOBuffer::F64(points),
        cells: VtkCells {
            cell_verts: VertexNumbers::XML {
                connectivity: flat,
                offsets,
            },
            types: vec![cell_type; n_cells],
        },
        data: Attributes {
            point: disp_field
                .iter()
                .map(|f| attribute(f, true))
                .chain(point_fields.iter().map(|f| attribute(f, false)))
                .collect(),
            cell: cell_fields.iter().map(|f| attribute(f, false)).collect(),
        },
    };
    Ok(Vtk {
        version: Version::new_xml(1, 0),
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(piece),
    })
}

/// A checked field as a vtkio attribute: scalars, or 3-vectors padded with zeros (always a
/// vector if `vector`, as the displacement is, even in 1D).
fn attribute(f: &Field, vector: bool) -> Attribute {
    let (elem, data) = if f.components == 1 && !vector {
        (
            ElementType::Scalars {
                num_comp: 1,
                lookup_table: None,
            },
            f.values.to_vec(),
        )
    } else {
        let data = f
            .values
            .chunks(f.components)
            .flat_map(|c| [0, 1, 2].map(|k| c.get(k).copied().unwrap_or(0.0)))
            .collect();
        (ElementType::Vectors, data)
    };
    Attribute::DataArray(DataArrayBase {
        name: f.name.to_string(),
        elem,
        data: IOBuffer::F64(data),
    })
}

/// Collects the `(time, file)` entries of a time series and writes them as a ParaView
/// `.pvd` collection.
///
/// File names are written as given; make them relative to the folder of the `.pvd` file
/// (usually just the file name) so that the results can be moved as a whole.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PvdWriter {
    entries: Vec<(f64, String)>,
}

impl PvdWriter {
    /// An empty collection.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds the data file `file` (relative to the `.pvd` file) at time `time`, in s.
    pub fn add(&mut self, time: f64, file: impl Into<String>) {
        self.entries.push((time, file.into()));
    }

    /// The entries added so far, in order.
    #[cfg(test)]
    pub fn entries(&self) -> &[(f64, String)] {
        &self.entries
    }

    /// True when no entry was added.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The `.pvd` XML text for the entries (see [`PvdWriter::write`]).
    ///
    /// # Errors
    /// [`VtkError::InvalidTime`] for a non-finite time; `path` only names the file.
    pub fn to_xml(&self, path: &Path) -> Result<String, VtkError> {
        let mut s = String::from(
            "<?xml version=\"1.0\"?>\n\
             <VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  \
             <Collection>\n",
        );
        for (time, file) in &self.entries {
            if !time.is_finite() {
                return Err(VtkError::InvalidTime {
                    path: path.to_path_buf(),
                    time: *time,
                    file: file.clone(),
                });
            }
            // `{:?}` prints the shortest representation that reads back exactly.
            let _ = writeln!(
                s,
                "    <DataSet timestep=\"{time:?}\" group=\"\" part=\"0\" file=\"{}\"/>",
                xml_escape(file)
            );
        }
        s.push_str("  </Collection>\n</VTKFile>\n");
        Ok(s)
    }

    /// Writes the `.pvd` collection to `path`, atomically (temporary file, then rename).
    ///
    /// # Errors
    /// [`VtkError::InvalidTime`] for a non-finite time, [`VtkError::Io`] if writing fails.
    pub fn write(&self, path: &Path) -> Result<(), VtkError> {
        let text = self.to_xml(path)?;
        write_atomically(path, |file| {
            file.write_all(text.as_bytes())
                .map_err(|source| VtkError::Io {
                    path: path.to_path_buf(),
                    source,
                })
        })
    }
}

/// Escapes the XML special characters of an attribute value.
fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// Writes `path` through `fill` into a temporary file in the same folder, then renames it
/// over `path`. The temporary file is removed on failure.
fn write_atomically(
    path: &Path,
    fill: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> Result<(), VtkError>,
) -> Result<(), VtkError> {
    let io_err = |source: std::io::Error| VtkError::Io {
        path: path.to_path_buf(),
        source,
    };
    let name = path.file_name().ok_or_else(|| {
        io_err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "the path has no file name",
        ))
    })?;
    // Unique per process and call, so that concurrent writers never share a temporary file.
    static COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let serial = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".{}-{serial}.tmp", std::process::id()));
    let tmp = path.with_file_name(tmp_name);

    let result = (|| {
        let file = std::fs::File::create(&tmp).map_err(io_err)?;
        let mut writer = std::io::BufWriter::new(file);
        fill(&mut writer)?;
        let file = writer.into_inner().map_err(|e| io_err(e.into_error()))?;
        file.sync_all().map_err(io_err)?;
        drop(file);
        std::fs::rename(&tmp, path).map_err(io_err)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{generators, Cells};
    use std::collections::BTreeMap;

    /// A temporary directory removed on drop.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(name: &str) -> Self {
            let dir = std::env::temp_dir()
                .join(format!("softway-vtk-test-{}-{name}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).unwrap();
            TempDir(dir)
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    /// Reads a `.vtu` back with vtkio: points, connectivity, offsets, types, and the point
    /// and cell data arrays by name.
    #[allow(clippy::type_complexity)]
    fn read_back(
        path: &Path,
    ) -> (
        Vec<f64>,
        Vec<u64>,
        Vec<u64>,
        Vec<CellType>,
        BTreeMap<String, (ElementType, Vec<f64>)>,
        BTreeMap<String, (ElementType, Vec<f64>)>,
    ) {
        let vtk = Vtk::import(path).expect("vtkio reads the file");
        let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
            panic!("not an unstructured grid");
        };
        assert_eq!(pieces.len(), 1);
        let piece = pieces
            .into_iter()
            .next()
            .unwrap()
            .into_loaded_piece_data(None)
            .unwrap();
        let points = piece.points.cast_into::<f64>().unwrap();
        let (connectivity, offsets) = piece.cells.cell_verts.into_xml();
        let arrays = |attrs: Vec<Attribute>| {
            attrs
                .into_iter()
                .map(|a| match a {
                    Attribute::DataArray(d) => (
                        d.name.clone(),
                        (d.elem.clone(), d.data.cast_into().unwrap()),
                    ),
                    Attribute::Field { .. } => panic!("unexpected field attribute"),
                })
                .collect()
        };
        (
            points,
            connectivity,
            offsets,
            piece.cells.types,
            arrays(piece.data.point),
            arrays(piece.data.cell),
        )
    }

    #[test]
    fn triangle_mesh_round_trip() {
        let dir = TempDir::new("tri");
        let mesh = generators::rectangle(2.0, 1.0, 2, 1).unwrap(); // 6 nodes, 4 triangles
        let n = mesh.n_nodes();
        let disp: Vec<f64> = (0..2 * n).map(|k| 0.01 * k as f64).collect();
        let velocity: Vec<f64> = (0..2 * n).map(|k| -(k as f64)).collect();
        let temperature: Vec<f64> = (0..n).map(|k| 300.0 + k as f64).collect();
        let stress: Vec<f64> = vec![1.5, -2.5, 3.25, 1e9];
        let path = dir.0.join("out.vtu");
        write_vtu(
            &path,
            &mesh,
            Some(&disp),
            &[
                Field {
                    name: "velocity",
                    components: 2,
                    values: &velocity,
                },
                Field {
                    name: "temperature",
                    components: 1,
                    values: &temperature,
                },
            ],
            &[Field {
                name: "von Mises stress",
                components: 1,
                values: &stress,
            }],
        )
        .unwrap();

        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("UnstructuredGrid"), "{text}");
        // No temporary file left behind.
        let names: Vec<_> = std::fs::read_dir(&dir.0).unwrap().collect();
        assert_eq!(names.len(), 1);

        let (points, conn, offsets, types, point, cell) = read_back(&path);
        let expect_points: Vec<f64> = mesh.points().flat_map(|p| [p[0], p[1], 0.0]).collect();
        assert_eq!(points, expect_points);
        let Cells::Tri3(tris) = &mesh.cells else {
            unreachable!()
        };
        let expect_conn: Vec<u64> = tris.iter().flatten().map(|&i| i as u64).collect();
        assert_eq!(conn, expect_conn);
        assert_eq!(offsets, vec![3, 6, 9, 12]);
        assert_eq!(types, vec![CellType::Triangle; 4]);

        let (elem, d) = &point["displacement"];
        assert_eq!(*elem, ElementType::Vectors);
        let expect: Vec<f64> = disp.chunks(2).flat_map(|c| [c[0], c[1], 0.0]).collect();
        assert_eq!(d, &expect);
        let (_, v) = &point["velocity"];
        assert_eq!(v.len(), 3 * n);
        assert_eq!(&v[3..6], &[-2.0, -3.0, 0.0]);
        let (elem, t) = &point["temperature"];
        assert!(matches!(elem, ElementType::Scalars { num_comp: 1, .. }));
        assert_eq!(t, &temperature);
        let (elem, s) = &cell["von Mises stress"];
        assert!(matches!(elem, ElementType::Scalars { num_comp: 1, .. }));
        assert_eq!(s, &stress);
        assert_eq!(point.len(), 3);
        assert_eq!(cell.len(), 1);

        // Writing again replaces the file.
        write_vtu(&path, &mesh, None, &[], &[]).unwrap();
        let (_, _, _, _, point, cell) = read_back(&path);
        assert!(point.is_empty() && cell.is_empty());
    }

    #[test]
    fn bar_mesh_round_trip() {
        let dir = TempDir::new("bar");
        let mesh = generators::bar(1.0, 4).unwrap();
        let disp = [0.0, 0.1, 0.2, 0.3, 0.4];
        let strain = [1.0, 2.0, 3.0, 4.0];
        let path = dir.0.join("bar.vtu");
        let f = Field {
            name: "strain",
            components: 1,
            values: &strain,
        };
        write_vtu(&path, &mesh, Some(&disp), &[], &[f]).unwrap();
        let (points, conn, offsets, types, point, cell) = read_back(&path);
        assert_eq!(
            points,
            vec![0.0, 0.0, 0.0, 0.25, 0.0, 0.0, 0.5, 0.0, 0.0, 0.75, 0.0, 0.0, 1.0, 0.0, 0.0]
        );
        assert_eq!(conn, vec![0, 1, 1, 2, 2, 3, 3, 4]);
        assert_eq!(offsets, vec![2, 4, 6, 8]);
        assert_eq!(types, vec![CellType::Line; 4]);
        assert_eq!(point["displacement"].1[3..6], [0.1, 0.0, 0.0]);
        assert_eq!(cell["strain"].1, strain);
    }

    /// Solid meshes are written as VTK's tetrahedra and hexahedra; the 10-node
    /// tetrahedron's mid-edge nodes in VTK's order (its edges 1-3 then 2-3, where Gmsh has
    /// 2-3 then 1-3), checked against the nodes' places: VTK's node 8 is the middle of the
    /// cell's corners 1 and 3.
    #[test]
    fn solid_meshes_round_trip_in_vtk_order() {
        let dir = TempDir::new("solid");
        for (kind, vtk, per) in [
            (CellKind::Hex8, CellType::Hexahedron, 8),
            (CellKind::Tet4, CellType::Tetra, 4),
            (CellKind::Tet10, CellType::QuadraticTetra, 10),
        ] {
            let mesh = generators::box_mesh(kind, [0.3, 0.2, 0.1], [2, 1, 1]).unwrap();
            let path = dir.0.join(format!("{kind:?}.vtu"));
            let disp: Vec<f64> = (0..mesh.n_dofs()).map(|k| k as f64).collect();
            write_vtu(&path, &mesh, Some(&disp), &[], &[]).unwrap();
            let (points, conn, offsets, types, point, _) = read_back(&path);
            assert_eq!(points, mesh.coords, "{kind:?}");
            assert_eq!(types, vec![vtk; mesh.cells.len()]);
            assert_eq!(
                offsets.last().copied(),
                Some((per * mesh.cells.len()) as u64)
            );
            assert_eq!(point["displacement"].1, disp);
            for c in conn.chunks_exact(per) {
                if kind == CellKind::Tet10 {
                    let p = |k: usize| mesh.point(c[k] as usize);
                    let (a, b, m) = (p(1), p(3), p(8));
                    assert!((0..3).all(|d| (0.5 * (a[d] + b[d]) - m[d]).abs() < 1e-15));
                }
            }
        }
        // A 3D mesh of triangles is refused.
        let mut flat = generators::rectangle(1.0, 1.0, 1, 1).unwrap();
        flat.dim = 3;
        flat.coords = vec![0.0; 12];
        let e = write_vtu(&dir.0.join("x.vtu"), &flat, None, &[], &[]).unwrap_err();
        assert!(e.to_string().contains("3-node triangles"), "{e}");
    }

    #[test]
    fn bad_fields_and_meshes_are_errors() {
        let dir = TempDir::new("bad");
        let mesh = generators::rectangle(1.0, 1.0, 1, 1).unwrap(); // 4 nodes, 2 cells
        let path = dir.0.join("bad.vtu");
        let four = [0.0; 4];
        let eight = [0.0; 8];
        let f = |name, components, values| Field {
            name,
            components,
            values,
        };
        let e = write_vtu(&path, &mesh, None, &[f("a", 4, &eight)], &[]).unwrap_err();
        assert!(
            matches!(e, VtkError::InvalidComponents { components: 4, .. }),
            "{e:?}"
        );
        let e = write_vtu(&path, &mesh, None, &[f("a", 0, &[])], &[]).unwrap_err();
        assert!(
            matches!(e, VtkError::InvalidComponents { components: 0, .. }),
            "{e:?}"
        );
        let e = write_vtu(&path, &mesh, None, &[f("a", 2, &four)], &[]).unwrap_err();
        assert!(
            matches!(
                e,
                VtkError::FieldLength {
                    len: 4,
                    expected: 8,
                    ..
                }
            ),
            "{e:?}"
        );
        assert!(e.to_string().contains("bad.vtu") && e.to_string().contains("\"a\""));
        let e = write_vtu(&path, &mesh, None, &[], &[f("c", 1, &four)]).unwrap_err();
        assert!(
            matches!(
                e,
                VtkError::FieldLength {
                    expected: 2,
                    location: "cells",
                    ..
                }
            ),
            "{e:?}"
        );
        let e = write_vtu(&path, &mesh, Some(&four), &[], &[]).unwrap_err();
        assert!(
            matches!(&e, VtkError::FieldLength { name, expected: 8, .. } if name == "displacement"),
            "{e:?}"
        );
        let e = write_vtu(
            &path,
            &mesh,
            Some(&eight),
            &[f("displacement", 2, &eight)],
            &[],
        )
        .unwrap_err();
        assert!(matches!(e, VtkError::DuplicateField { .. }), "{e:?}");
        let mut broken = mesh.clone();
        broken.cells = Cells::Tri3(vec![[0, 1, 9]]);
        let e = write_vtu(&path, &broken, None, &[], &[]).unwrap_err();
        assert!(matches!(e, VtkError::InvalidMesh { .. }), "{e:?}");
        let mut broken = mesh.clone();
        broken.dim = 1;
        let e = write_vtu(&path, &broken, None, &[], &[]).unwrap_err();
        assert!(matches!(e, VtkError::InvalidMesh { .. }), "{e:?}");
        let mut broken = mesh.clone();
        broken.coords.pop();
        let e = write_vtu(&path, &broken, None, &[], &[]).unwrap_err();
        assert!(matches!(e, VtkError::InvalidMesh { .. }), "{e:?}");
        // Nothing was written.
        assert_eq!(std::fs::read_dir(&dir.0).unwrap().count(), 0);
        // A missing folder is an I/O error naming the file.
        let e = write_vtu(&dir.0.join("no/such/dir.vtu"), &mesh, None, &[], &[]).unwrap_err();
        assert!(matches!(e, VtkError::Io { .. }), "{e:?}");
        assert!(e.to_string().contains("dir.vtu"));
    }

    #[test]
    fn pvd_lists_files_with_times() {
        let dir = TempDir::new("pvd");
        let mut pvd = PvdWriter::new();
        assert!(pvd.is_empty());
        pvd.add(0.0, "run_0000.vtu");
        pvd.add(1e-4, "run_0001.vtu");
        pvd.add(0.25, String::from("a&b <1>.vtu"));
        assert_eq!(pvd.entries().len(), 3);
        let path = dir.0.join("run.pvd");
        pvd.write(&path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.starts_with("<?xml"));
        assert!(text.contains("<VTKFile type=\"Collection\""));
        assert!(text.contains("timestep=\"0.0\" group=\"\" part=\"0\" file=\"run_0000.vtu\""));
        assert!(text.contains("timestep=\"0.0001\" group=\"\" part=\"0\" file=\"run_0001.vtu\""));
        assert!(
            text.contains("timestep=\"0.25\" group=\"\" part=\"0\" file=\"a&amp;b &lt;1&gt;.vtu\"")
        );
        assert_eq!(text.matches("<DataSet ").count(), 3);
        assert!(text.trim_end().ends_with("</VTKFile>"));
        assert_eq!(pvd.entries()[1], (1e-4, "run_0001.vtu".to_string()));

        pvd.add(f64::NAN, "bad.vtu");
        let e = pvd.write(&path).unwrap_err();
        assert!(matches!(e, VtkError::InvalidTime { .. }), "{e:?}");
        // The earlier file is untouched.
        assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
        assert_eq!(std::fs::read_dir(&dir.0).unwrap().count(), 1);
    }
}
