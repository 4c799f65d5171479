//! The 3D wheel's refined zone that moves with the contact: the paper's "relocation of the
//! condensed mesh together with the moving load" (§2, Fig. 4b), in 3D, for the annulus of
//! hexahedra rolling in its own frame ([`crate::bodies::rolling3d`]).
//!
//! **The mesh.** The annulus is swept about its axle ([`swept_annulus_hex8`]) through
//! angular stations on the lattice `theta_k = theta_c + 2 pi k / zone_sectors`
//! (`theta_c = -pi/2`, the base below the wheel at `t = 0`): every station within the
//! zone's half-width `K_0` of the centre (in lattice steps), every second one over the next
//! two cells, every fourth over the two after, and so on up to the pitch of the rim outside
//! the zone, `m = zone_sectors / sectors` (a power of two) steps. The section is the same at
//! every station: rings graded from the rim, the first as thick as the zone's pitch
//! `2 pi R / zone_sectors`, growing by `growth` up to the outer cells' size
//! `(R - bore) / rings`, then equal to the bore, so that the cells under the contact are
//! about cubes and shrink with the zone's pitch at every depth the contact's stresses reach
//! (all round the rim, as a swept mesh must). With the growth alone a ring at depth `d` is
//! about `(growth - 1) d` thick whatever the pitch; with `depth = Some(l)` it is at most
//! `s_f (1 + (d / l)^2)` (`s_f` the zone's pitch), the 2D zone's refinement in depth
//! ([`crate::mesh::zone`]), so that a ladder of pitches refines every depth the contact's
//! stresses reach (`l` about the patch's half-length). Layers are equal, or with
//! `axial = Some(w)` graded across the width about the mid-plane: as wide as the zone's
//! pitch within `w` of it, then growing by `growth` up to `thickness / layers` (a wide
//! wheel on a crowned base, whose patch is an ellipse about the mid-plane).
//!
//! **Relocation.** The mesh outside the zone repeats every `m` lattice steps, so turning the
//! frame of the mesh by one outer sector `Delta = 2 pi / sectors` with the contact keeps
//! every node there on a node: the material at station `k` after the turn is the material
//! that was at `k + m`, its vectors turned by `-Delta`. Where the zone moves (ahead of it
//! and behind it) a station's old place falls between two old stations, and its state is
//! interpolated along the arc between the nodes of the same ring and layer at those two
//! stations ([`Source::Triangle`] with a third weight of zero). The mesh, its matrices and
//! their factorization stay the same; [`crate::simulation::Relocation`] relabels the state.

use std::f64::consts::PI;

use super::generators::{swept_annulus_hex8, MeshError};
use super::zone::Source;
use super::Mesh;

/// The parameters of [`annulus_zone`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnnulusZoneOptions {
    /// The bore's radius (held), m.
    pub bore: f64,
    /// The rim's radius, m.
    pub radius: f64,
    /// The thickness along the axle, m.
    pub thickness: f64,
    /// Rings of the outer cells: their radial size is `(radius - bore) / rings`; with
    /// `growth = None`, the rings, all equal.
    pub rings: usize,
    /// Stations round the rim outside the zone (one relocation turns the frame by one).
    pub sectors: usize,
    /// Layers along the axle.
    pub layers: usize,
    /// The zone's pitch as a count round the rim: `sectors` times a power of two.
    pub zone_sectors: usize,
    /// The zone's width (the arc at the zone's pitch), rad.
    pub zone_width: f64,
    /// The rings' growth from the rim inwards (`None`: equal rings).
    pub growth: Option<f64>,
    /// The zone refined in depth as well (m; `None`: not): a ring at depth `d` is at most
    /// `s_f (1 + (d / l)^2)` thick, `s_f` the zone's pitch, so that the cells at a depth
    /// `d ~ l` shrink with the pitch (the 2D zone's rule, [`crate::mesh::zone`]); with the
    /// growth alone they are about `(growth - 1) d` thick whatever the pitch.
    pub depth: Option<f64>,
    /// The zone refined across the width as well (m; `None`: `layers` equal layers): the
    /// layers within this half-width of the mid-plane as wide as the zone's pitch, growing
    /// by `growth` (1.25 without it) outward up to `thickness / layers` (module docs).
    pub axial: Option<f64>,
}

