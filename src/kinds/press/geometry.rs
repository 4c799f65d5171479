//! Where the wheel sits on the rail before the load (the bodies' placement), and the two
//! meshes in the track's frame, joined into one.
//!
//! **Frame**: the rail's ([`crate::mesh::generators::rail3d`]): `x` along the rail, `y`
//! across it toward the field side, `z` up, the origin at the top of the crown of the
//! upright section in the rail's middle; the rail inclined toward the gauge side.
//!
//! **Lateral placement** as in the Manchester benchmark's track (Shackleton and Iwnicki
//! 2008; CONTACT's `mbench_a22_right.inp`: flange-back distance 1360 mm, the taping line
//! 70 mm outside the flange's back, gauge 1435 mm measured 14 mm below the top of the
//! rails): the wheel's taping line is `(1360 / 2 + 70) - 1435 / 2 = 32.5 mm` outside the
//! rail's gauge point (its innermost point of the head 14 mm below the top of the inclined
//! rail), plus the lateral shift.
//!
//! **Vertical placement**: the wheel's lowest line `z = z_axle - (R + p(y - y_taping))`
//! against the inclined head's surface, sampled every 5 um of the rail profile: the axle is
//! set so that the least vertical gap is 0, where the first contact is. Around it the gap's
//! second derivative across the rail (a parabola fitted over +-1 mm) is twice Hertz's
//! relative curvature `B`; along the rail the wheel's rolling radius gives `A = 1 / (2 r)`
//! (the rail is straight).

use std::collections::BTreeMap;
use std::f64::consts::PI;

use crate::mesh::generators::{MeshError, RailSpec, WheelSpec};
use crate::mesh::profiles::{uic60_head, Profile};
use crate::mesh::{Cells, Mesh};

/// Height of the gauge point below the top of the rail, m (the Manchester benchmark's
/// `GAUGHT = 14 mm`).
pub const GAUGE_HEIGHT: f64 = 0.014;
/// The wheel's taping line outside the rail's gauge point at no lateral shift, m:
/// `(1360 / 2 + 70) - 1435 / 2` mm (module docs).
pub const TAPING_OVER_GAUGE: f64 = 0.0325;

/// The bodies' placement before the load (module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Placement {
    /// `y` of the wheel's taping line in the track frame, m.
    pub taping_y: f64,
    /// Height of the axle, m.
    pub axle_z: f64,
    /// The first contact point, m.
    pub contact: [f64; 3],
    /// The contact's lateral coordinate on the rail's profile (before the inclination), m.
    pub rail_y: f64,
    /// The contact's lateral coordinate on the wheel's profile (from the taping line), m.
    pub wheel_y: f64,
    /// The wheel's rolling radius there, m.
    pub rolling_radius: f64,
    /// Hertz's relative curvatures `A` (along the rail, `1 / (2 r)`) and `B` (across, half
    /// the gap's second derivative), 1/m; `B <= 0`: conforming, no Hertz ellipse.
    pub curvatures: [f64; 2],
    /// The rail surface's upward unit normal at the contact.
    pub normal: [f64; 3],
}

/// Points of the inclined head's surface, `(s, y, z)`: the profile's own lateral
/// coordinate and the track frame's.
fn head_points(inclination: f64) -> Vec<[f64; 3]> {
    let head = uic60_head();
    let (a, b) = head.domain();
    let (sa, ca) = inclination.atan().sin_cos();
    let n = ((b - a) / 5e-6).ceil() as usize;
    (0..=n)
        .map(|k| {
            let s = a + (b - a) * k as f64 / n as f64;
            let h = head.height(s).unwrap_or(0.0);
            [s, s * ca - h * sa, s * sa + h * ca]
        })
        .collect()
}

/// The placement of a wheel of nominal radius `radius` and profile `tread` shifted
/// `lateral` (m, toward the field side) on the UIC60 rail inclined by `inclination`
/// (module docs). `None` when no point of the head lies under the tread.
pub fn place(tread: &Profile, radius: f64, inclination: f64, lateral: f64) -> Option<Placement> {
    let pts = head_points(inclination);
    let top = pts.iter().map(|p| p[2]).fold(f64::NEG_INFINITY, f64::max);
    let gauge_y = pts
        .iter()
        .filter(|p| p[2] >= top - GAUGE_HEIGHT)
        .map(|p| p[1])
        .fold(f64::INFINITY, f64::min);
    let taping_y = gauge_y + TAPING_OVER_GAUGE + lateral;
    // The wheel's lowest line minus the head, with the axle at 0.
    let gap = |p: &[f64; 3]| tread.height(p[1] - taping_y).map(|h| -(radius + h) - p[2]);
    let (k, m) = pts
        .iter()
        .enumerate()
        .filter_map(|(k, p)| gap(p).map(|g| (k, g)))
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    let c = pts[k];
    // A parabola g = c0 + c1 t + c2 t^2 fitted over |t| <= 1 mm, t = y - y_c.
    let (mut s, mut r) = ([[0.0; 3]; 3], [0.0; 3]);
    for p in &pts {
        let t = p[1] - c[1];
        if t.abs() > 1e-3 {
            continue;
        }
        let Some(g) = gap(p) else { continue };
        let row = [1.0, t, t * t];
        for i in 0..3 {
            r[i] += row[i] * (g - m);
            for j in 0..3 {
                s[i][j] += row[i] * row[j];
            }
        }
    }
    let mut flat: Vec<f64> = s.iter().flatten().copied().collect();
    crate::linalg::dense_solve_in_place(&mut flat, &mut r, 3);
    let wheel_y = c[1] - taping_y;
    let rolling_radius = radius + tread.height(wheel_y).unwrap_or(0.0);
    // The head's slope at the contact (the neighbours' chord), its upward normal.
    let (p0, p1) = (pts[k.saturating_sub(1)], pts[(k + 1).min(pts.len() - 1)]);
    let (dy, dz) = (p1[1] - p0[1], p1[2] - p0[2]);
    let l = dy.hypot(dz);
    Some(Placement {
        taping_y,
        axle_z: -m,
        contact: [0.0, c[1], c[2]],
        rail_y: c[0],
        wheel_y,
        rolling_radius,
        curvatures: [0.5 / rolling_radius, r[2]],
        normal: [0.0, -dz / l, dy / l],
    })
}

