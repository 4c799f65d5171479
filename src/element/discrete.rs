//! Discrete elements: point masses, spring-dampers (translational and rotational) and the
//! rigid hub (or axle) node that carries a mass and a load.
//!
//! Each element acts on one dof (against the ground) or two dofs (between them). On dofs
//! `a` (and `b`) a spring-damper of stiffness `k` and damping `c` adds
//! $$K_e = k\begin{bmatrix}1&-1\\\\-1&1\end{bmatrix},\quad
//!   C_e = c\begin{bmatrix}1&-1\\\\-1&1\end{bmatrix}\qquad\text{(between } a, b),\qquad
//!   K_e = \[k\],\ C_e = \[c\]\qquad\text{(to the ground)},$$
//! the force on `a` being `-k (u_a - u_b) - c (v_a - v_b)`: units N/m and N s/m on
//! translations, N m/rad and N m s/rad on rotations (a rotational spring is the same matrix
//! on rotation dofs). A point mass `m` on dof `a` adds `M_e = [m]` (kg; kg m^2 on a
//! rotation dof). A hub is a node of its own ([`crate::assembly::DofLayout`]) whose
//! translations carry its mass `m` (kg), whose rotation (if it has one) carries its moment
//! of inertia `J` (kg m^2), and which carries a load (N; N m on the rotation): entries of
//! the load vector `f` of `M v' + C v + K u = f`.
//!
//! The one-dof elements (point masses, ground springs, hub masses) form one element family
//! of the [`crate::assembly::Assembler`], the two-dof springs another
//! ([`Discrete::families`]); their values are scattered by [`Discrete::add_matrices_into`].

use crate::assembly::{Assembler, AssemblyError, DofLayout, ElementFamily};

/// Invalid discrete elements.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DiscreteError {
    /// A mass, stiffness or damping that is negative or not finite.
    #[error("{what} must be finite and non-negative, got {value}")]
    Negative {
        /// The quantity.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// A load that is not finite.
    #[error("{what} must be finite, got {value}")]
    NotFinite {
        /// The quantity.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// A spring between a dof and itself.
    #[error("a spring-damper joins dof {dof} to itself")]
    SameDof {
        /// The dof.
        dof: usize,
    },
    /// A hub's load does not have one entry per dof of its node, or the hub has more
    /// translations than dofs.
    #[error("hub on node {node}: {got} load entries / translations for {dofs} dofs")]
    HubDofs {
        /// The node.
        node: usize,
        /// Load entries or translations given.
        got: usize,
        /// Dofs of the node.
        dofs: usize,
    },
    /// A node not in the layout.
    #[error(transparent)]
    Layout(#[from] AssemblyError),
    /// The assembler's families are not this set's ([`Discrete::families`]).
    #[error("assembler family {family} is not this set's discrete family")]
    FamilyMismatch {
        /// The family index.
        family: usize,
    },
}

/// The dofs a spring-damper joins.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Link {
    /// Dof `a` to the ground.
    Ground(usize),
    /// Dof `a` to dof `b`.
    Between(usize, usize),
}

/// Translational (N/m, N s/m) or rotational (N m/rad, N m s/rad) spring-damper: the same
/// matrices, on translation or rotation dofs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpringKind {
    /// On translation dofs.
    Translational,
    /// On rotation dofs.
    Rotational,
}

/// A linear spring and viscous damper in parallel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringDamper {
    /// The dofs joined.
    pub link: Link,
    /// Translational or rotational (sets the units of the two values).
    pub kind: SpringKind,
    /// Stiffness `k`, N/m (rotational: N m/rad).
    pub stiffness: f64,
    /// Damping `c`, N s/m (rotational: N m s/rad).
    pub damping: f64,
}

/// A point mass on one dof.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointMass {
    /// The dof.
    pub dof: usize,
    /// Mass, kg (kg m^2 on a rotation dof).
    pub mass: f64,
}

