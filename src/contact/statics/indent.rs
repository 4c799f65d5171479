//! A rigid indenter of principal radii `R_x`, `R_y` pressed, frictionless, into the graded
//! quarter block of [`graded_block`] (hexahedra), by a prescribed approach: Hertz's point
//! contact solved on a finite mesh and read back as Hertz's quantities.
//!
//! - **The indenter.** Its surface is Hertz's paraboloid `z = -d + x^2 / (2 R_x) +
//!   y^2 / (2 R_y)` (the geometry Hertz's solution is exact for; a sphere differs by
//!   `O(a^4 / R^3)`), `d` its displacement toward the block. A top node `i` gets the row
//!   `g = -(Z_i + u_z) - (d - x_i^2 / (2 R_x) - y_i^2 / (2 R_y)) >= 0` (small deformation:
//!   the surface's height at the node's reference `x`, `y`).
//! - **Approach, not force.** The block's bottom is clamped, its faces `x = 0`, `y = 0` are
//!   symmetry planes: `K` stays positive definite, one factor serves every indentation, and
//!   the load `P` is the sum of the multipliers (times 4). A target load is reached by the
//!   secant on `delta ∝ P^(2/3)` (two solves on the one factor and the kept columns), and
//!   Hertz's values are those at the computed `P`.
//! - **Semi-axes.** From the nodal forces' second moments: Hertz's pressure has
//!   `∫ p x^2 dA / ∫ p dA = a_x^2 / 5`, so `a_x = sqrt(5 sum lambda_i x_i^2 / sum lambda_i)`
//!   (and `a_y` alike). The consistent nodal forces integrate against the interpolant of
//!   `x^2`, so the moment converges at second order in `h` and uses every node of the patch,
//!   where the active area's extent moves by whole cells ([`Indentation::extent`] reports it).
//! - **Peak pressure.** The centre node's force over its consistent area `∫ N_0 dA`, a
//!   second-order estimate of `p(0)`.
//! - **Approach.** The prescribed `d` is the indenter's motion relative to the clamped
//!   bottom at the depth `H`; Hertz's `delta` is relative to distant points of a half-space,
//!   where the point at depth `H` below the patch has moved by
//!   [`Hertz::axial_displacement`]`(H)`. The corrected approach adds that: the finite
//!   block's residual (its sides, its clamped bottom) decays as `1 / L`.

use std::time::Instant;

use super::{FactorChoice, Pivoting, Row, Statics, StaticsError};
use crate::contact::hertz::{Hertz, HertzError};
use crate::element::continuum::{assemble_continuum, CellError, SolidHex8};
use crate::material::Elastic;
use crate::mesh::generators::graded::{graded_block, GradedBlock};
use crate::mesh::generators::MeshError;
use crate::mesh::{CellKind, Cells, Mesh};

/// The indentation to solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IndentSpec {
    /// The block's mesh ([`CellKind::Hex8`]).
    pub block: GradedBlock,
    /// The block's material (the indenter is rigid: `E* = E / (1 - nu^2)`).
    pub material: Elastic,
    /// The indenter's radius of curvature along `x`, m.
    pub radius_x: f64,
    /// The indenter's radius of curvature along `y`, m.
    pub radius_y: f64,
    /// The target load on the whole body (four quarters), N.
    pub load: f64,
}

/// What the indentation gives (module docs), with Hertz's values at its load.
#[derive(Debug, Clone)]
pub struct Indentation {
    /// The mesh.
    pub mesh: Mesh,
    /// The displacement, m.
    pub u: Vec<f64>,
    /// Unknowns (dofs of the quarter).
    pub dofs: usize,
    /// The load on the whole body, N.
    pub load: f64,
    /// The semi-axes along `x` and `y` from the second moments, m.
    pub semi_axes: [f64; 2],
    /// The active area's extents along `x` and `y` (the farthest active node plus half the
    /// next cell), m.
    pub extent: [f64; 2],
    /// The peak pressure (the centre node's), Pa.
    pub peak_pressure: f64,
    /// The prescribed approach (relative to the clamped bottom), m.
    pub approach_block: f64,
    /// The approach relative to distant points of a half-space (module docs), m.
    pub approach: f64,
    /// The candidate top nodes: `(x, y, nodal pressure)`, the pressure the node's force over
    /// its consistent area (0 where free).
    pub patch: Vec<[f64; 3]>,
    /// Active nodes.
    pub active: usize,
    /// Whether every active node lies inside the candidates' region (else the patch is cut).
    pub inside: bool,
    /// Active-set iterations of the last solve.
    pub iterations: usize,
    /// Hertz's contact at the computed load.
    pub hertz: Hertz,
    /// Seconds to assemble and factor.
    pub factor_seconds: f64,
    /// Seconds of the contact solves.
    pub solve_seconds: f64,
}

