//! Builders of the paper's model problems from plain parameters (the scenarios call these).

use crate::assembly::Assembler;
use crate::contact::{ContactMethod, Obstacle, Wall};
use crate::element::bar2;
use crate::mesh::{Cells, Mesh};
use crate::simulation::{ContactPair, Problem};
use crate::time::step::LinearModel;
use crate::time::SpaceTimeParams;

/// An elastic bar moving rigidly towards a rigid wall (paper §3.1, Fig. 8).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BarImpact {
    /// Length `L`, m.
    pub length: f64,
    /// Axial stiffness `EA`, N.
    pub ea: f64,
    /// Mass per unit length `rho A`, kg/m.
    pub rho_a: f64,
    /// Initial speed towards the wall, m/s.
    pub speed: f64,
    /// Distance from the head to the wall, m.
    pub gap: f64,
    /// Number of elements.
    pub elements: usize,
    /// Lumped (true) or consistent (false) mass.
    pub lumped: bool,
    /// External damping `eta_z` per unit length (Eq. 22), N s/m^2.
    pub damping: f64,
}

impl BarImpact {
    /// Wave speed `c = sqrt(EA / rho A)`, m/s.
    pub fn wave_speed(&self) -> f64 {
        (self.ea / self.rho_a).sqrt()
    }
    /// Exact impact time `gap / v0`, s.
    pub fn exact_impact_time(&self) -> f64 {
        self.gap / self.speed
    }
    /// Exact contact duration `2 L / c`, s.
    pub fn exact_contact_duration(&self) -> f64 {
        2.0 * self.length / self.wave_speed()
    }
    /// Exact contact force `rho A c v0`, N.
    pub fn exact_contact_force(&self) -> f64 {
        self.rho_a * self.wave_speed() * self.speed
    }

    /// The bar's mesh: nodes from `x = 0` (tail) to `x = L` (head, node set "head").
    pub fn mesh(&self) -> Mesh {
        let n = self.elements;
        let points = (0..=n)
            .map(|i| [self.length * i as f64 / n as f64, 0.0])
            .collect();
        let cells = Cells::Bar2((0..n).map(|i| [i, i + 1]).collect());
        let mut node_sets = std::collections::BTreeMap::new();
        node_sets.insert("head".to_string(), vec![n]);
        node_sets.insert("tail".to_string(), vec![0]);
        Mesh {
            dim: 1,
            points,
            cells,
            node_sets,
        }
    }

    /// The model `M, K, C` of the bar.
    pub fn model(&self, mesh: &Mesh) -> LinearModel {
        let asm = Assembler::new(mesh);
        let le = |e: usize| {
            let c = mesh.cell_nodes(e);
            mesh.points[c[1]][0] - mesh.points[c[0]][0]
        };
        let mut m = asm.zeros();
        let mut k = asm.zeros();
        let mut c = asm.zeros();
        asm.assemble_serial_into(&mut m, |e, out| {
            let mut b = [[0.0; 2]; 2];
            bar2::mass_into(le(e), self.rho_a, self.lumped, &mut b);
            out.copy_from_slice(&[b[0][0], b[0][1], b[1][0], b[1][1]]);
        });
        asm.assemble_serial_into(&mut k, |e, out| {
            let mut b = [[0.0; 2]; 2];
            bar2::stiffness_into(le(e), self.ea, &mut b);
            out.copy_from_slice(&[b[0][0], b[0][1], b[1][0], b[1][1]]);
        });
        if self.damping > 0.0 {
            asm.assemble_serial_into(&mut c, |e, out| {
                let mut b = [[0.0; 2]; 2];
                bar2::mass_into(le(e), self.damping, self.lumped, &mut b);
                out.copy_from_slice(&[b[0][0], b[0][1], b[1][0], b[1][1]]);
            });
        }
        LinearModel {
            assembler: asm,
            m,
            k,
            c,
        }
    }

    /// The full problem: the bar moving at `speed` towards a wall at `L + gap`, run to
    /// `t_end`.
    pub fn problem(
        &self,
        params: SpaceTimeParams,
        contact: ContactMethod,
        t_end: f64,
    ) -> (Mesh, Problem) {
        let mesh = self.mesh();
        let model = self.model(&mesh);
        let n = mesh.n_dofs();
        let wall: Box<dyn Obstacle> = Box::new(Wall {
            position: self.length + self.gap,
            side: -1.0,
        });
        let steps = (t_end / params.h).round() as usize;
        let problem = Problem {
            dim: 1,
            reference: mesh.reference_positions(),
            model,
            params,
            gamma_schedule: vec![],
            dirichlet: vec![],
            load: Box::new(|_, f| f.fill(0.0)),
            obstacles: vec![wall],
            pairs: vec![ContactPair {
                node: self.elements,
                obstacle: 0,
            }],
            contact,
            u0: vec![0.0; n],
            v0: vec![self.speed; n],
            t0: 0.0,
            steps,
            gap_tol: 1e-12 * self.length,
            energy_stiffness: None,
        };
        (mesh, problem)
    }
}
