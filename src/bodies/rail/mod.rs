//! The track: a rail of beams on discrete pads, half-sleepers and ballast, its
//! receptance ([`receptance`]), the wheel's Hertz spring on it ([`hertz`]) and a constant
//! load moving along it ([`moving`]).
//!
//! Bajer's paper lists the "periodical structure of rails (sleepers); instability of motion
//! on the periodically placed supports" among the suspected sources of corrugation (C. I.
//! Bajer, *The space-time approach to rail/wheel contact and corrugations problem*, CAMES
//! 1998, §1); this module gives the solver that periodic structure.
//!
//! # The model
//!
//! One rail (per wheel) of [`crate::element::beam::Beam2`] elements (Timoshenko by
//! default, dofs `(w, theta)` per node) built by [`Body::rail`], `elements_per_bay`
//! elements a bay, a node at every sleeper. Sleeper `j` (`j = 0..=bays`) is at
//! `x_j = j s` (`s` the spacing) and is a dof of its own (a [`Joints`] dof after the rail's)
//! carrying the half-sleeper's mass `m_s`; a pad spring-damper `(k_p, c_p)` joins the rail's
//! deflection at `x_j` to the sleeper, a ballast spring-damper `(k_b, c_b)` joins the sleeper
//! to the ground:
//! $$m_s \ddot y_j + c_b \dot y_j + k_b y_j = k_p (w(x_j) - y_j) + c_p(\dot w(x_j) - \dot y_j).$$
//! The rail is not pinned anywhere: the ballast springs hold the track.
//!
//! # The parameter set
//!
//! `"uic60"` ([`TrackSpec::uic60`]): the UIC60 rail in vertical bending (`E = 210 GPa`,
//! `I = 3.055e-5 m^4`, `A = 7.69e-3 m^2`, `rho = 7850 kg/m^3`, `G = 77 GPa`,
//! `kappa = 0.4`), pads `200 MN/m` and `28 kN s/m`, half-sleeper `177.5 kg`, ballast
//! `40 MN/m` and `47 kN s/m`, spacing `0.6 m`: the set of J. C. O. Nielsen and A. Igeland,
//! *Vertical dynamic interaction between train and track - influence of wheel and track
//! imperfections*, Journal of Sound and Vibration 187(5), 1995, 825-839, also used in
//! J. C. O. Nielsen, *Numerical prediction of rail roughness growth on tangent railway
//! tracks*, Journal of Sound and Vibration 267, 2003, 537-548 (as quoted in the issue that
//! asked for this module; the values were not re-read from the papers here). The rail head's
//! transverse radius `0.3 m` (the crown radius of the UIC60 head) and Poisson's ratio `0.3`
//! are the Hertz contact's ([`hertz`]). No second set is shipped: the values of Zhai's
//! ballasted track could not be checked against a source at hand.
//!
//! # The ends
//!
//! A finite track reflects the waves a load sends along the rail; the middle must see an
//! infinite track. [`Ends::Absorbing`] (the default) grades a viscous damping up over the
//! end bays, proportional to the mass (`C += eta(x) M` on the rail's elements and the
//! sleepers' masses there), from zero at the zone's inner edge to `eta_max` at the track's
//! end as `eta_max (d / L_a)^2` (`d` the depth into the zone of length `L_a`): a sponge
//! layer. A propagating bending wave of group velocity `c_g` loses `exp(-eta / (2 c_g))` of
//! its amplitude per metre in it, and the slow (quadratic) grading keeps the impedance step
//! small where the wave enters. Dashpots at the rail's ends matched to its impedance were
//! not chosen: a beam's end impedance depends on the frequency (and needs a moment dashpot
//! too), so dashpots match one frequency only. [`Ends::Free`] leaves the ends free (for the
//! checks). The `"uic60"` set's 100 bays with 30 absorbing bays at each end and
//! `eta_max = 1000 1/s` change the receptances at mid-span and above the middle sleeper by
//! at most 1.9e-5 (relative) when the track is doubled, over 20 Hz-3 kHz away from the two
//! band edges (within 10% of the pinned-pinned frequency, and 2.75-3 kHz), against 1.1e-4
//! with free ends; at the band edges nothing converges (the infinite track's receptance is
//! singular there: [`receptance`]). The deflection under a load moving at 30 m/s changes by
//! 1.7e-5 of its peak (free ends 1.1e-5: at that speed the response under the load is its
//! near field, which neither end sees). `tests/track.rs` measures both.

