//! A model as a set of bodies: each body a mesh with its own semi-discrete
//! model `M v' + C v + K u = f` (its frame's terms included: [`crate::frame`] for a body
//! seen in a rotating frame), its supports, its constant load, its initial state, and the
//! rigid motion of its frame against the ground ([`Motion`]), by which the contact search
//! places it ([`crate::contact::search`]).
//!
//! [`assemble`] lays the bodies' dofs one after another (body `b` owns the dofs
//! `first_dof[b] .. first_dof[b + 1]` and its node `i` is the model's node
//! `first_node[b] + i`) and joins their matrices block-diagonally on one pattern: the bodies
//! meet through contact rows only. The pattern of the union is the union of the bodies'
//! patterns shifted, so the joined value arrays are the bodies' arrays one after another
//! (checked entry by entry).
//!
//! **Discrete elements between bodies** ([`Joints`], [`assemble_with`]): point masses,
//! spring-dampers and hubs ([`crate::element::discrete`]) on the joined numbering, joining
//! dofs of different bodies or dofs of their own appended after the bodies' (an axle node
//! carrying the unsprung mass and the axle load, a sleeper's mass). Their entries join the
//! pattern as two more element families; their stiffness counts in the strain energy
//! (tests/joints.rs: an axle on a spring to an elastic block oscillates at the series
//! stiffness's period, and springs between two free bodies keep the total momentum).
//!
//! **A rigid body** ([`Body::rigid`]) is a surface whose dofs are all held: the paper's
//! rigid base is one, met by the rim through the contact search with the same forces as
//! the rotating base's own pairs (tests/on_block.rs).
//!
//! **A translating frame that accelerates.** A body whose frame is pressed by a program
//! `d(t)` along `e` ([`Motion::Pressed`]: the base block of the wheel, carrying the paper's
//! kinematic load) has its material at `x = o(t) + X + u` with `o'' = d''(t) e`; its
//! equations in the frame carry the inertial load
//! $$f_{frame}(t) = -M\\,\mathbf{1}\_e\\,d\'\'(t)$$
//! (`1_e` the unit translation along `e`), which [`load_fn`] adds to the constant loads.

pub mod bar;
pub mod block;
pub mod rail;
pub mod rolling3d;
pub mod solid;
pub mod spinning;
pub mod wheel;

use crate::assembly::{Assembler, AssemblyError, ElementFamily};
use crate::contact::search::Motion;
use crate::contact::{Interface, Pair, Treatment};
use crate::element::beam::{lengths, Beam2, BeamError, BeamMatrix, BeamSection, BeamTheory};
use crate::element::discrete::{Discrete, DiscreteError};
use crate::linalg::spmv_add;
use crate::mesh::Cells;
use crate::mesh::Mesh;
use crate::model::{LinearModel, LoadFn};
use crate::simulation::Problem;
use crate::time::Integrator;

/// A body of the model (module docs).
#[derive(Debug, Clone)]
pub struct Body {
    /// Name (for messages and output).
    pub name: String,
    /// The mesh (a 2D triangle mesh; the body's own node indices and reference positions).
    pub mesh: Mesh,
    /// The body's model on the pattern of [`Assembler::new`] of its mesh.
    pub model: LinearModel,
    /// The elastic stiffness alone (the strain energy), on the same pattern.
    pub elastic: Vec<f64>,
    /// The rigid motion of the body's frame against the ground.
    pub motion: Motion,
    /// Supported dofs (the body's own indices): zero velocity.
    pub fixed_dofs: Vec<usize>,
    /// Constant load, N per dof.
    pub load: Vec<f64>,
    /// Initial displacement, m.
    pub u0: Vec<f64>,
    /// The position each dof's displacement adds to (`X` of a contact row's
    /// `c . (X + u)`): a node's coordinates for a body of triangles, `(Y, 0)` per node for a
    /// rail of beams (its deflection and rotation), m (rad).
    pub reference: Vec<f64>,
    /// The dofs of a unit rigid translation of the body along each axis of its frame (`x`,
    /// `y` and, in 3D, `z`; `None` along an axis the body's dofs cannot follow: a rail of
    /// beams along `x`).
    pub translations: Vec<Option<Vec<f64>>>,
}

