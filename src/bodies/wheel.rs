//! The elastic wheel on a rigid base, in the wheel's rotating frame (paper §4).
//!
//! The wheel (a disk of plane-stress triangles) does not turn; the base line turns about
//! its centre at `omega` and presses it to the flattening `d(t)`
//! ([`Flattening`]); the forces of the circular motion
//! are those of [`crate::frame`]. This module puts the pieces together: the mesh's element
//! geometry, `M`, `K` and the damping through [`crate::assembly`], the supports and the rim,
//! the spinning equilibrium and the rotating-frame terms of [`crate::frame`], and the
//! [`Problem`] of the driver ([`WheelModel::problem`]).
//!
//! **Support at the axle.** The paper does not state it. [`Support::CentrePinned`] (the
//! paper's spec, [`WheelSpec::paper`]) fixes the centre node: the wheel may then turn rigidly about the axle, the
//! motion the paper reports ("the material of the wheel rotates oscillatory"), which the
//! stress stiffening of [`crate::frame`] keeps neutral. [`Support::Hub`] clamps every node
//! within a hub radius and removes that rotation; the generated disk is then the annulus
//! from a ring on the hub's circle to the rim
//! ([`crate::mesh::generators::DiskOptions::hub`]), so the clamp holds that circle (on a mesh
//! without nodes near the circle the clamped radius is that of the last nodes inside it: the
//! run says so, and `support_radius_m` in its summary gives it).
//!
//! What the modes show (`softway modes`, `tests/modes.rs`): a single pinned node is a point
//! constraint whose stiffness vanishes under refinement, and only the modes that push the
//! disk against it, the `n = 1` pairs (one wave around the rim), depend on the mesh: the
//! lowest falls from 4587 Hz (12 rings) to 4352, 4206 and 4101 Hz (18, 24, 30 rings), with
//! 70-76% of its strain energy within 2.5 cm of the pin. Every other mode is the free
//! disk's and converges: the ovalisation pair `n = 2` at 11896 Hz (84.1 us) on the paper's
//! mesh and 11854 Hz (84.4 us) on 30 rings is the paper's "first eigenform, period about
//! 80 us". A 1 cm hub converges too (n = 2 at 81.3 / 81.8 / 81.95 us on 10 / 20 / 30 rings).
//! Rolling, the pin sets the answer: the static force at d = 0.1 cm falls from 633 to 554
//! kN as the disk is refined, its point reaction dominates the turn-averaged stress maps, and
//! the bounce of the disk between pin and contact (5.8 kHz) is driven by the node-passing
//! ripple. Scenarios therefore default to a hub clamped over a tenth of the radius
//! (`softway::scenario::DEFAULT_HUB_FRACTION`), with which the mean rolling force converges
//! on a rim ladder (scenarios/wheel.toml); the pin stays as the paper's option.

use crate::assembly::{Assembler, Tri3Mass};
use crate::contact::obstacle::{Flattening, RotatingLine};
use crate::contact::{Obstacle, Pair, Treatment};
use crate::element::tri3::{self, Tri3Geometry};
use crate::frame;
use crate::linalg::{Factor, LinalgError};
use crate::material::{Elastic, PlaneModel};
use crate::mesh::{Cells, Mesh};
use crate::model::LinearModel;
use crate::simulation::Problem;
use crate::time::Integrator;

/// How the wheel is held at the axle.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case", tag = "type")]
pub enum Support {
    /// The centre node pinned (both displacements zero).
    CentrePinned,
    /// Every node within `radius` (m) of the centre clamped.
    Hub {
        /// Hub radius, m.
        radius: f64,
    },
}

/// How the rim meets the base ([`crate::contact::Pair`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactSurface {
    /// One pair per rim node: the node's gap (the paper's).
    #[default]
    Nodes,
    /// One mortar-weighted pair per rim node on the rim's segments
    /// ([`crate::contact::Pair::Weighted`]).
    Segments,
}

