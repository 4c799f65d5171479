//! A 3D solid body spun up about an axle: the continuum body of [`super::solid`] with the
//! rotating-frame terms of [`crate::frame3d`] in its model, linearised about its spinning
//! equilibrium as the 2D wheel is ([`crate::frame`], [`super::wheel`]; paper §4).
//!
//! [`spinning_solid`] builds the body of `mesh` ([`super::solid::solid`]), then
//!
//! 1. the centrifugal load `f_c` of the spin ([`crate::frame3d::centrifugal_load`]);
//! 2. the spinning equilibrium `u_c` of `K u_c = f_c` on the body's supports or, for a free
//!    body (no supports), on six statically determinate ones ([`free_body_supports`]), which
//!    carry nothing when `f_c` has no resultant force or moment (a body symmetric about the
//!    axle); a free body whose load has one is refused ([`SpinningError::Unbalanced`]);
//! 3. `K_eff = K + K_sigma + K_s` (the stress stiffening of `u_c` when asked, the spin
//!    softening) in the model's `K`, the Coriolis matrix `G` added to its `C`;
//! 4. the constant load `K_eff u_c` (zero on the supports) and the initial displacement
//!    `u_c`: the body starts in its spinning equilibrium, at rest in the frame.
//!
//! The body's `elastic` stays `K` (its strain energy).

use crate::contact::search::Motion;
use crate::element::continuum::{geometries, SolidHex8, SolidTet10, SolidTet4};
use crate::frame3d::{self, GeometricStiffness, Spin, SpinError};
use crate::linalg::LinalgError;
use crate::mesh::{CellKind, Mesh};

use super::solid::{solid, Solid, SolidError, SolidSpec};

/// Why a body cannot be spun up.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpinningError {
    /// The mesh cannot be a continuum body.
    #[error(transparent)]
    Solid(#[from] SolidError),
    /// The spin or the mass cannot take the rotating-frame terms.
    #[error(transparent)]
    Spin(#[from] SpinError),
    /// The mesh is not of solid cells.
    #[error("a spinning body needs a 3D mesh of solid cells (tet4, tet10, hex8), not {0}")]
    NotSolid(&'static str),
    /// A support dof is past the body's dofs.
    #[error("support dof {dof} is out of range (the body has {dofs} dofs)")]
    Support {
        /// The dof.
        dof: usize,
        /// The body's dofs.
        dofs: usize,
    },
    /// A free body's centrifugal load has a resultant: the body needs supports.
    #[error(
        "the centrifugal load of the free body has a resultant force {force:e} N and moment \
         {moment:e} N m about the axle point (allowed: at most 1e-6 of its total magnitude, a \
         body symmetric about the axle): give the body supports that hold it"
    )]
    Unbalanced {
        /// The resultant force's magnitude, N.
        force: f64,
        /// The resultant moment's magnitude, N m.
        moment: f64,
    },
    /// The stiffness is singular on the free dofs of the static solve.
    #[error("the spinning equilibrium cannot be solved: {0}")]
    Linalg(String),
}

impl From<LinalgError> for SpinningError {
    fn from(e: LinalgError) -> Self {
        SpinningError::Linalg(e.to_string())
    }
}

/// How a body is spun.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpinSpec {
    /// The spin of the frame.
    pub spin: Spin,
    /// Include the stress stiffening of the centrifugal prestress (the 2D wheel's default).
    pub stress_stiffening: bool,
}

/// A spun-up solid: the body (its model in the rotating frame) and its spinning
/// equilibrium.
#[derive(Debug)]
pub struct SpinningSolid {
    /// The body with its stresses ([`Solid`]); its `model.k` is `K_eff`, `model.c` holds `G`,
    /// `load` is `K_eff u_c`, `u0` is `u_c`, `fixed_dofs` the supports given.
    pub solid: Solid,
    /// The spinning equilibrium `u_c`, m.
    pub u_spin: Vec<f64>,
    /// The centrifugal load `f_c`, N.
    pub centrifugal: Vec<f64>,
    /// The supports of the static solve (the body's, or [`free_body_supports`]).
    pub static_supports: Vec<usize>,
    /// The spin.
    pub spin: SpinSpec,
}

