//! The elastic rail under the rolling slice: a straight bar of the wheel's material with the
//! base's crown, whose frame translates under the wheel (the contact zone moves along the
//! rail) and is pressed up into the rim by the flattening program.
//!
//! **Why the rail translates and the wheel turns.** The wheel stays in its rotating frame,
//! as the paper's (§4): its material does not move in its mesh, and its moving refined zone
//! follows the contact round the rim. The rail's material moves straight, so its mesh
//! travels with it under the axle (a Lagrangian bar in a translating frame, [`Motion::Pressed`]):
//! no convective term, no remeshing, and a uniform pitch along the rail gives the contact
//! the same cells wherever it is. The price is a rail as long as the run's rolling, fine
//! along its whole length. (A rail meshed in the wheel's frame would need the material's
//! flow through its mesh, an Eulerian term the space-time scheme does not carry.)
//!
//! **Geometry.** In its own coordinates the rail runs along `x` from 0 to `length`, its top
//! at `y = 0` on its centre line `z = 0` and its foot at `y = -height`, `z` across it within
//! `+-width / 2`. With a crown `R_c` the top is the circle `y = sqrt(R_c^2 - z^2) - R_c`
//! across the rail (the rigid base's cylinder, [`crate::contact::RotatingBase::crown`]); the
//! columns of nodes below it are stretched so that the foot stays flat. Cells: `pitch`
//! along the rail over its whole length, `pitch` across within `+-fine_half_width` and in
//! depth within `fine_depth` of the top, growing by `growth` beyond (the rulers of
//! [`crate::mesh::generators::graded`]). The foot is held; the ends are free, or joined.
//!
//! **The bar closed on itself** ([`RailBlock::periodic`], the bar's default). Its last
//! station's nodes are merged into its first's ([`RailBlock::close`]): a ring of equal
//! stations, each cell shaped by the open bar's ([`crate::bodies::solid::solid_closed`]).
//! It has no free end to soften the rail as the patch nears it, and its step matrix does
//! not change under a shift by one station, so the column `A^{-1} e_d` of every rail node
//! the patch meets is its section's node's column at one station, shifted
//! ([`crate::contact::cyclic`], A rail closed on itself): the rail's columns cost no solve
//! once its section's are known, where each station the patch reaches would cost one a dof.
//! The top's facets leave out the seam's station, which the margins keep from the patch.
//!
//! **The ring rolled over again** ([`RailBlock::ring`]). A closed rail shorter than the
//! run's rolling and two margins is a ring the patch goes round again and again, as a
//! twin-disc machine's. Each time the patch has come within a margin of the seam ahead, the
//! rail's labels shift one station back and its frame one station on
//! ([`crate::simulation::RingShift`]): the same material in the same place, the seam a
//! station further ahead. The shift is the ring's symmetry, so the step matrix, its factor
//! and the cached columns stay as they are, and the model's size no longer grows with the
//! distance rolled.
//!
//! **Frame.** `x = o + v t + d(t) e_y + X + u` ([`Motion::Pressed`]) with `o = (-margin,
//! -rho, z_c)` (`rho` the spun rim's mean radius, `z_c` the wheel's mid-plane: at `t = 0`
//! the crest at `X = margin` touches the rim's lowest point), `v = -V (1 - xi, 0, eta)`
//! with `V = omega rho` (the rigid base's material velocity: the longitudinal creepage `xi`
//! as its turning line's, the lateral `eta` its slide along the axle, both as
//! [`crate::contact::RotatingBase`] poses them) and `d(t)` the flattening program. A frame
//! that accelerates loads the rail with `-M 1 d''` ([`crate::bodies::load_fn`]).
//!
//! **Spin.** The spin creepage `phi` is the wheel's turning about the contact's normal
//! relative to the rail, at `V phi`. The rail's frame cannot turn with it (the rail is long
//! and straight), so the turning is the rail's material's alone, under its mesh
//! ([`spin`], [`crate::contact::facets::MaterialSpin`]): the contact's tangential rows see the
//! rail's material at a point `x` move by `-V phi e_y x (x - p0)` beside the frame's
//! velocity, `p0` the point under the axle, which is the rigid base's rigid slip
//! `V phi n x (x - p0)` ([`crate::contact::RotatingBase`]) and Kalker's `phi (-y, x)`. Over the
//! patch's passage the turning is `2 a phi` (1e-3 rad at `phi` = 0.2 1/m, `a` = 2.5 mm), and the
//! geometry and the normal rows leave it out, as the rigid base's crown does.