/// How the normal and tangential contact problems meet (`rolling.coupling`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Coupling {
    /// The elastic wheel on its rigid base as it is: the normal pressure also strains the
    /// rim tangentially and the tangential traction moves it normally (Dundurs' `beta`
    /// between an elastic and a rigid body is `(1 - 2 nu)/(2 (1 - nu))` in plane strain,
    /// `(1 - nu)/2` in plane stress).
    #[default]
    Coupled,
    /// Carter's problem of elastically similar bodies, in which the two problems decouple: a
    /// second copy of the disk (the twin) carries the tangential tractions alone, the first
    /// the normal ones and the body loads; the gap reads the first, the slip the twin
    /// ([`crate::contact::Pair::Split`]), and the wheel's state is their sum. A verification
    /// of the friction against Carter's theory; twice the unknowns.
    Uncoupled,
}

/// Errors building the wheel model.
#[derive(Debug, thiserror::Error)]
pub enum WheelError {
    /// A triangle is degenerate or inverted.
    #[error("element {element} (nodes {nodes:?}): {source}")]
    Element {
        /// Element index (0-based).
        element: usize,
        /// Its nodes.
        nodes: [usize; 3],
        /// The cause.
        source: tri3::ElementError,
    },
    /// The mesh is not made of triangles.
    #[error("the wheel needs a mesh of 3-node triangles")]
    NotTriangles,
    /// No node at the centre / no node in the hub.
    #[error("the support holds no node: {0}")]
    Support(String),
    /// The matrices could not be factored.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
}

/// The wheel problem's physical data.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelSpec {
    /// Radius `R`, m (the contact candidates are the nodes at this radius).
    pub radius: f64,
    /// Thickness, m.
    pub thickness: f64,
    /// Material.
    pub material: Elastic,
    /// Plane stress or strain.
    pub plane: PlaneModel,
    /// Lumped mass.
    pub lumped: bool,
    /// External damping `eta_z` (Eq. 22), per unit volume, N s/m^4 (times the mass shape).
    pub damping: f64,
    /// Support at the axle.
    pub support: Support,
    /// Wheel spin, rad/s (the base turns at `+omega` in the wheel's frame).
    pub omega: f64,
    /// Flattening program.
    pub flattening: Flattening,
    /// Include the stress stiffening of the centrifugal prestress (default true).
    pub stress_stiffening: bool,
    /// Include the rotating-frame terms at all (false: a disk pressed by a turning line
    /// without inertial forces of the rotation).
    pub rotating_frame: bool,
    /// Longitudinal creepage of the rail against the rim (`rolling.creepage`;
    /// [`RotatingLine::creepage`]): 0 in free rolling; it transmits a tangential force only
    /// with friction.
    pub creepage: f64,
    /// Node or segment (mortar-weighted) contact (`wheel.contact_surface`).
    pub surface: ContactSurface,
    /// The normal and tangential problems coupled (the default) or not
    /// (`rolling.coupling`, [`Coupling`]).
    pub coupling: Coupling,
}

impl WheelSpec {
    /// The paper's wheel (§4): R = 10 cm, 1 cm thick, steel (E = 2.05e11 Pa, nu = 0.3,
    /// rho = 7830 kg/m^3), plane stress, consistent mass, centre pinned, omega = 300 rad/s,
    /// flattening 0.1 cm reached after 5 ms, all rotating-frame terms.
    pub fn paper() -> Self {
        Self {
            radius: 0.1,
            thickness: 0.01,
            material: Elastic {
                young: 2.05e11,
                poisson: 0.3,
                density: 7830.0,
            },
            plane: PlaneModel::Stress,
            lumped: false,
            damping: 0.0,
            support: Support::CentrePinned,
            omega: 300.0,
            flattening: Flattening {
                depth: 1e-3,
                settle_time: 5e-3,
            },
            stress_stiffening: true,
            rotating_frame: true,
            creepage: 0.0,
            surface: ContactSurface::Nodes,
            coupling: Coupling::Coupled,
        }
    }
}

pub use crate::assembly::assemble_mass_stiffness;

