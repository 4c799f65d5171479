//! Pixel geometry without drawing: rectangles, points, clipping and dashes (the bottom of
//! the crate: the audit, the styles and the drawing primitives all stand on it).

#[derive(Debug, Clone, Copy)]
pub(crate) struct Rect {
    pub(crate) x0: f64,
    pub(crate) y0: f64,
    pub(crate) x1: f64,
    pub(crate) y1: f64,
}

impl Rect {
    pub(crate) fn new(x0: f64, y0: f64, x1: f64, y1: f64) -> Self {
        Rect { x0, y0, x1, y1 }
    }
    pub(crate) fn w(&self) -> f64 {
        self.x1 - self.x0
    }
    pub(crate) fn h(&self) -> f64 {
        self.y1 - self.y0
    }
    pub(crate) fn cx(&self) -> f64 {
        0.5 * (self.x0 + self.x1)
    }
    pub(crate) fn cy(&self) -> f64 {
        0.5 * (self.y0 + self.y1)
    }
    pub(crate) fn grow(&self, d: f64) -> Rect {
        Rect::new(self.x0 - d, self.y0 - d, self.x1 + d, self.y1 + d)
    }
    pub(crate) fn contains(&self, (x, y): (f64, f64)) -> bool {
        x >= self.x0 && x <= self.x1 && y >= self.y0 && y <= self.y1
    }
    pub(crate) fn contains_rect(&self, r: &Rect) -> bool {
        r.x0 >= self.x0 && r.x1 <= self.x1 && r.y0 >= self.y0 && r.y1 <= self.y1
    }
    /// The common part (empty, with `x1 < x0` or `y1 < y0`, when none).
    pub(crate) fn intersect(&self, r: &Rect) -> Rect {
        Rect::new(
            self.x0.max(r.x0),
            self.y0.max(r.y0),
            self.x1.min(r.x1),
            self.y1.min(r.y1),
        )
    }
    /// The bounding box of `pts` (`None` when empty).
    pub(crate) fn bounding(pts: &[Pt]) -> Option<Rect> {
        let (first, rest) = pts.split_first()?;
        Some(
            rest.iter()
                .fold(Rect::new(first.0, first.1, first.0, first.1), |r, p| {
                    Rect::new(r.x0.min(p.0), r.y0.min(p.1), r.x1.max(p.0), r.y1.max(p.1))
                }),
        )
    }
}

pub(crate) type Pt = (f64, f64);

/// Liang–Barsky clipping of segment `a`–`b` to `r`. Returns the clipped
/// end points and whether each one is the original point.
pub(crate) fn clip_segment(a: Pt, b: Pt, r: &Rect) -> Option<(Pt, Pt, bool, bool)> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let mut t0: f64 = 0.0;
    let mut t1: f64 = 1.0;
    for (p, q) in [
        (-dx, a.0 - r.x0),
        (dx, r.x1 - a.0),
        (-dy, a.1 - r.y0),
        (dy, r.y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
            if t0 > t1 {
                return None;
            }
        }
    }
    let pa = (a.0 + t0 * dx, a.1 + t0 * dy);
    let pb = (a.0 + t1 * dx, a.1 + t1 * dy);
    Some((pa, pb, t0 == 0.0, t1 == 1.0))
}