use crate::contact::cyclic::{Copies, CyclicSymmetry};
use crate::contact::facets::MaterialSpin;
use crate::contact::obstacle::Flattening;
use crate::contact::search::Motion;
use crate::mesh::generators::graded::ruler;
use crate::mesh::generators::rail3d::{rail_section, rail_stations};
use crate::mesh::generators::{box_mesh, rail_extruded, MeshError, RailSpec};
use crate::mesh::{CellKind, Mesh};
use crate::simulation::RingShift;

/// The rail's section, its cells and its length margin, m (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RailBlock {
    /// Height from the crest to the foot, m.
    pub height: f64,
    /// Width across, m.
    pub width: f64,
    /// Cell size along the rail, and across and in depth near the crest, m.
    pub pitch: f64,
    /// Half-width of the fine cells across the rail, m.
    pub fine_half_width: f64,
    /// Depth of the fine cells below the crest, m.
    pub fine_depth: f64,
    /// Growth of the cells beyond the fine ones, in `[1, 2]`.
    pub growth: f64,
    /// Rail ahead of the patch at the start and behind it at the end, m.
    pub margin: f64,
    /// The distance the rail travels under the axle in the run, m (the run sets it).
    pub rolled: f64,
    /// The section: the crowned bar of `height` and `width`, or the UIC60 rail.
    pub profile: RailProfile,
    /// The rail's two ends joined ([`RailBlock::close`]): a ring of equal stations, with no
    /// free end, whose contact columns repeat shifted by a station
    /// ([`crate::contact::cyclic`], A rail closed on itself). The bar only.
    pub periodic: bool,
    /// A closed rail's length, m, when it is shorter than the run's rolling and two margins
    /// (`None`: that length): the ring rolled over again, its seam kept ahead of the patch
    /// ([`crate::simulation::RingShift`]).
    pub ring: Option<f64>,
}

/// A rail mesh closed on itself ([`RailBlock::close`]).
#[derive(Debug, Clone)]
pub struct ClosedRail {
    /// The mesh: the open mesh's nodes without its last station, its cells across the seam
    /// naming the first station's nodes. Node sets `"top"` (less the first station: no
    /// facet spans the seam) and `"foot"`.
    pub mesh: Mesh,
    /// Per node: its place in the section (the orbit) and its station along the rail.
    pub labels: Vec<(usize, usize)>,
    /// The stations along the rail.
    pub stations: usize,
}

/// The rail's section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RailProfile {
    /// A rectangular bar whose top has the base's crown (module docs).
    Bar,
    /// The UIC60 (60E1) section of [`rail_extruded`] (its head in the published profile,
    /// the crest's radius 0.3 m), upright or inclined by `inclination` (tan of the angle),
    /// its head's surface `pitch` fine within `fine_half_width` of the crest and its
    /// section's cells growing by `growth` to 10 mm, `pitch` long over the patch's travel
    /// and growing to 10 mm in the margins; `height`, `width` and `fine_depth` are the
    /// section's own.
    Uic60 {
        /// The inclination toward the track's centre (0: upright).
        inclination: f64,
    },
}

impl RailBlock {
    /// How far from the rail's top a rim node finds it, m: four flattenings `depth` or two
    /// pitches, the larger.
    pub fn reach(&self, depth: f64) -> f64 {
        (4.0 * depth).max(2.0 * self.pitch)
    }

    /// The rail's length for a run that rolls `rolled` m: the rolling plus a margin at
    /// each end, or the ring's ([`RailBlock::ring`]).
    pub fn length(&self, rolled: f64) -> f64 {
        self.ring.unwrap_or(rolled + 2.0 * self.margin)
    }