/// Why an indentation cannot be solved.
#[derive(Debug, thiserror::Error)]
pub enum IndentError {
    /// The block's mesh.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// A bad cell.
    #[error(transparent)]
    Cell(#[from] CellError),
    /// The contact solve.
    #[error(transparent)]
    Statics(#[from] StaticsError),
    /// Hertz's solution's input (radii, modulus, load).
    #[error(transparent)]
    Hertz(#[from] HertzError),
    /// The block is not of hexahedra.
    #[error("indentation: the block's `kind` must be hexahedra (Hex8), got {0:?}")]
    NotHexahedra(CellKind),
    /// The contact did not settle, or carries no load.
    #[error("indentation: the contact did not settle (active rows {active}, load {load} N)")]
    NoContact {
        /// Active rows.
        active: usize,
        /// The load, N.
        load: f64,
    },
}

/// Solves the indentation `spec` (module docs).
///
/// # Errors
/// [`IndentError`] for a bad mesh, material, radius or load, or a contact that does not
/// settle.
pub fn indent(spec: &IndentSpec) -> Result<Indentation, IndentError> {
    if spec.block.kind != CellKind::Hex8 {
        return Err(IndentError::NotHexahedra(spec.block.kind));
    }
    let (young, nu) = (spec.material.young, spec.material.poisson);
    let e_star = young / (1.0 - nu * nu);
    let target = Hertz::from_radii(spec.radius_x, spec.radius_y, e_star, spec.load)?;
    let clock = Instant::now();
    let mesh = graded_block(&spec.block)?;
    let el = SolidHex8 {
        d: crate::element::solid::elasticity_3d(&spec.material),
    };
    let a = assemble_continuum(&mesh, &el, spec.material.density, true)?;
    let n = mesh.n_dofs();
    let mut fixed = Vec::new();
    let set = |name: &str| mesh.node_set(name).unwrap_or(&[]).to_vec();
    fixed.extend(set("x0").iter().map(|&i| 3 * i));
    fixed.extend(set("y0").iter().map(|&i| 3 * i + 1));
    fixed.extend(
        set("z0")
            .iter()
            .flat_map(|&i| [3 * i, 3 * i + 1, 3 * i + 2]),
    );
    let (ax, ay) = target.semi_axes_xy();
    let reach = |p: &[f64]| (p[0] / ax).powi(2) + (p[1] / ay).powi(2);
    let candidates: Vec<usize> = set("z1")
        .into_iter()
        .filter(|&i| reach(mesh.point(i)) <= 2.5f64.powi(2))
        .collect();
    let rows: Vec<Row> = candidates
        .iter()
        .map(|&i| Row {
            nodes: vec![(i, 1.0)],
            direction: [0.0, 0.0, -1.0],
            offset: 0.0,
        })
        .collect();
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
    let x = mesh.reference_positions();
    let depth = spec.block.extent[2];
    let (rx, ry) = (spec.radius_x, spec.radius_y);
    let height = |i: usize| {
        let p = mesh.point(i);
        p[0] * p[0] / (2.0 * rx) + p[1] * p[1] / (2.0 * ry)
    };
    let heights: Vec<f64> = candidates.iter().map(|&i| height(i)).collect();
    let mut d = target.approach - target.axial_displacement(depth, young, nu);
    let (mut sol, mut load) = press(&mut statics, &x, &heights, d)?;
    for _ in 0..2 {
        if (load / spec.load - 1.0).abs() < 1e-3 {
            break;
        }
        d *= (spec.load / load).powf(2.0 / 3.0);
        (sol, load) = press(&mut statics, &x, &heights, d)?;
    }
    let solve_seconds = clock.elapsed().as_secs_f64();
    let hertz = Hertz::from_radii(rx, ry, e_star, load)?;
    let read = read_patch(&mesh, &candidates, &sol.active, reach);
    let next = |v: f64, axis: usize| {
        let r = crate::mesh::generators::graded::ruler(
            spec.block.extent[axis],
            spec.block.core[axis],
            spec.block.h,
            spec.block.ratio,
        )
        .unwrap_or_default();
        let k = r
            .iter()
            .position(|&c| c > v)
            .unwrap_or(r.len().saturating_sub(1));
        if k > 0 {
            v + 0.5 * (r[k] - v)
        } else {
            v
        }
    };
    Ok(Indentation {
        dofs: n,
        load,
        semi_axes: [
            (5.0 * read.fx2 / read.f0).sqrt(),
            (5.0 * read.fy2 / read.f0).sqrt(),
        ],
        extent: [next(read.extent[0], 0), next(read.extent[1], 1)],
        peak_pressure: read.peak,
        approach_block: d,
        approach: d + hertz.axial_displacement(depth, young, nu),
        patch: read.patch,
        active: sol.active.len(),
        inside: read.inside,
        iterations: sol.iterations,
        hertz,
        factor_seconds,
        solve_seconds,
        u: sol.u,
        mesh,
    })
}

/// The contact with the indenter moved by `d` (the candidates' surface `heights`), and its
/// load on the whole body (four quarters).
fn press(
    statics: &mut Statics,
    x: &[f64],
    heights: &[f64],
    d: f64,
) -> Result<(super::StaticContact, f64), IndentError> {
    let offsets: Vec<f64> = heights.iter().map(|h| d - h).collect();
    statics.set_offsets(&offsets)?;
    let s = statics.solve(x)?;
    let load = 4.0 * s.active.iter().map(|a| a.1).sum::<f64>();
    if !s.converged || load <= 0.0 || !load.is_finite() {
        return Err(IndentError::NoContact {
            active: s.active.len(),
            load,
        });
    }
    Ok((s, load))
}

/// The patch read from the nodal forces (module docs).
struct Read {
    /// `sum lambda`, `sum lambda x^2`, `sum lambda y^2` over the active nodes.
    f0: f64,
    fx2: f64,
    fy2: f64,
    /// The farthest active node along `x` and `y`.
    extent: [f64; 2],
    /// Every active node within twice Hertz's ellipse (the candidates reach 2.5 times).
    inside: bool,
    /// `(x, y, nodal pressure)` of the candidates.
    patch: Vec<[f64; 3]>,
    /// The centre node's pressure.
    peak: f64,
}

/// The moments, extents and nodal pressures of the `active` forces on the `candidates`;
/// `reach` is a point's squared normalized distance in Hertz's ellipse.
fn read_patch(
    mesh: &Mesh,
    candidates: &[usize],
    active: &[(usize, f64)],
    reach: impl Fn(&[f64]) -> f64,
) -> Read {
    let area = top_areas(mesh);
    let force: std::collections::HashMap<usize, f64> = active.iter().cloned().collect();
    let mut r = Read {
        f0: 0.0,
        fx2: 0.0,
        fy2: 0.0,
        extent: [0.0; 2],
        inside: true,
        patch: Vec::with_capacity(candidates.len()),
        peak: 0.0,
    };
    for &i in candidates {
        let p = mesh.point(i);
        let lam = force.get(&i).copied().unwrap_or(0.0);
        r.patch.push([p[0], p[1], lam / area[i]]);
        if lam > 0.0 {
            r.f0 += lam;
            r.fx2 += lam * p[0] * p[0];
            r.fy2 += lam * p[1] * p[1];
            r.extent = [r.extent[0].max(p[0]), r.extent[1].max(p[1])];
            r.inside &= reach(p) < 2.0f64.powi(2);
            if p[0] == 0.0 && p[1] == 0.0 {
                r.peak = lam / area[i];
            }
        }
    }
    r
}

/// The consistent areas `∫ N_i dA` of the top face's nodes (`z = 0`; 0 elsewhere): a
/// quarter of each top face of a hexahedron (rectangles on the graded block).
fn top_areas(mesh: &Mesh) -> Vec<f64> {
    let mut area = vec![0.0; mesh.n_nodes()];
    if let Cells::Hex8(hexes) = &mesh.cells {
        for h in hexes {
            let top = [h[4], h[5], h[6], h[7]];
            if top.iter().all(|&i| mesh.point(i)[2] == 0.0) {
                let (p0, p1, p3) = (mesh.point(top[0]), mesh.point(top[1]), mesh.point(top[3]));
                let a =
                    ((p1[0] - p0[0]) * (p3[1] - p0[1]) - (p1[1] - p0[1]) * (p3[0] - p0[0])).abs();
                for i in top {
                    area[i] += 0.25 * a;
                }
            }
        }
    }
    area
}