/// The sector `|theta| <= half_angle` of the wheel `mesh` (axle along `y` through the
/// origin, the contact at `theta = 0` under it), moved by `shift`: its cells whose nodes
/// all lie in the sector, renumbered; the node sets kept within it, and `"cut"`: the nodes
/// on the sector's two end planes (the last node planes kept).
pub fn wheel_sector(mesh: &Mesh, half_angle: f64, shift: [f64; 3]) -> Mesh {
    let angle = |i: usize| {
        let p = mesh.point(i);
        p[0].atan2(-p[2])
    };
    let Cells::Hex8(hexes) = &mesh.cells else {
        return mesh.clone();
    };
    let tol = 1e-9;
    let kept: Vec<[usize; 8]> = hexes
        .iter()
        .filter(|h| h.iter().all(|&i| angle(i).abs() <= half_angle + tol))
        .copied()
        .collect();
    let mut new = vec![usize::MAX; mesh.n_nodes()];
    let mut coords = Vec::new();
    let mut count = 0;
    for h in &kept {
        for &i in h {
            if new[i] == usize::MAX {
                new[i] = count;
                count += 1;
                let p = mesh.point(i);
                coords.extend([p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]]);
            }
        }
    }
    let cells: Vec<[usize; 8]> = kept.iter().map(|h| h.map(|i| new[i])).collect();
    let edge = (0..mesh.n_nodes())
        .filter(|&i| new[i] != usize::MAX)
        .map(|i| angle(i).abs())
        .fold(0.0f64, f64::max);
    let mut sets = BTreeMap::new();
    for (name, nodes) in &mesh.node_sets {
        let mut v: Vec<usize> = nodes
            .iter()
            .filter(|&&i| new[i] != usize::MAX)
            .map(|&i| new[i])
            .collect();
        v.sort_unstable();
        sets.insert(name.clone(), v);
    }
    let mut cut: Vec<usize> = (0..mesh.n_nodes())
        .filter(|&i| new[i] != usize::MAX && angle(i).abs() >= edge - 1e-9 && edge < PI - 1e-9)
        .map(|i| new[i])
        .collect();
    cut.sort_unstable();
    sets.insert("cut".to_string(), cut);
    Mesh::new(3, coords, Cells::Hex8(cells), sets)
}

/// Two hexahedral meshes as one: `b`'s nodes after `a`'s (its cells and node sets
/// renumbered, its sets prefixed `rail.`, `a`'s `wheel.`).
pub fn join(a: &Mesh, b: &Mesh) -> Mesh {
    let off = a.n_nodes();
    let mut coords = a.coords.clone();
    coords.extend_from_slice(&b.coords);
    let mut cells = Vec::new();
    if let Cells::Hex8(h) = &a.cells {
        cells.extend_from_slice(h);
    }
    if let Cells::Hex8(h) = &b.cells {
        cells.extend(h.iter().map(|c| c.map(|i| i + off)));
    }
    let mut sets = BTreeMap::new();
    for (k, v) in &a.node_sets {
        sets.insert(format!("wheel.{k}"), v.clone());
    }
    for (k, v) in &b.node_sets {
        sets.insert(
            format!("rail.{k}"),
            v.iter().map(|&i| i + off).collect::<Vec<_>>(),
        );
    }
    Mesh::new(3, coords, Cells::Hex8(cells), sets)
}

/// The wheel's and the rail's mesh specs for a contact zone of cells of `size` (m) over
/// `along` x `across` (half-lengths, m) about the placement `at`; `growth` the ratio of
/// successive cells away from it; the rest of `wheel` and `rail` as given.
///
/// # Errors
/// [`MeshError`] naming the first field out of its range.
pub fn mesh_specs(
    (mut wheel, mut rail): (WheelSpec, RailSpec),
    at: &Placement,
    size: f64,
    (along, across): (f64, f64),
    growth: f64,
) -> Result<(WheelSpec, RailSpec), MeshError> {
    wheel.tread_size = size;
    wheel.tread_band = at.wheel_y.abs() + across;
    wheel.fine_arc = along / at.rolling_radius;
    wheel.fine_pitch = size / at.rolling_radius;
    wheel.growth = growth;
    rail.head_size = size;
    rail.head_band = across;
    rail.focus_y = at.rail_y;
    rail.fine_size = size;
    rail.fine_half_length = along;
    rail.growth = growth;
    wheel.validate()?;
    rail.validate()?;
    Ok((wheel, rail))
}