pub mod hertz;
pub mod moving;
pub mod receptance;
pub mod rolling;

use crate::assembly::AssemblyError;
use crate::bodies::{assemble_with, first_dofs, Assembled, Body, Joints};
use crate::contact::search::Motion;
use crate::element::beam::{
    bending_mass_into, shape_functions, BeamError, BeamSection, BeamTheory,
};
use crate::element::discrete::{
    Discrete, DiscreteError, Link, PointMass, SpringDamper, SpringKind,
};

/// Invalid track data, or a solve that failed.
#[derive(Debug, thiserror::Error)]
pub enum TrackError {
    /// A parameter out of its range.
    #[error("track: {name} = {value}: {allowed}")]
    Invalid {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
    /// A parameter set that does not exist.
    #[error("track: no parameter set \"{0}\"; known: \"uic60\"")]
    UnknownSet(String),
    /// The rail's beam.
    #[error(transparent)]
    Beam(#[from] BeamError),
    /// The pads, sleepers and ballast.
    #[error(transparent)]
    Discrete(#[from] DiscreteError),
    /// The joined model.
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    /// A linear solve failed (a singular dynamic stiffness).
    #[error("track: {0}")]
    Solve(String),
    /// A point off the rail.
    #[error("track: x = {x} m is off the rail [0, {length}] m")]
    OffRail {
        /// The abscissa, m.
        x: f64,
        /// The rail's length, m.
        length: f64,
    },
}

/// How the track's ends treat the waves that reach them (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Ends {
    /// Free ends: the waves come back.
    Free,
    /// Mass-proportional damping graded up over the end bays (a sponge layer).
    Absorbing {
        /// Bays of the sponge at each end.
        bays: usize,
        /// `eta_max`, 1/s: the damping per unit mass at the track's ends.
        damping: f64,
    },
}

/// The track's data (module docs): the rail, the supports, the length and the mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackSpec {
    /// The rail's section and material.
    pub section: BeamSection,
    /// Euler-Bernoulli or Timoshenko (default).
    pub theory: BeamTheory,
    /// Pad stiffness `k_p`, N/m.
    pub pad_stiffness: f64,
    /// Pad damping `c_p`, N s/m.
    pub pad_damping: f64,
    /// Half-sleeper mass (per rail) `m_s`, kg.
    pub sleeper_mass: f64,
    /// Ballast stiffness under a half-sleeper `k_b`, N/m.
    pub ballast_stiffness: f64,
    /// Ballast damping under a half-sleeper `c_b`, N s/m.
    pub ballast_damping: f64,
    /// Sleeper spacing `s`, m.
    pub spacing: f64,
    /// Bays (the track has `bays + 1` sleepers, `bays * spacing` long).
    pub bays: usize,
    /// Rail elements per bay.
    pub elements_per_bay: usize,
    /// The ends.
    pub ends: Ends,
    /// The rail head's transverse radius `R_r`, m (the Hertz contact, [`hertz`]).
    pub head_radius: f64,
    /// Poisson's ratio of the rail and wheel steel (the Hertz contact).
    pub poisson: f64,
}

/// The names of the parameter sets ([`TrackSpec::named`]).
pub const SETS: [&str; 1] = ["uic60"];

impl Default for TrackSpec {
    fn default() -> Self {
        Self::uic60()
    }
}

impl TrackSpec {
    /// The `"uic60"` set (module docs): UIC60 on Nielsen and Igeland's pads, half-sleepers
    /// and ballast at 0.6 m, Timoshenko; 100 bays of 6 elements, 30 absorbing bays at each
    /// end with `eta_max = 1000 1/s`.
    pub fn uic60() -> Self {
        TrackSpec {
            section: BeamSection::UIC60,
            theory: BeamTheory::Timoshenko,
            pad_stiffness: 200.0e6,
            pad_damping: 28.0e3,
            sleeper_mass: 177.5,
            ballast_stiffness: 40.0e6,
            ballast_damping: 47.0e3,
            spacing: 0.6,
            bays: 100,
            elements_per_bay: 6,
            ends: Ends::Absorbing {
                bays: 30,
                damping: 1000.0,
            },
            head_radius: 0.3,
            poisson: 0.3,
        }
    }

    /// The parameter set `name` ([`SETS`]).
    ///
    /// # Errors
    /// [`TrackError::UnknownSet`].
    pub fn named(name: &str) -> Result<Self, TrackError> {
        match name {
            "uic60" => Ok(Self::uic60()),
            other => Err(TrackError::UnknownSet(other.to_string())),
        }
    }

