//! The graded disk ([`disk_graded`]): rings whose spacing grows from the rim inwards by a
//! ratio, each ring's node count chosen to keep the triangles near equilateral, consecutive
//! rings zipped into triangles; no rotational symmetry (split from [`super`]).

use super::{check_length, MeshError, MAX_NODES};
use crate::mesh::{Cells, Mesh};
use std::collections::BTreeMap;

/// Options of [`disk_graded`]. Every field has a default ([`DiskOptions::default`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiskOptions {
    /// Ratio of successive radial spacings between rings, from the rim inwards
    /// (dimensionless, in `[1, 2]`; `1` keeps the spacing of the rim all the way to the
    /// centre). Default [`DiskOptions::DEFAULT_GRADING`] (1.15): about 40 degrees for the
    /// smallest angle and fewer than 8 nodes per rim node up to 1,440 rim nodes. The
    /// generator adjusts it slightly so that a whole number of rings fills the radius.
    pub grading: f64,
    /// A hub of this radius (m), clamped by the wheel's support: `Some(r_h)` makes the mesh
    /// the annulus between a ring on the hub's circle and the rim (no node inside the hub,
    /// whose material the clamp holds still), so that the clamp holds exactly the circle
    /// of radius `r_h`; `None` (the default) meshes the whole disk down to its centre node.
    pub hub: Option<f64>,
}

impl DiskOptions {
    /// Default [`DiskOptions::grading`] (dimensionless): 1.15.
    pub const DEFAULT_GRADING: f64 = 1.15;
    /// Largest [`DiskOptions::grading`] accepted (dimensionless): 2.
    pub const MAX_GRADING: f64 = 2.0;
}

impl Default for DiskOptions {
    fn default() -> Self {
        DiskOptions {
            grading: Self::DEFAULT_GRADING,
            hub: None,
        }
    }
}

/// The golden angle `pi (3 - sqrt 5)`, rad (137.5 degrees): ring `k` of [`disk_graded`] is
/// turned by `k` times it.
const GOLDEN_ANGLE: f64 = 2.399_963_229_728_653;

/// `1 + x + ... + x^(m-1)`, accurate near `x = 1`.
fn geometric_sum(x: f64, m: usize) -> f64 {
    let d = x - 1.0;
    let mf = m as f64;
    if d.abs() < 1e-12 {
        mf + 0.5 * mf * (mf - 1.0) * d
    } else {
        (mf * d.ln_1p()).exp_m1() / d
    }
}

