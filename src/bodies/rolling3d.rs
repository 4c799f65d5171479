//! A 3D wheel rolling in its own frame on the rigid base: the paper's rotating frame (§4)
//! in 3D, its first rung ([`RollingSlice`]).
//!
//! A steel annulus of hexahedra ([`crate::mesh::generators::annulus_hex8`]) is spun up about
//! its axle `z` ([`super::spinning::spinning_solid`]: the centrifugal prestress, the spin
//! softening and the Coriolis matrix of [`crate::frame3d`], linearised about its spinning
//! equilibrium) and held at its bore. The rigid base turns about it
//! ([`RotatingBase`], the frame turning at `-omega` as the 2D wheel's), laid on the spun
//! rim's mean radius and pressed by a flattening program, and its material slides under the
//! rim by the longitudinal, lateral and spin creepages. Each rim node is a contact pair with
//! the base under the friction law given ([`crate::contact::FrictionLaw`], Coulomb's
//! isotropic cone in 3D), the soft way.
//!
//! **Uncoupled: Kalker's quasi-identical pair.** An elastic wheel on a rigid base is not a
//! pair of one material: the pressure strains the rim tangentially and the traction moves it
//! normally (Dundurs' `beta = (1 - 2 nu) / (2 (1 - nu))`), and Kalker's creep coefficients
//! are those of two bodies of one material, whose normal and tangential problems decouple.
//! [`Coupling::Uncoupled`] poses that pair as the 2D wheel does (Carter's twin): a second
//! copy of the spun wheel (the twin: the same step matrix, without the spin's load) carries
//! the tangential tractions alone, the wheel the normal ones; each rim node's gap reads the
//! wheel, its slip the twin ([`Pair::Split`]), and the wheel's state is their sum
//! ([`RollingSlice::own_state`]). The tangential compliance is then one wheel's on a rigid
//! base: Kalker's combined modulus `G = 2 G_1`, as on the coupled pair.
//!
//! **The elastic rail.** With [`SliceSpec::rail`] the base is a body: a straight bar of the
//! wheel's material with the base's crown ([`rail`]), whose frame translates under the wheel
//! at the base's material speed and is pressed by the flattening program. Each rim node is a
//! [`Pair::Searched`] against the rail's top facets ([`crate::contact::facets`]; the wheel's
//! frame turning, the rail's translating), and the moving zone relocates with the rail's
//! nodes left where they are ([`crate::simulation::Relocation::turned`]). Two bodies of one
//! material are Kalker's pair itself: no twin.
//!
//! [`PatchForce::of`] sums a step's pair states into the normal force and the tangential
//! force on the wheel along the base's travel `t_b` and along the axle: the creep forces.
//! `tests/rolling3d.rs` checks them against the 2D plane-stress wheel and full slip
//! (the book's docs/src/solids3d.md, "Rolling in 3D").

pub mod rail;

use crate::bodies::wheel::Coupling;
use crate::contact::facets::FacetSearch;
use crate::contact::search::Placed;
use crate::contact::Interface;

use crate::contact::cyclic::CyclicSymmetry;
use crate::contact::obstacle::Flattening;
use crate::contact::pair::tangent_basis;
use crate::contact::search::Motion;
use crate::contact::{FrictionLaw, Obstacle, Pair, RotatingBase, RotatingLine, Treatment};
use crate::frame3d::Spin;
use crate::material::{Elastic, PlaneModel};
use crate::mesh::generators::annulus_hex8;
use crate::mesh::generators::MeshError;
use crate::mesh::zone::Source;
use crate::mesh::zone3d::{annulus_zone, AnnulusZoneOptions};
use crate::model::PairState;
use crate::simulation::Problem;
use crate::time::{Coriolis, Integrator};
pub use rail::{RailBlock, RailProfile};

use super::solid::SolidSpec;
use super::spinning::{spinning_solid, SpinSpec, SpinningError};
use super::{Assembled, Body};

