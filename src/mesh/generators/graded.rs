//! A block graded toward a point of its top face, for a half-space-like body under a point
//! contact: the quarter `[0, lx] x [0, ly] x [-depth, 0]` of a larger block (its faces
//! `x = 0` and `y = 0` the symmetry planes through the contact point, the top `z = 0`).
//!
//! Along each axis the cells are `h` wide over the core `[0, core]` (rounded up to whole
//! cells) and then grow geometrically by `ratio` to the face (the last ones scaled so the
//! axis ends on it): the tensor product of three such rulers, as hexahedra or Kuhn's
//! tetrahedra of [`box_mesh`] (linear or quadratic) mapped onto them (the map is linear in
//! each cell, so the mid-edge nodes stay on their edges' midpoints). The cells are straight
//! boxes; away from the core they are long in one direction (a cell at `x` far out and `y`
//! in the core is `h` by the ruler's `dx`), which suits a field that varies on the scale of
//! the distance to the contact.
//!
//! Node sets: those of [`box_mesh`]: `"x0"`, `"y0"` (the symmetry planes), `"z1"` (the top,
//! the contact face), `"z0"` (the bottom), `"x1"`, `"y1"` (the far sides) and `"all"`.

use super::{box_mesh, check_length, MeshError};
use crate::mesh::{CellKind, Mesh};

/// The graded quarter block's dimensions (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GradedBlock {
    /// The cells: [`CellKind::Hex8`], [`CellKind::Tet4`] or [`CellKind::Tet10`].
    pub kind: CellKind,
    /// The extents `[lx, ly, depth]`, m.
    pub extent: [f64; 3],
    /// The core `[cx, cy, cz]` of cells `h` wide (from the contact point along `x`, `y` and
    /// down), m.
    pub core: [f64; 3],
    /// The core's cell size, m.
    pub h: f64,
    /// The growth ratio of neighbouring cells outside the core, in `[1, 2]`.
    pub ratio: f64,
}

/// The ruler of one axis from 0 to `length`: cells `h` wide to `core` (rounded up to whole
/// cells), then growing by `ratio`, the grown ones scaled so the last node is at `length`.
pub fn ruler(length: f64, core: f64, h: f64, ratio: f64) -> Result<Vec<f64>, MeshError> {
    check_length("length", length)?;
    check_length("h", h)?;
    if core.is_nan() || core < 0.0 {
        return Err(MeshError::OutOfRange {
            name: "core",
            value: core,
            min: 0.0,
            max: f64::INFINITY,
        });
    }
    if !(1.0..=2.0).contains(&ratio) {
        return Err(MeshError::OutOfRange {
            name: "ratio",
            value: ratio,
            min: 1.0,
            max: 2.0,
        });
    }
    let cells = |l: f64| (l / h - 1e-9).ceil().max(1.0);
    if cells(length.min(core)) > 1e6 {
        return Err(MeshError::TooLarge {
            name: "core / h",
            value: cells(length.min(core)) as usize,
            max: 1_000_000,
        });
    }
    if core >= length - 0.5 * h {
        let n = cells(length) as usize;
        return Ok((0..=n)
            .map(|i| {
                if i == n {
                    length
                } else {
                    length * i as f64 / n as f64
                }
            })
            .collect());
    }
    let n_core = cells(core) as usize;
    let mut x: Vec<f64> = (0..=n_core).map(|i| h * i as f64).collect();
    let start = h * n_core as f64;
    let rest = length - start;
    // Grown cells h r, h r^2, ... whose sum is nearest `rest`, then scaled onto it.
    let mut sizes = Vec::new();
    let (mut s, mut sum) = (h * ratio, 0.0);
    while sum + 0.5 * s < rest && sizes.len() < 100_000 {
        sizes.push(s);
        sum += s;
        s *= ratio;
    }
    if sizes.is_empty() {
        sizes.push(rest);
        sum = rest;
    }
    let scale = rest / sum;
    let mut at = start;
    let n = sizes.len();
    for (k, s) in sizes.iter().enumerate() {
        at += s * scale;
        x.push(if k + 1 == n { length } else { at });
    }
    Ok(x)
}

/// The graded quarter block of `spec` (module docs).
///
/// # Errors
/// [`MeshError`] naming an extent, core, size or ratio out of range, a kind that is not a
/// solid, or too many nodes.
pub fn graded_block(spec: &GradedBlock) -> Result<Mesh, MeshError> {
    let names = ["lx", "ly", "depth"];
    for (name, l) in names.into_iter().zip(spec.extent) {
        check_length(name, l)?;
    }
    let rulers = [0, 1, 2]
        .map(|a| ruler(spec.extent[a], spec.core[a], spec.h, spec.ratio))
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?;
    let counts = [0, 1, 2].map(|a| rulers[a].len() - 1);
    let mut mesh = box_mesh(spec.kind, [1.0; 3], counts)?;
    for p in mesh.coords.chunks_exact_mut(3) {
        for a in 0..3 {
            // The unit box's coordinate t onto the ruler (the depth's ruler from the top).
            let t = if a == 2 { 1.0 - p[2] } else { p[a] };
            let v = along(&rulers[a], t);
            p[a] = if a == 2 { -v } else { v };
        }
    }
    Ok(mesh)
}

