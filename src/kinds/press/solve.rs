//! The wheel pressed on the rail: two elastic bodies in frictionless static contact
//! ([`crate::contact::statics`], Two elastic bodies), solved on one factorization.
//!
//! - **The bodies.** A sector `|theta| <= sector` of the wheel of revolution (its cut
//!   faces and its bore held: a static press loads only the part of the wheel near the
//!   patch, and at the sector's ends, a few hundred patch widths away, the stresses of the
//!   press have decayed by Saint-Venant's principle; what holding them changes is the
//!   wheel's bulk compliance, which the approach at depth below leaves out) and the rail
//!   over its length with its foot held (a rail on a rigid bed).
//! - **The load by the approach.** The wheel is moved down rigidly by `d` (its held nodes
//!   with it) through the rows' offsets: a row's gap is
//!   `g = n . (x_s - sum N_i x_i) - d n_z`, so `K` holds no prescribed motion, is factored
//!   once, and each `d` is a solve on the kept columns. The load (the vertical resultant
//!   of the contact forces, `sum lambda_r n_z`) reaches the target by the secant on
//!   `d ∝ P^(2/3)` (Hertz's law; the bodies' bulk adds a linear part, so up to six steps).
//! - **Rows.** The wheel's tread nodes within the contact zone, each against the facet of
//!   the rail's head found in the undeformed configuration ([`facet_rows`]).
//! - **Read back.** The rail's nodal forces `F_i = sum_r lambda_r N_i` over its nodal areas
//!   `∫ N_i dA` give the pressure; the area is the active slave nodes' areas; the
//!   semi-axes the second moments of the forces (`∫ p x^2 dA / ∫ p dA = a^2 / 5` for
//!   Hertz's pressure); the approach the descent `d` of the hub relative to the rail's
//!   foot, and the approach between two points at `depth` below the patch in each body,
//!   to which the half-space's displacement at that depth is added back
//!   ([`Hertz::axial_displacement`] of the equivalent ellipse, Boussinesq's point load where
//!   the contact conforms) for the approach of distant points of two half-spaces, CONTACT's.

use std::time::Instant;

use super::geometry::{join, mesh_specs, place, wheel_sector, Placement};
use crate::contact::facets::{surface_facets, Facet, FacetError, FacetSearch};
use crate::contact::hertz::{reduced_modulus, Hertz};
use crate::contact::search::{Motion, Placed};
use crate::contact::statics::pair::facet_rows;
use crate::contact::statics::{FactorChoice, Pivoting, StaticContact, Statics, StaticsError};
use crate::element::continuum::{assemble_continuum, CellError, CellStresses, SolidHex8};
use crate::material::Elastic;
use crate::mesh::generators::{rail_extruded, wheel_of_revolution, MeshError, RailSpec, WheelSpec};
use crate::mesh::Mesh;

/// The press to solve (module docs); lengths in m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PressSpec {
    /// The wheel (its profile and radius; the contact zone's fields are set from the rest).
    pub wheel: WheelSpec,
    /// The rail (its length and inclination; the zone's fields set from the rest).
    pub rail: RailSpec,
    /// Half-angle of the wheel's sector kept, rad.
    pub sector: f64,
    /// Both bodies' material.
    pub material: Elastic,
    /// The vertical load, N.
    pub load: f64,
    /// The wheel's lateral shift toward the field side, m.
    pub lateral: f64,
    /// Cell size in the contact zone, m.
    pub size: f64,
    /// The contact zone's half-lengths along and across the rail, m.
    pub zone: (f64, f64),
    /// Ratio of successive cells away from the zone.
    pub growth: f64,
    /// Depth of the points the local approach is taken between, m.
    pub depth: f64,
}

/// A node of the rail's surface in the contact zone.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PatchNode {
    /// The rail's node (its own index).
    pub node: usize,
    /// Position along the rail, m.
    pub x: f64,
    /// Position across, m.
    pub y: f64,
    /// Contact pressure, Pa.
    pub pressure: f64,
}

/// One step of the secant on the approach.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SecantStep {
    /// The wheel's descent, m.
    pub descent: f64,
    /// The vertical load it carries, N.
    pub load: f64,
    /// Active rows.
    pub active: usize,
    /// Active-set iterations.
    pub iterations: usize,
}

