//! The wheel rolling on the track: the elastic wheel of [`crate::bodies::wheel`] in its rotating
//! frame, carried by a moving hub and an unsprung mass, loaded by the axle load and gravity
//! through a primary suspension, in contact with the rail of [`super::Track`] through the
//! contact search on the rail's beams ([`crate::contact::search`]), over an optional
//! irregularity of the rail's top ([`crate::contact::profile`]).
//!
//! # Frames
//!
//! The ground origin rides with the vehicle at the hub's nominal position. The wheel's dofs
//! are displacements in the frame turning with it at `Omega = -omega` about the axle (the
//! paper's frame: its material does not move in it; `omega = V (1 + xi) / R_s`, `R_s` the
//! spun rim's radius, `xi` the creepage below); the rail's and sleepers' are displacements in the track's frame, which
//! runs under the vehicle at `-V`: at time `t` the rail's abscissa `X = x_0 + V t` is under
//! the axle. The rail's top (its beam axis, `Y = 0`) is at `-R_s` in the ground: at `t = 0`
//! it touches the spun rim's lowest point.
//!
//! # The moving hub
//!
//! The paper's hub is clamped to the axle; here the axle is a node of its own with two
//! translation dofs `a` (in the wheel's frame, like the wheel's), and every node of the hub's
//! circle is tied to it by a stiff spring in both directions (`k_tie = 100 E t` each, `E` the
//! wheel's modulus, `t` its thickness: the ties add about `1 / (100 n_hub)` of the wheel's
//! compliance). An isotropic spring is the same in every frame, so the ties are constant
//! matrices. The axle carries the unsprung mass less the wheel's own (`m_a`); being at the
//! centre of the turning frame it has the frame's terms of a point mass there:
//! $$m_a(\ddot a + 2\Omega J\dot a - \Omega^2 a) = R(t)^T F(t) + \text{ties},$$
//! (`J` the quarter turn; [`crate::frame`]), the Coriolis entries `-2 Omega m_a`,
//! `+2 Omega m_a` in `C` and the softening `-Omega^2 m_a` in `K`.
//!
//! **The load.** The static wheel load `P = F_axle + m_u g` (`F_axle` the axle load per
//! wheel from the sprung mass, `m_u` the unsprung mass per wheel, the wheel's included) acts
//! downwards in the ground: `F_axle` on the axle, gravity on every mass of the wheel and the
//! axle. In the turning frame the ground's downward direction is `R(t)^T (0, -1)`, so the
//! load turns at `-Omega` there:
//! `f(t) = s(t) [g (d_x M 1_x + d_y M 1_y) + F_axle (d_x e_ax + d_y e_ay)]`,
//! `(d_x, d_y) = R(t)^T (0, -1)`, on the wheel's and the axle's dofs. It is
//! applied over `settle` seconds by the raised cosine `s(t) = (1 - cos(pi t / T_s)) / 2`
//! (then 1): the track and wheel start at rest, touching, unloaded.
//!
//! **The primary suspension** joins the axle to the vehicle (the frame's origin) by an
//! isotropic spring-damper `(k_s, c_s)`; the axle load is its static preload (a constant
//! force; `k_s = c_s = 0` by default). The damper acts on the axle's velocity against the
//! vehicle, `R(a' + Omega J a)` in the ground, which puts `c_s Omega J` into `K`.
//! Being isotropic, it holds the axle horizontally with the same stiffness as vertically (a
//! real axle box is stiffer along the track); with `k_s = 0` only the contact holds the axle
//! along the track (frictionless: a free drift the run reports as `axle_drift_m`).
//!
//! # Friction and creepage
//!
//! With friction (`contact.friction`) each rim node in contact carries a tangential force
//! along the rail's top through the search's tangential row
//! ([`crate::contact::search::Search::tangent_row`]): `c_t` the rail's normal turned by +90
//! degrees (on a flat rail `t = (-1, 0)` in the ground, the direction of the rail's travel
//! under the vehicle), whose wheel part is `t` turned back into the wheel's frame and whose
//! rail part acts on the deflection dofs only (the rail is axially rigid: `t_x` goes into no
//! dof), and `w_t = -t . (d_a - d_rail)` the drifts' difference, the wheel's
//! `Omega x x` (`Omega = -omega`) against the rail's `(-V, 0)`. A rim node at the bottom of
//! the spun rim (`x = (0, -R_s)`) drifts at `(-omega R_s, 0) = (-V (1 + xi), 0)`, so at
//! rest in both frames it slips at `c_t . v - w_t = t . (d_a - d_rail) = V xi` along `t`:
//! `xi > 0` (the wheel turning faster than it rolls, traction) slips the rim backwards
//! against the rail and friction pushes the wheel forward.
//!
//! **The creepage** `xi` (`vehicle.creepage`, dimensionless, default 0) is referred to the
//! spun, unloaded rim's radius `R_s`: `omega = V (1 + xi) / R_s`. Under load the rim is
//! flattened and its surface strained, so its rolling radius `rho = V / omega` at free
//! rolling (no mean tangential force) is not `R_s`: free rolling falls at a small `xi_0`,
//! not at 0 (about -0.05% on the 360-node wheel of `tests/rolling_friction.rs`; the
//! rigid-base wheel's `rolling.creepage` is referred to the measured rolling radius
//! instead).
//!
//! **The axle along the track.** A tangential force moves the axle along the track, and
//! only the suspension holds it there: without friction the axle drifts freely (above),
//! with friction a mean traction `Q` would accelerate it for ever. A run with friction
//! therefore needs `k_s > 0` (the scenario's check): the axle then sits `Q / k_s` ahead of
//! its nominal position, and the damper `c_s` settles the horizontal transient.
//!
//! **The scheme.** In full slip every pair in the patch should slide; with the space-time
//! scheme's `gamma = 0` (no numerical dissipation) loaded rim nodes stick for a step or
//! more and the traction falls short of `mu P`, more so on finer rims (21% on 1440 rim
//! nodes at 40 m/s and -3%); `gamma = 0.2` (or `alpha = 1`) removes it
//! (`tests/rolling_friction.rs`, the book's docs/src/track.md).
//!
//! # Two wheels
//!
//! With `vehicle.wheelbase = L` a second wheel rolls `L` behind the first on the same rail,
//! as the two wheels of a bogie on one rail do: the same mesh, spin, unsprung mass, axle
//! load, suspension and ramp, its frame turning with the first's about the centre `(-L, 0)`
//! of the ground ([`Trailing`]). Its dofs follow the rail's in the joined model
//! (`[wheel 1, rail, wheel 2, sleepers, axle 1, axle 2]`), its axle carries the same frame
//! terms, and its rim meets the rail through an interface of its own (interface 1, its
//! pairs after the first wheel's: [`WheelOnTrack::rim_pairs`]). The two wheels share
//! nothing but the track: the bogie's frame and secondary suspension, which would join
//! their axles, are left out (each axle hangs from the vehicle by its own primary
//! suspension, the axle load a constant force), so they interact through the rail alone,
//! as in the track models of corrugation growth with several wheelsets (Igeland 1996).
//!
//! # What is not modelled
//!
//! The rail is a beam along its axis: its top is its neutral axis (the head's rotation
//! `-h theta` along the track is left out), the contact is the 2D wheel's line contact
//! (the wheel's `thickness` sets its width), the rail's own weight is left out (its
//! static sag under gravity is the same everywhere and does not enter the dynamics).