impl Body {
    /// A body on `mesh` (2D, two dofs per node: triangles, or segments of a rigid surface):
    /// [`Body::on_mesh`] of a planar mesh.
    pub fn triangles(
        name: &str,
        mesh: Mesh,
        model: LinearModel,
        elastic: Vec<f64>,
        motion: Motion,
    ) -> Self {
        Self::on_mesh(name, mesh, model, elastic, motion)
    }

    /// A body on `mesh` of any dimension `dim` (`dim` displacement dofs per node: a
    /// continuum's cells, or a rigid surface's): the reference is the nodes' coordinates,
    /// the translations along each axis `c` the unit vector on every node's component `c`
    /// (`(1, 0, 1, 0, ..)` and `(0, 1, 0, 1, ..)` in the plane); no load, no initial
    /// displacement, no supports.
    pub fn on_mesh(
        name: &str,
        mesh: Mesh,
        model: LinearModel,
        elastic: Vec<f64>,
        motion: Motion,
    ) -> Self {
        let (n, dim) = (mesh.n_dofs(), mesh.dim);
        let unit = |c: usize| Some((0..n).map(|d| f64::from(u8::from(d % dim == c))).collect());
        Body {
            name: name.into(),
            reference: mesh.reference_positions(),
            translations: (0..dim).map(unit).collect(),
            model,
            elastic,
            motion,
            fixed_dofs: Vec::new(),
            load: vec![0.0; n],
            u0: vec![0.0; n],
            mesh,
        }
    }

    /// A rigid surface on `mesh` (its cells the segments a contact search meets): every dof
    /// held, no mass, no stiffness; the frame's [`Motion`] alone moves it. The paper's rigid
    /// base is such a body: a straight segment under the wheel, pressed by the flattening
    /// program ([`Motion::Pressed`]), met by the rim through the search like a deformable
    /// base (tests/on_block.rs runs the two and compares).
    pub fn rigid(name: &str, mesh: Mesh, motion: Motion) -> Self {
        let model = LinearModel::zeros(Assembler::new(&mesh));
        let elastic = model.k.clone();
        let mut b = Body::on_mesh(name, mesh, model, elastic, motion);
        b.fixed_dofs = (0..b.mesh.n_dofs()).collect();
        b
    }

    /// A rail of [`Beam2`] elements along the frame's `x` at height `y` (m), its nodes at
    /// the abscissae `xs` (increasing), dofs `(w, theta)` per node, pinned (`w = 0`) at the
    /// nodes `pinned`; the mass and stiffness of `section` in `theory`.
    ///
    /// # Errors
    /// [`BeamError`] for a bad section or abscissae that do not increase.
    pub fn rail(
        name: &str,
        xs: &[f64],
        y: f64,
        section: &BeamSection,
        theory: BeamTheory,
        motion: Motion,
        pinned: &[usize],
    ) -> Result<Self, BeamError> {
        section.validate(theory)?;
        let coords: Vec<f64> = xs.iter().flat_map(|&x| [x, y]).collect();
        let elements: Vec<[usize; 2]> = (1..xs.len()).map(|i| [i - 1, i]).collect();
        let lengths = lengths(&coords, 2, &elements)?;
        let mesh = Mesh::new(2, coords, Cells::Bar2(elements), Default::default());
        let asm = Assembler::new(&mesh);
        let op = |matrix| Beam2 {
            lengths: &lengths,
            section,
            theory,
            matrix,
        };
        let m = asm.assemble(&op(BeamMatrix::Mass));
        let k = asm.assemble(&op(BeamMatrix::Stiffness));
        let n = mesh.n_dofs();
        Ok(Body {
            name: name.into(),
            reference: (0..n).map(|d| if d % 2 == 0 { y } else { 0.0 }).collect(),
            translations: vec![
                None,
                Some((0..n).map(|d| f64::from(u8::from(d % 2 == 0))).collect()),
            ],
            model: LinearModel {
                c: asm.zeros(),
                assembler: asm,
                m,
                k: k.clone(),
            },
            elastic: k,
            motion,
            fixed_dofs: pinned.iter().map(|&i| 2 * i).collect(),
            load: vec![0.0; n],
            u0: vec![0.0; n],
            mesh,
        })
    }

