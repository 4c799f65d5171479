//! The wheel's model from its scenario: the mesh (generated, a Gmsh file, a moving zone),
//! its checks, and the model built on it.

use super::*;

/// Builds the wheel model of a scenario.
///
/// # Errors
/// [`RunError`] for a bad mesh or a singular model.
pub fn build(ws: &WheelScenario, sc_path: &Path) -> Result<WheelModel, RunError> {
    let mesh: Mesh = match &ws.mesh {
        MeshSource::Rings(n) => {
            disk_rings(ws.spec.radius, *n).map_err(|e| RunError::input(sc_path, e))?
        }
        MeshSource::Graded {
            rim_nodes,
            grading,
            band,
        } => {
            let opts = DiskOptions {
                grading: *grading,
                // A hub clamps the circle of its radius: the mesh is the annulus outside it.
                hub: match ws.spec.support {
                    Support::Hub { radius } => Some(radius),
                    Support::CentrePinned => None,
                },
            };
            match band {
                None => disk_graded(ws.spec.radius, *rim_nodes, opts),
                Some(b) => crate::mesh::generators::disk_symmetric_rim(
                    ws.spec.radius,
                    *rim_nodes,
                    *b,
                    opts,
                ),
            }
            .map_err(|e| RunError::input(sc_path, e))?
        }
        MeshSource::Gmsh(p) => read_mesh_file(p, &ws.spec, sc_path)?,
        MeshSource::Zone(o) => {
            let z = disk_zone(o).map_err(|e| RunError::input(sc_path, e))?;
            let mut wm = WheelModel::new(z.mesh, ws.spec.clone())
                .map_err(|e| RunError::input(sc_path, e))?;
            wm.zone = Some((z.sources, z.step));
            return pressed_to_load(wm, ws, sc_path);
        }
    };
    let wm = WheelModel::new(mesh, ws.spec.clone()).map_err(|e| RunError::input(sc_path, e))?;
    pressed_to_load(wm, ws, sc_path)
}

/// The model with the flattening that carries `wheel.load` ([`load::flattening_for_load`]),
/// or as it is when the flattening was given.
fn pressed_to_load(
    mut wm: WheelModel,
    ws: &WheelScenario,
    sc_path: &Path,
) -> Result<WheelModel, RunError> {
    if let Some(p) = ws.load {
        let found = load::flattening_for_load(&wm, p)
            .map_err(|e| RunError::input(sc_path, format!("wheel.load = {p} N: {e}")))?;
        wm.spec.flattening.depth = found.depth;
    }
    Ok(wm)
}

/// Reads the wheel's Gmsh mesh `p` (the scenario's `wheel.mesh`) and checks it is a disk
/// of the wheel's radius about the axle ([`check_disk`]) held by its support in every part
/// ([`check_supported`]).
///
/// # Errors
/// [`RunError::Input`] naming the scenario `sc_path`, the key `wheel.mesh`, the mesh file
/// and what is wrong.
pub fn read_mesh_file(p: &Path, spec: &WheelSpec, sc_path: &Path) -> Result<Mesh, RunError> {
    let at_fault = |e: String| RunError::Input {
        path: sc_path.to_path_buf(),
        message: format!("`wheel.mesh` = \"{}\": {e}", p.display()),
    };
    let (mesh, tags) = read_msh_tagged(p).map_err(|e| at_fault(e.to_string()))?;
    check_disk(&mesh, &tags, spec.radius).map_err(at_fault)?;
    check_supported(&mesh, &tags, spec).map_err(at_fault)?;
    Ok(mesh)
}

