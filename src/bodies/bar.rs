//! Builders of the paper's model problems from plain parameters (the scenarios call these).

use crate::assembly::Assembler;
use crate::contact::{Obstacle, Pair, Treatment, Wall};
use crate::element::bar2;
use crate::mesh::{Cells, Mesh};
use crate::model::LinearModel;
use crate::simulation::Problem;
use crate::time::Integrator;

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
        let coords = (0..=n).map(|i| self.length * i as f64 / n as f64).collect();
        let cells = Cells::Bar2((0..n).map(|i| [i, i + 1]).collect());
        let mut node_sets = std::collections::BTreeMap::new();
        node_sets.insert("head".to_string(), vec![n]);
        node_sets.insert("tail".to_string(), vec![0]);
        Mesh::new(1, coords, cells, node_sets)
    }

    /// The model `M, K, C` of the bar.
    pub fn model(&self, mesh: &Mesh) -> LinearModel {
        bar_model(mesh, self.ea, self.rho_a, self.lumped, self.damping)
    }

    /// The problem: the bar moving at `speed` towards a wall at `L + gap`, run to `t_end`
    /// with the step `h`.
    pub fn problem(
        &self,
        integrator: Integrator,
        treatment: Treatment,
        h: f64,
        t_end: f64,
    ) -> (Mesh, Problem) {
        let mesh = self.mesh();
        let model = self.model(&mesh);
        let n = mesh.n_dofs();
        let wall: Box<dyn Obstacle> = Box::new(Wall {
            position: self.length + self.gap,
            side: -1.0,
        });
        let problem = Problem {
            dim: 1,
            reference: mesh.reference_positions(),
            model,
            integrator,
            h,
            gamma_schedule: vec![],
            dirichlet: vec![],
            load: Box::new(|_, f| f.fill(0.0)),
            obstacles: vec![wall],
            interfaces: Vec::new(),
            pairs: vec![Pair::Obstacle {
                node: self.elements,
                obstacle: 0,
            }],
            treatment,
            u0: vec![0.0; n],
            v0: vec![self.speed; n],
            t0: 0.0,
            steps: (t_end / h).round() as usize,
            gap_tol: 1e-12 * self.length,
            energy_stiffness: None,
            friction: None,
        };
        (mesh, problem)
    }
}