/// The assembled wheel: mesh, element geometry, matrices and the spinning equilibrium.
#[derive(Debug)]
pub struct WheelModel {
    /// The mesh (centre at the origin).
    pub mesh: Mesh,
    /// Triangles.
    pub triangles: Vec<[usize; 3]>,
    /// Element geometry.
    pub geometry: Vec<Tri3Geometry>,
    /// Elasticity matrix.
    pub d: [[f64; 3]; 3],
    /// `M`, `K_eff`, `C` (damping + Coriolis).
    pub model: LinearModel,
    /// The elastic stiffness `K` alone (strain energy, stresses).
    pub k_elastic: Vec<f64>,
    /// Supported dofs.
    pub fixed_dofs: Vec<usize>,
    /// Rim nodes (contact candidates), by angle.
    pub rim: Vec<usize>,
    /// The spinning equilibrium `u_c`.
    pub u_spin: Vec<f64>,
    /// The constant load `K_eff u_c`.
    pub load: Vec<f64>,
    /// The data.
    pub spec: WheelSpec,
    /// The model of the disk and its twin (nodes `N..2N` the twin of nodes `0..N`) for
    /// [`Coupling::Uncoupled`], built on [`doubled`] meshes; `None` when coupled.
    pub twin: Option<Box<WheelModel>>,
    /// The refined zone's relocation when the mesh has one ([`crate::mesh::zone`]): the
    /// source of each node's state and the angle of one relocation, rad.
    pub zone: Option<(Vec<crate::mesh::zone::Source>, f64)>,
}

/// The mesh twice over: nodes `N + i` at the places of nodes `i`, the cells of the second
/// copy on them, every node set holding both copies; two bodies without a common node.
pub fn doubled(mesh: &Mesh) -> Mesh {
    let n = mesh.n_nodes();
    let mut coords = mesh.coords.clone();
    coords.extend_from_slice(&mesh.coords);
    let one = mesh.cells.connectivity();
    let flat: Vec<usize> = one
        .iter()
        .copied()
        .chain(one.iter().map(|i| i + n))
        .collect();
    let cells = Cells::from_flat(mesh.cells.kind(), &flat);
    let node_sets = mesh
        .node_sets
        .iter()
        .map(|(k, v)| {
            (
                k.clone(),
                v.iter().copied().chain(v.iter().map(|i| i + n)).collect(),
            )
        })
        .collect();
    Mesh::new(mesh.dim, coords, cells, node_sets)
}

/// Element geometry of every triangle, with an error naming a bad element.
///
/// # Errors
/// [`WheelError::Element`].
pub fn triangle_geometry(mesh: &Mesh) -> Result<(Vec<[usize; 3]>, Vec<Tri3Geometry>), WheelError> {
    let Cells::Tri3(tris) = &mesh.cells else {
        return Err(WheelError::NotTriangles);
    };
    let mut g = Vec::with_capacity(tris.len());
    for (e, t) in tris.iter().enumerate() {
        g.push(
            tri3::geometry(&tri3::corners(mesh, *t)).map_err(|source| WheelError::Element {
                element: e,
                nodes: *t,
                source,
            })?,
        );
    }
    Ok((tris.clone(), g))
}

/// Solves `K u = f` with the given fixed dofs (and, when `pin_rotation`, the tangential
/// displacement of one rim node, to remove the rigid rotation of a wheel pinned at one
/// node; a load with no moment about the centre gives that pin no reaction).
///
/// # Errors
/// [`LinalgError`] when `K` is singular on the free dofs.
pub fn static_solve(
    asm: &Assembler,
    k: &[f64],
    f: &[f64],
    fixed: &[usize],
) -> Result<Vec<f64>, LinalgError> {
    let n = asm.pattern.nrows();
    let mut is_fixed = vec![false; n];
    for &d in fixed {
        is_fixed[d] = true;
    }
    let mut a = k.to_vec();
    crate::linalg::set_identity_rows(&asm.pattern, &mut a, &is_fixed);
    // Symmetric (rows and columns of the fixed dofs replaced): a Cholesky where K is
    // positive definite on the free dofs.
    let mut lu = Factor::auto(&asm.pattern, &a)?;
    let mut u: Vec<f64> = f
        .iter()
        .zip(&is_fixed)
        .map(|(&x, &fx)| if fx { 0.0 } else { x })
        .collect();
    lu.solve_in_place(&mut u);
    Ok(u)
}