    /// The cells along, across and in depth of a bar rolled over for `rolled` m (of a
    /// UIC60 rail: the cells along, its section's cells and 1).
    ///
    /// # Errors
    /// [`MeshError`] for a size out of range.
    pub fn counts(&self, rolled: f64) -> Result<[usize; 3], MeshError> {
        match self.profile {
            RailProfile::Bar => {
                let [a, c, d] = self.rulers(rolled)?;
                Ok([a.len() - 1, c.len() - 1, d.len() - 1])
            }
            RailProfile::Uic60 { .. } => {
                let spec = self.uic60(rolled);
                let (section, _, _) = rail_section(&spec)?;
                Ok([rail_stations(&spec).len() - 1, section.quads.len(), 1])
            }
        }
    }

    /// The rail's nodes for `rolled` m of rolling (0 when it cannot be built).
    pub fn nodes(&self, rolled: f64) -> usize {
        match self.profile {
            RailProfile::Bar => self
                .counts(rolled)
                .map_or(0, |[a, b, c]| (a + 1) * (b + 1) * (c + 1)),
            RailProfile::Uic60 { .. } => {
                let spec = self.uic60(rolled);
                rail_section(&spec).map_or(0, |(section, _, _)| {
                    section.points.len() * rail_stations(&spec).len()
                })
            }
        }
    }

    /// The UIC60 rail's spec: `pitch` along the patch's travel (and two fine half-widths
    /// beyond) and on its head's surface within `fine_half_width` of the crest; the margins
    /// graded to the section's 10 mm.
    fn uic60(&self, rolled: f64) -> RailSpec {
        let inclination = match self.profile {
            RailProfile::Uic60 { inclination } => inclination,
            RailProfile::Bar => 0.0,
        };
        RailSpec {
            length: self.length(rolled),
            inclination,
            focus_y: 0.0,
            head_size: self.pitch,
            head_band: self.fine_half_width.max(self.pitch),
            section_size: 0.01_f64.max(self.pitch),
            fine_size: self.pitch,
            // Fine over the patch's travel, growing to the section's size in the margins.
            fine_half_length: (0.5 * rolled + 2.0 * self.fine_half_width)
                .min(0.5 * self.length(rolled)),
            coarse_size: 0.01_f64.max(self.pitch),
            growth: self.growth.max(1.01),
        }
    }

    /// The rulers along, across (from `-width / 2`) and down from the crest.
    fn rulers(&self, rolled: f64) -> Result<[Vec<f64>; 3], MeshError> {
        let length = self.length(rolled);
        let along = ruler(length, length, self.pitch, self.growth.max(1.0))?;
        let half = ruler(
            0.5 * self.width,
            self.fine_half_width,
            self.pitch,
            self.growth,
        )?;
        let across: Vec<f64> = half
            .iter()
            .rev()
            .map(|&z| -z)
            .chain(half.iter().skip(1).copied())
            .collect();
        let depth = ruler(self.height, self.fine_depth, self.pitch, self.growth)?;
        Ok([along, across, depth])
    }