    /// Adds springs and dampers from dofs of this body to its frame (the rail's pads and
    /// ballast under its sleepers: [`crate::element::discrete`]'s ground spring-damper,
    /// `K_e = [k]`, `C_e = [c]`): `(dof, k N/m, c N s/m)` each, on the pattern's diagonal.
    ///
    /// # Errors
    /// [`DiscreteError`] for a dof past the body's or a stiffness or damping that is
    /// negative or not finite.
    pub fn with_ground_springs(
        mut self,
        springs: &[(usize, f64, f64)],
    ) -> Result<Self, DiscreteError> {
        for &(d, k, c) in springs {
            for (what, value) in [("spring stiffness", k), ("damping", c)] {
                if !(value.is_finite() && value >= 0.0) {
                    return Err(DiscreteError::Negative { what, value });
                }
            }
            let slot = (d < self.model.n())
                .then(|| self.model.assembler.slot(d, d))
                .flatten()
                .ok_or(DiscreteError::Layout(AssemblyError::DofOutOfRange {
                    family: 0,
                    element: 0,
                    dof: d,
                    n_dofs: self.model.n(),
                }))?;
            self.model.k[slot] += k;
            self.elastic[slot] += k;
            self.model.c[slot] += c;
        }
        Ok(self)
    }

    /// `Phi` of each element of a rail built by [`Body::rail`] (0 for Euler-Bernoulli).
    pub fn rail_phi(&self, section: &BeamSection, theory: BeamTheory) -> Vec<f64> {
        match &self.mesh.cells {
            Cells::Bar2(e) => e
                .iter()
                .map(|&[a, b]| section.phi(theory, self.mesh.point(b)[0] - self.mesh.point(a)[0]))
                .collect(),
            _ => Vec::new(),
        }
    }
}

/// The bodies joined into one model (module docs).
#[derive(Debug, Clone)]
pub struct Assembled {
    /// The dimension of the bodies (all alike; 2 without bodies).
    pub dim: usize,
    /// The joined model.
    pub model: LinearModel,
    /// The joined elastic stiffness.
    pub elastic: Vec<f64>,
    /// Reference positions, each body's in its own frame, m.
    pub reference: Vec<f64>,
    /// First dof of each body, and the number of the bodies' dofs last (the joints' own
    /// dofs follow, up to [`LinearModel::n`]).
    pub first_dof: Vec<usize>,
    /// First node of each body, and the number of nodes last.
    pub first_node: Vec<usize>,
    /// Supported dofs of the model.
    pub fixed_dofs: Vec<usize>,
    /// Constant load of the model, N.
    pub load: Vec<f64>,
    /// Initial displacement of the model, m.
    pub u0: Vec<f64>,
}

impl Assembled {
    /// The driver's problem of the joined `bodies` (those it was assembled from) meeting
    /// through `interfaces` with the contact `pairs`, from `t = 0` and the bodies' initial
    /// displacements at rest, for `steps` steps of `h` with `integrator`: supports held,
    /// the loads of [`load_fn`], the strain energy on the elastic stiffness, the soft way,
    /// frictionless, a penetration tolerance of 1e-12 m (change any field after).
    pub fn problem(
        &self,
        bodies: &[Body],
        (interfaces, pairs): (Vec<Interface>, Vec<Pair>),
        (integrator, h, steps): (Integrator, f64, usize),
    ) -> Problem {
        Problem {
            dim: self.dim,
            reference: self.reference.clone(),
            model: self.model.clone(),
            integrator,
            h,
            gamma_schedule: Vec::new(),
            dirichlet: self.fixed_dofs.iter().map(|&d| (d, 0.0)).collect(),
            load: load_fn(bodies, self),
            obstacles: Vec::new(),
            interfaces,
            pairs,
            treatment: Treatment::SOFT_WAY,
            u0: self.u0.clone(),
            v0: vec![0.0; self.model.n()],
            t0: 0.0,
            steps,
            gap_tol: 1e-12,
            energy_stiffness: Some(self.elastic.clone()),
            friction: None,
        }
    }
}