/// A rigid hub or axle: a node of its own whose first `translations` dofs carry `mass` and
/// whose other dofs (rotations) carry `inertia`, loaded by `load` (one entry per dof).
#[derive(Debug, Clone, PartialEq)]
pub struct Hub {
    /// The node ([`DofLayout`]).
    pub node: usize,
    /// How many of the node's dofs are translations (the dimension), the rest rotations.
    pub translations: usize,
    /// Mass, kg.
    pub mass: f64,
    /// Moment of inertia about each rotation dof, kg m^2.
    pub inertia: f64,
    /// Load on each dof of the node: N on translations, N m on rotations.
    pub load: Vec<f64>,
}

/// A set of discrete elements, as two element families with their values.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Discrete {
    /// Dofs of the one-dof elements.
    single_dofs: Vec<usize>,
    /// `(m, c, k)` of each one-dof element.
    single_values: Vec<[f64; 3]>,
    /// Dof pairs of the two-dof springs, flattened.
    link_dofs: Vec<usize>,
    /// `(c, k)` of each two-dof spring.
    link_values: Vec<[f64; 2]>,
    /// Constant nodal loads `(dof, value)`.
    loads: Vec<(usize, f64)>,
}

fn non_negative(what: &'static str, value: f64) -> Result<f64, DiscreteError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(DiscreteError::Negative { what, value })
    }
}

impl Discrete {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// True when the set holds no element and no load.
    pub fn is_empty(&self) -> bool {
        self.single_dofs.is_empty() && self.link_dofs.is_empty() && self.loads.is_empty()
    }

    /// Adds a point mass.
    ///
    /// # Errors
    /// [`DiscreteError::Negative`].
    pub fn add_mass(&mut self, p: PointMass) -> Result<(), DiscreteError> {
        let m = non_negative("mass", p.mass)?;
        self.single_dofs.push(p.dof);
        self.single_values.push([m, 0.0, 0.0]);
        Ok(())
    }

    /// Adds a spring-damper.
    ///
    /// # Errors
    /// [`DiscreteError::Negative`], [`DiscreteError::SameDof`].
    pub fn add_spring(&mut self, s: SpringDamper) -> Result<(), DiscreteError> {
        let k = non_negative("stiffness", s.stiffness)?;
        let c = non_negative("damping", s.damping)?;
        match s.link {
            Link::Ground(a) => {
                self.single_dofs.push(a);
                self.single_values.push([0.0, c, k]);
            }
            Link::Between(a, b) if a == b => return Err(DiscreteError::SameDof { dof: a }),
            Link::Between(a, b) => {
                self.link_dofs.extend([a, b]);
                self.link_values.push([c, k]);
            }
        }
        Ok(())
    }

    /// Adds a hub on a node of `layout`: its masses and its load.
    ///
    /// # Errors
    /// [`DiscreteError::Layout`] for a node not in the layout, [`DiscreteError::HubDofs`],
    /// [`DiscreteError::Negative`], [`DiscreteError::NotFinite`].
    pub fn add_hub(&mut self, layout: &DofLayout, hub: &Hub) -> Result<(), DiscreteError> {
        let dofs = layout.dofs(hub.node)?;
        let bad = |got| DiscreteError::HubDofs {
            node: hub.node,
            got,
            dofs: dofs.len(),
        };
        if hub.load.len() != dofs.len() {
            return Err(bad(hub.load.len()));
        }
        if hub.translations > dofs.len() {
            return Err(bad(hub.translations));
        }
        let m = non_negative("hub mass", hub.mass)?;
        let j = non_negative("hub inertia", hub.inertia)?;
        for (i, d) in dofs.enumerate() {
            if !hub.load[i].is_finite() {
                return Err(DiscreteError::NotFinite {
                    what: "hub load",
                    value: hub.load[i],
                });
            }
            let mass = if i < hub.translations { m } else { j };
            self.add_mass(PointMass { dof: d, mass })?;
            self.loads.push((d, hub.load[i]));
        }
        Ok(())
    }