/// The solved press (module docs).
#[derive(Debug, Clone)]
pub struct Pressed {
    /// Both bodies' mesh, the wheel's nodes first ([`join`]).
    pub mesh: Mesh,
    /// The wheel's nodes.
    pub wheel_nodes: usize,
    /// The displacement, m: the elastic one, plus the rigid descent on the wheel.
    pub u: Vec<f64>,
    /// The von Mises stress per cell, Pa.
    pub von_mises: Vec<f64>,
    /// Where the bodies were placed.
    pub placement: Placement,
    /// Unknowns.
    pub dofs: usize,
    /// Contact rows (slave nodes with a facet).
    pub rows: usize,
    /// The load carried (vertical resultant of the contact forces), N.
    pub load: f64,
    /// The vertical reaction of the rail's foot, N (equilibrium: minus the load).
    pub foot_reaction: f64,
    /// The rail's nodes in the zone with their pressures.
    pub patch: Vec<PatchNode>,
    /// The zone's rail facets as triangles of [`Pressed::patch`]'s indices.
    pub patch_triangles: Vec<[usize; 3]>,
    /// The active slave nodes' area, m^2.
    pub area: f64,
    /// The pressure's centre `(x, y)`, m.
    pub centre: [f64; 2],
    /// The semi-axes along and across the rail from the second moments, m.
    pub semi_axes: [f64; 2],
    /// The active slave nodes' extent: `[x_min, x_max, y_min, y_max]`, m.
    pub extent: [f64; 4],
    /// The largest nodal pressure, Pa.
    pub peak_pressure: f64,
    /// The hub's descent relative to the rail's foot, m.
    pub descent: f64,
    /// The approach between the points at the depths `depths` in each body, m.
    pub approach_local: f64,
    /// The depths of the two points (wheel, rail), m.
    pub depths: [f64; 2],
    /// The approach of distant points of two half-spaces (module docs), m.
    pub approach: f64,
    /// Hertz's contact of the local curvatures at the load carried (none where the
    /// profiles conform).
    pub hertz: Option<Hertz>,
    /// The secant's steps.
    pub secant: Vec<SecantStep>,
    /// Seconds to mesh, assemble and factor.
    pub factor_seconds: f64,
    /// Seconds of the contact solves.
    pub solve_seconds: f64,
}