use super::{Track, TrackError, TrackSpec};
use crate::bodies::wheel::WheelModel;
use crate::bodies::{assemble_with, first_dofs, Assembled, Body, Joints};
use crate::contact::profile::Profile;
use crate::contact::search::{Motion, Placed, Search, SearchError};
use crate::contact::{Interface, Pair, Treatment};
use crate::element::beam::shape_functions;
use crate::element::discrete::{Link, PointMass, SpringDamper, SpringKind};
use crate::linalg::spmv_add;
use crate::model::LoadFn;
use crate::simulation::Problem;
use crate::time::Integrator;

/// The vehicle's share over one wheel (module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Vehicle {
    /// Unsprung mass per wheel, the wheel's own included, kg.
    #[serde(rename = "unsprung_mass_kg")]
    pub unsprung_mass: f64,
    /// Static load per wheel from the sprung mass, N.
    #[serde(rename = "axle_load_N")]
    pub axle_load: f64,
    /// Speed along the track, m/s.
    #[serde(rename = "speed_m_s")]
    pub speed: f64,
    /// Primary suspension's stiffness (isotropic), N/m.
    #[serde(rename = "suspension_stiffness_N_m")]
    pub suspension_stiffness: f64,
    /// Primary suspension's damping (isotropic), N s/m.
    #[serde(rename = "suspension_damping_N_s_m")]
    pub suspension_damping: f64,
    /// Gravity, m/s^2.
    #[serde(rename = "gravity_m_s2")]
    pub gravity: f64,
    /// Time over which the static load is applied, s.
    #[serde(rename = "settle_s")]
    pub settle: f64,
    /// Longitudinal creepage `xi`, dimensionless, referred to the spun rim's radius `R_s`:
    /// the wheel turns at `omega = V (1 + xi) / R_s`; positive: traction (module docs,
    /// Friction and creepage). 0 for rolling at `V / R_s`.
    pub creepage: f64,
    /// A second wheel (module docs, Two wheels): the distance it trails the first by along
    /// the track, m; `None`: one wheel.
    #[serde(rename = "wheelbase_m", skip_serializing_if = "Option::is_none")]
    pub wheelbase: Option<f64>,
}