/// Splits a sequence of optional pixel points into polylines clipped to
/// `r`; `None` breaks the line. Also returns isolated points (valid points
/// without valid neighbours) inside `r`.
pub(crate) fn clip_polylines(pts: &[Option<Pt>], r: &Rect) -> (Vec<Vec<Pt>>, Vec<Pt>) {
    let mut lines = Vec::new();
    let mut isolated = Vec::new();
    let mut cur: Vec<Pt> = Vec::new();
    let flush = |cur: &mut Vec<Pt>, lines: &mut Vec<Vec<Pt>>| {
        if cur.len() >= 2 {
            lines.push(std::mem::take(cur));
        } else {
            cur.clear();
        }
    };
    for (i, p) in pts.iter().enumerate() {
        let prev = if i > 0 { pts[i - 1] } else { None };
        let next = pts.get(i + 1).copied().flatten();
        match (prev, *p) {
            (Some(a), Some(b)) => match clip_segment(a, b, r) {
                Some((ca, cb, a_in, b_in)) => {
                    if cur.is_empty() || !a_in {
                        flush(&mut cur, &mut lines);
                        cur.push(ca);
                    }
                    cur.push(cb);
                    if !b_in {
                        flush(&mut cur, &mut lines);
                    }
                }
                None => flush(&mut cur, &mut lines),
            },
            (None, Some(b)) => {
                flush(&mut cur, &mut lines);
                if next.is_none() && r.contains(b) {
                    isolated.push(b);
                }
            }
            (_, None) => flush(&mut cur, &mut lines),
        }
    }
    flush(&mut cur, &mut lines);
    (lines, isolated)
}

/// Cuts polylines into dashes of length `on` separated by gaps `off`.
pub(crate) fn dash_polyline(pts: &[Pt], on: f64, off: f64) -> Vec<Vec<Pt>> {
    let mut out = Vec::new();
    if pts.len() < 2 || on <= 0.0 || off <= 0.0 {
        return out;
    }
    let mut drawing = true;
    let mut left = on;
    let mut cur = vec![pts[0]];
    for w in pts.windows(2) {
        let (mut a, b) = (w[0], w[1]);
        let mut len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        while len > 0.0 {
            if len <= left {
                left -= len;
                len = 0.0;
                if drawing {
                    cur.push(b);
                }
            } else {
                let t = left / len;
                let p = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
                if drawing {
                    cur.push(p);
                    out.push(std::mem::take(&mut cur));
                } else {
                    cur = vec![p];
                }
                len -= left;
                a = p;
                drawing = !drawing;
                left = if drawing { on } else { off };
            }
        }
    }
    if drawing && cur.len() >= 2 {
        out.push(cur);
    }
    out
}

/// Sutherland–Hodgman clipping of a polygon to `r` (empty when nothing is left).
pub(crate) fn clip_polygon(pts: &[Pt], r: &Rect) -> Vec<Pt> {
    let mut poly: Vec<Pt> = pts.to_vec();
    // (inside test, intersection with the edge) for the four edges.
    type Edge = (fn(Pt, &Rect) -> bool, fn(Pt, Pt, &Rect) -> Pt);
    let edges: [Edge; 4] = [
        (|p, r| p.0 >= r.x0, |a, b, r| at_x(a, b, r.x0)),
        (|p, r| p.0 <= r.x1, |a, b, r| at_x(a, b, r.x1)),
        (|p, r| p.1 >= r.y0, |a, b, r| at_y(a, b, r.y0)),
        (|p, r| p.1 <= r.y1, |a, b, r| at_y(a, b, r.y1)),
    ];
    for (inside, cut) in edges {
        if poly.is_empty() {
            break;
        }
        let input = std::mem::take(&mut poly);
        let mut prev = input[input.len() - 1];
        for &cur in &input {
            match (inside(prev, r), inside(cur, r)) {
                (true, true) => poly.push(cur),
                (true, false) => poly.push(cut(prev, cur, r)),
                (false, true) => {
                    poly.push(cut(prev, cur, r));
                    poly.push(cur);
                }
                (false, false) => {}
            }
            prev = cur;
        }
    }
    poly
}

fn at_x(a: Pt, b: Pt, x: f64) -> Pt {
    let t = (x - a.0) / (b.0 - a.0);
    (x, a.1 + t * (b.1 - a.1))
}

fn at_y(a: Pt, b: Pt, y: f64) -> Pt {
    let t = (y - a.1) / (b.1 - a.1);
    (a.0 + t * (b.0 - a.0), y)
}