    /// The rail's mesh of hexahedra for `rolled` m of rolling under a crown `crown` (m;
    /// `None`: a flat top), in its own coordinates (module docs). Node sets `"top"`, `"foot"`,
    /// `"x0"`, `"x1"` (the ends) and `"all"`.
    ///
    /// # Errors
    /// [`MeshError`] for a size out of range, a crown narrower than the rail, or too many
    /// nodes.
    pub fn mesh(&self, rolled: f64, crown: Option<f64>) -> Result<Mesh, MeshError> {
        if let RailProfile::Uic60 { .. } = self.profile {
            let spec = self.uic60(rolled);
            spec.validate()?;
            let mut mesh = rail_extruded(&spec)?;
            // rail_extruded's (x along from the middle, y across, z up) to the rail's own
            // (x along from its start, y up, z across): a turn about x.
            let half = 0.5 * spec.length;
            for p in mesh.coords.chunks_exact_mut(3) {
                let [x, y, z] = [p[0], p[1], p[2]];
                p.copy_from_slice(&[x + half, z, -y]);
            }
            // The contact searches the head's whole surface along the whole rail (its
            // running band is fine only over the patch's travel): a rim node within reach
            // of the margins finds the head there too.
            mesh.node_sets.remove("running");
            if let Some(set) = mesh.node_sets.get("head").cloned() {
                mesh.node_sets.insert("top".to_string(), set);
            }
            return Ok(mesh);
        }
        if let Some(rc) = crown {
            if !(rc.is_finite() && rc > 0.5 * self.width) {
                return Err(MeshError::OutOfRange {
                    name: "crown radius (m, above half the rail's width)",
                    value: rc,
                    min: 0.5 * self.width,
                    max: f64::INFINITY,
                });
            }
        }
        let [along, across, depth] = self.rulers(rolled)?;
        let counts = [along.len() - 1, across.len() - 1, depth.len() - 1];
        // The box's axes (a, b, c) are the rail's (x, -z, y): a turn that keeps the cells'
        // orientation.
        let mut mesh = box_mesh(CellKind::Hex8, [1.0; 3], counts)?;
        let at =
            |r: &[f64], t: f64| r[((t * (r.len() - 1) as f64).round() as usize).min(r.len() - 1)];
        let height = self.height;
        for p in mesh.coords.chunks_exact_mut(3) {
            let x = at(&along, p[0]);
            let z = -at(&across, p[1]);
            // From the top (c = 1) down.
            let y0 = -at(&depth, 1.0 - p[2]);
            let top = crown.map_or(0.0, |rc| (rc * rc - z * z).sqrt() - rc);
            let y = y0 + top * (1.0 + y0 / height);
            p.copy_from_slice(&[x, y, z]);
        }
        let rename = [("z1", "top"), ("z0", "foot")];
        for (from, to) in rename {
            if let Some(set) = mesh.node_sets.remove(from) {
                mesh.node_sets.insert(to.to_string(), set);
            }
        }
        for gone in ["y0", "y1"] {
            mesh.node_sets.remove(gone);
        }
        Ok(mesh)
    }
}

impl RailBlock {
    /// The bar `open` ([`RailBlock::mesh`]) with its ends joined: the nodes of its last
    /// station (at `x = length`) merged into the first's (at `x = 0`), the cells keeping
    /// their order. Each cell is shaped by the open mesh's
    /// ([`crate::bodies::solid::solid_closed`]); the rail is a ring of `stations` equal
    /// stations under a shift by one of which its step matrix does not change.
    ///
    /// # Errors
    /// [`MeshError::Invalid`] when the stations along the open mesh are not equal, or a node
    /// of the last station has no twin in the first.
    pub fn close(&self, open: &Mesh) -> Result<ClosedRail, MeshError> {
        let dim = open.dim;
        let nodes = open.n_nodes();
        let xs: Vec<f64> = (0..nodes).map(|n| open.coords[dim * n]).collect();
        let length = xs.iter().copied().fold(0.0_f64, f64::max);
        // The stations: the distinct x, which must be equally spaced.
        let mut along: Vec<f64> = xs.clone();
        along.sort_by(f64::total_cmp);
        along.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * length);
        let stations = along.len().saturating_sub(1);
        let dx = length / stations.max(1) as f64;
        if stations < 3
            || along
                .iter()
                .enumerate()
                .any(|(i, &x)| (x - i as f64 * dx).abs() > 1e-9 * length)
        {
            return Err(MeshError::Invalid(format!(
                "a rail closed on itself needs equal stations along it ({} stations over {length} m)",
                stations
            )));
        }
        let station = |n: usize| (xs[n] / dx).round() as usize;
        let key = |n: usize| {
            (
                open.coords[dim * n + 1].to_bits(),
                open.coords[dim * n + 2].to_bits(),
            )
        };
        // The orbits: the first station's nodes in their order.
        let mut orbit_of = std::collections::HashMap::new();
        for n in (0..nodes).filter(|&n| station(n) == 0) {
            let o = orbit_of.len();
            orbit_of.insert(key(n), o);
        }
        let mut new_of = vec![usize::MAX; nodes];
        let mut labels = Vec::with_capacity(nodes);
        let mut coords = Vec::with_capacity(dim * nodes);
        let mut first = vec![usize::MAX; orbit_of.len()];
        for n in 0..nodes {
            let i = station(n);
            let Some(&o) = orbit_of.get(&key(n)) else {
                return Err(MeshError::Invalid(format!(
                    "node {n} of the rail has no twin on its first station: its section varies along it"
                )));
            };
            if i == stations {
                continue;
            }
            new_of[n] = labels.len();
            if i == 0 {
                first[o] = labels.len();
            }
            labels.push((o, i));
            coords.extend_from_slice(open.point(n));
        }
        for n in 0..nodes {
            if station(n) == stations {
                new_of[n] = first[orbit_of[&key(n)]];
            }
        }
        let mut cells = open.cells.clone();
        for c in cells.connectivity_mut() {
            *c = new_of[*c];
        }
        let mut sets = std::collections::BTreeMap::new();
        for name in ["top", "foot"] {
            let mut set: Vec<usize> = open
                .node_set(name)
                .unwrap_or_default()
                .iter()
                .filter(|&&n| name != "top" || station(n) != 0 && station(n) != stations)
                .map(|&n| new_of[n])
                .collect();
            set.sort_unstable();
            set.dedup();
            sets.insert(name.to_string(), set);
        }
        Ok(ClosedRail {
            mesh: Mesh::new(dim, coords, cells, sets),
            labels,
            stations,
        })
    }
}

