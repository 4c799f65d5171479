//! Cross-sections meshed with quadrilaterals, and the graded spacings the generators of
//! [`crate::mesh::generators::wheel_of_revolution`] and
//! [`crate::mesh::generators::rail_extruded`] lay along their profiles, sections and
//! lengths.
//!
//! A [`QuadSection`] is built block by block: rows of nodes are added first (a block's
//! bottom and top), then [`QuadSection::ruled_block`] fills the space between two rows of
//! equal length with straight lines from each bottom node to its top node, cut at the same
//! fractions in every column. Blocks that share a row share its nodes, so the section is
//! conforming by construction. Quadrilaterals are counter-clockwise in the section's
//! `(u, v)` plane when the top row lies above the bottom one (larger `v`) and both run
//! toward larger `u`.

/// A 2D mesh of quadrilaterals in a section plane `(u, v)`, m.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct QuadSection {
    /// The nodes `(u, v)`, m.
    pub points: Vec<[f64; 2]>,
    /// The quadrilaterals, counter-clockwise (module docs).
    pub quads: Vec<[usize; 4]>,
}

impl QuadSection {
    /// An empty section.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds the nodes `pts` and returns their indices.
    pub fn add_row(&mut self, pts: &[[f64; 2]]) -> Vec<usize> {
        let first = self.points.len();
        self.points.extend_from_slice(pts);
        (first..self.points.len()).collect()
    }