    /// The two element families: one-dof elements (masses, ground springs) and two-dof
    /// springs, to pass (in this order) to [`Assembler::try_with_families`].
    pub fn families(&self) -> [ElementFamily; 2] {
        [
            ElementFamily::try_new(1, self.single_dofs.clone()).expect("one dof each"),
            ElementFamily::try_new(2, self.link_dofs.clone()).expect("two dofs each"),
        ]
    }

    /// Adds the discrete elements' `M`, `C` and `K` into the value arrays of `asm`, whose
    /// families `first` and `first + 1` are [`Discrete::families`].
    ///
    /// # Errors
    /// [`DiscreteError::FamilyMismatch`] when the assembler's families there are not these.
    pub fn add_matrices_into(
        &self,
        asm: &Assembler,
        first: usize,
        m: &mut [f64],
        c: &mut [f64],
        k: &mut [f64],
    ) -> Result<(), DiscreteError> {
        let fams = self.families();
        for (i, fam) in fams.iter().enumerate() {
            if first + i >= asm.n_families() || asm.family(first + i) != fam {
                return Err(DiscreteError::FamilyMismatch { family: first + i });
            }
        }
        for (which, values) in [m, c, k].into_iter().enumerate() {
            asm.assemble_family_serial_into(first, values, |e, out| {
                out[0] = self.single_values[e][which];
            });
            if which > 0 {
                asm.assemble_family_serial_into(first + 1, values, |e, out| {
                    let v = self.link_values[e][which - 1];
                    out.copy_from_slice(&[v, -v, -v, v]);
                });
            }
        }
        Ok(())
    }