impl ClosedRail {
    /// Its shift by one station over a model whose first `first_node` nodes are another
    /// body's (outside the symmetry), and the node the set-up's check takes a column of: the
    /// crest's node (of `top`, the closed mesh's) at the middle station, as a model node.
    ///
    /// # Errors
    /// A message when the labels are not whole stations, or no top node is at the middle.
    pub fn shift(
        &self,
        first_node: usize,
        top: &[usize],
    ) -> Result<(CyclicSymmetry, usize), String> {
        let mut labels = vec![None; first_node];
        labels.extend(self.labels.iter().copied().map(Some));
        let sym = CyclicSymmetry::partial(3, self.stations, &labels, Copies::Shift)?;
        let x = &self.mesh.coords;
        let probe = top
            .iter()
            .copied()
            .filter(|&n| self.labels[n].1 == self.stations / 2)
            .max_by(|&a, &b| x[3 * a + 1].total_cmp(&x[3 * b + 1]))
            .ok_or("the closed rail has no top node at its middle station")?;
        Ok((sym, first_node + probe))
    }

    /// The ring rolled over again ([`RailBlock::ring`]) of `length` (m), its nodes after the
    /// model's first `first_node`: node `(o, i)` takes the state of `(o, i + 1)` at each
    /// shift, the frame one station on, when the patch (from `margin`, at `speed` m/s along
    /// the ring) comes within `margin` of the seam ahead.
    pub fn ring_shift(&self, first_node: usize, length: f64, margin: f64, speed: f64) -> RingShift {
        let n = self.stations;
        let mut node_of = vec![0; self.labels.len()];
        for (m, &(o, i)) in self.labels.iter().enumerate() {
            node_of[o * n + i] = m;
        }
        let mut sources: Vec<usize> = (0..first_node).collect();
        sources.extend(
            self.labels
                .iter()
                .map(|&(o, i)| first_node + node_of[o * n + (i + 1) % n]),
        );
        let pitch = length / n as f64;
        RingShift {
            sources,
            pitch,
            step: pitch,
            start: margin,
            speed,
            limit: length - margin,
        }
    }
}

/// The rail's frame (module docs): under the wheel of spun radius `rho` turning at `omega`
/// with the creepages `xi` and `eta`, its crest at `X = margin` under the axle at `t = 0`
/// on the wheel's mid-plane `z_c`, pressed by `flattening`.
pub fn rail_frame(
    rho: f64,
    omega: f64,
    [xi, eta]: [f64; 2],
    margin: f64,
    z_c: f64,
    flattening: Flattening,
) -> Motion {
    let speed = omega * rho;
    Motion::Pressed {
        origin: [-margin, -rho, z_c],
        velocity: [-speed * (1.0 - xi), 0.0, -speed * eta],
        direction: [0.0, 1.0, 0.0],
        program: flattening,
    }
}