fn gcd(mut a: usize, mut b: usize) -> usize {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// The rings of [`disk_graded`]: radii `r_0 = 0 < ... < r_m = radius` and node counts
/// (`1` for the centre, `rim_nodes` for the rim).
struct RingLayout {
    radii: Vec<f64>,
    counts: Vec<usize>,
}

/// The ring radii of the whole disk (ring 0 the centre): `m` gaps from the rim inwards,
/// the first the rim pitch `h`, each `g` times the one outside it, `g` adjusted so that they
/// fill the radius ([`disk_graded`], Rings).
fn disk_ring_radii(radius: f64, rim_nodes: usize, grading: f64) -> Vec<f64> {
    // Radius in units of the rim pitch h = 2 pi R / n.
    let q = rim_nodes as f64 / std::f64::consts::TAU;
    // Rings whose gaps h, h g, h g^2, ... add up to the radius: h (g^m - 1) / (g - 1) = R.
    let m_exact = if grading == 1.0 {
        q
    } else {
        (q * (grading - 1.0)).ln_1p() / (grading - 1.0).ln_1p()
    };
    let m = if q <= 1.0 {
        1
    } else {
        (m_exact.round() as usize).max(1)
    };
    // The ratio g' that makes m whole gaps, the first (at the rim) exactly h, fill the
    // radius: sum_{j<m} g'^j = q, on (0, q - 1] for m >= 2 (bisection: the sum grows with g').
    let ratio = if m == 1 {
        1.0
    } else {
        let (mut lo, mut hi) = (0.0_f64, q - 1.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if geometric_sum(mid, m) > q {
                hi = mid;
            } else {
                lo = mid;
            }
            if hi - lo <= 1e-15 * hi {
                break;
            }
        }
        0.5 * (lo + hi)
    };
    // Ring k lies m - k gaps inside the rim.
    (0..=m)
        .map(|k| {
            if k == 0 {
                0.0
            } else if k == m {
                radius
            } else {
                radius * (1.0 - geometric_sum(ratio, m - k) / q)
            }
        })
        .collect()
}

/// The ring radii of the annulus outside a hub of radius `hub` (ring 0 stands for the
/// centre and is no node; ring 1 is the hub's circle): gaps from the rim inwards, the first
/// the rim pitch `h`, each `g` times the one outside it, but graded down again towards the
/// hub, at most `s_hub + (g - 1) (r - hub)` at radius `r` with `s_hub` a sixteenth of the
/// hub's circumference (so that the hub's circle carries about 16 nodes and the clamp is a
/// circle, not a polygon of a few sides); the inner gaps are scaled so that the last ends on
/// the hub.
fn hub_ring_radii(radius: f64, h: f64, grading: f64, hub: f64) -> Vec<f64> {
    let band = radius - hub;
    let s_hub = std::f64::consts::TAU * hub / 16.0;
    let cap = |r: f64| (s_hub + (grading - 1.0) * (r - hub)).max(h.min(s_hub));
    let mut gaps = vec![h.min(band)];
    let mut outer = radius - gaps[0];
    let mut g = h;
    while outer > hub {
        g = (g * grading).min(cap(outer));
        if outer - 0.5 * g <= hub {
            break;
        }
        gaps.push(g);
        outer -= g;
    }
    // Scale the inner gaps so that the band ends exactly on the hub.
    if gaps.len() > 1 {
        let inner: f64 = gaps[1..].iter().sum();
        let scale = (band - gaps[0]) / inner;
        for x in &mut gaps[1..] {
            *x *= scale;
        }
    }
    let mut radii = vec![radius];
    for x in &gaps {
        let last = *radii.last().unwrap_or(&radius);
        radii.push(last - x);
    }
    let n = radii.len();
    radii[n - 1] = hub;
    radii.push(0.0);
    radii.reverse();
    radii
}

fn graded_rings(
    radius: f64,
    rim_nodes: usize,
    grading: f64,
    hub: f64,
) -> Result<RingLayout, MeshError> {
    let too_large = || MeshError::TooLarge {
        name: "rim_nodes",
        value: rim_nodes,
        max: MAX_NODES,
    };
    if rim_nodes >= MAX_NODES {
        return Err(too_large());
    }
    let h = std::f64::consts::TAU * radius / rim_nodes as f64;
    let radii: Vec<f64> = if hub > 0.0 {
        hub_ring_radii(radius, h, grading, hub)
    } else {
        disk_ring_radii(radius, rim_nodes, grading)
    };
    let m = radii.len() - 1;
    if m >= MAX_NODES {
        return Err(too_large());
    }
    let r = |k: usize| radii[k];
    // Node counts, from the rim inwards, with the total checked before anything is stored.
    let mut counts = vec![0_usize; m + 1];
    counts[0] = 1;
    counts[m] = rim_nodes;
    let mut total = 1 + rim_nodes;
    for k in (1..m).rev() {
        let (r_in, r_k, r_out) = (r(k - 1), r(k), r(k + 1));
        // Tangential spacing: the geometric mean of the gaps on either side (on the hub's
        // circle, the gap outside it: inside is no mesh).
        let spacing = if hub > 0.0 && k == 1 {
            r_out - r_k
        } else {
            ((r_k - r_in) * (r_out - r_k)).sqrt()
        };
        let c = (std::f64::consts::TAU * r_k / spacing).round();
        let c = if c.is_finite() && c >= 3.0 {
            c as usize
        } else {
            3
        };
        counts[k] = c;
        total = total
            .checked_add(c)
            .filter(|&t| t <= MAX_NODES)
            .ok_or_else(too_large)?;
    }
    // No rotation but the identity may map the mesh onto itself: if all rings share a
    // factor, the innermost ring takes the next count coprime to the rim's.
    if m >= 2 && counts[1..].iter().fold(0, |g, &c| gcd(g, c)) > 1 {
        while gcd(counts[1], rim_nodes) > 1 {
            counts[1] += 1;
        }
    }
    Ok(RingLayout {
        radii: (0..=m).map(r).collect(),
        counts,
    })
}

/// Node `i` of the flat planar coordinates `coords`.
fn xy(coords: &[f64], i: usize) -> &[f64] {
    &coords[2 * i..2 * i + 2]
}

/// Signed area of the triangle `t` of the flat planar coordinates `coords`.
pub(super) fn signed_area(coords: &[f64], t: [usize; 3]) -> f64 {
    let [a, b, c] = t.map(|i| xy(coords, i));
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Triangulates the annulus between an inner ring (`a >= 2` nodes from `inner`, first node
/// at angle `inner_angle`) and an outer ring (`b` nodes from `outer`) of the flat planar
/// coordinates `coords`, counter-clockwise: `a + b` triangles.
///
/// The zipper starts on the edge from the inner ring's first node to the outer node nearest
/// in angle, and walks around: each step adds the triangle that advances along one ring,
/// the one whose new edge across the annulus is the shorter (ties: the outer ring), unless
/// that triangle would not have a positive area and the other would.
fn zip_rings(
    coords: &[f64],
    (inner, a, inner_angle): (usize, usize, f64),
    (outer, b): (usize, usize),
    tris: &mut Vec<[usize; 3]>,
) {
    let ia = |i: usize| inner + i % a;
    let j0 = (0..b)
        .min_by(|&x, &y| {
            let d = |j: usize| {
                let p = xy(coords, outer + j);
                ((p[1].atan2(p[0]) - inner_angle + std::f64::consts::PI)
                    .rem_euclid(std::f64::consts::TAU)
                    - std::f64::consts::PI)
                    .abs()
            };
            d(x).total_cmp(&d(y))
        })
        .unwrap_or(0);
    let ob = |j: usize| outer + (j0 + j) % b;
    let (mut i, mut j) = (0, 0);
    while i < a || j < b {
        let advance_outer = if i == a {
            true
        } else if j == b {
            false
        } else {
            let t_out = [ia(i), ob(j), ob(j + 1)];
            let t_in = [ia(i), ob(j), ia(i + 1)];
            let shorter_outer = distance(xy(coords, ia(i)), xy(coords, ob(j + 1)))
                <= distance(xy(coords, ia(i + 1)), xy(coords, ob(j)));
            let (ok_out, ok_in) = (
                signed_area(coords, t_out) > 0.0,
                signed_area(coords, t_in) > 0.0,
            );
            if shorter_outer {
                ok_out || !ok_in
            } else {
                !ok_in && ok_out
            }
        };
        if advance_outer {
            tris.push([ia(i), ob(j), ob(j + 1)]);
            j += 1;
        } else {
            tris.push([ia(i), ob(j), ia(i + 1)]);
            i += 1;
        }
    }
}

/// A disk of radius `radius` (m) refined towards the rim, with exactly `rim_nodes` nodes on
/// the rim and no rotational symmetry: unlike [`super::disk_rings`], whose six-fold pattern shows
/// in rolling results, no rotation about the centre but the identity maps it onto itself
/// (when it has at least one ring between the centre and the rim, i.e. from 10 rim nodes on
/// with the default grading; below that it is a fan of the centre and the rim).
///
/// **Rings.** A centre node (ring 0, at the origin) and rings `k = 1..=m` of radii
/// `0 < r_1 < ... < r_m = radius`. The gap between the rim and the ring inside it equals the
/// rim pitch `h = 2 pi radius / rim_nodes`, and each gap inwards is `g` times the one
/// outside it (`opts.grading`, [`DiskOptions`]): `radius - r_k = h (1 + g + ... +
/// g^(m-k-1))`. The number of rings `m` is `h (g^m - 1) / (g - 1) = radius` rounded, and
/// `g` is then adjusted (bisection) so that the gaps add up to the radius exactly, the rim
/// gap staying `h` (e.g. 1.15 becomes 1.161, 1.139, 1.145, 1.154, 1.146 for 72, 144, 288,
/// 576, 1,440 rim nodes). Ring `k` carries `n_k = round(2 pi r_k / s_k)` nodes (at least
/// 3), `s_k` the geometric mean of the gaps on either side, so the triangles are about as
/// long as they are wide; the rim carries exactly `rim_nodes`. If all the counts shared a
/// factor `d`, a rotation by `2 pi / d` would map the mesh onto itself: the innermost ring
/// then takes the next larger count coprime to `rim_nodes`.
///
/// **Nodes.** Ring `k` holds its nodes at equal angles `k gamma + 2 pi i / n_k`
/// (`i = 0..n_k`, numbered from the first at or above the positive `x` axis), turned by `k`
/// golden angles `gamma = pi (3 - sqrt 5)` (137.5 degrees, an irrational fraction of a
/// turn). In units of each ring's pitch the turns are then unrelated from ring to ring;
/// turning ring `k` by the same fraction `frac(k phi)` of its own pitch instead would give
/// every pair of neighbour rings the same relative phase on the `x` axis, and their zipper
/// patterns would line up there in a band across the disk. The rim is not turned (its first
/// node is on the positive `x` axis) and lies on the circle of radius `radius`.
///
/// **Triangles.** The centre is joined to ring 1 by a fan; each pair of consecutive rings
/// by a "zipper": from the inner ring's first node and the outer node nearest to it in
/// angle, it walks counter-clockwise around the annulus, each step adding the triangle that
/// advances along one ring, the one whose new edge across the annulus is the shorter (a
/// local Delaunay choice: about 40 degrees for the smallest angle, against 32 to 34 for
/// the rule that advances along the ring whose next node comes first in angle). The
/// annulus between rings of `a` and `b` nodes holds `a + b` triangles; the mesh has
/// `N = 1 + sum n_k` nodes and `2 N - 2 - rim_nodes` counter-clockwise triangles, and its
/// boundary is the rim polygon. Everything is deterministic.
///
/// **Size and quality** (default grading; [`crate::mesh::quality::quality`]): 72, 144, 288, 576
/// and 1,440 rim nodes give 261, 719, 1,715, 3,773 and 10,811 nodes (the nodes per rim node
/// grow slowly, like the logarithm of the rim count, below 8 up to 1,440; a uniform mesh of
/// the same rim, `grading = 1`, has about `rim_nodes^2 / (4 pi)`), with the smallest angle
/// 39.0 to 41.0 degrees, the largest 93.8 to 94.6 and the aspect ratio at most 1.29
/// (39.0 and 95.4 degrees and 1.30 over every rim count from 72 to 2,000). Grading 1, 1.1,
/// 1.3, 1.5 and 2 give 41.9, 41.5, 35.7, 32.9 and 27.3 degrees at worst over those five
/// rims (165,560, 14,196, 6,456, 4,895 and 3,460 nodes at 1,440).
///
/// Nodes are numbered ring by ring (centre first), counter-clockwise within a ring. Node
/// sets: `"centre"` (`[0]`), `"rim"` (the last ring, counter-clockwise from the positive `x`
/// axis) and `"all"`.
///
/// # Errors
/// [`MeshError::InvalidLength`] unless `radius` is finite and positive,
/// [`MeshError::CountBelow`] if `rim_nodes < 3`, [`MeshError::OutOfRange`] unless
/// `opts.grading` is in `[1, 2]`, [`MeshError::TooLarge`] past [`MAX_NODES`] nodes.
pub fn disk_graded(radius: f64, rim_nodes: usize, opts: DiskOptions) -> Result<Mesh, MeshError> {
    check_length("radius", radius)?;
    if rim_nodes < 3 {
        return Err(MeshError::CountBelow {
            name: "rim_nodes",
            value: rim_nodes,
            min: 3,
        });
    }
    let g = opts.grading;
    if !(1.0..=DiskOptions::MAX_GRADING).contains(&g) {
        return Err(MeshError::OutOfRange {
            name: "grading",
            value: g,
            min: 1.0,
            max: DiskOptions::MAX_GRADING,
        });
    }
    let hub = match opts.hub {
        None => 0.0,
        Some(h)
            if h.is_finite()
                && h > 0.0
                && h < radius * (1.0 - 2.0 * std::f64::consts::TAU / rim_nodes as f64) =>
        {
            h
        }
        Some(h) => {
            return Err(MeshError::OutOfRange {
                name: "hub (m)",
                value: h,
                min: 0.0,
                max: radius * (1.0 - 2.0 * std::f64::consts::TAU / rim_nodes as f64),
            })
        }
    };
    let layout = graded_rings(radius, rim_nodes, g, hub)?;
    let m = layout.radii.len() - 1;
    Ok(build_disk(&layout, hub, |k, n_k| {
        // The turn of ring k in units of its own pitch, in [0, 1).
        if k == m {
            0.0
        } else {
            golden_twist(k, n_k)
        }
    }))
}

/// A disk like [`disk_graded`] whose outer band of depth `band` (m) has the rim's rotational
/// symmetry: every ring in it carries the rim's `rim_nodes` nodes, so a rotation by
/// `2 pi / rim_nodes` maps the band onto itself and no polygon order of the rim is coupled
/// to another by the band's mesh (the graded disk's rings, of other counts and turns,
/// couple order `n` to orders `n +- c_k` of the ring counts `c_k`; a load of order `n` on
/// the rim reaches the interior attenuated about as `exp(-n band / radius)`).
///
/// **The band.** From the rim inwards, `b` rings (an even number, at least 2) of `rim_nodes`
/// nodes each at radii `r_j = r_band q^j`, `r_band = radius - band`, the ratio `q` the
/// nearest to `1 + pi sqrt(3) / rim_nodes` that makes `r_b = radius` (each gap `sqrt(3)/2`
/// of the local pitch: near-equilateral triangles), every other ring turned by half a pitch
/// (the rim and the band's inner ring are not turned): each annulus is `2 rim_nodes`
/// triangles of one shape. **Inside it** the graded disk of radius `r_band` with
/// `rim_nodes` nodes on its outer ring (`opts`: grading and hub as for [`disk_graded`]).
/// Node sets as [`disk_graded`]'s.
///
/// # Errors
/// As [`disk_graded`]; [`MeshError::OutOfRange`] unless `band` is at least the rim's pitch
/// and leaves a tenth of the radius (and the hub) inside it.
pub fn disk_symmetric_rim(
    radius: f64,
    rim_nodes: usize,
    band: f64,
    opts: DiskOptions,
) -> Result<Mesh, MeshError> {
    check_length("radius", radius)?;
    if rim_nodes < 3 {
        return Err(MeshError::CountBelow {
            name: "rim_nodes",
            value: rim_nodes,
            min: 3,
        });
    }
    let pitch = std::f64::consts::TAU * radius / rim_nodes as f64;
    let inner_min = (0.1 * radius).max(opts.hub.unwrap_or(0.0) + 2.0 * pitch);
    if !(band.is_finite() && band >= pitch && radius - band >= inner_min) {
        return Err(MeshError::OutOfRange {
            name: "band (m)",
            value: band,
            min: pitch,
            max: radius - inner_min,
        });
    }
    let r_band = radius - band;
    if let Some(h) = opts.hub.filter(|h| !(h.is_finite() && *h > 0.0)) {
        return Err(MeshError::OutOfRange {
            name: "hub (m)",
            value: h,
            min: 0.0,
            max: r_band - 2.0 * pitch,
        });
    }
    // The interior: a graded disk of radius r_band whose outer ring has the rim's count.
    let g = opts.grading;
    if !(1.0..=DiskOptions::MAX_GRADING).contains(&g) {
        return Err(MeshError::OutOfRange {
            name: "grading",
            value: g,
            min: 1.0,
            max: DiskOptions::MAX_GRADING,
        });
    }
    let hub = opts.hub.unwrap_or(0.0);
    let mut layout = graded_rings(r_band, rim_nodes, g, hub)?;
    let m_inner = layout.radii.len() - 1;
    let q0 = 1.0 + std::f64::consts::PI * 3f64.sqrt() / rim_nodes as f64;
    let mut b = ((radius / r_band).ln() / q0.ln()).round().max(2.0) as usize;
    b += b % 2;
    if m_inner + b >= MAX_NODES
        || (m_inner + b)
            .checked_mul(rim_nodes)
            .is_none_or(|t| t > MAX_NODES)
    {
        return Err(MeshError::TooLarge {
            name: "rim_nodes",
            value: rim_nodes,
            max: MAX_NODES,
        });
    }
    let q = (radius / r_band).powf(1.0 / b as f64);
    for j in 1..=b {
        layout.radii.push(if j == b {
            radius
        } else {
            r_band * q.powi(j as i32)
        });
        layout.counts.push(rim_nodes);
    }
    Ok(build_disk(&layout, hub, |k, n_k| {
        if k < m_inner {
            golden_twist(k, n_k)
        } else {
            // The band's inner ring (k = m_inner) and every other ring out to the rim
            // unturned, the others by half a pitch.
            0.5 * ((k - m_inner) % 2) as f64
        }
    }))
}

/// Ring `k`'s turn in units of its own pitch (`n_k` nodes), in `[0, 1)`: `k` golden angles
/// ([`disk_graded`], Nodes).
fn golden_twist(k: usize, n_k: usize) -> f64 {
    (k as f64 * GOLDEN_ANGLE * n_k as f64 / std::f64::consts::TAU).rem_euclid(1.0)
}

/// The mesh of the rings of `layout` (a centre node, or none inside a `hub` > 0), ring `k`
/// of `n_k` nodes turned by `twist(k, n_k)` of its own pitch, consecutive rings zipped
/// ([`disk_graded`], Triangles).
fn build_disk(layout: &RingLayout, hub: f64, twist: impl Fn(usize, usize) -> f64) -> Mesh {
    let RingLayout { radii, counts } = layout;
    let m = radii.len() - 1;
    // With a hub there is no centre node: ring 1 is the first.
    let centre = usize::from(hub == 0.0);
    let n_nodes: usize = counts.iter().sum::<usize>() - (1 - centre);

    let mut coords = Vec::with_capacity(2 * n_nodes);
    let mut starts = Vec::with_capacity(m + 1);
    let mut first_angle = Vec::with_capacity(m + 1);
    if centre == 1 {
        coords.extend([0.0, 0.0]);
    }
    starts.push(0);
    first_angle.push(0.0);
    for k in 1..=m {
        let n_k = counts[k];
        let twist = twist(k, n_k);
        starts.push(coords.len() / 2);
        first_angle.push(std::f64::consts::TAU * twist / n_k as f64);
        for i in 0..n_k {
            let theta = std::f64::consts::TAU * (i as f64 + twist) / n_k as f64;
            coords.extend([radii[k] * theta.cos(), radii[k] * theta.sin()]);
        }
    }

    let mut tris = Vec::with_capacity(2 * n_nodes);
    if centre == 1 {
        for j in 0..counts[1] {
            tris.push([0, starts[1] + j, starts[1] + (j + 1) % counts[1]]);
        }
    }
    for k in 2..=m {
        zip_rings(
            &coords,
            (starts[k - 1], counts[k - 1], first_angle[k - 1]),
            (starts[k], counts[k]),
            &mut tris,
        );
    }

    let mut node_sets = BTreeMap::new();
    if centre == 1 {
        node_sets.insert("centre".to_string(), vec![0]);
    } else {
        node_sets.insert(
            "hub".to_string(),
            (starts[1]..starts[1] + counts[1]).collect(),
        );
    }
    node_sets.insert("rim".to_string(), (starts[m]..n_nodes).collect());
    node_sets.insert("all".to_string(), (0..n_nodes).collect());

    Mesh::new(2, coords, Cells::Tri3(tris), node_sets)
}