/// A body's own state from the driver's vector `x` into `out` (its `out.len()` values):
/// `x`'s first values, plus its twin's when `x` holds a twin after them (`x.len() = 2
/// out.len()`: the uncoupled pair of the 2D and 3D wheels, whose state is the sum of the
/// two copies).
pub fn own_with_twin(x: &[f64], out: &mut [f64]) {
    let n = out.len();
    out.copy_from_slice(&x[..n]);
    if x.len() == 2 * n {
        for (o, t) in out.iter_mut().zip(&x[n..]) {
            *o += t;
        }
    }
}

/// Joins `bodies` (module docs).
///
/// # Errors
/// [`AssemblyError`] when a body's mesh is not a 2D triangle mesh or a body's arrays do not
/// match its mesh.
pub fn assemble(bodies: &[Body]) -> Result<Assembled, AssemblyError> {
    assemble_with(bodies, &Joints::default())
}

/// The bodies' first dofs in the joined model, and the number of their dofs last: the
/// numbering [`assemble`] gives, by which [`Joints`] name the bodies' dofs.
pub fn first_dofs(bodies: &[Body]) -> Vec<usize> {
    let mut first = vec![0];
    for b in bodies {
        first.push(first.last().unwrap_or(&0) + b.mesh.n_dofs());
    }
    first
}

/// Discrete elements between bodies and on dofs of their own (module docs): `dofs` dofs
/// after the bodies' (an axle's translations, a sleeper's deflection, ...), and the
/// elements, numbered in the joined model ([`first_dofs`]).
#[derive(Debug, Clone, Default)]
pub struct Joints {
    /// How many dofs of their own the joints add after the bodies' dofs.
    pub dofs: usize,
    /// The elements (masses, spring-dampers, hubs) on the joined numbering.
    pub discrete: Discrete,
}