/// The spin creepage `phi` (1/m) under the wheel of spun radius `rho` turning at `omega`, its
/// mid-plane at `z_c` (module docs, Spin): the rail's material turns about the upward normal
/// through the point under the axle, `p0 = (0, -rho, z_c)`, at `-V phi` (`V = omega rho`),
/// so that a point of the wheel at rest in its frame slides on it at the rigid base's
/// `V phi n x (x - p0)` ([`crate::contact::RotatingBase`]).
pub fn spin(rho: f64, omega: f64, phi: f64, z_c: f64) -> MaterialSpin {
    MaterialSpin {
        axis: [0.0, 1.0, 0.0],
        pivot: [0.0, -rho, z_c],
        rate: -omega * rho * phi,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bodies::solid::{solid, SolidSpec};
    use crate::material::{Elastic, PlaneModel};
    use crate::model::LinearModel;

    fn block() -> RailBlock {
        RailBlock {
            height: 0.02,
            width: 0.02,
            pitch: 1e-3,
            fine_half_width: 3e-3,
            fine_depth: 2e-3,
            growth: 1.4,
            margin: 0.01,
            rolled: 0.03,
            profile: RailProfile::Bar,
            periodic: false,
            ring: None,
        }
    }

    /// The rail's steel, consistent mass.
    fn steel() -> SolidSpec {
        SolidSpec {
            material: Elastic {
                young: 2e11,
                poisson: 0.3,
                density: 7800.0,
            },
            plane: PlaneModel::Stress,
            thickness: 1.0,
            lumped: false,
        }
    }

    /// The crest on the crown's circle, the foot flat, the fine pitch where the contact
    /// runs, and every cell turned the right way (positive Jacobians).
    #[test]
    fn the_rail_is_crowned_on_top_flat_below_and_fine_along_its_crest() {
        let b = block();
        let rc = 0.1;
        let mesh = b.mesh(0.03, Some(rc)).unwrap();
        let x = &mesh.coords;
        for &n in mesh.node_set("top").unwrap() {
            let (y, z) = (x[3 * n + 1], x[3 * n + 2]);
            assert!(
                (y - ((rc * rc - z * z).sqrt() - rc)).abs() < 1e-15,
                "{y} {z}"
            );
        }
        for &n in mesh.node_set("foot").unwrap() {
            assert!((x[3 * n + 1] + 0.02).abs() < 1e-15);
        }
        let [na, nc, nd] = b.counts(0.03).unwrap();
        assert_eq!(na, 50);
        assert!(nc > 6 && nd > 2, "{nc} {nd}");
        assert_eq!(b.nodes(0.03), mesh.n_nodes());
        // The element refuses an inverted or degenerate cell.
        let spec = steel();
        assert!(solid("rail", mesh, &spec, Motion::Fixed).is_ok());
        // The UIC60 rail turned into the rail's frame: its crest at the origin's height on
        // z = 0, its top the head's surface along the whole rail, its foot 172 mm below,
        // every cell turned the right way.
        let uic = RailBlock {
            profile: RailProfile::Uic60 { inclination: 0.0 },
            pitch: 2e-3,
            fine_half_width: 6e-3,
            ..b
        };
        let mesh = uic.mesh(0.03, None).unwrap();
        let x = &mesh.coords;
        let top = mesh.node_set("top").unwrap();
        let crest = top.iter().map(|&n| x[3 * n + 1]).fold(f64::MIN, f64::max);
        assert!(crest.abs() < 1e-9, "{crest}");
        let length = uic.length(0.03);
        for &n in top {
            // The head between its flanks (72 mm wide), along the whole rail.
            assert!(x[3 * n + 2].abs() <= 0.037 && x[3 * n + 1] > -0.05);
            assert!(x[3 * n] >= -1e-12 && x[3 * n] <= length + 1e-12);
        }
        for end in [0.0, length] {
            assert!(top.iter().any(|&n| (x[3 * n] - end).abs() < 1e-12));
        }
        let foot = mesh.node_set("foot").unwrap();
        assert!(
            foot.iter().all(|&n| (x[3 * n + 1] + 0.172).abs() < 1e-3),
            "foot"
        );
        assert_eq!(uic.nodes(0.03), mesh.n_nodes());
        assert!(solid("rail", mesh, &spec, Motion::Fixed).is_ok());
    }

    /// The bar closed on itself: one station fewer than the open bar, every cell shaped,
    /// and its stiffness and mass the same under a shift by one station (the claim the
    /// shifted columns rest on), with the open bar's mass and the rigid translations still
    /// free of strain. The top leaves out the seam's stations; the UIC60 rail's unequal
    /// stations are refused.
    #[test]
    fn the_closed_bar_repeats_under_a_shift_by_one_station() {
        use crate::bodies::solid::solid_closed;
        let b = RailBlock {
            periodic: true,
            ..block()
        };
        let open = b.mesh(0.03, Some(0.1)).unwrap();
        let closed = b.close(&open).unwrap();
        let [na, nc, nd] = b.counts(0.03).unwrap();
        assert_eq!(closed.stations, na);
        let per = (nc + 1) * (nd + 1);
        assert_eq!(closed.mesh.n_nodes(), na * per);
        assert_eq!(open.n_nodes(), (na + 1) * per);
        let spec = steel();
        let body = solid_closed("rail", &open, closed.mesh.clone(), &spec, Motion::Fixed)
            .unwrap()
            .body;
        let whole = solid("rail", open.clone(), &spec, Motion::Fixed)
            .unwrap()
            .body;
        let model = &body.model;
        // The node one station on.
        let mut node_of = vec![usize::MAX; na * per];
        for (m, &(o, i)) in closed.labels.iter().enumerate() {
            node_of[o * na + i] = m;
        }
        let shift = |m: usize| {
            let (o, i) = closed.labels[m];
            node_of[o * na + (i + 1) % na]
        };
        let n = 3 * closed.mesh.n_nodes();
        let kmax = model.k.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
        let mmax = model.m.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
        let mut entries = 0;
        for i in 0..n {
            for j in 0..n {
                let Some(s) = model.assembler.slot(i, j) else {
                    continue;
                };
                let (si, sj) = (3 * shift(i / 3) + i % 3, 3 * shift(j / 3) + j % 3);
                let t = model
                    .assembler
                    .slot(si, sj)
                    .expect("the shifted entry in the pattern");
                assert!((model.k[s] - model.k[t]).abs() <= 1e-12 * kmax, "k {i} {j}");
                assert!((model.m[s] - model.m[t]).abs() <= 1e-12 * mmax, "m {i} {j}");
                entries += 1;
            }
        }
        assert_eq!(entries, model.assembler.nnz());
        // The mass of the open bar; a rigid translation strains nothing.
        let total = |m: &LinearModel, dofs: usize| {
            let mut sum = 0.0;
            for i in (0..dofs).step_by(3) {
                for j in (0..dofs).step_by(3) {
                    if let Some(s) = m.assembler.slot(i, j) {
                        sum += m.m[s];
                    }
                }
            }
            sum
        };
        let (mc, mo) = (total(model, n), total(&whole.model, 3 * open.n_nodes()));
        assert!((mc - mo).abs() < 1e-12 * mo, "{mc} {mo}");
        for c in 0..3 {
            let mut worst: f64 = 0.0;
            for i in 0..n {
                let mut f = 0.0;
                for m in 0..closed.mesh.n_nodes() {
                    if let Some(s) = model.assembler.slot(i, 3 * m + c) {
                        f += model.k[s];
                    }
                }
                worst = worst.max(f.abs());
            }
            assert!(worst < 1e-9 * kmax, "translation {c}: {worst:e}");
        }
        // No top node on the seam's station; the foot on every station.
        let top = closed.mesh.node_set("top").unwrap();
        assert!(top.iter().all(|&m| closed.labels[m].1 != 0));
        assert_eq!(closed.mesh.node_set("foot").unwrap().len(), na * (nc + 1));
        let uic = RailBlock {
            profile: RailProfile::Uic60 { inclination: 0.0 },
            pitch: 2e-3,
            fine_half_width: 6e-3,
            margin: 0.1,
            ..b
        };
        let graded = uic.mesh(0.03, None).unwrap();
        assert!(matches!(uic.close(&graded), Err(MeshError::Invalid(_))));
    }
}