    /// Checks every value.
    ///
    /// # Errors
    /// [`TrackError::Invalid`] naming the parameter, [`TrackError::Beam`] for the section.
    pub fn validate(&self) -> Result<(), TrackError> {
        self.section.validate(self.theory)?;
        let positive = "must be finite and > 0";
        let non_negative = "must be finite and >= 0";
        for (name, value, strict) in [
            ("pad_stiffness", self.pad_stiffness, true),
            ("pad_damping", self.pad_damping, false),
            ("sleeper_mass", self.sleeper_mass, true),
            ("ballast_stiffness", self.ballast_stiffness, true),
            ("ballast_damping", self.ballast_damping, false),
            ("spacing", self.spacing, true),
            ("head_radius", self.head_radius, true),
        ] {
            let ok = value.is_finite() && if strict { value > 0.0 } else { value >= 0.0 };
            if !ok {
                let allowed = if strict { positive } else { non_negative };
                return Err(TrackError::Invalid {
                    name,
                    value,
                    allowed,
                });
            }
        }
        if !(self.poisson.is_finite() && self.poisson > -1.0 && self.poisson < 0.5) {
            return Err(TrackError::Invalid {
                name: "poisson",
                value: self.poisson,
                allowed: "must be in (-1, 0.5)",
            });
        }
        if self.bays < 2 {
            return Err(TrackError::Invalid {
                name: "bays",
                value: self.bays as f64,
                allowed: "give at least 2 bays",
            });
        }
        if self.elements_per_bay == 0 {
            return Err(TrackError::Invalid {
                name: "elements_per_bay",
                value: 0.0,
                allowed: "give at least one element a bay",
            });
        }
        if let Ends::Absorbing { bays, damping } = self.ends {
            if 2 * bays >= self.bays {
                return Err(TrackError::Invalid {
                    name: "end_bays",
                    value: bays as f64,
                    allowed: "the two sponges must leave bays between them (2 end_bays < bays)",
                });
            }
            if !(damping.is_finite() && damping >= 0.0) {
                return Err(TrackError::Invalid {
                    name: "end_damping",
                    value: damping,
                    allowed: "must be finite and >= 0",
                });
            }
        }
        Ok(())
    }

    /// The track's length, m.
    pub fn length(&self) -> f64 {
        self.bays as f64 * self.spacing
    }

    /// The support's static stiffness, pad and ballast in series, N/m.
    pub fn support_stiffness(&self) -> f64 {
        1.0 / (1.0 / self.pad_stiffness + 1.0 / self.ballast_stiffness)
    }

    /// The sponge's damping per unit mass at `x` (m), 1/s (module docs; zero in the middle).
    pub fn sponge(&self, x: f64) -> f64 {
        match self.ends {
            Ends::Free => 0.0,
            Ends::Absorbing { bays, damping } => {
                let la = bays as f64 * self.spacing;
                if la <= 0.0 {
                    return 0.0;
                }
                let depth = (la - x).max(x - (self.length() - la)).max(0.0);
                damping * (depth / la).min(1.0).powi(2)
            }
        }
    }

    /// Builds the track (module docs).
    ///
    /// # Errors
    /// [`TrackError`] for invalid data.
    pub fn build(&self) -> Result<Track, TrackError> {
        let (rail, xs, phi) = self.rail()?;
        let bodies = vec![rail];
        let n_rail = first_dofs(&bodies)[1];
        let (discrete, pads) = self.supports(0, n_rail)?;
        let joints = Joints {
            dofs: self.bays + 1,
            discrete,
        };
        let joined = assemble_with(&bodies, &joints)?;
        Ok(Track {
            spec: *self,
            bodies,
            joined,
            xs,
            phi,
            pads,
        })
    }