/// Joins `bodies` and the discrete elements `joints` (module docs): the bodies' dofs first,
/// then the joints' own. The joints' springs add to the elastic stiffness (their energy is
/// strain energy), their hubs' loads to the load.
///
/// # Errors
/// [`AssemblyError`] when a body's arrays do not match its mesh or a joint names a dof
/// past the model's.
pub fn assemble_with(bodies: &[Body], joints: &Joints) -> Result<Assembled, AssemblyError> {
    let mut first_dof = vec![0];
    let mut first_node = vec![0];
    let mut families = Vec::with_capacity(bodies.len());
    if let Some(b) = bodies.iter().find(|b| b.mesh.dim != bodies[0].mesh.dim) {
        return Err(AssemblyError::MixedDimensions {
            first: bodies[0].mesh.dim,
            other: b.mesh.dim,
        });
    }
    for b in bodies {
        let o = *first_dof.last().unwrap_or(&0);
        let fam = ElementFamily::of_mesh(&b.mesh);
        let dofs = (0..fam.len())
            .flat_map(|e| fam.element_dofs(e).iter().map(move |&d| d + o))
            .collect();
        families.push(ElementFamily::try_new(fam.ndof_e(), dofs)?);
        first_dof.push(o + b.mesh.n_dofs());
        first_node.push(first_node.last().unwrap_or(&0) + b.mesh.n_nodes());
    }
    let n_bodies = *first_dof.last().unwrap_or(&0);
    let n = n_bodies + joints.dofs;
    families.extend(joints.discrete.families());
    let assembler = Assembler::try_with_families(n, families)?;
    let nnz = assembler.nnz();
    let mut model = LinearModel {
        m: vec![0.0; nnz],
        k: vec![0.0; nnz],
        c: vec![0.0; nnz],
        assembler,
    };
    let mut elastic = vec![0.0; nnz];
    let (mut reference, mut fixed_dofs, mut load, mut u0) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (bi, b) in bodies.iter().enumerate() {
        let o = first_dof[bi];
        let nd = b.mesh.n_dofs();
        let own = &b.model;
        let sizes_ok = own.n() == nd
            && [own.k.len(), own.c.len(), b.elastic.len()]
                .iter()
                .all(|&l| l == own.m.len())
            && b.load.len() == nd
            && b.u0.len() == nd
            && b.reference.len() == nd
            && b.translations.iter().flatten().all(|t| t.len() == nd)
            && b.fixed_dofs.iter().all(|&d| d < nd);
        if !sizes_ok {
            return Err(AssemblyError::DofOutOfRange {
                family: bi,
                element: 0,
                dof: nd,
                n_dofs: own.n(),
            });
        }
        // The union's column `o + j` holds the body's column `j` shifted (and, where a
        // joint couples the dof, the joint's entries): each body entry goes to its slot.
        // The bodies' blocks do not overlap, so the values are the bodies' own, bit for bit.
        let cp = own.pattern().col_ptr();
        let ri = own.pattern().row_idx();
        for j in 0..nd {
            for k in cp[j]..cp[j + 1] {
                let Some(slot) = model.assembler.slot(ri[k] + o, j + o) else {
                    return Err(AssemblyError::DofOutOfRange {
                        family: bi,
                        element: k,
                        dof: ri[k] + o,
                        n_dofs: n,
                    });
                };
                let kk = k - cp[0];
                model.m[slot] = own.m[kk];
                model.k[slot] = own.k[kk];
                model.c[slot] = own.c[kk];
                elastic[slot] = b.elastic[kk];
            }
        }
        reference.extend_from_slice(&b.reference);
        fixed_dofs.extend(b.fixed_dofs.iter().map(|&d| d + o));
        load.extend_from_slice(&b.load);
        u0.extend_from_slice(&b.u0);
    }
    if joints.dofs > 0 || !joints.discrete.is_empty() {
        // The joints' matrices on the joined pattern; their stiffness is strain energy too.
        let nb = bodies.len();
        let (mut mj, mut cj, mut kj) = (vec![0.0; nnz], vec![0.0; nnz], vec![0.0; nnz]);
        joints
            .discrete
            .add_matrices_into(&model.assembler, nb, &mut mj, &mut cj, &mut kj)
            .map_err(|_| AssemblyError::DofOutOfRange {
                family: nb,
                element: 0,
                dof: n,
                n_dofs: n,
            })?;
        for s in 0..nnz {
            model.m[s] += mj[s];
            model.c[s] += cj[s];
            model.k[s] += kj[s];
            elastic[s] += kj[s];
        }
        reference.resize(n, 0.0);
        u0.resize(n, 0.0);
        load.resize(n, 0.0);
        joints.discrete.add_load_into(1.0, &mut load);
    }
    Ok(Assembled {
        dim: bodies.first().map_or(2, |b| b.mesh.dim),
        model,
        elastic,
        reference,
        first_dof,
        first_node,
        fixed_dofs,
        load,
        u0,
    })
}