/// Why a rolling slice cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RollingSliceError {
    /// The annulus's mesh.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The spin-up.
    #[error(transparent)]
    Spinning(#[from] SpinningError),
    /// The assembly.
    #[error("{0}")]
    Assembly(String),
    /// A creepage or the flattening is not finite, or the spin not positive.
    #[error("`{name}` = {value}: must be {allowed}")]
    Parameter {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
}

/// The wheel, its mesh, its spin and the base's creepages.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SliceSpec {
    /// The rim's radius, m.
    pub radius: f64,
    /// The bore's radius, where the wheel is held, m.
    pub bore: f64,
    /// The thickness along the axle, m.
    pub thickness: f64,
    /// Rings, sectors and layers of hexahedra.
    pub counts: [usize; 3],
    /// The material.
    pub material: Elastic,
    /// Lumped (`true`) or consistent mass.
    pub lumped: bool,
    /// The wheel's spin, rad/s (> 0; the frame turns at `-omega`, the base at `+omega`).
    pub omega: f64,
    /// The base's flattening program.
    pub flattening: Flattening,
    /// Longitudinal, lateral and spin (1/m) creepages ([`RotatingBase`]).
    pub creepages: [f64; 3],
    /// A refined zone that moves with the contact ([`crate::mesh::zone3d`]; `None`: the
    /// annulus of `counts`, equal rings and sectors).
    pub zone: Option<SliceZone>,
    /// The base's crown across the rolling direction, m ([`RotatingBase::crown`]; `None`:
    /// a plane): with it the patch is Hertz's ellipse about the wheel's mid-plane.
    pub crown: Option<f64>,
    /// The wheel on its rigid base as it is, or Kalker's quasi-identical pair through a twin
    /// wheel that carries the tangential tractions alone ([`Coupling::Uncoupled`]; module
    /// docs, Uncoupled).
    pub coupling: Coupling,
    /// An elastic rail in place of the rigid base ([`rail`]; `None`: the rigid base).
    pub rail: Option<RailBlock>,
}

impl SliceSpec {
    /// The mesh of the refined zone, when the spec has one ([`crate::mesh::zone3d`]).
    pub fn zone_options(&self) -> Option<AnnulusZoneOptions> {
        let [rings, sectors, layers] = self.counts;
        self.zone.map(|z| AnnulusZoneOptions {
            bore: self.bore,
            radius: self.radius,
            thickness: self.thickness,
            rings,
            sectors,
            layers,
            zone_sectors: z.sectors,
            zone_width: z.width,
            growth: z.growth,
            depth: z.depth,
            axial: z.axial,
        })
    }
}

/// The moving refined zone of a [`SliceSpec`] ([`crate::mesh::zone3d`]): `counts`' rings
/// give the outer cells' radial size, its sectors the pitch outside the zone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SliceZone {
    /// The zone's pitch as a count round the rim (the sectors times a power of two).
    pub sectors: usize,
    /// The zone's width, rad.
    pub width: f64,
    /// The rings' growth from the rim inwards, the first as thick as the zone's pitch
    /// (`None`: `counts`' equal rings).
    pub growth: Option<f64>,
    /// The zone refined in depth as well, m ([`AnnulusZoneOptions::depth`]).
    pub depth: Option<f64>,
    /// The zone refined across the width about the mid-plane as well, m
    /// ([`AnnulusZoneOptions::axial`]).
    pub axial: Option<f64>,
}

/// A built zone: the relocation's sources and step, and the stations' arcs.
#[derive(Debug, Clone)]
pub struct BuiltZone {
    /// Per node, where its state comes from at a relocation.
    pub sources: Vec<Source>,
    /// The angle of one relocation, rad.
    pub step: f64,
    /// Nodes that land on a node at a relocation.
    pub exact_nodes: usize,
    /// Stations round the rim.
    pub stations: usize,
    /// Rings (radial cells).
    pub rings: usize,
    /// The nodes that turn with the zone's frame (the wheel's and its twin's; an elastic
    /// rail's nodes follow, each its own source).
    pub turned: usize,
    /// Layers (cells along the axle).
    pub layers: usize,
}