    /// The rail as a body in the ground's frame (module docs, its sponge included), with its
    /// nodes' abscissae and each element's `Phi`.
    ///
    /// # Errors
    /// [`TrackError`] for invalid data.
    pub fn rail(&self) -> Result<(Body, Vec<f64>, Vec<f64>), TrackError> {
        self.validate()?;
        let ne = self.bays * self.elements_per_bay;
        let le = self.spacing / self.elements_per_bay as f64;
        let xs: Vec<f64> = (0..=ne).map(|i| i as f64 * le).collect();
        let mut rail = Body::rail(
            "rail",
            &xs,
            0.0,
            &self.section,
            self.theory,
            Motion::Fixed,
            &[],
        )?;
        let phi = vec![self.section.phi(self.theory, le); ne];
        // The sponge on the rail: C += eta(x_e) M_e, eta at the element's middle.
        let mut me = [[0.0; 4]; 4];
        bending_mass_into(&self.section, self.theory, le, &mut me);
        for e in 0..ne {
            let eta = self.sponge(xs[e] + 0.5 * le);
            if eta == 0.0 {
                continue;
            }
            let dofs = [2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3];
            for a in 0..4 {
                for b in 0..4 {
                    let slot = rail
                        .model
                        .assembler
                        .slot(dofs[a], dofs[b])
                        .ok_or(TrackError::Solve("rail pattern".into()))?;
                    rail.model.c[slot] += eta * me[a][b];
                }
            }
        }
        Ok((rail, xs, phi))
    }

    /// The pads, sleepers and ballast as discrete elements on a joined numbering where the
    /// rail's dofs start at `rail_first` and the sleepers' (one each) at `sleeper_first`,
    /// with each sleeper's pad `(rail deflection dof, sleeper dof)`.
    ///
    /// # Errors
    /// [`TrackError::Discrete`] for a negative value.
    pub fn supports(
        &self,
        rail_first: usize,
        sleeper_first: usize,
    ) -> Result<(Discrete, Vec<(usize, usize)>), TrackError> {
        let sleepers = self.bays + 1;
        let mut discrete = Discrete::new();
        let spring = |link, stiffness, damping| SpringDamper {
            link,
            kind: SpringKind::Translational,
            stiffness,
            damping,
        };
        let mut pads = Vec::with_capacity(sleepers);
        for j in 0..sleepers {
            let w = rail_first + 2 * j * self.elements_per_bay;
            let y = sleeper_first + j;
            let x = j as f64 * self.spacing;
            discrete.add_mass(PointMass {
                dof: y,
                mass: self.sleeper_mass,
            })?;
            discrete.add_spring(spring(
                Link::Between(w, y),
                self.pad_stiffness,
                self.pad_damping,
            ))?;
            let sponge = self.sponge(x) * self.sleeper_mass;
            discrete.add_spring(spring(
                Link::Ground(y),
                self.ballast_stiffness,
                self.ballast_damping + sponge,
            ))?;
            pads.push((w, y));
        }
        Ok((discrete, pads))
    }
}

/// A built track (module docs): its body, the joined model with the sleepers, the rail's
/// node abscissae and each sleeper's pad.
#[derive(Debug, Clone)]
pub struct Track {
    /// The data it was built from.
    pub spec: TrackSpec,
    /// The rail (one body).
    pub bodies: Vec<Body>,
    /// The joined model: the rail's dofs `(w, theta)` per node, then one dof per sleeper.
    pub joined: Assembled,
    /// The rail's node abscissae, m.
    pub xs: Vec<f64>,
    /// `Phi` of each rail element (0 for Euler-Bernoulli).
    pub phi: Vec<f64>,
    /// Each sleeper's pad: (the rail's deflection dof above it, the sleeper's dof).
    pub pads: Vec<(usize, usize)>,
}

impl Track {
    /// Dofs of the model.
    pub fn n(&self) -> usize {
        self.joined.model.n()
    }

    /// The rail's length, m.
    pub fn length(&self) -> f64 {
        *self.xs.last().unwrap_or(&0.0)
    }

    /// The element under `x` (m) and the local coordinate `xi` in `[0, 1]` there.
    ///
    /// # Errors
    /// [`TrackError::OffRail`].
    pub fn element_at(&self, x: f64) -> Result<(usize, f64), TrackError> {
        let l = self.length();
        if !(x.is_finite() && (0.0..=l).contains(&x)) {
            return Err(TrackError::OffRail { x, length: l });
        }
        let ne = self.xs.len() - 1;
        let le = l / ne as f64;
        let e = ((x / le).floor() as usize).min(ne - 1);
        let xi = ((x - self.xs[e]) / (self.xs[e + 1] - self.xs[e])).clamp(0.0, 1.0);
        Ok((e, xi))
    }

    /// The rail's deflection shape functions at `x`: the element's four dofs
    /// `(w1, theta1, w2, theta2)` and `N_w` there (the beam's own,
    /// [`shape_functions`]).
    ///
    /// # Errors
    /// [`TrackError::OffRail`].
    pub fn point(&self, x: f64) -> Result<([usize; 4], [f64; 4]), TrackError> {
        let (e, xi) = self.element_at(x)?;
        let le = self.xs[e + 1] - self.xs[e];
        let (nw, _) = shape_functions(self.phi[e], le, xi);
        Ok(([2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3], nw))
    }

