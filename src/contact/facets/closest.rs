//! The closest point of a facet to a point: exact on a triangle (Ericson 2005, *Real-Time
//! Collision Detection*, section 5.1.5: the Voronoi regions of the vertices, the edges and
//! the face), Newton's method on the bilinear quadrilateral's two parameters with its edges
//! (straight lines, solved exactly) and its two triangles as the fallback.
//!
//! Parameters: a triangle `(a, b, c)` is `x = a + xi (b - a) + eta (c - a)` (weights
//! `1 - xi - eta, xi, eta`); a quadrilateral `(x_0, x_1, x_2, x_3)` is the bilinear map of
//! the unit square,
//! $$x(\xi, \eta) = (1-\xi)(1-\eta) x_0 + \xi (1-\eta) x_1 + \xi \eta x_2 + (1-\xi) \eta x_3.$$

use crate::contact::obstacle::{dot, Vector};

/// `a - b`.
pub(crate) fn sub(a: Vector, b: Vector) -> Vector {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a x b`.
pub(crate) fn cross(a: Vector, b: Vector) -> Vector {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a / |a|` (the zero vector stays zero).
pub(crate) fn unit(a: Vector) -> Vector {
    let l = dot(a, a).sqrt();
    if l > 0.0 {
        a.map(|c| c / l)
    } else {
        a
    }
}

/// The parameters `(xi, eta)` of the closest point of the triangle `(a, b, c)` to `p`
/// (module docs; Ericson's `ClosestPtPointTriangle`, with the point's barycentric
/// coordinates `v = xi`, `w = eta`).
pub fn closest_on_triangle(p: Vector, a: Vector, b: Vector, c: Vector) -> (f64, f64) {
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (0.0, 0.0);
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (1.0, 0.0);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (d1 / (d1 - d3), 0.0);
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (0.0, 1.0);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (0.0, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (1.0 - w, w);
    }
    let denom = 1.0 / (va + vb + vc);
    (vb * denom, vc * denom)
}

/// The point of the triangle `(a, b, c)` at `(xi, eta)`.
pub fn triangle_point(x: &[Vector; 3], xi: f64, eta: f64) -> Vector {
    std::array::from_fn(|d| (1.0 - xi - eta) * x[0][d] + xi * x[1][d] + eta * x[2][d])
}

/// The bilinear quadrilateral's weights at `(xi, eta)` (module docs).
pub fn quad_weights(xi: f64, eta: f64) -> [f64; 4] {
    [
        (1.0 - xi) * (1.0 - eta),
        xi * (1.0 - eta),
        xi * eta,
        (1.0 - xi) * eta,
    ]
}

/// The point of the quadrilateral `x` at `(xi, eta)`.
pub fn quad_point(x: &[Vector; 4], xi: f64, eta: f64) -> Vector {
    let w = quad_weights(xi, eta);
    std::array::from_fn(|d| w[0] * x[0][d] + w[1] * x[1][d] + w[2] * x[2][d] + w[3] * x[3][d])
}

/// The quadrilateral's tangents `(dx/dxi, dx/deta)` at `(xi, eta)`.
pub fn quad_tangents(x: &[Vector; 4], xi: f64, eta: f64) -> (Vector, Vector) {
    let a = sub(x[1], x[0]);
    let b = sub(x[3], x[0]);
    let c: Vector = std::array::from_fn(|d| x[0][d] - x[1][d] + x[2][d] - x[3][d]);
    (
        std::array::from_fn(|d| a[d] + eta * c[d]),
        std::array::from_fn(|d| b[d] + xi * c[d]),
    )
}

/// The quadrilateral's unit normal at `(xi, eta)`, `x_xi x x_eta` (outward for nodes
/// counter-clockwise seen from outside).
pub fn quad_normal(x: &[Vector; 4], xi: f64, eta: f64) -> Vector {
    let (txi, teta) = quad_tangents(x, xi, eta);
    unit(cross(txi, teta))
}

/// The squared distance from `p` to the quadrilateral's point at `(xi, eta)`.
fn quad_distance2(x: &[Vector; 4], p: Vector, (xi, eta): (f64, f64)) -> f64 {
    let r = sub(quad_point(x, xi, eta), p);
    dot(r, r)
}

/// The parameter in `[0, 1]` of the closest point of the segment `[a, b]` to `p`.
fn closest_on_segment(p: Vector, a: Vector, b: Vector) -> f64 {
    let e = sub(b, a);
    let l2 = dot(e, e);
    if l2 > 0.0 {
        (dot(sub(p, a), e) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Newton's iterations on the squared distance from `p` to the quadrilateral from the
/// parameters `start`: the stationary point, when they converge (to `1e-14` in the
/// parameters within 30 iterations) inside the unit square.
fn quad_newton(x: &[Vector; 4], p: Vector, start: (f64, f64)) -> Option<(f64, f64)> {
    let c: Vector = std::array::from_fn(|d| x[0][d] - x[1][d] + x[2][d] - x[3][d]);
    let (mut xi, mut eta) = start;
    for _ in 0..30 {
        let r = sub(quad_point(x, xi, eta), p);
        let (txi, teta) = quad_tangents(x, xi, eta);
        let g = [dot(r, txi), dot(r, teta)];
        let (h11, h22) = (dot(txi, txi), dot(teta, teta));
        let mut h12 = dot(txi, teta) + dot(r, c);
        if h11 * h22 - h12 * h12 <= 1e-12 * h11 * h22 {
            // Not convex here: Gauss-Newton (the first-order part of the Hessian).
            h12 = dot(txi, teta);
        }
        let det = h11 * h22 - h12 * h12;
        if det.is_nan() || det <= 0.0 {
            return None;
        }
        let dxi = -(h22 * g[0] - h12 * g[1]) / det;
        let deta = -(h11 * g[1] - h12 * g[0]) / det;
        xi += dxi;
        eta += deta;
        if !(xi.is_finite() && eta.is_finite()) || xi.abs() > 10.0 || eta.abs() > 10.0 {
            return None;
        }
        if dxi.abs().max(deta.abs()) < 1e-14 {
            let inside =
                (-1e-12..=1.0 + 1e-12).contains(&xi) && (-1e-12..=1.0 + 1e-12).contains(&eta);
            return inside.then_some((xi.clamp(0.0, 1.0), eta.clamp(0.0, 1.0)));
        }
    }
    None
}

/// The parameters `(xi, eta)` of the closest point of the bilinear quadrilateral `x`
/// (module docs) to `p`: the best of the interior stationary point that Newton's method
/// finds from the closest point of the quadrilateral's two triangles `(0, 1, 2)` and
/// `(0, 2, 3)`, the closest points of its four edges (straight: exact), and, should Newton
/// not converge, that starting point itself. On a planar quadrilateral Newton converges in
/// one or two iterations; on a curved one its stationary point is the exact closest point
/// when the minimum is inside.
pub fn closest_on_quad(p: Vector, x: &[Vector; 4]) -> (f64, f64) {
    // The two triangles' closest points, as quadrilateral parameters.
    let (v, w) = closest_on_triangle(p, x[0], x[1], x[2]);
    let first = (v + w, w);
    let (v, w) = closest_on_triangle(p, x[0], x[2], x[3]);
    let second = (v, v + w);
    let start = if quad_distance2(x, p, first) <= quad_distance2(x, p, second) {
        first
    } else {
        second
    };
    let mut best = (quad_distance2(x, p, start), start);
    let mut consider = |par: (f64, f64)| {
        let d2 = quad_distance2(x, p, par);
        if d2 < best.0 {
            best = (d2, par);
        }
    };
    if let Some(par) = quad_newton(x, p, start) {
        consider(par);
    }
    consider((closest_on_segment(p, x[0], x[1]), 0.0));
    consider((1.0, closest_on_segment(p, x[1], x[2])));
    consider((1.0 - closest_on_segment(p, x[2], x[3]), 1.0));
    consider((0.0, 1.0 - closest_on_segment(p, x[3], x[0])));
    best.1
}