/// The spun wheel and its base, ready for the driver.
pub struct RollingSlice {
    /// The wheel (one body).
    pub bodies: Vec<Body>,
    /// Its assembled model.
    pub joined: Assembled,
    /// The rim's nodes, each a contact pair with the base.
    pub rim: Vec<usize>,
    /// The base.
    pub base: RotatingBase,
    /// The spun rim's mean radius, m (the base's radius).
    pub spun_radius: f64,
    /// Per rim node (in `rim`'s order), the arc of the rim it stands for, rad.
    pub rim_arc: Vec<f64>,
    /// Per rim node, the width along the axle it stands for (half the layers beside it), m.
    pub rim_width: Vec<f64>,
    /// The moving refined zone, when the spec has one.
    pub zone: Option<BuiltZone>,
    /// The wheel's nodes when a twin follows them (nodes `N..2N` the twin of `0..N`;
    /// [`Coupling::Uncoupled`]), else `None`.
    pub twin: Option<usize>,
    /// The elastic rail, when the spec has one: the second body, met by the rim through
    /// the facet search (module docs, The elastic rail).
    pub rail: Option<BuiltRail>,
}

/// The elastic rail of a [`RollingSlice`], built.
#[derive(Debug, Clone)]
pub struct BuiltRail {
    /// The rim's nodes against the rail's top.
    pub interface: Interface,
    /// The rail's frame.
    pub motion: Motion,
    /// The rail's cells along, across and in depth.
    pub counts: [usize; 3],
    /// The rail's length, m.
    pub length: f64,
    /// A rail closed on itself ([`RailBlock::periodic`]): its shift by one station, over the
    /// model's nodes (the wheel's outside it), and the node its check takes a column of (the
    /// crest's node at the middle station).
    pub shift: Option<(CyclicSymmetry, usize)>,
    /// A ring shorter than the run's rolling ([`RailBlock::ring`]): its seam kept ahead of
    /// the patch.
    pub ring: Option<crate::simulation::RingShift>,
}