    /// The rail's deflection at `x` (m) of the displacement `u` (m).
    ///
    /// # Errors
    /// [`TrackError::OffRail`].
    pub fn deflection_at(&self, u: &[f64], x: f64) -> Result<f64, TrackError> {
        let (dofs, nw) = self.point(x)?;
        Ok((0..4).map(|a| nw[a] * u[dofs[a]]).sum())
    }

    /// The deflection (m per N of force along `w`) at `x` of the element under `x`, clamped at
    /// both its nodes, loaded by a unit point force at `x`: what the interpolation of the
    /// nodal values misses under a point load (zero at the nodes).
    ///
    /// The element's shape functions are the homogeneous solutions of the beam
    /// (Hermite cubics; Timoshenko's interdependent interpolation), so the exact static field
    /// under a point force inside an element is the interpolation of the (exact) nodal values
    /// plus the clamped-clamped element's own response. With `a = x - x_1`, `b = l - a`, the
    /// shear force `V_0` and the moment `M_0` at the element's left end solve
    /// `M_0 l - V_0 l^2 / 2 = -b^2 / 2` and
    /// `M_0 l^2 / (2 EI) - V_0 (l^3 / (6 EI) - l / (kappa G A)) = -b^3 / (6 EI) + b / (kappa G A)`
    /// (`theta(l) = w(l) = 0`; no shear term for Euler-Bernoulli), and
    /// `w(a) = M_0 a^2 / (2 EI) - V_0 a^3 / (6 EI) + V_0 a / (kappa G A)`; for
    /// Euler-Bernoulli this is `a^3 b^3 / (3 EI l^3)`.
    ///
    /// # Errors
    /// [`TrackError::OffRail`].
    pub fn local_flexibility(&self, x: f64) -> Result<f64, TrackError> {
        let (e, xi) = self.element_at(x)?;
        let l = self.xs[e + 1] - self.xs[e];
        let (a, b) = (xi * l, (1.0 - xi) * l);
        let s = &self.spec.section;
        let ei = s.ei();
        let cs = match self.spec.theory {
            crate::element::beam::BeamTheory::EulerBernoulli => 0.0,
            crate::element::beam::BeamTheory::Timoshenko => {
                1.0 / (s.shear_coefficient * s.shear_modulus * s.area)
            }
        };
        // [l, -l^2/2; l^2/(2EI), -(l^3/(6EI) - l cs)] [M0; V0] = [r1; r2].
        let (a11, a12) = (l, -0.5 * l * l);
        let (a21, a22) = (0.5 * l * l / ei, -(l * l * l / (6.0 * ei) - l * cs));
        let (r1, r2) = (-0.5 * b * b, -b * b * b / (6.0 * ei) + b * cs);
        let det = a11 * a22 - a12 * a21;
        let m0 = (r1 * a22 - a12 * r2) / det;
        let v0 = (a11 * r2 - a21 * r1) / det;
        Ok(m0 * a * a / (2.0 * ei) - v0 * a * a * a / (6.0 * ei) + v0 * a * cs)
    }

    /// The rail's deflection (m) under a point force `force` (N, along `w`) at `x` of the
    /// displacement `u` (m): the interpolation of the nodal values plus the element's own
    /// clamped-clamped response ([`Track::local_flexibility`]); exact in statics, and in
    /// dynamics up to the element's own inertia.
    ///
    /// # Errors
    /// [`TrackError::OffRail`].
    pub fn deflection_under_load(&self, u: &[f64], x: f64, force: f64) -> Result<f64, TrackError> {
        Ok(self.deflection_at(u, x)? + force * self.local_flexibility(x)?)
    }

    /// The sleeper nearest `x` (m).
    pub fn sleeper_near(&self, x: f64) -> usize {
        let j = (x / self.spec.spacing).round().max(0.0) as usize;
        j.min(self.pads.len() - 1)
    }

    /// The abscissa of sleeper `j`, m.
    pub fn sleeper_x(&self, j: usize) -> f64 {
        j as f64 * self.spec.spacing
    }

    /// The middle sleeper (`bays / 2`).
    pub fn middle_sleeper(&self) -> usize {
        self.spec.bays / 2
    }