/// Checks that every part of the mesh (its triangles joined through shared nodes) holds a
/// node of the wheel's support: a part with no path to the support would float free (a disk
/// and a separate annulus run with the annulus carrying no load). `tags` are the nodes' Gmsh
/// tags, for the message. A support that holds no node at all is left to
/// [`WheelModel::new`].
///
/// # Errors
/// A message naming the parts, a node of the loose part (Gmsh tag) and the support.
pub fn check_supported(mesh: &Mesh, tags: &[u64], spec: &WheelSpec) -> Result<(), String> {
    let crate::mesh::Cells::Tri3(tris) = &mesh.cells else {
        return Ok(());
    };
    let Ok(held) = crate::bodies::wheel::held_nodes(mesh, spec) else {
        return Ok(());
    };
    let n = mesh.n_nodes();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for t in tris {
        for k in 1..3 {
            let (a, b) = (root(&mut parent, t[0]), root(&mut parent, t[k]));
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut supported = vec![false; n];
    for &i in &held {
        let r = root(&mut parent, i);
        supported[r] = true;
    }
    let tag = |i: usize| tags.get(i).copied().unwrap_or(i as u64);
    let roots: Vec<usize> = (0..n).map(|i| root(&mut parent, i)).collect();
    let mut parts: Vec<usize> = roots.clone();
    parts.sort_unstable();
    parts.dedup();
    // The loose part holding the smallest node tag, its size and that tag.
    let loose = (0..n)
        .filter(|&i| !supported[roots[i]])
        .min_by_key(|&i| tag(i));
    let Some(first) = loose else {
        return Ok(());
    };
    let size = roots.iter().filter(|&&r| r == roots[first]).count();
    let support = match spec.support {
        Support::CentrePinned => format!("the pinned centre, node {}", tag(held[0])),
        Support::Hub { radius } => format!(
            "the hub's {} nodes within wheel.hub_radius = {radius} m",
            held.len()
        ),
    };
    Err(format!(
        "the mesh is in {} parts and one of {size} nodes (node {} among them) has no path to the support ({support}): it would float free; join the parts (Gmsh: Coherence Mesh) or remove the loose one",
        parts.len(),
        tag(first)
    ))
}

/// Relative tolerance on the radius of the rim of a mesh read from a file.
const RIM_TOLERANCE: f64 = 1e-3;

/// Checks that a mesh read from a file is a disk of `radius` (m) centred at the axle: its
/// largest radius is `radius`, every node of its outer boundary (boundary nodes beyond half
/// the radius) is on that circle, and so is every node of a `"rim"` group. `tags` are the
/// nodes' Gmsh tags, for the message.
///
/// # Errors
/// A message naming the node (Gmsh tag), its position and what is allowed.
pub fn check_disk(mesh: &Mesh, tags: &[u64], radius: f64) -> Result<(), String> {
    let r = |i: usize| mesh.point(i)[0].hypot(mesh.point(i)[1]);
    let tag = |i: usize| tags.get(i).copied().unwrap_or(i as u64);
    let off = |i: usize| (r(i) / radius - 1.0).abs() > RIM_TOLERANCE;
    let describe = |i: usize, what: &str| {
        format!(
            "node {} at ({:.6e}, {:.6e}) m, {what}, is at radius {:.6e} m: the wheel's rim must be the circle of wheel.radius = {radius} m about the axle (0, 0), within {RIM_TOLERANCE:e} (an off-centre, out-of-round or wrongly scaled mesh)",
            tag(i),
            mesh.point(i)[0],
            mesh.point(i)[1],
            r(i)
        )
    };
    let Some(far) = (0..mesh.n_nodes()).max_by(|&a, &b| r(a).total_cmp(&r(b))) else {
        return Err("the mesh has no nodes".into());
    };
    if off(far) {
        return Err(describe(far, "the farthest from the axle"));
    }
    if let crate::mesh::Cells::Tri3(tris) = &mesh.cells {
        let mut edges: std::collections::HashMap<(usize, usize), u32> =
            std::collections::HashMap::new();
        for t in tris {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *edges.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        let mut boundary: Vec<usize> = edges
            .iter()
            .filter(|(_, &n)| n == 1)
            .flat_map(|(&(a, b), _)| [a, b])
            .filter(|&i| r(i) > 0.5 * radius)
            .collect();
        boundary.sort_unstable();
        if let Some(&i) = boundary.iter().find(|&&i| off(i)) {
            return Err(describe(i, "on the outer boundary"));
        }
    }
    if let Some(&i) = mesh
        .node_set("rim")
        .unwrap_or(&[])
        .iter()
        .find(|&&i| off(i))
    {
        return Err(describe(i, "in the group \"rim\""));
    }
    Ok(())
}
