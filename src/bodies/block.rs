//! The paper's wheel on a deformable base: the wheel of [`crate::bodies::wheel`] (its rotating
//! frame, its hub, its spinning equilibrium) pressed onto, then rolling along, an elastic
//! block: a second body of triangles in a frame that translates under the wheel, clamped at
//! its bottom, met through a contact search ([`crate::contact::interface`]).
//!
//! **Frames.** The wheel's dofs are displacements in the frame that turns with it at
//! `-omega` about the axle (the paper's: its material does not move in it); the block's are
//! displacements in a frame that translates at `V = (-omega rho, 0)` (`rho = R_s - d`, the
//! rolling radius after the flattening `d`, `R_s` the spun rim's radius): the block's
//! surface runs under the wheel at the rim's speed, rolling without slip. The block is
//! pressed up by the paper's flattening program `d(t)` ([`Motion::Pressed`]): at `t = 0`
//! its top touches the spun rim's lowest point, and at the end of settling it has moved up
//! by `d`. The frame's acceleration loads the block with `-M 1 d''(t)` ([`crate::bodies`]).
//!
//! **Contact.** Every rim node of the wheel is a slave node against the block's top
//! segments ([`Pair::Searched`]): its pair's row is that of the segment under it at the
//! start of each step. The pairs are the rim's, in the order of [`WheelModel::rim`], as on
//! the rigid base; every treatment works on them.
//!
//! **The block's mesh.** Columns of the rim's node spacing (`block.dx`, default: the rim's
//! pitch), rows growing by `block.grading` from the top down to `block.depth`; its length
//! covers the run's travel `omega rho T` plus `block.margin` before and after.
//!
//! **Hertz's line contact.** Two cylinders' axes parallel, radii `R_1`, `R_2` (a flat block:
//! `R_2 = infinity`), pressed by the force `P'` per unit length, touch on a strip of
//! half-width
//! $$a = \sqrt{\frac{4 P\' R}{\pi E^\*}},\qquad \frac1R = \frac1{R_1} + \frac1{R_2},\qquad
//!   \frac1{E^\*} = \frac{1-\nu_1^2}{E_1} + \frac{1-\nu_2^2}{E_2}$$
//! in plane strain (Johnson, Contact Mechanics, Eq. 4.43 with 5.2b); in plane stress the
//! factors `1 - nu^2` are 1 ([`hertz_half_width`]). For two identical plane-strain bodies
//! `E* = E / (2 (1 - nu^2))`. The half-width of a computed patch is read from its nodal forces
//! `F_i` at ground abscissae `x_i` by their second moment: for Hertz's elliptic pressure
//! `sum F (x - x_c)^2 / sum F = a^2 / 4` ([`patch_half_width`]).

use crate::bodies::wheel::{triangle_geometry, WheelError, WheelModel};
use crate::bodies::{self, Assembled, Body};
use crate::contact::search::{top_segments, Motion, Placed, Search, SearchError};
use crate::contact::{Interface, Pair, Treatment};
use crate::element::tri3::Tri3Geometry;
use crate::material::{Elastic, PlaneModel};
use crate::mesh::generators::{block_graded, MeshError};
use crate::mesh::Mesh;
use crate::model::LinearModel;
use crate::simulation::Problem;
use crate::time::Integrator;

/// The block under the wheel (scenario table `[block]`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct BlockSpec {
    /// The block's material.
    pub material: Elastic,
    /// Depth below the surface, m (clamped at the bottom).
    pub depth: f64,
    /// Column width at the top, m (`None`: the rim's node pitch).
    pub dx: Option<f64>,
    /// Growth of the rows from the top down, in `[1, 2]`.
    pub grading: f64,
    /// Length of block before and after the run's travel, m.
    pub margin: f64,
    /// The contact search's reach, m (`None`: four columns).
    pub reach: Option<f64>,
}