/// An annulus with a refined zone and its relocation map ([`annulus_zone`]).
#[derive(Debug, Clone)]
pub struct AnnulusZone {
    /// The mesh (node sets `"bore"`, `"rim"`, `"all"`; node `(i, j, k)` is
    /// `i + (radii.len()) (j + angles.len() k)`).
    pub mesh: Mesh,
    /// The rings' radii, from the bore to the rim, m.
    pub radii: Vec<f64>,
    /// The stations' angles, increasing from the zone's centre `-pi/2`, rad.
    pub angles: Vec<f64>,
    /// The layers' boundaries along the axle, from 0 to the thickness, m.
    pub zs: Vec<f64>,
    /// The angle of one relocation, `2 pi / sectors`, rad.
    pub step: f64,
    /// Per node, where its state comes from at a relocation (module docs).
    pub sources: Vec<Source>,
    /// Nodes that are on a node of the old mesh at a relocation.
    pub exact_nodes: usize,
}

impl AnnulusZone {
    /// The angle a station's node stands for: half the two sectors beside it, rad.
    pub fn station_arc(&self, j: usize) -> f64 {
        let n = self.angles.len();
        let next = if j + 1 < n {
            self.angles[j + 1]
        } else {
            self.angles[0] + 2.0 * PI
        };
        let prev = if j > 0 {
            self.angles[j - 1]
        } else {
            self.angles[n - 1] - 2.0 * PI
        };
        0.5 * (next - prev)
    }
}

/// The zone's lattice steps from station `k`'s place to the next wanted station beyond the
/// centre: the pitch at lattice distance `d` from the centre (module docs).
fn pitch(d: usize, k0: usize, levels: u32) -> usize {
    let mut edge = k0;
    for l in 0..levels {
        if d <= edge {
            return 1 << l;
        }
        // Two cells of the next pitch.
        edge += 2 << (l + 1);
    }
    1 << levels
}

/// Builds the annulus of `o` with its zone (module docs).
///
/// # Errors
/// [`MeshError`] naming the parameter: lengths not finite and positive, a bore not inside
/// the rim, fewer than 8 sectors, zone sectors that are not the sectors times a power of
/// two, a zone narrower than two of its pitches or wider (with its transitions) than half
/// the rim, a growth outside `(1, 2]`, too many nodes.
pub fn annulus_zone(o: &AnnulusZoneOptions) -> Result<AnnulusZone, MeshError> {
    let (ks, radii, zs) = layout(o)?;
    let nf = o.zone_sectors;
    let ratio = nf / o.sectors;
    let dl = 2.0 * PI / nf as f64;
    let angles: Vec<f64> = ks.iter().map(|&k| -0.5 * PI + dl * k as f64).collect();
    let mesh = swept_annulus_hex8(&radii, &angles, &zs)?;
    let (nr1, nt, nz) = (radii.len(), angles.len(), zs.len() - 1);
    let id = |i: usize, j: usize, l: usize| i + nr1 * (j + nt * l);
    let mut sources = Vec::with_capacity(nr1 * nt * (nz + 1));
    let mut exact = 0;
    for l in 0..=nz {
        for &k in &ks {
            let from = (k + ratio) % nf;
            let at = ks.partition_point(|&q| q < from);
            let src = |i: usize| -> Source {
                if at < nt && ks[at] == from {
                    Source::Node(id(i, at, l))
                } else {
                    // Between the stations `at - 1` and `at` (wrapping past the last).
                    let (ja, jb) = ((at + nt - 1) % nt, at % nt);
                    let ka = ks[ja] as f64;
                    let mut kb = ks[jb] as f64;
                    let mut f = from as f64;
                    if kb <= ka {
                        kb += nf as f64;
                        if f < ka {
                            f += nf as f64;
                        }
                    }
                    let w = (f - ka) / (kb - ka);
                    Source::Triangle {
                        nodes: [id(i, ja, l), id(i, jb, l), id(i, ja, l)],
                        weights: [1.0 - w, w, 0.0],
                    }
                }
            };
            for i in 0..nr1 {
                let s = src(i);
                exact += usize::from(matches!(s, Source::Node(_)));
                sources.push(s);
            }
        }
    }
    // The swept mesh numbers (i, j, l) as `id`: sources were pushed in that order.
    Ok(AnnulusZone {
        mesh,
        radii,
        angles,
        zs,
        step: 2.0 * PI / o.sectors as f64,
        sources,
        exact_nodes: exact,
    })
}