/// The model `M, K, C` of bars (two-node elements along x): axial stiffness `ea` (N), mass
/// per length `rho_a` (kg/m), lumped or consistent, external damping `damping` per length
/// (Eq. 22, N s/m^2).
pub fn bar_model(mesh: &Mesh, ea: f64, rho_a: f64, lumped: bool, damping: f64) -> LinearModel {
    let asm = Assembler::new(mesh);
    let le = |e: usize| {
        let c = mesh.cell_nodes(e);
        mesh.point(c[1])[0] - mesh.point(c[0])[0]
    };
    let mut m = asm.zeros();
    let mut k = asm.zeros();
    let mut c = asm.zeros();
    asm.assemble_serial_into(&mut m, |e, out| {
        let mut b = [[0.0; 2]; 2];
        bar2::mass_into(le(e), rho_a, lumped, &mut b);
        out.copy_from_slice(&[b[0][0], b[0][1], b[1][0], b[1][1]]);
    });
    asm.assemble_serial_into(&mut k, |e, out| {
        let mut b = [[0.0; 2]; 2];
        bar2::stiffness_into(le(e), ea, &mut b);
        out.copy_from_slice(&[b[0][0], b[0][1], b[1][0], b[1][1]]);
    });
    if damping > 0.0 {
        asm.assemble_serial_into(&mut c, |e, out| {
            let mut b = [[0.0; 2]; 2];
            bar2::mass_into(le(e), damping, lumped, &mut b);
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

/// Two equal elastic bars colliding head on: bar A (`x` in `[0, L]`) moves at `speed`
/// towards bar B (`x` in `[L + gap, 2 L + gap]`) at rest. Exact (d'Alembert): contact from
/// `gap / v0` for `2 L / c` with the force `rho A c v0 / 2`; afterwards A is at rest and B
/// moves at `v0`: the bars exchange velocities, and the energy is kept.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoBars {
    /// Length of each bar `L`, m.
    pub length: f64,
    /// Axial stiffness `EA`, N.
    pub ea: f64,
    /// Mass per unit length `rho A`, kg/m.
    pub rho_a: f64,
    /// Initial speed of bar A, m/s.
    pub speed: f64,
    /// Distance between the bars, m.
    pub gap: f64,
    /// Elements per bar.
    pub elements: usize,
    /// Lumped (true) or consistent (false) mass.
    pub lumped: bool,
}

impl TwoBars {
    /// Bar A alone against a wall at the same distance: the same wave speed, impact time
    /// and contact duration.
    pub fn bar_a(&self) -> BarImpact {
        BarImpact {
            length: self.length,
            ea: self.ea,
            rho_a: self.rho_a,
            speed: self.speed,
            gap: self.gap,
            elements: self.elements,
            lumped: self.lumped,
            damping: 0.0,
        }
    }
    /// Wave speed `c`, m/s.
    pub fn wave_speed(&self) -> f64 {
        self.bar_a().wave_speed()
    }
    /// Exact impact time `gap / v0`, s.
    pub fn exact_impact_time(&self) -> f64 {
        self.bar_a().exact_impact_time()
    }
    /// Exact contact duration `2 L / c`, s.
    pub fn exact_contact_duration(&self) -> f64 {
        self.bar_a().exact_contact_duration()
    }
    /// Exact contact force `rho A c v0 / 2`, N.
    pub fn exact_contact_force(&self) -> f64 {
        0.5 * self.rho_a * self.wave_speed() * self.speed
    }

    /// The mesh: bar A's nodes `0..=N` (node sets "a", "a_head"), then bar B's
    /// `N+1..=2N+1` ("b", "b_tail").
    pub fn mesh(&self) -> Mesh {
        let n = self.elements;
        let mut coords: Vec<f64> = (0..=n).map(|i| self.length * i as f64 / n as f64).collect();
        coords.extend((0..=n).map(|i| self.length + self.gap + self.length * i as f64 / n as f64));
        let mut cells: Vec<[usize; 2]> = (0..n).map(|i| [i, i + 1]).collect();
        cells.extend((0..n).map(|i| [n + 1 + i, n + 2 + i]));
        let mut node_sets = std::collections::BTreeMap::new();
        node_sets.insert("a".to_string(), (0..=n).collect());
        node_sets.insert("b".to_string(), (n + 1..=2 * n + 1).collect());
        node_sets.insert("a_head".to_string(), vec![n]);
        node_sets.insert("b_tail".to_string(), vec![n + 1]);
        Mesh::new(1, coords, Cells::Bar2(cells), node_sets)
    }

    /// The problem: bar A's head facing bar B's tail (a node-to-node pair along `+x`), run
    /// to `t_end` with the step `h`.
    pub fn problem(
        &self,
        integrator: Integrator,
        treatment: Treatment,
        h: f64,
        t_end: f64,
    ) -> (Mesh, Problem) {
        let mesh = self.mesh();
        let model = bar_model(&mesh, self.ea, self.rho_a, self.lumped, 0.0);
        let n = self.elements;
        let mut v0 = vec![0.0; 2 * n + 2];
        v0[..=n].fill(self.speed);
        let pb = Problem {
            dim: 1,
            reference: mesh.reference_positions(),
            model,
            integrator,
            h,
            gamma_schedule: vec![],
            dirichlet: vec![],
            load: Box::new(|_, f| f.fill(0.0)),
            obstacles: vec![],
            interfaces: Vec::new(),
            pairs: vec![Pair::Nodes {
                a: n,
                b: n + 1,
                normal: [1.0, 0.0, 0.0],
            }],
            treatment,
            u0: vec![0.0; 2 * n + 2],
            v0,
            t0: 0.0,
            steps: (t_end / h).round() as usize,
            gap_tol: 1e-12 * self.length,
            energy_stiffness: None,
            friction: None,
        };
        (mesh, pb)
    }
}