impl Vehicle {
    /// The static wheel load `F_axle + m_u g`, N.
    pub fn static_load(&self) -> f64 {
        self.axle_load + self.unsprung_mass * self.gravity
    }
}

/// Errors of building the wheel on the track.
#[derive(Debug, thiserror::Error)]
pub enum RollingError {
    /// The track.
    #[error(transparent)]
    Track(#[from] TrackError),
    /// The search.
    #[error(transparent)]
    Search(#[from] SearchError),
    /// The wheel.
    #[error(transparent)]
    Wheel(#[from] crate::bodies::wheel::WheelError),
    /// The joined model.
    #[error("joining the wheel and the track: {0}")]
    Assembly(#[from] crate::assembly::AssemblyError),
    /// The wheel's own mass exceeds the unsprung mass.
    #[error("vehicle.unsprung_mass = {unsprung} kg is less than the wheel's own mass {wheel:.1} kg (the unsprung mass includes the wheel)")]
    Mass {
        /// The unsprung mass, kg.
        unsprung: f64,
        /// The wheel's, kg.
        wheel: f64,
    },
    /// A value out of range or a wheel that cannot roll here.
    #[error("{0}")]
    Unsupported(String),
}

/// The wheel, its axle and the track (module docs).
#[derive(Debug)]
pub struct WheelOnTrack {
    /// The wheel's model (its hub's dofs are freed here).
    pub wheel: WheelModel,
    /// The track's data.
    pub track: TrackSpec,
    /// The vehicle.
    pub vehicle: Vehicle,
    /// The wheel (0) and the rail (1).
    pub bodies: Vec<Body>,
    /// The joined model: wheel, rail, sleepers (one dof each), the axle's two dofs.
    pub joined: Assembled,
    /// The rim against the rail's top.
    pub interface: Interface,
    /// The rail's node abscissae, m.
    pub xs: Vec<f64>,
    /// `Phi` of each rail element.
    pub phi: Vec<f64>,
    /// Each sleeper's pad: (the rail's deflection dof above it, the sleeper's dof).
    pub pads: Vec<(usize, usize)>,
    /// The axle's dofs (x, y in the wheel's frame).
    pub axle: [usize; 2],
    /// The wheel's own mass, kg.
    pub wheel_mass: f64,
    /// The axle's point mass, kg.
    pub axle_mass: f64,
    /// The rail's abscissa under the axle at `t = 0`, m.
    pub start: f64,
    /// The spun rim's radius, m.
    pub rim_radius: f64,
    /// The tie springs' stiffness, N/m each.
    pub tie_stiffness: f64,
    /// The second wheel, when `vehicle.wheelbase` is given (module docs, Two wheels).
    pub trailing: Option<Trailing>,
}

/// The second wheel of [`WheelOnTrack`] (module docs, Two wheels): the first's model again,
/// its axle `wheelbase` behind the first's.
#[derive(Debug)]
pub struct Trailing {
    /// How far it trails the first wheel, m.
    pub wheelbase: f64,
    /// Its first dof in the joined model (its dofs follow the rail's).
    pub first_dof: usize,
    /// Its axle's dofs (x, y in its frame, which turns as the first wheel's).
    pub axle: [usize; 2],
    /// Its rim against the rail's top (interface 1; its pairs follow the first wheel's).
    pub interface: Interface,
}

impl WheelOnTrack {
    /// The wheel `wheel` (a coupled wheel in its rotating frame, held by a hub, turning at
    /// `V (1 + xi) / R_s`: [`wheel_at_speed`] at the speed `V (1 + xi)`) on the track `track`, its axle over the rail's
    /// abscissa `start` at `t = 0`, the rail's top carrying `profile`.
    ///
    /// # Errors
    /// [`RollingError`].
    pub fn new(
        wheel: WheelModel,
        track: &TrackSpec,
        vehicle: Vehicle,
        start: f64,
        profile: Option<Profile>,
    ) -> Result<Self, RollingError> {
        let (r_s, omega) = check_wheel(&wheel, &vehicle)?;
        let v = vehicle.speed;
        let (mut rail, xs, phi) = track.rail()?;
        let length = track.length();
        if !(start.is_finite() && start >= 0.0 && start <= length) {
            return Err(TrackError::OffRail { x: start, length }.into());
        }
        let rail_motion = Motion::Translating {
            origin: [-start, -r_s, 0.0],
            velocity: [-v, 0.0, 0.0],
        };
        let (wb, hub_dofs) = freed_wheel_body(&wheel);
        rail.motion = rail_motion;
        let wheelbase = match vehicle.wheelbase {
            None => None,
            Some(l) if l.is_finite() && l > 0.0 && l <= start => Some(l),
            Some(l) => {
                return Err(RollingError::Unsupported(format!(
                    "the second wheel's wheelbase {l} m: give a distance > 0 that leaves it on the rail (its axle {start} m from the rail's start behind the first's)"
                )))
            }
        };
        let mut bodies = vec![wb, rail];
        if let Some(l) = wheelbase {
            let (mut second, _) = freed_wheel_body(&wheel);
            second.name = "trailing wheel".into();
            second.motion = trailing_frame(l, omega);
            bodies.push(second);
        }
        let first = first_dofs(&bodies);
        let (n_wheel, n_rail_end) = (first[1], first[2]);
        let n_bodies = *first.last().unwrap_or(&0);
        let sleepers = track.bays + 1;
        let (discrete, pads) = track.supports(n_wheel, n_bodies)?;
        let axle = [n_bodies + sleepers, n_bodies + sleepers + 1];
        let wheel_mass = wheel_mass(&wheel, n_wheel);
        let axle_mass = vehicle.unsprung_mass - wheel_mass;
        if axle_mass.is_nan() || axle_mass <= 0.0 {
            return Err(RollingError::Mass {
                unsprung: vehicle.unsprung_mass,
                wheel: wheel_mass,
            });
        }
        let tie_stiffness = 100.0 * wheel.spec.material.young * wheel.spec.thickness;
        let axle_of = AxleOf {
            dofs: axle,
            mass: axle_mass,
            tie_stiffness,
            vehicle: &vehicle,
        };
        let mut discrete = axle_of.joints(discrete, &hub_dofs)?;
        let second_axle = [axle[0] + 2, axle[1] + 2];
        let axle_of_second = AxleOf {
            dofs: second_axle,
            ..axle_of
        };
        if wheelbase.is_some() {
            let hub: Vec<usize> = hub_dofs.iter().map(|&d| d + n_rail_end).collect();
            discrete = axle_of_second.joints(discrete, &hub)?;
        }
        let joints = Joints {
            dofs: sleepers + if wheelbase.is_some() { 4 } else { 2 },
            discrete,
        };
        let mut joined = assemble_with(&bodies, &joints)?;
        axle_of.add_frame_terms(&mut joined, omega)?;
        let rim_interface = |search, motion, first_dof| {
            Interface::new(
                search,
                Placed { motion, first_dof },
                wheel.rim.clone(),
                &wheel.mesh.reference_positions(),
            )
        };
        let search = rail_search(&xs, &phi, length, rail_motion, n_wheel, profile.clone())?;
        let interface = rim_interface(
            search,
            Motion::Rotating {
                centre: [0.0; 3],
                omega: -omega,
                angle0: 0.0,
            },
            0,
        );
        let trailing = match wheelbase {
            Some(l) => {
                axle_of_second.add_frame_terms(&mut joined, omega)?;
                let search = rail_search(&xs, &phi, length, rail_motion, n_wheel, profile)?;
                Some(Trailing {
                    wheelbase: l,
                    first_dof: n_rail_end,
                    axle: second_axle,
                    interface: rim_interface(search, trailing_frame(l, omega), n_rail_end),
                })
            }
            None => None,
        };
        Ok(Self {
            track: *track,
            vehicle,
            bodies,
            joined,
            interface,
            xs,
            phi,
            pads,
            axle,
            wheel_mass,
            axle_mass,
            start,
            rim_radius: r_s,
            tie_stiffness,
            trailing,
            wheel,
        })
    }

    /// The driver's problem: `steps` steps of `h` with `integrator`, the soft way,
    /// frictionless (set `treatment` and `friction` after), the load of the module docs.
    pub fn problem(&self, integrator: Integrator, h: f64, steps: usize) -> Problem {
        let mut pairs = Pair::searched(0, &self.interface, 0);
        let mut interfaces = vec![self.interface.clone()];
        if let Some(tr) = &self.trailing {
            pairs.extend(Pair::searched(1, &tr.interface, tr.first_dof / 2));
            interfaces.push(tr.interface.clone());
        }
        let mut p = self
            .joined
            .problem(&self.bodies, (interfaces, pairs), (integrator, h, steps));
        p.load = self.load_fn();
        p.treatment = Treatment::SOFT_WAY;
        p
    }

    /// The load at time `t` (module docs). Allocates once here; the returned function
    /// allocates nothing.
    pub fn load_fn(&self) -> LoadFn {
        let n = self.joined.model.n();
        let n_wheel = self.joined.first_dof[1];
        let base = self.joined.load.clone();
        // The wheels' dofs and their axles' (the second wheel's when there is one).
        let second = self.trailing.as_ref().map(|tr| (tr.first_dof, tr.axle));
        let on_wheel =
            |d: usize| d < n_wheel || second.is_some_and(|(f, _)| (f..f + n_wheel).contains(&d));
        let on_axle =
            |d: usize, c: usize| d == self.axle[c] || second.is_some_and(|(_, a)| d == a[c]);
        let moving = |d: usize, c: usize| on_wheel(d) || on_axle(d, c);
        // M 1_x and M 1_y on the wheels' and the axles' dofs (the joined mass: the ties
        // carry none).
        let mut unit = [vec![0.0; n], vec![0.0; n]];
        for (c, out) in unit.iter_mut().enumerate() {
            let mut ones = vec![0.0; n];
            for (d, one) in ones.iter_mut().enumerate() {
                if d % 2 == c && on_wheel(d) || on_axle(d, c) {
                    *one = 1.0;
                }
            }
            spmv_add(
                self.joined.model.pattern(),
                &self.joined.model.m,
                1.0,
                &ones,
                out,
            );
            for (d, o) in out.iter_mut().enumerate() {
                if !moving(d, c) {
                    *o = 0.0;
                }
            }
        }
        let g = self.vehicle.gravity;
        let f_axle = self.vehicle.axle_load;
        let settle = self.vehicle.settle;
        let frame = self.bodies[0].motion;
        let axle = self.axle;
        Box::new(move |t, f| {
            f.copy_from_slice(&base);
            let s = ramp(t, settle);
            let d = frame.rotate_back(t, [0.0, -1.0, 0.0]);
            for (fi, (ux, uy)) in f.iter_mut().zip(unit[0].iter().zip(&unit[1])) {
                *fi += s * g * (d[0] * ux + d[1] * uy);
            }
            f[axle[0]] += s * f_axle * d[0];
            f[axle[1]] += s * f_axle * d[1];
            if let Some((_, a)) = second {
                f[a[0]] += s * f_axle * d[0];
                f[a[1]] += s * f_axle * d[1];
            }
        })
    }

    /// The rail's abscissa under the axle at time `t`, m.
    pub fn under_axle(&self, t: f64) -> f64 {
        self.start + self.vehicle.speed * t
    }

    /// The contact pairs of the first wheel's rim (`..n`) and of the second's (`n..`), `n`
    /// the rim's nodes: the order of [`WheelOnTrack::problem`]'s pairs.
    pub fn rim_pairs(&self) -> usize {
        self.interface.nodes().len()
    }

    /// The second wheel's axle displacement in the ground (x along the track, y up) at `t`,
    /// m; `None` with one wheel.
    pub fn trailing_axle_ground(&self, t: f64, u: &[f64]) -> Option<[f64; 2]> {
        let tr = self.trailing.as_ref()?;
        let a = [u[tr.axle[0]], u[tr.axle[1]], 0.0];
        let g = self.bodies[0].motion.rotate(t, a);
        Some([g[0], g[1]])
    }

    /// The axle's displacement in the ground (x along the track, y up) at `t`, m.
    pub fn axle_ground(&self, t: f64, u: &[f64]) -> [f64; 2] {
        let a = [u[self.axle[0]], u[self.axle[1]], 0.0];
        let g = self.bodies[0].motion.rotate(t, a);
        [g[0], g[1]]
    }

    /// The rail's deflection at its abscissa `x` (m, up), from the element's own shape.
    ///
    /// # Errors
    /// [`TrackError::OffRail`].
    pub fn rail_deflection(&self, x: f64, u: &[f64]) -> Result<f64, TrackError> {
        let length = *self.xs.last().unwrap_or(&0.0);
        if !(x.is_finite() && (0.0..=length).contains(&x)) {
            return Err(TrackError::OffRail { x, length });
        }
        let ne = self.xs.len() - 1;
        let le = length / ne as f64;
        let e = ((x / le).floor() as usize).min(ne - 1);
        let xi = ((x - self.xs[e]) / le).clamp(0.0, 1.0);
        let (nw, _) = shape_functions(self.phi[e], le, xi);
        let o = self.joined.first_dof[1] + 2 * e;
        Ok((0..4).map(|k| nw[k] * u[o + k]).sum())
    }

    /// The pad force of sleeper `j` (compression positive), N: `k_p (y_j - w_j) + c_p (v_y - v_w)`.
    pub fn pad_force(&self, j: usize, u: &[f64], v: &[f64]) -> f64 {
        let (w, y) = self.pads[j];
        -(self.track.pad_stiffness * (u[w] - u[y]) + self.track.pad_damping * (v[w] - v[y]))
    }

    /// The sleeper nearest the rail's abscissa `x`.
    pub fn sleeper_near(&self, x: f64) -> usize {
        ((x / self.track.spacing).round().max(0.0) as usize).min(self.track.bays)
    }

    /// The track alone (the rail, its sleepers and ends), as [`TrackSpec::build`] builds it.
    ///
    /// # Errors
    /// [`TrackError`].
    pub fn track_alone(&self) -> Result<Track, TrackError> {
        self.track.build()
    }
}

/// The most rebuilds [`wheel_at_speed`] makes to find `omega = speed / R_s(omega)`.
pub const SPIN_REBUILDS: usize = 16;

/// The wheel of `spec` on `mesh` turning at `speed / R_s` (`speed = V (1 + xi)` with a
/// creepage `xi`), `R_s` its spun rim's radius, as [`WheelOnTrack::new`] needs it. `R_s`
/// moves with `omega` by the centrifugal expansion `e(omega) ~ rho omega^2 R^2 / E`, so
/// `omega = speed / R_s(omega)` is found by rebuilding until the rim's speed `omega R_s`
/// is `speed` within 1e-12 of it (the check of [`WheelOnTrack::new`] takes 1e-9): each
/// rebuild shrinks the error by about `2 e` (two rebuilds at 100 km/h, where `e` is 3e-6;
/// at 1,500 km/h, `e` 7.5e-4, two left 1.7e-9 and the wheel was refused on an unkeyed
/// check, issue 47).
///
/// # Errors
/// [`RollingError::Wheel`] from a build, [`RollingError::Unsupported`] when
/// [`SPIN_REBUILDS`] rebuilds do not find the speed (a spin near the disk's limit, where the
/// expansion runs away).
pub fn wheel_at_speed(
    mesh: crate::mesh::Mesh,
    spec: crate::bodies::wheel::WheelSpec,
    speed: f64,
) -> Result<WheelModel, RollingError> {
    let mut omega = speed / spec.radius;
    for _ in 0..SPIN_REBUILDS {
        let m = WheelModel::new(
            mesh.clone(),
            crate::bodies::wheel::WheelSpec {
                omega,
                ..spec.clone()
            },
        )?;
        let rim_speed = omega * m.spinning_radius();
        if (rim_speed - speed).abs() <= 1e-12 * speed.abs() {
            return Ok(m);
        }
        omega = speed / m.spinning_radius();
    }
    Err(RollingError::Unsupported(format!(
        "no spin of the wheel rolls its spun rim at {speed} m/s: {SPIN_REBUILDS} rebuilds for its centrifugal expansion did not settle (omega = {omega} rad/s; the disk near its spin limit)"
    )))
}

/// The raised-cosine ramp from 0 at `t = 0` to 1 at `t = settle` (1 after; 1 throughout
/// when `settle` is 0).
pub fn ramp(t: f64, settle: f64) -> f64 {
    if settle <= 0.0 || t >= settle {
        1.0
    } else if t <= 0.0 {
        0.0
    } else {
        0.5 * (1.0 - (std::f64::consts::PI * t / settle).cos())
    }
}

/// Checks that `wheel` can roll on a track with `vehicle`: a coupled wheel in its rotating
/// frame without a moving zone, held by a hub, turning at `V (1 + xi) / R_s` (its frame
/// terms were built for its own omega); its spun radius `R_s` and omega.
fn check_wheel(wheel: &WheelModel, vehicle: &Vehicle) -> Result<(f64, f64), RollingError> {
    let ws = &wheel.spec;
    if wheel.twin.is_some() || wheel.zone.is_some() || !ws.rotating_frame {
        return Err(RollingError::Unsupported(
            "the wheel on a track is a coupled wheel in its rotating frame without a moving zone"
                .into(),
        ));
    }
    if !matches!(ws.support, crate::bodies::wheel::Support::Hub { .. }) {
        return Err(RollingError::Unsupported(
            "the wheel on a track needs a hub (wheel.support = hub): its nodes are tied to the axle".into(),
        ));
    }
    let r_s = wheel.spinning_radius();
    let v = vehicle.speed;
    let omega = ws.omega;
    let xi = vehicle.creepage;
    let rim_speed = v * (1.0 + xi);
    let mismatch = (omega * r_s - rim_speed).abs();
    if !xi.is_finite() || mismatch.is_nan() || mismatch > 1e-9 * v.abs().max(1.0) {
        return Err(RollingError::Unsupported(format!(
            "the wheel turns at {omega} rad/s but rolls at {v} m/s with creepage {xi} on a radius of {r_s} m: build it with omega = V (1 + xi) / R_s"
        )));
    }
    Ok((r_s, omega))
}

/// The wheel's body with its hub freed (the hub's dofs returned, to be tied to the axle);
/// the spinning equilibrium's load kept on every dof (its hub reactions balance: the ties
/// start unstretched).
fn freed_wheel_body(wheel: &WheelModel) -> (Body, Vec<usize>) {
    let mut wb = crate::bodies::block::wheel_body(wheel);
    let hub_dofs = std::mem::take(&mut wb.fixed_dofs);
    wb.load = vec![0.0; wb.load.len()];
    spmv_add(
        wheel.model.pattern(),
        &wheel.model.k,
        1.0,
        &wheel.u_spin,
        &mut wb.load,
    );
    (wb, hub_dofs)
}

/// The second wheel's frame: the first's, its centre `wheelbase` behind along the track.
fn trailing_frame(wheelbase: f64, omega: f64) -> Motion {
    Motion::Rotating {
        centre: [-wheelbase, 0.0, 0.0],
        omega: -omega,
        angle0: 0.0,
    }
}

/// The wheel's mass: the sum of its mass matrix's products with a unit motion along y.
fn wheel_mass(wheel: &WheelModel, n_wheel: usize) -> f64 {
    let dir = 1;
    let ones: Vec<f64> = (0..n_wheel)
        .map(|d| f64::from(u8::from(d % 2 == dir)))
        .collect();
    let mut out = vec![0.0; n_wheel];
    spmv_add(wheel.model.pattern(), &wheel.model.m, 1.0, &ones, &mut out);
    out.iter().sum()
}

/// The axle: its two dofs (x, y in the wheel's frame), its point mass, the ties to the
/// wheel's hub and the vehicle's suspension.
struct AxleOf<'a> {
    dofs: [usize; 2],
    mass: f64,
    tie_stiffness: f64,
    vehicle: &'a Vehicle,
}

impl AxleOf<'_> {
    /// The track's supports `discrete` with the axle added: the hub's dofs tied to it, its
    /// mass on each dof, the suspension to the ground, and the pattern's `(ax, ay)` entries
    /// for the frame's terms (their values added by [`AxleOf::add_frame_terms`]).
    fn joints(
        &self,
        mut discrete: crate::element::discrete::Discrete,
        hub_dofs: &[usize],
    ) -> Result<crate::element::discrete::Discrete, RollingError> {
        let (axle, vehicle) = (self.dofs, self.vehicle);
        let spring = |link, stiffness, damping| SpringDamper {
            link,
            kind: SpringKind::Translational,
            stiffness,
            damping,
        };
        let joint = |e: crate::element::discrete::DiscreteError| RollingError::Track(e.into());
        for &d in hub_dofs {
            discrete
                .add_spring(spring(
                    Link::Between(d, axle[d % 2]),
                    self.tie_stiffness,
                    0.0,
                ))
                .map_err(joint)?;
        }
        for &a in &axle {
            discrete
                .add_mass(PointMass {
                    dof: a,
                    mass: self.mass,
                })
                .map_err(joint)?;
            discrete
                .add_spring(spring(
                    Link::Ground(a),
                    vehicle.suspension_stiffness,
                    vehicle.suspension_damping,
                ))
                .map_err(joint)?;
        }
        discrete
            .add_spring(spring(Link::Between(axle[0], axle[1]), 0.0, 0.0))
            .map_err(joint)?;
        Ok(discrete)
    }

    /// The axle's frame terms for the wheel's `omega` and the suspension damper's (module
    /// docs), added to the joined model.
    fn add_frame_terms(&self, joined: &mut Assembled, omega: f64) -> Result<(), RollingError> {
        let (axle, axle_mass, vehicle) = (self.dofs, self.mass, self.vehicle);
        let om = -omega;
        let slot = |i, j| {
            joined
                .model
                .assembler
                .slot(i, j)
                .ok_or_else(|| RollingError::Unsupported("the axle's pattern".into()))
        };
        let (sxy, syx) = (slot(axle[0], axle[1])?, slot(axle[1], axle[0])?);
        let (sxx, syy) = (slot(axle[0], axle[0])?, slot(axle[1], axle[1])?);
        let m = &mut joined.model;
        m.c[sxy] -= 2.0 * om * axle_mass;
        m.c[syx] += 2.0 * om * axle_mass;
        m.k[sxx] -= om * om * axle_mass;
        m.k[syy] -= om * om * axle_mass;
        m.k[sxy] -= vehicle.suspension_damping * om;
        m.k[syx] += vehicle.suspension_damping * om;
        Ok(())
    }
}

/// The search on the rail's top (nodes at `xs`, elements' `phi`, moving by `motion`, its
/// dofs from `first_dof` on), carrying `profile`: segment k is element ne - 1 - k, right
/// to left.
fn rail_search(
    xs: &[f64],
    phi: &[f64],
    length: f64,
    motion: Motion,
    first_dof: usize,
    profile: Option<Profile>,
) -> Result<Search, RollingError> {
    let ne = xs.len() - 1;
    let segments: Vec<[usize; 2]> = (0..ne).map(|k| [ne - k, ne - 1 - k]).collect();
    let seg_phi = (0..ne).map(|k| phi[ne - 1 - k]).collect();
    let points: Vec<f64> = xs.iter().flat_map(|&x| [x, 0.0]).collect();
    let le = length / ne as f64;
    let mut search = Search::new(
        2,
        Placed { motion, first_dof },
        points,
        segments,
        le.min(0.02),
    )?
    .on_beams(seg_phi)?;
    if let Some(p) = profile {
        search = search.with_profile(p)?;
    }
    Ok(search)
}