/// The stations, rings and layers of [`annulus_zone`] without the mesh:
/// `(stations, rings, layers)`, for a size estimate.
///
/// # Errors
/// As [`annulus_zone`].
pub fn annulus_zone_counts(o: &AnnulusZoneOptions) -> Result<(usize, usize, usize), MeshError> {
    let (ks, radii, zs) = layout(o)?;
    Ok((ks.len(), radii.len() - 1, zs.len() - 1))
}

/// The rim nodes at the zone's own pitch, along the rim and across it: the stations
/// within the zone's width and the layers' boundaries within its axial half-width (every
/// boundary without one), for a size estimate.
///
/// # Errors
/// As [`annulus_zone`].
pub fn annulus_zone_fine_rim(o: &AnnulusZoneOptions) -> Result<(usize, usize), MeshError> {
    let (ks, _, zs) = layout(o)?;
    let nf = o.zone_sectors;
    let n = ks.len();
    // A station next to one a lattice step away (round the rim).
    let along = (0..n)
        .filter(|&i| {
            let next = (ks[(i + 1) % n] + nf - ks[i]) % nf;
            let prev = (ks[i] + nf - ks[(i + n - 1) % n]) % nf;
            next == 1 || prev == 1
        })
        .count();
    let sf = o.radius * 2.0 * PI / nf as f64;
    let across = match o.axial {
        None => zs.len(),
        Some(_) => (0..zs.len())
            .filter(|&i| {
                let near = |j: usize| ((zs[i] - zs[j]).abs() - sf).abs() < 1e-6 * sf;
                (i > 0 && near(i - 1)) || (i + 1 < zs.len() && near(i + 1))
            })
            .count(),
    };
    Ok((along, across))
}

/// The stations' lattice indices, the rings' radii and the layers' boundaries (module
/// docs), checked.
#[allow(clippy::type_complexity)]
fn layout(o: &AnnulusZoneOptions) -> Result<(Vec<usize>, Vec<f64>, Vec<f64>), MeshError> {
    for (name, l) in [
        ("bore", o.bore),
        ("radius", o.radius),
        ("thickness", o.thickness),
        ("zone_width", o.zone_width),
    ] {
        if !(l.is_finite() && l > 0.0) {
            return Err(MeshError::InvalidLength { name, value: l });
        }
    }
    if o.bore >= o.radius {
        return Err(MeshError::OutOfRange {
            name: "bore (a share of the radius)",
            value: o.bore / o.radius,
            min: 0.0,
            max: 1.0,
        });
    }
    for (name, n) in [("rings", o.rings), ("layers", o.layers)] {
        if n == 0 {
            return Err(MeshError::InvalidCount { name, value: n });
        }
    }
    if o.sectors < 8 {
        return Err(MeshError::CountBelow {
            name: "sectors",
            value: o.sectors,
            min: 8,
        });
    }
    let nf = o.zone_sectors;
    let ratio = nf / o.sectors;
    if nf < o.sectors || nf % o.sectors != 0 || !ratio.is_power_of_two() {
        return Err(MeshError::OutOfRange {
            name: "zone_sectors (the sectors times 1, 2, 4, ...)",
            value: nf as f64,
            min: o.sectors as f64,
            max: f64::INFINITY,
        });
    }
    let levels = ratio.trailing_zeros();
    let dl = 2.0 * PI / nf as f64;
    let k0 = (0.5 * o.zone_width / dl).ceil() as usize;
    let outer_edge = (0..levels).fold(k0, |e, l| e + (2 << (l + 1)));
    if k0 < 1 || 4 * (outer_edge + ratio) > nf {
        return Err(MeshError::OutOfRange {
            name: "zone_width (rad: two of the zone's pitches at least, and with its transitions within half the rim)",
            value: o.zone_width,
            min: 2.0 * dl,
            max: PI,
        });
    }
    let ks: Vec<usize> = (0..nf)
        .filter(|&k| k % pitch(k.min(nf - k), k0, levels) == 0)
        .collect();
    let radii = ring_radii(o, dl)?;
    let zs = layer_bounds(o, o.radius * dl)?;
    Ok((ks, radii, zs))
}