impl WheelModel {
    /// Builds the model on `mesh` (a disk centred at the origin).
    ///
    /// # Errors
    /// [`WheelError`].
    pub fn new(mesh: Mesh, spec: WheelSpec) -> Result<Self, WheelError> {
        let twin = match spec.coupling {
            Coupling::Coupled => None,
            Coupling::Uncoupled => Some(Box::new(Self::new(
                doubled(&mesh),
                WheelSpec {
                    coupling: Coupling::Coupled,
                    ..spec.clone()
                },
            )?)),
        };
        let (triangles, geometry) = triangle_geometry(&mesh)?;
        let d = spec.plane.elasticity_matrix(&spec.material);
        let asm = Assembler::new(&mesh);
        let (m, k) = assemble_mass_stiffness(
            &asm,
            &geometry,
            &d,
            &spec.material,
            spec.thickness,
            spec.lumped,
        );
        let n = mesh.n_dofs();
        let held = held_nodes(&mesh, &spec)?;
        let fixed_dofs: Vec<usize> = held.iter().flat_map(|&i| [2 * i, 2 * i + 1]).collect();
        let rim = rim_nodes(&mesh);
        // External damping eta_z N^T N: the mass shape with eta_z in place of rho (Eq. 22).
        let mut c = asm.zeros();
        if spec.damping > 0.0 {
            asm.add_assembled(
                &Tri3Mass {
                    geometry: &geometry,
                    density: spec.damping,
                    thickness: spec.thickness,
                    lumped: spec.lumped,
                },
                &mut c,
            );
        }
        let mut k_eff = k.clone();
        let mut u_spin = vec![0.0; n];
        let mut load = vec![0.0; n];
        if spec.rotating_frame && spec.omega != 0.0 {
            // The rotating-frame terms of crate::frame, about the spinning equilibrium.
            let om = -spec.omega;
            let fc = frame::centrifugal_load(&asm.pattern, &m, om, &mesh.reference_positions());
            u_spin = static_solve(
                &asm,
                &k,
                &fc,
                &static_fixed_dofs(&mesh, &spec, &fixed_dofs, &rim),
            )?;
            let k_sigma = spec.stress_stiffening.then(|| {
                frame::stress_stiffening(&asm, &geometry, &triangles, &d, spec.thickness, &u_spin)
            });
            k_eff = frame::effective_stiffness(&k, k_sigma.as_deref(), &m, om);
            frame::add_coriolis(&asm, &m, om, &mut c);
            // The constant load K_eff u_c of the linearisation (frame module docs).
            crate::linalg::spmv_add(&asm.pattern, &k_eff, 1.0, &u_spin, &mut load);
            for &dof in &fixed_dofs {
                load[dof] = 0.0;
            }
        }
        Ok(Self {
            mesh,
            triangles,
            geometry,
            d,
            model: LinearModel {
                assembler: asm,
                m,
                k: k_eff,
                c,
            },
            k_elastic: k,
            fixed_dofs,
            rim,
            u_spin,
            load,
            spec,
            twin,
            zone: None,
        })
    }

    /// The radius within which the support holds the nodes, m: the largest radius of a held
    /// node (0 for the pinned centre).
    pub fn support_radius(&self) -> f64 {
        self.fixed_dofs
            .iter()
            .map(|&d| {
                let p = self.mesh.point(d / 2);
                p[0].hypot(p[1])
            })
            .fold(0.0, f64::max)
    }

    /// The rim nodes a full rim would have at the pitch under the contact: the node-passing
    /// frequency is `omega` times it over `2 pi`. The rim's count, or with a refined zone
    /// the count at the zone's (finest) pitch.
    pub fn passing_nodes(&self) -> usize {
        if self.zone.is_none() {
            return self.rim.len();
        }
        let angle_of = |i: usize| angle(self.mesh.point(i));
        let n = self.rim.len();
        let finest = (0..n)
            .map(|k| {
                let d = angle_of(self.rim[(k + 1) % n]) - angle_of(self.rim[k]);
                d.rem_euclid(2.0 * std::f64::consts::PI)
            })
            .filter(|&d| d > 0.0)
            .fold(f64::INFINITY, f64::min);
        (2.0 * std::f64::consts::PI / finest).round() as usize
    }