    /// Adds `scale` times the hubs' loads into `f` (no allocation: for the time loop).
    ///
    /// # Panics
    /// If `f` is shorter than a loaded dof.
    pub fn add_load_into(&self, scale: f64, f: &mut [f64]) {
        for &(d, v) in &self.loads {
            f[d] += scale * v;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_masses_and_springs_assemble_the_textbook_matrices() {
        // Ground - k1 - [m1] - k2 - [m2], dampers alongside, a rotational spring on dof 2.
        let mut d = Discrete::new();
        let spring = |link, k, c| SpringDamper {
            link,
            kind: SpringKind::Translational,
            stiffness: k,
            damping: c,
        };
        d.add_spring(spring(Link::Ground(0), 3.0, 0.3)).unwrap();
        d.add_spring(spring(Link::Between(0, 1), 5.0, 0.5)).unwrap();
        d.add_mass(PointMass { dof: 0, mass: 2.0 }).unwrap();
        d.add_mass(PointMass { dof: 1, mass: 7.0 }).unwrap();
        d.add_spring(SpringDamper {
            link: Link::Ground(2),
            kind: SpringKind::Rotational,
            stiffness: 11.0,
            damping: 0.0,
        })
        .unwrap();
        let asm = Assembler::try_with_families(3, d.families().to_vec()).unwrap();
        let (mut m, mut c, mut k) = (asm.zeros(), asm.zeros(), asm.zeros());
        d.add_matrices_into(&asm, 0, &mut m, &mut c, &mut k)
            .unwrap();
        let (m, c, k) = (asm.to_dense(&m), asm.to_dense(&c), asm.to_dense(&k));
        let km = [[8.0, -5.0, 0.0], [-5.0, 5.0, 0.0], [0.0, 0.0, 11.0]];
        let cm = [[0.8, -0.5, 0.0], [-0.5, 0.5, 0.0], [0.0, 0.0, 0.0]];
        let mm = [[2.0, 0.0, 0.0], [0.0, 7.0, 0.0], [0.0, 0.0, 0.0]];
        for i in 0..3 {
            for j in 0..3 {
                assert_eq!(k[(i, j)], km[i][j]);
                assert!((c[(i, j)] - cm[i][j]).abs() < 1e-15);
                assert_eq!(m[(i, j)], mm[i][j]);
            }
        }
    }

    #[test]
    fn hub_masses_its_translations_and_rotation_and_carries_its_load() {
        let mut layout = DofLayout::new();
        layout.push_nodes(2, 2);
        let hub_node = layout.push_nodes(1, 3).start;
        let mut d = Discrete::new();
        let hub = Hub {
            node: hub_node,
            translations: 2,
            mass: 500.0,
            inertia: 12.0,
            load: vec![0.0, -9.81 * 500.0, 3.0],
        };
        d.add_hub(&layout, &hub).unwrap();
        let asm = Assembler::try_with_families(layout.n_dofs(), d.families().to_vec()).unwrap();
        let (mut m, mut c, mut k) = (asm.zeros(), asm.zeros(), asm.zeros());
        d.add_matrices_into(&asm, 0, &mut m, &mut c, &mut k)
            .unwrap();
        let md = asm.to_dense(&m);
        assert_eq!((md[(4, 4)], md[(5, 5)], md[(6, 6)]), (500.0, 500.0, 12.0));
        let mut f = vec![1.0; 7];
        d.add_load_into(2.0, &mut f);
        assert_eq!(
            f,
            vec![1.0, 1.0, 1.0, 1.0, 1.0, 1.0 - 2.0 * 9.81 * 500.0, 7.0]
        );
    }

    #[test]
    fn bad_discrete_elements_are_errors() {
        let mut d = Discrete::new();
        assert_eq!(
            d.add_mass(PointMass { dof: 0, mass: -1.0 }),
            Err(DiscreteError::Negative {
                what: "mass",
                value: -1.0
            })
        );
        let s = SpringDamper {
            link: Link::Between(3, 3),
            kind: SpringKind::Translational,
            stiffness: 1.0,
            damping: 0.0,
        };
        assert_eq!(d.add_spring(s), Err(DiscreteError::SameDof { dof: 3 }));
        let s = SpringDamper {
            stiffness: f64::INFINITY,
            link: Link::Ground(0),
            ..s
        };
        assert!(matches!(
            d.add_spring(s),
            Err(DiscreteError::Negative { .. })
        ));
        let layout = DofLayout::uniform(1, 2);
        let hub = Hub {
            node: 0,
            translations: 2,
            mass: 1.0,
            inertia: 0.0,
            load: vec![0.0],
        };
        assert!(matches!(
            d.add_hub(&layout, &hub),
            Err(DiscreteError::HubDofs { .. })
        ));
        let nan = Hub {
            load: vec![0.0, f64::NAN],
            ..hub.clone()
        };
        assert!(matches!(
            d.add_hub(&layout, &nan),
            Err(DiscreteError::NotFinite { .. })
        ));
        let three = Hub {
            translations: 3,
            load: vec![0.0; 2],
            ..hub.clone()
        };
        assert!(matches!(
            d.add_hub(&layout, &three),
            Err(DiscreteError::HubDofs { got: 3, .. })
        ));
        let hub = Hub { node: 4, ..hub };
        assert!(matches!(
            d.add_hub(&layout, &hub),
            Err(DiscreteError::Layout(_))
        ));
        // A spring on a dof past the model is refused by the assembler.
        d.add_spring(SpringDamper {
            link: Link::Between(0, 9),
            kind: SpringKind::Translational,
            stiffness: 1.0,
            damping: 0.0,
        })
        .unwrap();
        assert!(matches!(
            Assembler::try_with_families(2, d.families().to_vec()),
            Err(AssemblyError::DofOutOfRange { dof: 9, .. })
        ));
        // The wrong assembler for the set.
        let other = Assembler::try_with_families(10, vec![]).unwrap();
        let (mut m, mut c, mut k) = (other.zeros(), other.zeros(), other.zeros());
        assert!(d
            .add_matrices_into(&other, 0, &mut m, &mut c, &mut k)
            .is_err());
    }
}