/// The layers' boundaries along the axle (module docs), `sf` the zone's pitch.
fn layer_bounds(o: &AnnulusZoneOptions, sf: f64) -> Result<Vec<f64>, MeshError> {
    let t = o.thickness;
    let Some(w) = o.axial else {
        return Ok((0..=o.layers)
            .map(|k| t * k as f64 / o.layers as f64)
            .collect());
    };
    let half = 0.5 * t;
    let core = (w / sf).ceil();
    if !(w.is_finite() && w > 0.0 && core * sf < half) {
        return Err(MeshError::OutOfRange {
            name: "zone_axial (m: the refined half-width about the mid-plane, in whole pitches within half the thickness)",
            value: w,
            min: 0.0,
            max: half - sf,
        });
    }
    let g = o.growth.unwrap_or(1.25);
    let outer = (t / o.layers as f64).max(sf);
    // Offsets from the mid-plane: the core's cells, then growing ones up to the face.
    let mut d: Vec<f64> = (0..=core as usize).map(|k| sf * k as f64).collect();
    let mut size = sf;
    loop {
        size = (size * g).min(outer);
        let last = d[d.len() - 1];
        if last + size >= half {
            // The face: a remainder under half a cell joins the last cell.
            if half - last < 0.5 * size && d.len() > core as usize + 1 {
                d.pop();
            }
            d.push(half);
            break;
        }
        d.push(last + size);
        if d.len() > 100_000 {
            return Err(MeshError::TooLarge {
                name: "zone_axial",
                value: d.len(),
                max: 100_000,
            });
        }
    }
    let mut zs: Vec<f64> = d.iter().rev().map(|x| half - x).collect();
    zs.extend(d[1..].iter().map(|x| half + x));
    Ok(zs)
}