    /// The rim radius of the spinning wheel (undeformed radius plus the centrifugal
    /// expansion), m: the flattening `d` is measured from it.
    pub fn spinning_radius(&self) -> f64 {
        self.rim
            .iter()
            .map(|&i| {
                let p = self.mesh.point(i);
                norm(&[p[0] + self.u_spin[2 * i], p[1] + self.u_spin[2 * i + 1]])
            })
            .fold(0.0, f64::max)
    }

    /// The rotating base, at `spinning_radius() - d(t)` from the axle.
    pub fn base(&self) -> RotatingLine {
        RotatingLine {
            centre: [0.0; 3],
            radius: self.spinning_radius(),
            omega: self.spec.omega,
            theta0: 0.0,
            flattening: self.spec.flattening,
            creepage: self.spec.creepage,
        }
    }

    /// The contact pairs, one per rim node in the order of [`WheelModel::rim`]: the node's
    /// own gap, or its mortar-weighted gap with its two neighbours round the rim
    /// ([`ContactSurface`]).
    pub fn contact_pairs(&self) -> Vec<Pair> {
        match self.spec.surface {
            ContactSurface::Nodes => self
                .rim
                .iter()
                .map(|&node| Pair::Obstacle { node, obstacle: 0 })
                .collect(),
            ContactSurface::Segments => {
                let p = |i: usize| self.mesh.point(i);
                let angle = |i: usize| p(i)[1].atan2(p(i)[0]);
                let n = self.rim.len();
                let mut order: Vec<usize> = (0..n).collect();
                order.sort_by(|&a, &b| angle(self.rim[a]).total_cmp(&angle(self.rim[b])));
                let mut pos = vec![0; n];
                for (k, &i) in order.iter().enumerate() {
                    pos[i] = k;
                }
                let dist = |a: usize, b: usize| {
                    let (x, y) = (p(a), p(b));
                    ((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2)).sqrt()
                };
                (0..n)
                    .map(|i| {
                        let k = pos[i];
                        let node = self.rim[i];
                        let prev = self.rim[order[(k + n - 1) % n]];
                        let next = self.rim[order[(k + 1) % n]];
                        Pair::Weighted {
                            nodes: [node, prev, next],
                            weights: Pair::mortar_weights(dist(prev, node), dist(node, next)),
                            obstacle: 0,
                        }
                    })
                    .collect()
            }
        }
    }

    /// The simulation problem from `t = 0` for `steps` steps.
    pub fn problem(
        &self,
        integrator: Integrator,
        h: f64,
        gamma_schedule: Vec<(f64, f64)>,
        treatment: Treatment,
        steps: usize,
    ) -> Problem {
        let base: Box<dyn Obstacle> = Box::new(self.base());
        // Uncoupled (Coupling::Uncoupled): the disk and its twin, the loads and the
        // spinning equilibrium on the disk alone, each rim node's tangential row on its twin.
        let (on, pairs) = match self.twin.as_deref() {
            None => (self, self.contact_pairs()),
            Some(twin) => {
                let nodes = self.mesh.n_nodes();
                let pairs = self
                    .rim
                    .iter()
                    .map(|&node| Pair::Split {
                        node,
                        shadow: node + nodes,
                        obstacle: 0,
                    })
                    .collect();
                (twin, pairs)
            }
        };
        let n = on.mesh.n_dofs();
        let own = self.mesh.n_dofs();
        let mut load = vec![0.0; n];
        load[..own].copy_from_slice(&self.load);
        let mut u0 = vec![0.0; n];
        u0[..own].copy_from_slice(&self.u_spin);
        Problem {
            dim: 2,
            reference: on.mesh.reference_positions(),
            model: on.model.clone(),
            integrator,
            h,
            gamma_schedule,
            dirichlet: on.fixed_dofs.iter().map(|&d| (d, 0.0)).collect(),
            load: Box::new(move |_, f| f.copy_from_slice(&load)),
            obstacles: vec![base],
            interfaces: Vec::new(),
            pairs,
            treatment,
            u0,
            v0: vec![0.0; n],
            t0: 0.0,
            steps,
            gap_tol: 1e-9 * self.spec.radius,
            energy_stiffness: Some(on.k_elastic.clone()),
            friction: None,
        }
    }