/// The model's load at time `t`: the bodies' constant loads plus, for each body whose frame
/// accelerates ([`Motion::acceleration`]), the inertial load `-M 1 a(t)` on its free dofs
/// (module docs). Allocates once here; the returned function allocates nothing.
pub fn load_fn(bodies: &[Body], joined: &Assembled) -> LoadFn {
    let base = joined.load.clone();
    let mut frames = Vec::new();
    for (bi, b) in bodies.iter().enumerate() {
        if !matches!(b.motion, Motion::Pressed { .. }) {
            continue;
        }
        let nd = b.mesh.n_dofs();
        let mut unit = vec![vec![0.0; nd]; b.translations.len()];
        for (c, out) in unit.iter_mut().enumerate() {
            if let Some(ones) = &b.translations[c] {
                spmv_add(b.model.pattern(), &b.model.m, 1.0, ones, out);
            }
            for &d in &b.fixed_dofs {
                out[d] = 0.0;
            }
        }
        frames.push((joined.first_dof[bi], b.motion, unit));
    }
    Box::new(move |t, f| {
        f.copy_from_slice(&base);
        for (o, motion, unit) in &frames {
            let a = motion.acceleration(t);
            for (c, col) in unit.iter().enumerate() {
                if a[c] != 0.0 {
                    for (fi, m1) in f[*o..*o + col.len()].iter_mut().zip(col) {
                        *fi -= a[c] * m1;
                    }
                }
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assembly::assemble_mass_stiffness;
    use crate::bodies::wheel::triangle_geometry;
    use crate::contact::obstacle::Flattening;
    use crate::material::{Elastic, PlaneModel};
    use crate::mesh::generators::rectangle;

    fn block(lx: f64, ly: f64, nx: usize, ny: usize, motion: Motion) -> Body {
        let mesh = rectangle(lx, ly, nx, ny).unwrap();
        let (_, geometry) = triangle_geometry(&mesh).unwrap();
        let mat = Elastic {
            young: 2e11,
            poisson: 0.3,
            density: 7800.0,
        };
        let d = PlaneModel::Stress.elasticity_matrix(&mat);
        let asm = Assembler::new(&mesh);
        let (m, k) = assemble_mass_stiffness(&asm, &geometry, &d, &mat, 0.01, false);
        let nd = mesh.n_dofs();
        let model = LinearModel {
            c: asm.zeros(),
            assembler: asm,
            m,
            k: k.clone(),
        };
        let mut b = Body::triangles("block", mesh, model, k, motion);
        b.fixed_dofs = vec![0, 1];
        b.load = (0..nd).map(|d| d as f64).collect();
        b
    }

    /// The joined matrices act on each body's dofs as the body's own, and on nothing else.
    #[test]
    fn the_joined_model_is_block_diagonal() {
        let a = block(1.0, 0.5, 3, 2, Motion::Fixed);
        let b = block(0.4, 0.3, 2, 3, Motion::Fixed);
        let j = assemble(&[a.clone(), b.clone()]).unwrap();
        let (na, nb) = (a.mesh.n_dofs(), b.mesh.n_dofs());
        assert_eq!(j.first_dof, vec![0, na, na + nb]);
        assert_eq!(j.first_node, vec![0, na / 2, (na + nb) / 2]);
        let x: Vec<f64> = (0..na + nb).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut y = vec![0.0; na + nb];
        spmv_add(j.model.pattern(), &j.model.k, 1.0, &x, &mut y);
        let mut ya = vec![0.0; na];
        spmv_add(a.model.pattern(), &a.model.k, 1.0, &x[..na], &mut ya);
        let mut yb = vec![0.0; nb];
        spmv_add(b.model.pattern(), &b.model.k, 1.0, &x[na..], &mut yb);
        for (got, want) in y.iter().zip(ya.iter().chain(&yb)) {
            assert!(
                (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                "{got} {want}"
            );
        }
        assert_eq!(j.fixed_dofs, vec![0, 1, na, na + 1]);
        assert_eq!(j.load[na + 3], 3.0);
    }

    /// A pressed frame's inertial load is `-M 1 d''` along the pressing: its sum over the
    /// free dofs is minus the free mass times the acceleration.
    #[test]
    fn a_pressed_frame_loads_its_body_with_its_inertia() {
        let program = Flattening {
            depth: 1e-3,
            settle_time: 2e-3,
        };
        let motion = Motion::Pressed {
            origin: [0.0; 3],
            velocity: [3.0, 0.0, 0.0],
            direction: [0.0, 1.0, 0.0],
            program,
        };
        let mut b = block(1.0, 0.5, 4, 2, motion);
        b.fixed_dofs.clear();
        b.load.iter_mut().for_each(|f| *f = 0.0);
        let bodies = [b];
        let j = assemble(&bodies).unwrap();
        let f = load_fn(&bodies, &j);
        let mut out = vec![0.0; j.model.n()];
        let t = 0.3e-3;
        f(t, &mut out);
        let mass = 7800.0 * 1.0 * 0.5 * 0.01;
        let fy: f64 = out.iter().skip(1).step_by(2).sum();
        let fx: f64 = out.iter().step_by(2).sum();
        assert!((fy + mass * program.accel(t)).abs() < 1e-9 * mass * program.accel(t).abs());
        assert_eq!(fx, 0.0);
        // d'' is the derivative of d' (central difference).
        let e = 1e-9;
        let fd = (program.rate(t + e) - program.rate(t - e)) / (2.0 * e);
        assert!((fd - program.accel(t)).abs() < 1e-5 * program.accel(t).abs());
    }
}