/// The ruler's point at the unit coordinate `t` (linear in each cell).
fn along(r: &[f64], t: f64) -> f64 {
    let n = r.len() - 1;
    let s = (t * n as f64).clamp(0.0, n as f64);
    let i = (s.floor() as usize).min(n - 1);
    let f = s - i as f64;
    if f < 1e-9 {
        r[i]
    } else if f > 1.0 - 1e-9 {
        r[i + 1]
    } else {
        r[i] + f * (r[i + 1] - r[i])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::quality::quality;

    fn spec(kind: CellKind) -> GradedBlock {
        GradedBlock {
            kind,
            extent: [0.1, 0.08, 0.12],
            core: [0.004, 0.003, 0.004],
            h: 5e-4,
            ratio: 1.3,
        }
    }

    /// The rulers: `h` in the core, each grown cell at most `ratio` times its neighbour
    /// (up to the last cells' scaling), ending on the face.
    #[test]
    fn a_ruler_is_fine_in_its_core_and_grows_by_its_ratio() {
        let r = ruler(0.1, 0.004, 5e-4, 1.3).unwrap();
        assert_eq!(r[0], 0.0);
        assert_eq!(*r.last().unwrap(), 0.1);
        for w in r.windows(2).take(8) {
            assert!((w[1] - w[0] - 5e-4).abs() < 1e-15);
        }
        for w in r.windows(3) {
            let q = (w[2] - w[1]) / (w[1] - w[0]);
            assert!(q > 0.7 && q < 1.3 * 1.0 + 1e-9, "{q}");
        }
        // A core past the length: uniform.
        let u = ruler(1.0, 2.0, 0.25, 1.5).unwrap();
        assert_eq!(u, vec![0.0, 0.25, 0.5, 0.75, 1.0]);
        assert!(matches!(
            ruler(1.0, 0.1, 0.01, 2.5),
            Err(MeshError::OutOfRange { name: "ratio", .. })
        ));
        assert!(matches!(
            ruler(1.0, -0.1, 0.01, 1.2),
            Err(MeshError::OutOfRange { name: "core", .. })
        ));
    }

    /// The block's volume is `lx ly depth` (the cells tile it: an invariant), no cell is
    /// inverted or degenerate, and the cells at the contact point are `h` cubes.
    #[test]
    fn the_graded_block_has_its_volume_and_no_bad_cell() {
        for kind in [CellKind::Hex8, CellKind::Tet4, CellKind::Tet10] {
            let s = spec(kind);
            let m = graded_block(&s).unwrap();
            let q = quality(&m);
            assert_eq!((q.inverted, q.degenerate), (0, 0), "{kind:?}");
            let v = 0.1 * 0.08 * 0.12;
            assert!((q.volume - v).abs() < 1e-12 * v, "{kind:?}: {}", q.volume);
            let top = m.node_set("z1").unwrap();
            assert!(top.iter().all(|&i| m.point(i)[2] == 0.0));
            let bottom = m.node_set("z0").unwrap();
            assert!(bottom.iter().all(|&i| m.point(i)[2] == -0.12));
            assert!(m
                .node_set("x0")
                .unwrap()
                .iter()
                .all(|&i| m.point(i)[0] == 0.0));
            assert!(m
                .node_set("y1")
                .unwrap()
                .iter()
                .all(|&i| m.point(i)[1] == 0.08));
            // The cell at the origin: a cube of side h.
            let near: Vec<usize> = (0..m.n_nodes())
                .filter(|&i| m.point(i).iter().all(|c| c.abs() <= 5e-4 + 1e-15))
                .collect();
            let corners = near
                .iter()
                .filter(|&&i| {
                    m.point(i)
                        .iter()
                        .all(|c| c.abs() < 1e-15 || (c.abs() - 5e-4).abs() < 1e-15)
                })
                .count();
            assert_eq!(corners, 8, "{kind:?}");
        }
        // The hexahedra: a cell's longest edge over its shortest at most the rulers' largest
        // cell over h (the tensor product's bound).
        let m = graded_block(&spec(CellKind::Hex8)).unwrap();
        let largest = [0.1, 0.08, 0.12]
            .iter()
            .zip(spec(CellKind::Hex8).core)
            .map(|(&l, c)| {
                let r = ruler(l, c, 5e-4, 1.3).unwrap();
                r.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max)
            })
            .fold(0.0, f64::max);
        let crate::mesh::Cells::Hex8(hexes) = &m.cells else {
            panic!("hexahedra")
        };
        for h in hexes {
            let p = |k: usize| m.point(h[k]);
            let e = [
                (p(1)[0] - p(0)[0]).abs(),
                (p(3)[1] - p(0)[1]).abs(),
                (p(4)[2] - p(0)[2]).abs(),
            ];
            let (lo, hi) = (
                e.iter().cloned().fold(f64::MAX, f64::min),
                e.iter().cloned().fold(0.0, f64::max),
            );
            assert!(hi / lo <= largest / 5e-4 * (1.0 + 1e-9));
        }
    }
}