    /// The wheel's own state from the driver's into `out` (`n` dofs of [`Mesh::n_dofs`]): the
    /// same values when coupled, the sum of the disk's and its twin's when uncoupled.
    pub fn own_state(&self, x: &[f64], out: &mut [f64]) {
        super::own_with_twin(x, out);
    }

    /// Element stresses `[sxx, syy, txy]` (Pa) of the displacement `u`, into `out`
    /// ([`tri3::stresses_into`]; their `J2` and von Mises:
    /// [`PlaneModel::stress_invariants`]).
    pub fn stresses_into(&self, u: &[f64], out: &mut [[f64; 3]]) {
        tri3::stresses_into(&self.geometry, &self.triangles, &self.d, u, out);
    }
}

/// The nodes held by the support: the centre node, or every node within the hub radius.
pub(crate) fn held_nodes(mesh: &Mesh, spec: &WheelSpec) -> Result<Vec<usize>, WheelError> {
    match spec.support {
        Support::CentrePinned => {
            let c = (0..mesh.n_nodes())
                .min_by(|&a, &b| norm(mesh.point(a)).total_cmp(&norm(mesh.point(b))))
                .ok_or_else(|| WheelError::Support("empty mesh".into()))?;
            if norm(mesh.point(c)) > 1e-6 * spec.radius {
                return Err(WheelError::Support(format!(
                    "no node at the centre (the nearest is {:.3e} m away)",
                    norm(mesh.point(c))
                )));
            }
            Ok(vec![c])
        }
        Support::Hub { radius } => {
            let v = crate::mesh::generators::nodes_within(mesh, &[0.0, 0.0], radius);
            if v.is_empty() {
                return Err(WheelError::Support(format!(
                    "no node within the hub radius {radius} m"
                )));
            }
            Ok(v)
        }
    }
}

/// The rim, sorted by angle: the node set "rim" (a Gmsh physical group, or the
/// generator's), else the nodes at the outer radius.
pub(crate) fn rim_nodes(mesh: &Mesh) -> Vec<usize> {
    let rmax = mesh.points().map(norm).fold(0.0, f64::max);
    let mut rim: Vec<usize> = match mesh.node_set("rim") {
        Some(r) if !r.is_empty() => r.to_vec(),
        _ => (0..mesh.n_nodes())
            .filter(|&i| norm(mesh.point(i)) > rmax * (1.0 - 1e-6))
            .collect(),
    };
    rim.sort_by(|&a, &b| angle(mesh.point(a)).total_cmp(&angle(mesh.point(b))));
    rim
}

/// The dofs held in the static centrifugal equilibrium: the support's, and for a pinned
/// wheel the tangential dof of one rim node (no reaction: the load is radial).
fn static_fixed_dofs(mesh: &Mesh, spec: &WheelSpec, fixed: &[usize], rim: &[usize]) -> Vec<usize> {
    let mut fixed_static = fixed.to_vec();
    if matches!(spec.support, Support::CentrePinned) {
        if let Some(&r) = rim.first() {
            let p = mesh.point(r);
            fixed_static.push(if p[0].abs() > p[1].abs() {
                2 * r + 1
            } else {
                2 * r
            });
        }
    }
    fixed_static
}

/// Distance of the planar point `p` from the origin.
fn norm(p: &[f64]) -> f64 {
    (p[0] * p[0] + p[1] * p[1]).sqrt()
}

/// Polar angle of the planar point `p`.
fn angle(p: &[f64]) -> f64 {
    p[1].atan2(p[0])
}