    /// Fills the space between the node rows `bottom` and `top` (of equal length, at least
    /// 2) with quadrilaterals: the nodes of row `j` (`0 < j < t.len() - 1`) lie on the
    /// straight line from each bottom node to its top node, at the fraction `t[j]` of it
    /// (`t` increasing from 0 to 1). Returns the node rows, bottom to top.
    ///
    /// # Panics
    /// If the rows differ in length or are shorter than 2, or `t` has fewer than 2 values.
    pub fn ruled_block(&mut self, bottom: &[usize], top: &[usize], t: &[f64]) -> Vec<Vec<usize>> {
        assert!(bottom.len() == top.len() && bottom.len() >= 2 && t.len() >= 2);
        let mut rows = vec![bottom.to_vec()];
        for &f in &t[1..t.len() - 1] {
            let pts: Vec<[f64; 2]> = bottom
                .iter()
                .zip(top)
                .map(|(&b, &u)| {
                    let (p, q) = (self.points[b], self.points[u]);
                    [p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1])]
                })
                .collect();
            rows.push(self.add_row(&pts));
        }
        rows.push(top.to_vec());
        for w in rows.windows(2) {
            for i in 0..w[0].len() - 1 {
                self.quads
                    .push([w[0][i], w[0][i + 1], w[1][i + 1], w[1][i]]);
            }
        }
        rows
    }

    /// The signed area of quadrilateral `q` (shoelace), m^2.
    pub fn quad_area(&self, q: [usize; 4]) -> f64 {
        let p = q.map(|i| self.points[i]);
        0.5 * (0..4)
            .map(|k| {
                let (a, b) = (p[k], p[(k + 1) % 4]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum::<f64>()
    }

    /// The area of the section (sum of the signed quadrilateral areas), m^2.
    pub fn area(&self) -> f64 {
        self.quads.iter().map(|&q| self.quad_area(q)).sum()
    }
}

/// Node positions from 0 to `length` (m or rad): steps of `fine` over the first
/// `fine_span`, then steps growing by the factor `growth` up to `coarse`; the steps past
/// the fine span are scaled together so that the last position is `length` exactly (the
/// last growing step dropped when less than half of it would remain). The first position
/// is 0, the last `length`.
///
/// The arguments are checked by the generators (finite, positive, `growth >= 1`,
/// `fine <= coarse`).
pub fn graded(length: f64, fine: f64, fine_span: f64, growth: f64, coarse: f64) -> Vec<f64> {
    let n_fine = ((fine_span.min(length) / fine).round() as usize).max(1);
    let fine_len = n_fine as f64 * fine;
    let mut steps: Vec<f64>;
    if fine_len >= length - 0.5 * fine {
        let n = ((length / fine).round() as usize).max(1);
        steps = vec![length / n as f64; n];
    } else {
        steps = vec![fine; n_fine];
        let rest = length - fine_len;
        let (mut h, mut sum) = (fine, 0.0);
        let mut grown = Vec::new();
        while sum < rest {
            h = (h * growth).min(coarse);
            grown.push(h);
            sum += h;
        }
        if grown.len() > 1 && sum - rest > 0.5 * h {
            grown.pop();
            sum -= h;
        }
        let s = rest / sum;
        steps.extend(grown.iter().map(|g| g * s));
    }
    let mut x = Vec::with_capacity(steps.len() + 1);
    let mut acc = 0.0;
    x.push(0.0);
    for (k, s) in steps.iter().enumerate() {
        acc += s;
        x.push(if k + 1 == steps.len() { length } else { acc });
    }
    x
}

/// Node positions from `a` to `b` (`a < focus < b`, or the focus at an end), graded on
/// both sides of `focus` as [`graded`]: steps of `fine` within `fine_half` of it.
pub fn graded_about(
    a: f64,
    b: f64,
    focus: f64,
    fine: f64,
    fine_half: f64,
    growth: f64,
    coarse: f64,
) -> Vec<f64> {
    let focus = focus.clamp(a, b);
    let mut x: Vec<f64> = Vec::new();
    if focus > a {
        let left = graded(focus - a, fine, fine_half, growth, coarse);
        x.extend(left.iter().rev().map(|d| focus - d));
        x[0] = a;
    }
    if focus < b {
        let right = graded(b - focus, fine, fine_half, growth, coarse);
        let skip = usize::from(!x.is_empty());
        x.extend(right.iter().skip(skip).map(|d| focus + d));
        let n = x.len();
        x[n - 1] = b;
    }
    x
}

/// Points placed on a curve given by a dense polyline `line` (`(u, v)`), at the arc
/// lengths `s` (from the polyline's start, increasing, within its length): each point's
/// `u` is interpolated on the polyline, and its `v` is then `exact(u)` (the curve's own
/// height, so that the points lie on the curve rather than on the chords).
pub fn on_curve(line: &[[f64; 2]], s: &[f64], exact: impl Fn(f64) -> f64) -> Vec<[f64; 2]> {
    let cum = arc_lengths(line);
    let mut k = 0;
    s.iter()
        .map(|&si| {
            while k + 2 < line.len() && cum[k + 1] < si {
                k += 1;
            }
            let d = cum[k + 1] - cum[k];
            let f = if d > 0.0 {
                ((si - cum[k]) / d).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let u = line[k][0] + f * (line[k + 1][0] - line[k][0]);
            [u, exact(u)]
        })
        .collect()
}

/// Cumulative chord lengths along a polyline (0 at its start).
pub fn arc_lengths(line: &[[f64; 2]]) -> Vec<f64> {
    let mut cum = Vec::with_capacity(line.len());
    let mut acc = 0.0;
    cum.push(0.0);
    for w in line.windows(2) {
        acc += (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
        cum.push(acc);
    }
    cum
}

/// Hexahedra from a quadrilateral section swept through `layers` positions: quad `q` of
/// the section between layer `k` and layer `next(k)` gives the hexahedron
/// `[q at k, q at next(k)]` (node of section node `i` in layer `k` is `k n + i`, `n` the
/// section's node count); each is turned positive (its two faces swapped) where its
/// Jacobian at the centre, computed from `coords` (3 per node), is negative.
pub fn sweep_hexes(
    section: &QuadSection,
    cells: usize,
    next: impl Fn(usize) -> usize,
    coords: &[f64],
) -> Vec<[usize; 8]> {
    let n = section.points.len();
    let mut hexes = Vec::with_capacity(cells * section.quads.len());
    for k in 0..cells {
        let k1 = next(k);
        for q in &section.quads {
            let mut h = [
                k * n + q[0],
                k * n + q[1],
                k * n + q[2],
                k * n + q[3],
                k1 * n + q[0],
                k1 * n + q[1],
                k1 * n + q[2],
                k1 * n + q[3],
            ];
            if hex_centre_jacobian(coords, &h) < 0.0 {
                h = [h[4], h[5], h[6], h[7], h[0], h[1], h[2], h[3]];
            }
            hexes.push(h);
        }
    }
    hexes
}

/// The Jacobian determinant of the trilinear map of hexahedron `h` at its centre.
fn hex_centre_jacobian(coords: &[f64], h: &[usize; 8]) -> f64 {
    let x = |i: usize| [coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]];
    let p = h.map(x);
    let mut d = [[0.0; 3]; 3];
    // Corner signs of d/dxi, d/deta, d/dzeta at the centre (Gmsh/VTK order).
    const S: [[f64; 3]; 8] = [
        [-1.0, -1.0, -1.0],
        [1.0, -1.0, -1.0],
        [1.0, 1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
        [1.0, -1.0, 1.0],
        [1.0, 1.0, 1.0],
        [-1.0, 1.0, 1.0],
    ];
    for (c, s) in p.iter().zip(S) {
        for a in 0..3 {
            for b in 0..3 {
                d[a][b] += 0.125 * s[a] * c[b];
            }
        }
    }
    d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1])
        - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
        + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0])
}