/// Errors of building the wheel on its block.
#[derive(Debug, thiserror::Error)]
pub enum OnBlockError {
    /// The wheel.
    #[error(transparent)]
    Wheel(#[from] WheelError),
    /// The block's mesh.
    #[error("the block's mesh: {0}")]
    Mesh(#[from] MeshError),
    /// The search.
    #[error(transparent)]
    Search(#[from] SearchError),
    /// The joined model.
    #[error("joining the wheel and the block: {0}")]
    Assembly(#[from] crate::assembly::AssemblyError),
    /// The wheel is not a rotating-frame model that rolls.
    #[error("{0}")]
    Unsupported(String),
}

/// The wheel and its block (module docs).
#[derive(Debug)]
pub struct WheelOnBlock {
    /// The wheel's model.
    pub wheel: WheelModel,
    /// The block's specification.
    pub spec: BlockSpec,
    /// The two bodies: the wheel (0) and the block (1).
    pub bodies: Vec<Body>,
    /// The bodies joined.
    pub joined: Assembled,
    /// The rim against the block's top.
    pub interface: Interface,
    /// The block's element geometry.
    pub block_geometry: Vec<Tri3Geometry>,
    /// Rolling radius `rho`, m.
    pub rolling_radius: f64,
    /// The block's length, m.
    pub length: f64,
}

impl WheelOnBlock {
    /// Builds the wheel `wheel` on the block `spec` for a run of `duration` seconds.
    ///
    /// # Errors
    /// [`OnBlockError`].
    pub fn new(wheel: WheelModel, spec: BlockSpec, duration: f64) -> Result<Self, OnBlockError> {
        let ws = &wheel.spec;
        if wheel.twin.is_some() || wheel.zone.is_some() {
            return Err(OnBlockError::Unsupported(
                "the wheel on a block is a coupled wheel without a moving zone".into(),
            ));
        }
        let r_spin = wheel.spinning_radius();
        let depth_flat = ws.flattening.depth;
        let rho = r_spin - depth_flat;
        let speed = ws.omega * rho;
        let pitch = 2.0 * std::f64::consts::PI * ws.radius / wheel.rim.len() as f64;
        let dx = spec.dx.unwrap_or(pitch);
        let length = 2.0 * spec.margin + speed.abs() * duration;
        let mesh = block_graded(length, spec.depth, dx, spec.grading)?;
        let (_, geometry) = triangle_geometry(&mesh)?;
        let d = ws.plane.elasticity_matrix(&spec.material);
        let asm = crate::assembly::Assembler::new(&mesh);
        let (m, k) = crate::assembly::assemble_mass_stiffness(
            &asm,
            &geometry,
            &d,
            &spec.material,
            ws.thickness,
            ws.lumped,
        );
        let fixed_dofs: Vec<usize> = mesh.node_sets["bottom"]
            .iter()
            .flat_map(|&i| [2 * i, 2 * i + 1])
            .collect();
        let segments = top_segments(&mesh.coords, mesh.dim, &mesh.node_sets["top"]);
        let block_motion = Motion::Pressed {
            origin: [-spec.margin, -r_spin - spec.depth, 0.0],
            velocity: [-speed, 0.0, 0.0],
            direction: [0.0, 1.0, 0.0],
            program: ws.flattening,
        };
        let wheel_motion = Motion::Rotating {
            centre: [0.0; 3],
            omega: -ws.omega,
            angle0: 0.0,
        };
        let model = LinearModel {
            c: asm.zeros(),
            assembler: asm,
            m,
            k: k.clone(),
        };
        let mut block = Body::triangles("block", mesh, model, k, block_motion);
        block.fixed_dofs = fixed_dofs;
        let wheel_body = wheel_body(&wheel);
        let bodies = vec![wheel_body, block];
        let joined = bodies::assemble(&bodies)?;
        let reach = spec.reach.unwrap_or(4.0 * dx);
        let search = Search::new(
            2,
            Placed {
                motion: block_motion,
                first_dof: joined.first_dof[1],
            },
            bodies[1].mesh.reference_positions(),
            segments,
            reach,
        )?;
        let interface = Interface::new(
            search,
            Placed {
                motion: wheel_motion,
                first_dof: 0,
            },
            wheel.rim.clone(),
            &wheel.mesh.reference_positions(),
        );
        Ok(Self {
            wheel,
            spec,
            bodies,
            joined,
            interface,
            block_geometry: geometry,
            rolling_radius: rho,
            length,
        })
    }

    /// The block's mesh.
    pub fn block_mesh(&self) -> &Mesh {
        &self.bodies[1].mesh
    }

    /// The wheel's frame.
    pub fn wheel_motion(&self) -> Motion {
        self.bodies[0].motion
    }

    /// The block's frame.
    pub fn block_motion(&self) -> Motion {
        self.bodies[1].motion
    }

    /// The contact pairs: one per rim node, in the order of [`WheelModel::rim`].
    pub fn pairs(&self) -> Vec<Pair> {
        Pair::searched(0, &self.interface, 0)
    }

    /// The effective modulus `E*` of the wheel against the block in the wheel's plane model
    /// (module docs), Pa.
    pub fn contact_modulus(&self) -> f64 {
        let ws = &self.wheel.spec;
        contact_modulus(ws.plane, &ws.material, &self.spec.material)
    }

    /// Hertz's half-width for a total force `force` (N) on the wheel's thickness, m.
    pub fn hertz_half_width(&self, force: f64) -> f64 {
        let ws = &self.wheel.spec;
        hertz_half_width(force / ws.thickness, ws.radius, self.contact_modulus())
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
        Problem {
            gamma_schedule,
            treatment,
            gap_tol: 1e-9 * self.wheel.spec.radius,
            ..self.joined.problem(
                &self.bodies,
                (vec![self.interface.clone()], self.pairs()),
                (integrator, h, steps),
            )
        }
    }

    /// The ground abscissa of rim node `slot` at time `t` with the model's displacements `u`,
    /// m.
    pub fn rim_x(&self, slot: usize, t: f64, u: &[f64]) -> f64 {
        let i = self.wheel.rim[slot];
        let p = self.wheel.mesh.point(i);
        self.wheel_motion()
            .place(t, [p[0] + u[2 * i], p[1] + u[2 * i + 1], 0.0])[0]
    }
}

/// The wheel of `wheel` as a body: its model in the frame turning at `-omega` about the
/// axle, its hub, its spinning equilibrium's load and initial displacement.
pub fn wheel_body(wheel: &WheelModel) -> Body {
    let mut b = Body::triangles(
        "wheel",
        wheel.mesh.clone(),
        wheel.model.clone(),
        wheel.k_elastic.clone(),
        Motion::Rotating {
            centre: [0.0; 3],
            omega: -wheel.spec.omega,
            angle0: 0.0,
        },
    );
    b.fixed_dofs = wheel.fixed_dofs.clone();
    b.load = wheel.load.clone();
    b.u0 = wheel.u_spin.clone();
    b
}

/// `E*` of two bodies in the plane model `plane` (module docs), Pa.
pub fn contact_modulus(plane: PlaneModel, a: &Elastic, b: &Elastic) -> f64 {
    let f = |m: &Elastic| match plane {
        PlaneModel::Strain => (1.0 - m.poisson * m.poisson) / m.young,
        PlaneModel::Stress => 1.0 / m.young,
    };
    1.0 / (f(a) + f(b))
}

/// Hertz's half-width `a = sqrt(4 P' R / (pi E*))` of a cylinder of radius `radius` (m) on a
/// flat under `force_per_length` (N/m) with the modulus `e_star` (Pa), m.
pub fn hertz_half_width(force_per_length: f64, radius: f64, e_star: f64) -> f64 {
    (4.0 * force_per_length * radius / (std::f64::consts::PI * e_star)).sqrt()
}

/// The half-width and centre of a patch from its nodal forces `forces` (N, compressive
/// positive; others ignored) at abscissae `x` (m): `a = 2 sqrt(sum F (x - x_c)^2 / sum F)`,
/// `x_c = sum F x / sum F` (module docs). `None` without a compressive force.
pub fn patch_half_width(x: &[f64], forces: &[f64]) -> Option<(f64, f64)> {
    let (mut s0, mut s1) = (0.0, 0.0);
    for (&xi, &f) in x.iter().zip(forces) {
        if f > 0.0 {
            s0 += f;
            s1 += f * xi;
        }
    }
    if s0 <= 0.0 {
        return None;
    }
    let xc = s1 / s0;
    let s2: f64 = x
        .iter()
        .zip(forces)
        .filter(|(_, &f)| f > 0.0)
        .map(|(&xi, &f)| f * (xi - xc) * (xi - xc))
        .sum();
    Some((2.0 * (s2 / s0).sqrt(), xc))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The second-moment half-width of Hertz's elliptic pressure sampled finely is its `a`.
    #[test]
    fn the_second_moment_of_an_elliptic_pressure_gives_its_half_width() {
        let (a, xc) = (3e-3, 0.4e-3);
        let n = 20_000;
        let x: Vec<f64> = (0..n)
            .map(|i| xc - a + 2.0 * a * (i as f64 + 0.5) / n as f64)
            .collect();
        let f: Vec<f64> = x
            .iter()
            .map(|&xi| (1.0 - ((xi - xc) / a).powi(2)).max(0.0).sqrt())
            .collect();
        let (got, c) = patch_half_width(&x, &f).unwrap();
        assert!((got - a).abs() < 1e-4 * a, "{got} against {a}");
        assert!((c - xc).abs() < 1e-9);
        assert!(patch_half_width(&x, &vec![0.0; n]).is_none());
    }

    #[test]
    fn hertz_for_identical_bodies_in_plane_strain_uses_half_the_plane_modulus() {
        let steel = Elastic {
            young: 2.05e11,
            poisson: 0.3,
            density: 7830.0,
        };
        let e = contact_modulus(PlaneModel::Strain, &steel, &steel);
        assert!((e - 2.05e11 / (2.0 * (1.0 - 0.09))).abs() < 1e-3);
        assert!((contact_modulus(PlaneModel::Stress, &steel, &steel) - 1.025e11).abs() < 1e-3);
        // Johnson's example scale: 1 MN/m on R = 0.1 m, E* = 1.1e11 Pa: a = 1.08 mm.
        let a = hertz_half_width(1e6, 0.1, 1.1e11);
        assert!((a - (4e5 / (std::f64::consts::PI * 1.1e11)).sqrt()).abs() < 1e-15);
    }
}