impl RollingSlice {
    /// Spins the annulus of `spec` up, holds it at its bore and lays the base on its rim.
    ///
    /// # Errors
    /// [`RollingSliceError`] naming the bad mesh parameter, spin or creepage.
    pub fn new(spec: &SliceSpec) -> Result<Self, RollingSliceError> {
        let check = |name, value: f64, ok: bool, allowed| {
            if ok {
                Ok(())
            } else {
                Err(RollingSliceError::Parameter {
                    name,
                    value,
                    allowed,
                })
            }
        };
        check(
            "omega",
            spec.omega,
            spec.omega.is_finite() && spec.omega > 0.0,
            "finite and > 0 (rad/s)",
        )?;
        let f = spec.flattening;
        check(
            "flattening",
            f.depth,
            f.depth.is_finite() && f.depth >= 0.0 && f.depth < 0.1 * spec.radius,
            "finite, >= 0 and below a tenth of the radius (m)",
        )?;
        check(
            "settle_time",
            f.settle_time,
            f.settle_time.is_finite() && f.settle_time >= 0.0,
            "finite and >= 0 (s)",
        )?;
        for (name, c) in ["xi", "eta", "phi"].into_iter().zip(spec.creepages) {
            check(name, c, c.is_finite(), "finite")?;
        }
        if let Some(rc) = spec.crown {
            check(
                "crown",
                rc,
                rc.is_finite() && rc > 0.5 * spec.thickness,
                "finite and above half the wheel's thickness (m)",
            )?;
        }
        let [_, nt, nz] = spec.counts;
        let (mesh, zone, arcs, zs) = match spec.zone_options() {
            None => (
                annulus_hex8(spec.bore, spec.radius, spec.thickness, spec.counts)?,
                None,
                vec![2.0 * std::f64::consts::PI / nt as f64; nt],
                (0..=nz)
                    .map(|k| spec.thickness * k as f64 / nz as f64)
                    .collect::<Vec<f64>>(),
            ),
            Some(o) => {
                let built = annulus_zone(&o)?;
                let arcs = (0..built.angles.len())
                    .map(|j| built.station_arc(j))
                    .collect();
                let zone = BuiltZone {
                    stations: built.angles.len(),
                    rings: built.radii.len() - 1,
                    layers: built.zs.len() - 1,
                    turned: built.sources.len(),
                    sources: built.sources,
                    step: built.step,
                    exact_nodes: built.exact_nodes,
                };
                (built.mesh, Some(zone), arcs, built.zs)
            }
        };
        let fixed: Vec<usize> = mesh
            .node_set("bore")
            .unwrap_or_default()
            .iter()
            .flat_map(|&n| (0..3).map(move |c| 3 * n + c))
            .collect();
        let rim = mesh.node_set("rim").unwrap_or_default().to_vec();
        // The rim set runs through the stations, layer by layer.
        let rim_arc = (0..rim.len()).map(|i| arcs[i % arcs.len()]).collect();
        let last = zs.len() - 1;
        let widths: Vec<f64> = (0..=last)
            .map(|k| 0.5 * (zs[(k + 1).min(last)] - zs[k.saturating_sub(1)]))
            .collect();
        let rim_width = (0..rim.len()).map(|i| widths[i / arcs.len()]).collect();
        let solid_spec = SolidSpec {
            material: spec.material,
            plane: PlaneModel::Stress,
            thickness: 1.0,
            lumped: spec.lumped,
        };
        let spin = SpinSpec {
            spin: Spin::new([0.0; 3], [0.0, 0.0, 1.0], -spec.omega).map_err(SpinningError::from)?,
            stress_stiffening: true,
        };
        let frame = Motion::Rotating {
            centre: [0.0; 3],
            omega: -spec.omega,
            angle0: 0.0,
        };
        let s = spinning_solid("wheel", mesh, &solid_spec, frame, &fixed, spin)?;
        let x = s.solid.body.mesh.reference_positions();
        let spun_radius = rim
            .iter()
            .map(|&n| (x[3 * n] + s.u_spin[3 * n]).hypot(x[3 * n + 1] + s.u_spin[3 * n + 1]))
            .sum::<f64>()
            / rim.len().max(1) as f64;
        let mut bodies = vec![s.solid.body];
        let mut zone = zone;
        let twin = match spec.coupling {
            Coupling::Coupled => None,
            Coupling::Uncoupled => {
                // The twin: the same spun wheel (its step matrix, the spin's softening and
                // stress stiffening, its Coriolis term), without the spin's load and
                // displacement, held at the bore as the wheel is.
                let wheel = &bodies[0];
                let nodes = wheel.mesh.n_nodes();
                let mut twin = wheel.clone();
                twin.name = "twin".into();
                twin.load.iter_mut().for_each(|f| *f = 0.0);
                twin.u0.iter_mut().for_each(|u| *u = 0.0);
                bodies.push(twin);
                // A relocation carries the twin's state as the wheel's.
                if let Some(z) = zone.as_mut() {
                    let shifted: Vec<Source> = z
                        .sources
                        .iter()
                        .map(|s| match *s {
                            Source::Node(m) => Source::Node(m + nodes),
                            Source::Triangle { nodes: t, weights } => Source::Triangle {
                                nodes: t.map(|k| k + nodes),
                                weights,
                            },
                        })
                        .collect();
                    z.sources.extend(shifted);
                    z.turned = z.sources.len();
                }
                Some(nodes)
            }
        };
        let [xi, eta, phi] = spec.creepages;
        let rail = match spec.rail {
            None => None,
            Some(block) => {
                if twin.is_some() {
                    return Err(RollingSliceError::Assembly(
                        "the elastic rail meets the wheel alone: no twin (the rail is the other body of the pair)".into(),
                    ));
                }
                let open = block.mesh(block.rolled, spec.crown)?;
                let closed = if block.periodic {
                    Some(block.close(&open)?)
                } else {
                    None
                };
                let rail_mesh = closed.as_ref().map_or(&open, |c| &c.mesh);
                let counts = block.counts(block.rolled)?;
                let motion = rail::rail_frame(
                    spun_radius,
                    spec.omega,
                    [xi, eta],
                    block.margin,
                    0.5 * spec.thickness,
                    spec.flattening,
                );
                let top = rail_mesh.node_set("top").unwrap_or_default().to_vec();
                let foot = rail_mesh.node_set("foot").unwrap_or_default().to_vec();
                let first_dof = bodies[0].mesh.n_dofs();
                let search = FacetSearch::on_mesh(
                    rail_mesh,
                    Some(&top),
                    Placed { motion, first_dof },
                    block.reach(spec.flattening.depth),
                )
                .map_err(|e| RollingSliceError::Assembly(e.to_string()))?
                .with_spin(
                    (phi != 0.0)
                        .then(|| rail::spin(spun_radius, spec.omega, phi, 0.5 * spec.thickness)),
                );
                let interface = Interface::new(
                    search,
                    Placed {
                        motion: frame,
                        first_dof: 0,
                    },
                    rim.clone(),
                    &bodies[0].reference,
                );
                let first_node = bodies[0].mesh.n_nodes();
                let shift = match &closed {
                    None => None,
                    Some(c) => Some(
                        c.shift(first_node, &top)
                            .map_err(RollingSliceError::Assembly)?,
                    ),
                };
                let speed = match motion {
                    Motion::Pressed { velocity, .. } => -velocity[0],
                    _ => 0.0,
                };
                let ring = closed
                    .as_ref()
                    .zip(block.ring)
                    .map(|(c, length)| c.ring_shift(first_node, length, block.margin, speed));
                let solid = match closed {
                    None => super::solid::solid("rail", open, &solid_spec, motion),
                    Some(c) => {
                        super::solid::solid_closed("rail", &open, c.mesh, &solid_spec, motion)
                    }
                };
                let mut body = solid
                    .map_err(|e| RollingSliceError::Assembly(e.to_string()))?
                    .body;
                body.fixed_dofs = foot
                    .iter()
                    .flat_map(|&n| (0..3).map(move |c| 3 * n + c))
                    .collect();
                // A relocation leaves the rail's nodes where they are.
                if let Some(z) = zone.as_mut() {
                    let first = z.sources.len();
                    z.sources
                        .extend((0..body.mesh.n_nodes()).map(|n| Source::Node(first + n)));
                }
                bodies.push(body);
                Some(BuiltRail {
                    interface,
                    motion,
                    counts,
                    length: block.length(block.rolled),
                    shift,
                    ring,
                })
            }
        };
        let joined =
            super::assemble(&bodies).map_err(|e| RollingSliceError::Assembly(e.to_string()))?;
        let base = RotatingBase {
            line: RotatingLine {
                centre: [0.0, 0.0, 0.5 * spec.thickness],
                radius: spun_radius,
                omega: spec.omega,
                theta0: 0.0,
                flattening: spec.flattening,
                creepage: xi,
            },
            lateral: eta,
            spin: phi,
            crown: spec.crown,
        };
        Ok(Self {
            bodies,
            joined,
            rim,
            base,
            spun_radius,
            rim_arc,
            rim_width,
            zone,
            twin,
            rail,
        })
    }