/// The body `name` of `mesh`'s solid cells with `spec`, in the frame `motion`, held on
/// `fixed_dofs` (none: a free body), spun up by `spin` (module docs).
///
/// # Errors
/// [`SpinningError`] naming the bad cell, spin, support or load.
pub fn spinning_solid(
    name: &str,
    mesh: Mesh,
    spec: &SolidSpec,
    motion: Motion,
    fixed_dofs: &[usize],
    spin: SpinSpec,
) -> Result<SpinningSolid, SpinningError> {
    let kind = mesh.cells.kind();
    if mesh.dim != 3 {
        return Err(SpinningError::NotSolid(kind.describe()));
    }
    let d = crate::element::solid::elasticity_3d(&spec.material);
    let k_sigma = |mesh: &Mesh, u: &[f64], asm: &crate::assembly::Assembler| match kind {
        CellKind::Tet4 => sigma(mesh, &SolidTet4 { d }, asm, u),
        CellKind::Tet10 => sigma(mesh, &SolidTet10 { d }, asm, u),
        CellKind::Hex8 => sigma(mesh, &SolidHex8 { d }, asm, u),
        other => Err(SpinningError::NotSolid(other.describe())),
    };
    if !matches!(kind, CellKind::Tet4 | CellKind::Tet10 | CellKind::Hex8) {
        return Err(SpinningError::NotSolid(kind.describe()));
    }
    let mut s = solid(name, mesh, spec, motion)?;
    let n = s.body.mesh.n_dofs();
    if let Some(&dof) = fixed_dofs.iter().find(|&&d| d >= n) {
        return Err(SpinningError::Support { dof, dofs: n });
    }
    let body = &mut s.body;
    let asm = &body.model.assembler;
    frame3d::scalar_mass(asm, &body.model.m)?;
    let x = body.mesh.reference_positions();
    let fc = frame3d::centrifugal_load(&asm.pattern, &body.model.m, &spin.spin, &x);
    let static_supports = if fixed_dofs.is_empty() {
        check_balanced(&fc, &x, &spin.spin)?;
        free_body_supports(&body.mesh)
    } else {
        fixed_dofs.to_vec()
    };
    let u_c = super::wheel::static_solve(asm, &body.elastic, &fc, &static_supports)?;
    let mut k_eff = body.elastic.clone();
    if spin.stress_stiffening {
        for (a, b) in k_eff.iter_mut().zip(k_sigma(&body.mesh, &u_c, asm)?) {
            *a += b;
        }
    }
    frame3d::add_spin_softening(asm, &body.model.m, &spin.spin, &mut k_eff);
    frame3d::add_coriolis(asm, &body.model.m, &spin.spin, &mut body.model.c);
    let mut load = vec![0.0; n];
    crate::linalg::spmv_add(&asm.pattern, &k_eff, 1.0, &u_c, &mut load);
    for &dof in fixed_dofs {
        load[dof] = 0.0;
    }
    body.model.k = k_eff;
    body.load = load;
    body.u0 = u_c.clone();
    body.fixed_dofs = fixed_dofs.to_vec();
    Ok(SpinningSolid {
        solid: s,
        u_spin: u_c,
        centrifugal: fc,
        static_supports,
        spin,
    })
}

/// The stress stiffening of `mesh`'s cells of the element `el` under `u`.
fn sigma<E: GeometricStiffness<N>, const N: usize>(
    mesh: &Mesh,
    el: &E,
    asm: &crate::assembly::Assembler,
    u: &[f64],
) -> Result<Vec<f64>, SpinningError> {
    let g = geometries(mesh, el).map_err(SolidError::from)?;
    Ok(frame3d::stress_stiffening(asm, mesh, el, &g, u))
}

/// Refuses a load `f` on the nodes `x` with a resultant force or moment about the spin's
/// point above `1e-6` of its total magnitude (times the body's size for the moment).
fn check_balanced(f: &[f64], x: &[f64], spin: &Spin) -> Result<(), SpinningError> {
    let p = spin.point();
    let (mut force, mut moment, mut total, mut size) = ([0.0; 3], [0.0; 3], 0.0, 0.0f64);
    for (fi, xi) in f.chunks_exact(3).zip(x.chunks_exact(3)) {
        let r = [xi[0] - p[0], xi[1] - p[1], xi[2] - p[2]];
        for a in 0..3 {
            force[a] += fi[a];
        }
        moment[0] += r[1] * fi[2] - r[2] * fi[1];
        moment[1] += r[2] * fi[0] - r[0] * fi[2];
        moment[2] += r[0] * fi[1] - r[1] * fi[0];
        total += (fi[0] * fi[0] + fi[1] * fi[1] + fi[2] * fi[2]).sqrt();
        size = size.max((r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt());
    }
    let (fm, mm) = (
        force.iter().map(|v| v * v).sum::<f64>().sqrt(),
        moment.iter().map(|v| v * v).sum::<f64>().sqrt(),
    );
    if fm > 1e-6 * total || mm > 1e-6 * total * size {
        return Err(SpinningError::Unbalanced {
            force: fm,
            moment: mm,
        });
    }
    Ok(())
}

/// Six statically determinate supports of a free 3D body (3-2-1): the three dofs of node
/// `A` (node 0), two of the node `B` farthest from it (the components other than `AB`'s
/// largest), one of the node `C` farthest from the line `AB` (the component along which
/// `AB x AC` is largest). They remove the six rigid motions and carry no force under a
/// self-equilibrated load. An empty list for a mesh without nodes.
pub fn free_body_supports(mesh: &Mesh) -> Vec<usize> {
    let n = mesh.n_nodes();
    if n == 0 || mesh.dim != 3 {
        return Vec::new();
    }
    let p = |i: usize| -> [f64; 3] {
        let q = mesh.point(i);
        [q[0], q[1], q[2]]
    };
    let a = p(0);
    let sub = |u: [f64; 3], v: [f64; 3]| [u[0] - v[0], u[1] - v[1], u[2] - v[2]];
    let cross = |u: [f64; 3], v: [f64; 3]| {
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    };
    let len2 = |u: [f64; 3]| u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    let argmax = |u: [f64; 3]| (0..3).fold(0, |k, c| if u[c].abs() > u[k].abs() { c } else { k });
    let b = (0..n)
        .max_by(|&i, &j| len2(sub(p(i), a)).total_cmp(&len2(sub(p(j), a))))
        .unwrap_or(0);
    let ab = sub(p(b), a);
    let c = (0..n)
        .max_by(|&i, &j| len2(cross(ab, sub(p(i), a))).total_cmp(&len2(cross(ab, sub(p(j), a)))))
        .unwrap_or(0);
    let normal = cross(ab, sub(p(c), a));
    let kb = argmax(ab);
    let mut dofs = vec![0, 1, 2];
    dofs.extend((0..3).filter(|&k| k != kb).map(|k| 3 * b + k));
    dofs.push(3 * c + argmax(normal));
    dofs
}