    /// The abscissa of the middle sleeper, m.
    pub fn middle(&self) -> f64 {
        self.sleeper_x(self.middle_sleeper())
    }

    /// The middle of the bay after the middle sleeper, m.
    pub fn middle_span(&self) -> f64 {
        self.middle() + 0.5 * self.spec.spacing
    }

    /// The force in pad `j` (N, compression positive: the rail pressing the sleeper down),
    /// `k_p (y_j - w_j) + c_p (y_j' - w_j')`, of the displacement `u` and velocity `v`.
    pub fn pad_force(&self, u: &[f64], v: &[f64], j: usize) -> f64 {
        let (w, y) = self.pads[j];
        self.spec.pad_stiffness * (u[y] - u[w]) + self.spec.pad_damping * (v[y] - v[w])
    }

    /// The static displacement (m) under a force `force` (N, along the rail's `w`: negative
    /// downwards) at `x` (m): `K u = N_w(x) force`.
    ///
    /// # Errors
    /// [`TrackError`] for a point off the rail or a failed solve.
    pub fn static_displacement(&self, x: f64, force: f64) -> Result<Vec<f64>, TrackError> {
        let mut pencil = receptance::Pencil::new(self)?;
        pencil.factor(0.0)?;
        pencil.static_displacement(self, x, force)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_uic60_set_builds_with_a_sleeper_dof_each() {
        let t = TrackSpec::uic60().build().unwrap();
        let s = &t.spec;
        let rail_dofs = 2 * (s.bays * s.elements_per_bay + 1);
        assert_eq!(t.n(), rail_dofs + s.bays + 1);
        assert_eq!(t.pads.len(), s.bays + 1);
        assert_eq!(t.pads[3], (2 * 3 * s.elements_per_bay, rail_dofs + 3));
        assert!((t.length() - 60.0).abs() < 1e-12);
        // The sponge: zero in the middle, eta_max at the ends, quadratic.
        assert_eq!(s.sponge(t.middle()), 0.0);
        assert_eq!(s.sponge(0.0), 1000.0);
        assert_eq!(s.sponge(60.0), 1000.0);
        assert!((s.sponge(0.5 * 18.0) - 250.0).abs() < 1e-9);
        assert_eq!(s.sponge(18.0), 0.0);
        assert!(matches!(
            TrackSpec::named("zhai"),
            Err(TrackError::UnknownSet(_))
        ));
    }

    /// The clamped-clamped element's flexibility under the load: zero at the nodes,
    /// `l^3 / (192 EI)` at the middle for Euler-Bernoulli (`a^3 b^3 / (3 EI l^3)`), plus the
    /// shear's `l / (4 kappa G A)` for Timoshenko (the clamped-clamped beam's middle).
    #[test]
    fn the_local_flexibility_is_the_clamped_clamped_element() {
        let mut s = TrackSpec::uic60();
        s.bays = 4;
        s.ends = Ends::Free;
        for theory in [BeamTheory::EulerBernoulli, BeamTheory::Timoshenko] {
            s.theory = theory;
            let t = s.build().unwrap();
            let l = 0.1;
            let ei = s.section.ei();
            let kga = s.section.shear_coefficient * s.section.shear_modulus * s.section.area;
            let shear = if theory == BeamTheory::Timoshenko {
                l / (4.0 * kga)
            } else {
                0.0
            };
            let mid = t.local_flexibility(0.65).unwrap();
            let want = l * l * l / (192.0 * ei) + shear;
            assert!((mid / want - 1.0).abs() < 1e-9, "{theory:?} {mid} {want}");
            assert!(t.local_flexibility(0.6).unwrap().abs() < 1e-20);
            let (a, b) = (0.03, 0.07);
            let eb = a * a * a * b * b * b / (3.0 * ei * l * l * l);
            let got = t.local_flexibility(0.63).unwrap();
            if theory == BeamTheory::EulerBernoulli {
                assert!((got / eb - 1.0).abs() < 1e-9, "{got} {eb}");
            } else {
                assert!(got > eb);
            }
        }
    }

    #[test]
    fn bad_values_are_refused_by_name() {
        let mut s = TrackSpec::uic60();
        s.pad_stiffness = -1.0;
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("pad_stiffness"), "{e}");
        let mut s = TrackSpec::uic60();
        s.ends = Ends::Absorbing {
            bays: 50,
            damping: 1.0,
        };
        assert!(s.validate().unwrap_err().to_string().contains("end_bays"));
    }
}