    /// The driver's problem: `steps` steps of `h` with the space-time scheme (`alpha`,
    /// `gamma`, the Coriolis term implicit), each rim node a pair with the base under
    /// `friction`, the soft way.
    pub fn problem(
        &self,
        (alpha, gamma): (f64, f64),
        h: f64,
        steps: usize,
        friction: FrictionLaw,
    ) -> Problem {
        let integrator = Integrator::SpaceTime {
            alpha,
            gamma,
            coriolis: Coriolis::Implicit,
        };
        self.problem_with((integrator, h, steps), Treatment::SOFT_WAY, Some(friction))
    }

    /// The driver's problem with the integrator, the treatment and the friction law given
    /// (`None`: frictionless): what a scenario sets ([`crate::kinds::rolling3d`]).
    pub fn problem_with(
        &self,
        (integrator, h, steps): (Integrator, f64, usize),
        treatment: Treatment,
        friction: Option<FrictionLaw>,
    ) -> Problem {
        let mut p = self.joined.problem(
            &self.bodies,
            (Vec::new(), Vec::new()),
            (integrator, h, steps),
        );
        p.friction = friction;
        p.treatment = treatment;
        if let Some(rail) = &self.rail {
            p.interfaces = vec![rail.interface.clone()];
            p.pairs = self
                .rim
                .iter()
                .enumerate()
                .map(|(slot, &node)| Pair::Searched {
                    node,
                    interface: 0,
                    slot,
                })
                .collect();
            return p;
        }
        let base: Box<dyn Obstacle> = Box::new(self.base);
        p.obstacles = vec![base];
        p.pairs = self
            .rim
            .iter()
            .map(|&node| match self.twin {
                None => Pair::Obstacle { node, obstacle: 0 },
                Some(nodes) => Pair::Split {
                    node,
                    shadow: node + nodes,
                    obstacle: 0,
                },
            })
            .collect();
        p
    }

    /// The wheel's own displacement (or velocity) from the driver's vector `x`: its first
    /// `3 N` values, plus the twin's when one carries the tangential tractions (an elastic
    /// rail's follow them and are left out).
    pub fn own_state(&self, x: &[f64]) -> Vec<f64> {
        let n = self.bodies[0].mesh.n_dofs();
        let mut out = x[..n].to_vec();
        if self.twin.is_some() {
            for (o, t) in out.iter_mut().zip(&x[n..2 * n]) {
                *o += t;
            }
        }
        out
    }
}