/// Why a press cannot be solved.
#[derive(Debug, thiserror::Error)]
pub enum PressError {
    /// A mesh.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// A bad cell.
    #[error(transparent)]
    Cell(#[from] CellError),
    /// The facets of the rail.
    #[error(transparent)]
    Facet(#[from] FacetError),
    /// The contact solve.
    #[error(transparent)]
    Statics(#[from] StaticsError),
    /// No point of the rail's head lies under the tread.
    #[error(
        "press: the wheel shifted by press.lateral_mm = {0} does not stand over the rail's head"
    )]
    Placement(f64),
    /// The contact did not settle or carries no load.
    #[error("press: the contact did not settle (active rows {active}, load {load} N); widen press.zone_mm or refine press.contact_size_mm")]
    NoContact {
        /// Active rows.
        active: usize,
        /// The load, N.
        load: f64,
    },
}

/// The two bodies meshed, placed and joined: the mesh, the wheel's nodes, the placement
/// and the rail's mesh alone.
fn bodies(spec: &PressSpec) -> Result<(Mesh, usize, Placement, Mesh), PressError> {
    let tread = spec.wheel.profile.profile();
    let at = place(
        &tread,
        spec.wheel.nominal_radius,
        spec.rail.inclination,
        spec.lateral,
    )
    .ok_or(PressError::Placement(1e3 * spec.lateral))?;
    let (w, r) = mesh_specs(
        (spec.wheel, spec.rail),
        &at,
        spec.size,
        spec.zone,
        spec.growth,
    )?;
    let wheel = wheel_sector(
        &wheel_of_revolution(&w)?,
        spec.sector,
        [0.0, at.taping_y, at.axle_z],
    );
    let rail = rail_extruded(&r)?;
    let n_w = wheel.n_nodes();
    Ok((join(&wheel, &rail), n_w, at, rail))
}

/// The dofs a press of `spec` has (its meshes built, nothing solved).
///
/// # Errors
/// As [`press`]'s meshes.
pub fn press_dofs(spec: &PressSpec) -> Result<usize, PressError> {
    Ok(bodies(spec)?.0.n_dofs())
}

/// The held dofs of the joined mesh: the wheel's inner face and cut faces, the rail's foot.
fn held_dofs(mesh: &Mesh) -> Vec<usize> {
    let set = |name: &str| mesh.node_set(name).unwrap_or(&[]).to_vec();
    let mut held: Vec<usize> = set("wheel.axle");
    held.extend(set("wheel.cut"));
    held.extend(set("rail.foot"));
    held.sort_unstable();
    held.dedup();
    held.iter()
        .flat_map(|&i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect()
}

/// The press's two bodies as one linear model (consistent mass, stiffness, no damping)
/// with their held dofs, for `softway matrix` (no contact rows).
///
/// # Errors
/// As [`press`]'s meshes and cells.
pub fn free_model(spec: &PressSpec) -> Result<(crate::model::LinearModel, Vec<usize>), PressError> {
    let (mesh, ..) = bodies(spec)?;
    let el = SolidHex8 {
        d: crate::element::solid::elasticity_3d(&spec.material),
    };
    let a = assemble_continuum(&mesh, &el, spec.material.density, false)?;
    let c = vec![0.0; a.k.len()];
    let model = crate::model::LinearModel {
        assembler: a.assembler,
        m: a.m,
        k: a.k,
        c,
    };
    Ok((model, held_dofs(&mesh)))
}

/// Solves the press `spec` (module docs).
///
/// # Errors
/// [`PressError`]: a mesh out of its ranges, no contact.
pub fn press(spec: &PressSpec) -> Result<Pressed, PressError> {
    let clock = Instant::now();
    let (mesh, n_w, at, rail) = bodies(spec)?;
    let el = SolidHex8 {
        d: crate::element::solid::elasticity_3d(&spec.material),
    };
    let a = assemble_continuum(&mesh, &el, spec.material.density, true)?;
    let n = mesh.n_dofs();
    let set = |name: &str| mesh.node_set(name).unwrap_or(&[]).to_vec();
    let fixed = held_dofs(&mesh);
    // The slave nodes: the tread's within the zone; the master: the rail's running surface.
    let (along, across) = spec.zone;
    let slaves: Vec<usize> = set("wheel.tread")
        .into_iter()
        .filter(|&i| {
            let p = mesh.point(i);
            p[0].abs() <= along * (1.0 + 1e-9) && (p[1] - at.contact[1]).abs() <= across
        })
        .collect();
    let region = rail.node_set("running").unwrap_or(&[]).to_vec();
    let placed = Placed {
        motion: Motion::Fixed,
        first_dof: 3 * n_w,
    };
    let mut search = FacetSearch::on_mesh(&rail, Some(&region), placed, 4.0 * spec.size + 2e-3)?;
    search.update(0.0, &vec![0.0; n]);
    let x = mesh.reference_positions();
    let found = facet_rows(&x, &slaves, &search, n_w);
    let normal_z: Vec<f64> = found.iter().map(|f| f.row.direction[2]).collect();
    let rows: Vec<_> = found.into_iter().map(|f| f.row).collect();
    let n_rows = rows.len();
    let mut statics = Statics::new(
        &a.assembler.pattern,
        &a.k,
        &fixed,
        &vec![0.0; n],
        3,
        rows,
        FactorChoice::Auto,
    )?;
    statics.pivoting = Pivoting::Block;
    let factor_seconds = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let e_star = reduced_modulus(
        spec.material.young,
        spec.material.poisson,
        spec.material.young,
        spec.material.poisson,
    );
    let guess = Hertz::new(
        at.curvatures[0],
        at.curvatures[1].max(1e-3),
        e_star,
        spec.load,
    )
    .map(|h| h.approach)
    .unwrap_or(2e-5);
    let (sol, load, d, secant) = secant(&mut statics, &x, &normal_z, spec.load, 2.0 * guess)?;
    let solve_seconds = clock.elapsed().as_secs_f64();
    let mut u = sol.u.clone();
    // The foot's vertical reaction: (K u)_z on its held nodes (the unmodified K).
    let mut ku = vec![0.0; n];
    crate::linalg::spmv_into(&a.assembler.pattern, &a.k, &u, &mut ku);
    let foot_reaction: f64 = set("rail.foot").iter().map(|&i| ku[3 * i + 2]).sum();
    let von_mises = von_mises_of(el, a.geometry, &mesh, &u);
    let read = read_patch(&mesh, &rail, n_w, &statics, &sol, search.facets())?;
    let hertz = if at.curvatures[1] > 0.0 {
        Hertz::new(at.curvatures[0], at.curvatures[1], e_star, load).ok()
    } else {
        None
    };
    // The approach between points at `depth` in each body, and back to distant points.
    let c = [read.centre[0], read.centre[1], at.contact[2]];
    let nrm = at.normal;
    let nearest = |range: std::ops::Range<usize>, sign: f64| {
        let target: Vec<f64> = (0..3).map(|k| c[k] + sign * spec.depth * nrm[k]).collect();
        range
            .min_by(|&i, &j| {
                let di: f64 = (0..3).map(|k| (mesh.point(i)[k] - target[k]).powi(2)).sum();
                let dj: f64 = (0..3).map(|k| (mesh.point(j)[k] - target[k]).powi(2)).sum();
                di.total_cmp(&dj)
            })
            .unwrap_or(0)
    };
    let (iw, ir) = (nearest(0..n_w, 1.0), nearest(n_w..mesh.n_nodes(), -1.0));
    let along_n = |i: usize| (0..3).map(|k| u[3 * i + k] * nrm[k]).sum::<f64>();
    let depth_of = |i: usize| {
        (0..3)
            .map(|k| (mesh.point(i)[k] - c[k]) * nrm[k])
            .sum::<f64>()
            .abs()
    };
    let depths = [depth_of(iw), depth_of(ir)];
    let approach_local = d * nrm[2] - (along_n(iw) - along_n(ir));
    let (young, nu) = (spec.material.young, spec.material.poisson);
    let w = |z: f64| match &hertz {
        Some(h) => h.axial_displacement(z, young, nu),
        None => {
            let g = young / (2.0 * (1.0 + nu));
            load * (3.0 - 2.0 * nu) / (4.0 * std::f64::consts::PI * g * z)
        }
    };
    let approach = approach_local + w(depths[0]) + w(depths[1]);
    for i in 0..n_w {
        u[3 * i + 2] -= d;
    }
    Ok(Pressed {
        wheel_nodes: n_w,
        von_mises,
        placement: at,
        dofs: n,
        rows: n_rows,
        load,
        foot_reaction,
        patch: read.patch,
        patch_triangles: read.triangles,
        area: read.area,
        centre: read.centre,
        semi_axes: read.semi_axes,
        extent: read.extent,
        peak_pressure: read.peak,
        descent: d,
        approach_local,
        depths,
        approach,
        hertz,
        secant,
        factor_seconds,
        solve_seconds,
        u,
        mesh,
    })
}

/// The secant on the descent from `d0` to the vertical load `target` (module docs): the
/// contact, its load, its descent and the steps.
fn secant(
    statics: &mut Statics,
    x: &[f64],
    normal_z: &[f64],
    target: f64,
    d0: f64,
) -> Result<(StaticContact, f64, f64, Vec<SecantStep>), PressError> {
    let mut d = d0;
    let mut steps = Vec::new();
    let mut last = None;
    for _ in 0..8 {
        let offsets: Vec<f64> = normal_z.iter().map(|nz| d * nz).collect();
        statics.set_offsets(&offsets)?;
        let sol = statics.solve(x)?;
        let load: f64 = sol
            .active_rows
            .iter()
            .zip(&sol.active)
            .map(|(&r, &(_, l))| l * normal_z[r])
            .sum();
        steps.push(SecantStep {
            descent: d,
            load,
            active: sol.active.len(),
            iterations: sol.iterations,
        });
        if !sol.converged || !load.is_finite() {
            return Err(PressError::NoContact {
                active: sol.active.len(),
                load,
            });
        }
        let close = (load / target - 1.0).abs() < 1e-3;
        last = Some((sol, load, d));
        if close {
            break;
        }
        d = if load > 0.0 {
            d * (target / load).powf(2.0 / 3.0)
        } else {
            2.0 * d
        };
    }
    match last {
        Some((sol, load, d)) if load > 0.0 => Ok((sol, load, d, steps)),
        _ => Err(PressError::NoContact {
            active: 0,
            load: 0.0,
        }),
    }
}

/// The von Mises stress of each cell of `mesh` under `u`, Pa.
fn von_mises_of(
    el: SolidHex8,
    geometry: Vec<crate::element::hex8::Hex8Geometry>,
    mesh: &Mesh,
    u: &[f64],
) -> Vec<f64> {
    let cells = crate::element::continuum::Cells {
        element: el,
        geometry,
        connectivity: mesh.cells.connectivity().to_vec(),
        dim: 3,
    };
    let mut s = vec![0.0; 6 * cells.geometry.len()];
    cells.stresses_into(u, &mut s);
    s.chunks_exact(6)
        .map(|c| crate::element::solid::von_mises(&[c[0], c[1], c[2], c[3], c[4], c[5]]))
        .collect()
}

/// What the contact forces give on the surfaces.
struct Read {
    patch: Vec<PatchNode>,
    triangles: Vec<[usize; 3]>,
    area: f64,
    centre: [f64; 2],
    semi_axes: [f64; 2],
    extent: [f64; 4],
    peak: f64,
}

/// The consistent nodal areas `∫ N_i dA` of `facets` (a quarter of each quadrilateral's
/// area at each corner, a third of a triangle's) over the nodes of `mesh`.
fn nodal_areas(mesh: &Mesh, facets: &[Facet]) -> Vec<f64> {
    let mut area = vec![0.0; mesh.n_nodes()];
    let p = |i: usize| {
        let q = mesh.point(i);
        [q[0], q[1], q[2]]
    };
    let cross_norm = |a: [f64; 3], b: [f64; 3]| {
        let c = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
    };
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    for f in facets {
        let nodes = f.nodes();
        let whole = match nodes.len() {
            4 => 0.5 * cross_norm(sub(p(nodes[2]), p(nodes[0])), sub(p(nodes[3]), p(nodes[1]))),
            _ => 0.5 * cross_norm(sub(p(nodes[1]), p(nodes[0])), sub(p(nodes[2]), p(nodes[0]))),
        };
        for &i in nodes {
            area[i] += whole / nodes.len() as f64;
        }
    }
    area
}

/// The rail's nodal forces and pressures, the active area, the moments.
fn read_patch(
    mesh: &Mesh,
    rail: &Mesh,
    n_w: usize,
    statics: &Statics,
    sol: &StaticContact,
    rail_facets: &[Facet],
) -> Result<Read, PressError> {
    let rail_area = nodal_areas(rail, rail_facets);
    let wheel_region: Vec<usize> = mesh.node_set("wheel.tread").unwrap_or(&[]).to_vec();
    let wheel_facets = surface_facets(mesh, Some(&wheel_region))?;
    let wheel_area = nodal_areas(mesh, &wheel_facets);
    let mut force = vec![0.0; rail.n_nodes()];
    let (mut area, mut extent) = (
        0.0,
        [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ],
    );
    for (&r, &(s, lam)) in sol.active_rows.iter().zip(&sol.active) {
        for &(i, w) in &statics.rows()[r].nodes[1..] {
            force[i - n_w] -= lam * w;
        }
        if lam > 0.0 {
            area += wheel_area[s];
            let p = mesh.point(s);
            extent = [
                extent[0].min(p[0]),
                extent[1].max(p[0]),
                extent[2].min(p[1]),
                extent[3].max(p[1]),
            ];
        }
    }
    let mut patch = Vec::new();
    let mut index = vec![usize::MAX; rail.n_nodes()];
    let (mut f0, mut fx, mut fy) = (0.0, 0.0, 0.0);
    let mut peak: f64 = 0.0;
    for (i, (&f, &a)) in force.iter().zip(&rail_area).enumerate() {
        if a <= 0.0 {
            continue;
        }
        let p = rail.point(i);
        let pressure = f / a;
        peak = peak.max(pressure);
        index[i] = patch.len();
        patch.push(PatchNode {
            node: i,
            x: p[0],
            y: p[1],
            pressure,
        });
        f0 += f;
        fx += f * p[0];
        fy += f * p[1];
    }
    let centre = [fx / f0, fy / f0];
    let (mut mx, mut my) = (0.0, 0.0);
    for (i, &f) in force.iter().enumerate() {
        let p = rail.point(i);
        mx += f * (p[0] - centre[0]).powi(2);
        my += f * (p[1] - centre[1]).powi(2);
    }
    let mut triangles = Vec::with_capacity(2 * rail_facets.len());
    for f in rail_facets {
        let v: Vec<usize> = f.nodes().iter().map(|&i| index[i]).collect();
        triangles.push([v[0], v[1], v[2]]);
        if v.len() == 4 {
            triangles.push([v[0], v[2], v[3]]);
        }
    }
    Ok(Read {
        patch,
        triangles,
        area,
        centre,
        semi_axes: [(5.0 * mx / f0).sqrt(), (5.0 * my / f0).sqrt()],
        extent,
        peak,
    })
}