/// The rings' radii from the bore to the rim (module docs).
fn ring_radii(o: &AnnulusZoneOptions, dl: f64) -> Result<Vec<f64>, MeshError> {
    let depth = o.radius - o.bore;
    let outer = depth / o.rings as f64;
    let Some(g) = o.growth else {
        return Ok((0..=o.rings)
            .map(|i| o.bore + depth * i as f64 / o.rings as f64)
            .collect());
    };
    if !(g > 1.0 && g <= 2.0) {
        return Err(MeshError::OutOfRange {
            name: "growth",
            value: g,
            min: 1.0,
            max: 2.0,
        });
    }
    // From the rim inwards: graded while below the outer size and within half the depth.
    if let Some(l) = o.depth {
        if !(l.is_finite() && l > 0.0) {
            return Err(MeshError::InvalidLength {
                name: "zone_depth",
                value: l,
            });
        }
    }
    let sf = o.radius * dl;
    let mut from_rim = vec![0.0];
    let mut t = sf;
    while t < outer && from_rim[from_rim.len() - 1] + t < 0.5 * depth {
        let last = from_rim[from_rim.len() - 1] + t;
        from_rim.push(last);
        t *= g;
        if let Some(l) = o.depth {
            t = t.min(sf * (1.0 + (last / l).powi(2)));
        }
        if from_rim.len() > 100_000 {
            return Err(MeshError::TooLarge {
                name: "zone_depth",
                value: from_rim.len(),
                max: 100_000,
            });
        }
    }
    let graded = from_rim[from_rim.len() - 1];
    let rest = ((depth - graded) / outer).ceil().max(1.0) as usize;
    for i in 1..=rest {
        from_rim.push(graded + (depth - graded) * i as f64 / rest as f64);
    }
    let mut radii: Vec<f64> = from_rim.iter().rev().map(|d| o.radius - d).collect();
    radii[0] = o.bore;
    Ok(radii)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(zone_sectors: usize, growth: Option<f64>) -> AnnulusZoneOptions {
        AnnulusZoneOptions {
            bore: 0.04,
            radius: 0.1,
            thickness: 0.01,
            rings: 6,
            sectors: 48,
            layers: 1,
            zone_sectors,
            zone_width: 20f64.to_radians(),
            growth,
            depth: None,
            axial: None,
        }
    }

    /// The fine rim counted for the cost estimate is the built zone's: the stations with a
    /// neighbour at the zone's pitch, and the layers' boundaries with a neighbour at it.
    #[test]
    fn the_fine_rim_is_the_built_zones_finest_pitch() {
        for (sectors, axial) in [(384, Some(2.5e-3)), (768, Some(3.5e-3)), (384, None)] {
            let mut o = options(sectors, Some(1.3));
            o.thickness = 0.04;
            o.layers = 8;
            o.axial = axial;
            let z = annulus_zone(&o).unwrap();
            let fine = |x: &[f64], pitch: f64| {
                (0..x.len())
                    .filter(|&i| {
                        let near = |j: usize| ((x[i] - x[j]).abs() - pitch).abs() < 1e-9 * pitch;
                        (i > 0 && near(i - 1)) || (i + 1 < x.len() && near(i + 1))
                    })
                    .count()
            };
            let dl = 2.0 * PI / sectors as f64;
            let along = fine(&z.angles, dl);
            let across = match axial {
                Some(_) => fine(&z.zs, 0.1 * dl),
                None => z.zs.len(),
            };
            assert_eq!(annulus_zone_fine_rim(&o).unwrap(), (along, across));
            assert!(along > 10 && across > 2, "{along} {across}");
        }
    }

    /// Across the width the layers are the zone's pitch within the half-width asked, then
    /// grow by the growth up to the outer size, symmetric about the mid-plane, from face to
    /// face; the relocation's map covers every layer.
    #[test]
    fn the_layers_are_graded_about_the_mid_plane() {
        let mut o = options(384, Some(1.3));
        o.thickness = 0.04;
        o.layers = 8;
        o.axial = Some(2.5e-3);
        let z = annulus_zone(&o).unwrap();
        let sf = 0.1 * 2.0 * PI / 384.0;
        let (first, last) = (z.zs[0], z.zs[z.zs.len() - 1]);
        assert_eq!((first, last), (0.0, 0.04));
        let n = z.zs.len();
        let widths: Vec<f64> = z.zs.windows(2).map(|w| w[1] - w[0]).collect();
        for (k, w) in widths.iter().enumerate() {
            // Symmetric about the mid-plane.
            assert!((w - widths[n - 2 - k]).abs() < 1e-15, "{widths:?}");
            let mid = 0.5 * (z.zs[k] + z.zs[k + 1]) - 0.02;
            if mid.abs() < 2.5e-3 {
                assert!((w - sf).abs() < 1e-15, "{k}: {w} in the core");
            } else {
                assert!(
                    *w <= 1.5 * 0.005 + 1e-15 && *w >= sf * (1.0 - 1e-12),
                    "{k}: {w}"
                );
            }
        }
        // Growing outward, by at most the growth (the face's last cell may take a rest).
        let h = widths.len() / 2;
        for k in h..widths.len() - 2 {
            assert!(
                widths[k + 1] >= widths[k] * (1.0 - 1e-12)
                    && widths[k + 1] <= 1.3 * widths[k] * (1.0 + 1e-12),
                "{widths:?}"
            );
        }
        let counts = annulus_zone_counts(&o).unwrap();
        assert_eq!(counts.2, n - 1);
        assert_eq!(z.sources.len(), z.mesh.n_nodes());
        // Wider than the wheel: refused, naming it.
        o.axial = Some(0.03);
        let e = annulus_zone(&o).unwrap_err().to_string();
        assert!(e.contains("zone_axial"), "{e}");
    }

    /// Without refinement every station is on the outer pitch and a relocation is a pure
    /// relabelling: every node's source is a node, the one a sector ahead at the same ring
    /// and layer, at the place one step further round.
    #[test]
    fn an_unrefined_zone_relocates_onto_nodes() {
        let z = annulus_zone(&options(48, None)).unwrap();
        assert_eq!(z.angles.len(), 48);
        assert_eq!(z.exact_nodes, z.sources.len());
        let x = z.mesh.reference_positions();
        for (n, s) in z.sources.iter().enumerate() {
            let Source::Node(m) = *s else { panic!() };
            // Node m turned by -step lands on node n.
            let (c, si) = (z.step.cos(), z.step.sin());
            let p = [
                c * x[3 * m] + si * x[3 * m + 1],
                -si * x[3 * m] + c * x[3 * m + 1],
            ];
            assert!((p[0] - x[3 * n]).abs() < 1e-12 && (p[1] - x[3 * n + 1]).abs() < 1e-12);
        }
    }

    /// The stations: the zone's pitch over the zone's width, doubling outwards to the outer
    /// pitch, symmetric about the centre; the interpolated sources' weights place the old
    /// point at its angle; the outer stations relocate onto nodes.
    #[test]
    fn the_zone_is_fine_under_the_base_and_interpolates_where_it_moves() {
        let z = annulus_zone(&options(48 * 8, Some(1.25))).unwrap();
        let dl = 2.0 * PI / 384.0;
        // Symmetric about -pi/2.
        let rel: Vec<f64> = z.angles.iter().map(|a| a + 0.5 * PI).collect();
        let mut back: Vec<f64> = rel
            .iter()
            .map(|a| if *a == 0.0 { 0.0 } else { 2.0 * PI - a })
            .collect();
        back.sort_by(f64::total_cmp);
        for (a, b) in rel.iter().zip(&back) {
            assert!((a - b).abs() < 1e-9, "{a} {b}");
        }
        // The zone's pitch over its width, the outer pitch far from it.
        assert!((rel[1] - dl).abs() < 1e-12);
        let gaps: Vec<f64> = rel.windows(2).map(|w| (w[1] - w[0]) / dl).collect();
        assert!(gaps
            .iter()
            .all(|g| [1.0, 2.0, 4.0, 8.0].iter().any(|p| (g - p).abs() < 1e-9)));
        let fine = gaps.iter().filter(|g| (*g - 1.0).abs() < 1e-9).count();
        assert!(fine as f64 * dl >= 0.5 * 20f64.to_radians());
        assert!((gaps[gaps.len() / 2] - 8.0).abs() < 1e-9);
        // The rings: the first as thick as the zone's pitch, the last at the outer size.
        let r = &z.radii;
        let t0 = r[r.len() - 1] - r[r.len() - 2];
        assert!((t0 / (0.1 * dl) - 1.0).abs() < 1e-9, "{t0}");
        assert_eq!(r[0], 0.04);
        assert!(r.windows(2).all(|w| w[1] - w[0] <= 0.01 + 1e-12));
        // Interpolated sources: the old point's angle.
        let nr1 = r.len();
        let nt = z.angles.len();
        let x = z.mesh.reference_positions();
        let angle = |n: usize| x[3 * n + 1].atan2(x[3 * n]);
        let mut interpolated = 0;
        for (n, s) in z.sources.iter().enumerate().take(nr1 * nt) {
            let want = angle(n) + z.step;
            let got = match *s {
                Source::Node(m) => angle(m),
                Source::Triangle { nodes, weights } => {
                    interpolated += 1;
                    assert_eq!(weights[2], 0.0);
                    let (a, mut b) = (angle(nodes[0]), angle(nodes[1]));
                    if b < a {
                        b += 2.0 * PI;
                    }
                    a + weights[1] * (b - a)
                }
            };
            let d = (got - want).rem_euclid(2.0 * PI);
            assert!(d.min(2.0 * PI - d) < 1e-9, "node {n}: {got} vs {want}");
        }
        assert!(interpolated > 0 && interpolated < nr1 * nt / 4);
    }

    #[test]
    fn bad_zones_are_refused_naming_the_parameter() {
        let e = annulus_zone(&options(48 * 3, None)).unwrap_err();
        assert!(e.to_string().contains("zone_sectors"), "{e}");
        let mut o = options(384, None);
        o.zone_width = 3.5;
        assert!(annulus_zone(&o)
            .unwrap_err()
            .to_string()
            .contains("zone_width"));
        let e = annulus_zone(&options(384, Some(1.0))).unwrap_err();
        assert!(e.to_string().contains("growth"), "{e}");
    }
}