impl RollingSlice {
    /// The annulus's cyclic symmetry: its `sectors` copies of one sector round the axle
    /// (`z`), each node the copy `j` (its sector) of the orbit of its ring and layer
    /// ([`crate::mesh::generators::annulus_hex8`]'s numbering). The spun wheel, its bore's
    /// support and its step matrix repeat with it; the contact's columns are turned from
    /// one sector's ([`crate::simulation::Simulation::set_cyclic_symmetry`]).
    ///
    /// # Panics
    /// Never for a slice [`RollingSlice::new`] built.
    pub fn symmetry(&self, [nr, nt, nz]: [usize; 3]) -> CyclicSymmetry {
        let per = (nr + 1) * nt * (nz + 1);
        let orbits = (nr + 1) * (nz + 1);
        let copies = if self.twin.is_some() { 2 } else { 1 };
        let mut labels = vec![(0, 0); copies * per];
        for w in 0..copies {
            for k in 0..=nz {
                for j in 0..nt {
                    for i in 0..=nr {
                        labels[w * per + i + (nr + 1) * (j + nt * k)] =
                            (w * orbits + i + (nr + 1) * k, j);
                    }
                }
            }
        }
        CyclicSymmetry::new(3, nt, &labels).expect("the annulus's numbering")
    }
}

/// The base's forces on the wheel at a step: the normal force and the tangential force
/// along the base's travel `t_b` and along the axle `e_z`, N.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PatchForce {
    /// The normal force, N.
    pub normal: f64,
    /// The tangential force along `t_b`, N.
    pub along: f64,
    /// The tangential force along the axle, N.
    pub lateral: f64,
}

impl PatchForce {
    /// The forces of the pair states `pairs` at time `t` on `base` (the pairs' tangents
    /// are [`tangent_basis`] of the base's normal).
    pub fn of(base: &RotatingBase, t: f64, pairs: &[PairState]) -> Self {
        let frame = base.frame(t);
        let tangents = tangent_basis(3, frame.normal);
        let (mut normal, mut f) = (0.0, [0.0; 3]);
        for ps in pairs {
            normal += ps.force;
            let q = friction_force(tangents, ps);
            for c in 0..3 {
                f[c] += q[c];
            }
        }
        Self {
            normal,
            along: dot(f, frame.travel),
            lateral: f[2],
        }
    }

    /// The forces of the pair states `pairs` at time `t` on `base`, each pair's normal and
    /// tangents those of the base at its rim node's deformed position (`rim[i]` the node of
    /// `pairs[i]`, `x_ref` the reference positions, `u` the displacements): on a crowned
    /// base the normals tilt across the patch. On a plane it is [`PatchForce::of`]. The
    /// normal force is the total force's part along the base's normal under the axle.
    pub fn at(
        base: &RotatingBase,
        t: f64,
        pairs: &[PairState],
        (rim, x_ref, u): (&[usize], &[f64], &[f64]),
    ) -> Self {
        if base.crown.is_none() {
            return Self::of(base, t, pairs);
        }
        let frame = base.frame(t);
        let mut f = [0.0; 3];
        for (ps, &node) in pairs.iter().zip(rim) {
            if ps.force == 0.0 && ps.tangential_force == 0.0 && ps.tangential_force_2 == 0.0 {
                continue;
            }
            let x: [f64; 3] = std::array::from_fn(|c| x_ref[3 * node + c] + u[3 * node + c]);
            let n = base.half_space(t, x).normal;
            let q = friction_force(tangent_basis(3, n), ps);
            for c in 0..3 {
                f[c] += ps.force * n[c] + q[c];
            }
        }
        Self {
            normal: dot(f, frame.normal),
            along: dot(f, frame.travel),
            lateral: f[2],
        }
    }

    /// The spin moment of the friction forces on the wheel about the base's normal through
    /// its point under the axle, N m: `sum ((x - p0) x f) . n` over the pairs, `x` the
    /// deformed position of the pair's rim node (`rim[i]` the node of `pairs[i]`, `x_ref`
    /// the reference positions and `u` the displacements, three per node), `f` its friction
    /// force.
    pub fn spin_moment(
        base: &RotatingBase,
        t: f64,
        pairs: &[PairState],
        (rim, x_ref, u): (&[usize], &[f64], &[f64]),
    ) -> f64 {
        let frame = base.frame(t);
        let tangents = tangent_basis(3, frame.normal);
        let n = frame.normal;
        pairs
            .iter()
            .zip(rim)
            .filter(|(ps, _)| ps.tangential_force != 0.0 || ps.tangential_force_2 != 0.0)
            .map(|(ps, &node)| {
                let x: [f64; 3] = std::array::from_fn(|c| x_ref[3 * node + c] + u[3 * node + c]);
                let r: [f64; 3] = std::array::from_fn(|c| x[c] - frame.p0[c]);
                // A crowned base's tangents tilt with its normal across the patch.
                let tg = match base.crown {
                    None => tangents,
                    Some(_) => tangent_basis(3, base.half_space(t, x).normal),
                };
                let f = friction_force(tg, ps);
                // (r x f) . n
                n[0] * (r[1] * f[2] - r[2] * f[1])
                    + n[1] * (r[2] * f[0] - r[0] * f[2])
                    + n[2] * (r[0] * f[1] - r[1] * f[0])
            })
            // (From +0: an empty sum of f64 is -0.)
            .fold(0.0, |a, m| a + m)
    }
}

/// The unit normal and tangents of the rows of slot `slot` of the rim against the elastic
/// rail at time `t`, in the wheel's mesh frame: its target's normal in the ground and
/// [`tangent_basis`] of it, as the facet search poses the rows
/// ([`crate::contact::facets`]), turned back into the wheel's frame. Zero without a
/// target (an open pair: no force).
pub fn rail_directions(rail: &Interface, slot: usize, t: f64) -> ([f64; 3], [[f64; 3]; 2]) {
    match rail.target(slot) {
        None => ([0.0; 3], [[0.0; 3]; 2]),
        Some(target) => {
            let back = |d| rail.slave().motion.rotate_back(t, d);
            let [t1, t2] = tangent_basis(3, target.normal);
            (back(target.normal), [back(t1), back(t2)])
        }
    }
}

/// The rail's forces on the wheel at a step and their spin moment about the base's normal
/// through `p0` (the nominal rail's frame in the wheel's, [`RotatingBase::frame`]): each
/// pair's normal and friction forces along its rows' directions ([`rail_directions`]),
/// summed, and projected as [`PatchForce::at`] projects the base's; the spin moment of the
/// friction forces as [`PatchForce::spin_moment`].
pub fn rail_patch_force(
    rail: &Interface,
    base: &RotatingBase,
    t: f64,
    pairs: &[PairState],
    (rim, x_ref, u): (&[usize], &[f64], &[f64]),
) -> (PatchForce, f64) {
    let frame = base.frame(t);
    let n = frame.normal;
    let (mut f, mut spin) = ([0.0; 3], 0.0);
    for (slot, (ps, &node)) in pairs.iter().zip(rim).enumerate() {
        if ps.force == 0.0 && ps.tangential_force == 0.0 && ps.tangential_force_2 == 0.0 {
            continue;
        }
        let (normal, tg) = rail_directions(rail, slot, t);
        let q = friction_force(tg, ps);
        for c in 0..3 {
            f[c] += ps.force * normal[c] + q[c];
        }
        let r: [f64; 3] =
            std::array::from_fn(|c| x_ref[3 * node + c] + u[3 * node + c] - frame.p0[c]);
        spin += n[0] * (r[1] * q[2] - r[2] * q[1])
            + n[1] * (r[2] * q[0] - r[0] * q[2])
            + n[2] * (r[0] * q[1] - r[1] * q[0]);
    }
    (
        PatchForce {
            normal: dot(f, n),
            along: dot(f, frame.travel),
            lateral: f[2],
        },
        spin,
    )
}

/// A pair's friction force on the wheel in 3D, from its components along the two tangents
/// `t1`, `t2` of the base's normal ([`tangent_basis`]), N.
pub fn friction_force([t1, t2]: [[f64; 3]; 2], ps: &PairState) -> [f64; 3] {
    std::array::from_fn(|c| ps.tangential_force * t1[c] + ps.tangential_force_2 * t2[c])
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
