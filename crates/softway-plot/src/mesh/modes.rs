//! Mode shapes: the deformed mesh of each mode over its outline at rest.

use super::grid::{bbox_union, grid_shape, Grid, GridSpec, Note};
use super::*;

/// The boundary of a triangle mesh (the edges of one triangle only) as closed loops of
/// node indices (first node repeated at the end); an open chain where the boundary is not
/// a manifold.
pub(super) fn boundary_loops(points: &[[f64; 2]], triangles: &[[usize; 3]]) -> Vec<Vec<usize>> {
    let mut count: HashMap<(usize, usize), u32> = HashMap::new();
    for t in triangles.iter().filter(|t| tri_ok(points, t)) {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let mut edges: Vec<(usize, usize)> = count
        .into_iter()
        .filter(|&(_, c)| c == 1)
        .map(|(e, _)| e)
        .collect();
    edges.sort_unstable();
    let mut next: HashMap<usize, Vec<usize>> = HashMap::new();
    for &(a, b) in &edges {
        next.entry(a).or_default().push(b);
        next.entry(b).or_default().push(a);
    }
    let mut used: std::collections::HashSet<(usize, usize)> = std::collections::HashSet::new();
    let mut loops = Vec::new();
    for &(a, b) in &edges {
        if used.contains(&(a, b)) {
            continue;
        }
        used.insert((a, b));
        let mut chain = vec![a, b];
        let mut cur = b;
        while let Some(&n) = next[&cur]
            .iter()
            .find(|&&n| !used.contains(&(cur.min(n), cur.max(n))))
        {
            used.insert((cur.min(n), cur.max(n)));
            chain.push(n);
            cur = n;
        }
        loops.push(chain);
    }
    loops
}

/// The displacement at `q` interpolated linearly in the first triangle that holds it, or
/// `None` outside the mesh.
pub(super) fn displacement_at(
    q: [f64; 2],
    points: &[[f64; 2]],
    triangles: &[[usize; 3]],
    disp: &[[f64; 2]],
) -> Option<[f64; 2]> {
    for t in triangles.iter().filter(|t| tri_ok(points, t)) {
        let [a, b, c] = [points[t[0]], points[t[1]], points[t[2]]];
        let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        if det == 0.0 {
            continue;
        }
        let l1 = ((q[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (q[1] - a[1])) / det;
        let l2 = ((b[0] - a[0]) * (q[1] - a[1]) - (q[0] - a[0]) * (b[1] - a[1])) / det;
        let l0 = 1.0 - l1 - l2;
        let tol = -1e-9;
        if l0 >= tol && l1 >= tol && l2 >= tol {
            let (d0, d1, d2) = (disp[t[0]], disp[t[1]], disp[t[2]]);
            return Some([
                l0 * d0[0] + l1 * d1[0] + l2 * d2[0],
                l0 * d0[1] + l1 * d1[1] + l2 * d2[1],
            ]);
        }
    }
    None
}

/// What is drawn of each mode shape: the deformed nodes, each node's displacement over the
/// panel's largest (0 to 1), the material lines carried by the displacement (`None`: a
/// break) and the outline's loops.
struct Shape {
    deformed: Vec<[f64; 2]>,
    rel: Vec<f64>,
    lines: Vec<Vec<Option<[f64; 2]>>>,
    loops: Vec<Vec<usize>>,
}

impl Shape {
    fn of(f: &ModeShape) -> Self {
        let deformed = f
            .points
            .iter()
            .zip(f.displacement)
            .map(|(p, d)| {
                if d[0].is_finite() && d[1].is_finite() {
                    [p[0] + d[0], p[1] + d[1]]
                } else {
                    [f64::NAN, f64::NAN]
                }
            })
            .collect();
        let mags: Vec<f64> = f.displacement.iter().map(|d| d[0].hypot(d[1])).collect();
        let top = mags
            .iter()
            .filter(|m| m.is_finite())
            .fold(0.0f64, |a, &m| a.max(m));
        let rel = mags
            .iter()
            .map(|m| if top > 0.0 { m / top } else { 0.0 })
            .collect();
        let lines = f
            .lines
            .iter()
            .map(|l| {
                l.iter()
                    .map(|&q| {
                        displacement_at(q, f.points, f.triangles, f.displacement)
                            .map(|d| [q[0] + d[0], q[1] + d[1]])
                    })
                    .collect()
            })
            .collect();
        Shape {
            deformed,
            rel,
            lines,
            loops: boundary_loops(f.points, f.triangles),
        }
    }
}

pub(crate) fn render_mode_shapes(
    frames: &[ModeShape],
    cols: usize,
    size: (u32, u32),
) -> Res<Vec<u8>> {
    check_per_point(
        frames
            .iter()
            .map(|f| (f.displacement.len(), f.points, f.triangles)),
        ("no mode shapes", "shape", "displacements"),
    )?;
    let n = frames.len();
    let (cols, rows) = grid_shape(n, cols);
    let unit = unit_scale(frames[0].length_unit_scale);
    let shapes: Vec<Shape> = frames.iter().map(Shape::of).collect();
    let bb0 = bbox_union(frames.iter().zip(&shapes).flat_map(|(f, s)| {
        [
            mesh_bbox(f.points, f.triangles, unit),
            mesh_bbox(&s.deformed, f.triangles, unit),
        ]
        .into_iter()
        .flatten()
    }));
    let bb = pad_bbox(
        bb0.ok_or_else(|| Fail::Empty("no shape has a drawable triangle".into()))?,
        0.03,
    );
    let vr = (0.0, 1.0);
    let xl = axis_label("x", &frames[0].length_unit);
    let yl = axis_label("y", &frames[0].length_unit);
    let cb_label = frames[0].colorbar_label.clone();

    render(size, |area, fig| {
        let st = Sty::new(fig, (fig.out.0 / cols as f64, fig.out.1 / rows as f64));
        let (fs, pad) = (st.fs, st.pad);
        // Two lines of title per panel.
        let line_h = 1.15 * (CAP + DESC) * fs;
        let title_band = if frames.iter().any(|f| !f.title.is_empty()) {
            2.0 * line_h + 0.6 * pad
        } else {
            0.5 * CAP * fs
        };
        let note = Note::fit(&frames[0].note, fig, &st);
        let spec = GridSpec {
            cols,
            rows,
            bb,
            vr,
            cb_label: &cb_label,
            title_band,
            hgap: 1.6 * fs,
            what: "shapes",
        };
        let grid = Grid::fit(fig, &st, &spec, &note)?;
        for (i, (f, shape)) in frames.iter().zip(&shapes).enumerate() {
            let v = grid.view(i, bb, unit);
            audit::with_clip(v.r, || draw_shape(area, &v, f, shape, fig, &st))?;
            grid.draw_axes(area, &v, (i, n), &st)?;
            draw_shape_title(area, &f.title, &v, &grid, &st)?;
        }
        let cb = grid.draw_labels(area, (&xl, &yl), &st)?;
        note.draw(area, fig, &st)?;
        draw_colorbar(area, cb, vr, &grid.ct, &cb_label, (false, false), &st)
    })
}

/// One shape in its panel `v`: the deformed mesh coloured by the relative displacement,
/// the outline at rest dashed grey, the material lines, and the deformed outline solid
/// and dark.
fn draw_shape(
    area: &Area,
    v: &MeshView,
    f: &ModeShape,
    shape: &Shape,
    fig: &Fig,
    st: &Sty,
) -> Res<()> {
    let (m, d) = (&shape.rel, &shape.deformed);
    let size_px = fill_triangles(area, v, d, f.triangles, |t| {
        let tri = f.triangles[t];
        viridis((m[tri[0]] + m[tri[1]] + m[tri[2]]) / 3.0)
    })?;
    draw_edges(
        area,
        v,
        d,
        f.triangles,
        size_px >= 10.0 * fig.k,
        false,
        WHITE.mix(0.35),
        st,
    )?;
    // The undeformed outline, dashed grey; the deformed one, solid and dark.
    for l in &shape.loops {
        let pts: Vec<Pt> = l.iter().map(|&k| v.px(f.points[k])).collect();
        for dash in crate::geom::dash_polyline(&pts, 1.2 * st.fs, 0.6 * st.fs) {
            draw_polyline(area, &dash, RGBColor(120, 120, 120).to_rgba(), st.lw)?;
        }
    }
    for l in &shape.lines {
        for run in l.split(|q| q.is_none()) {
            let pts: Vec<Pt> = run.iter().flatten().map(|&q| v.px(q)).collect();
            if pts.len() > 1 {
                draw_polyline(area, &pts, RGBColor(30, 30, 30).to_rgba(), st.thin)?;
            }
        }
    }
    for l in &shape.loops {
        let pts: Vec<Pt> = l.iter().map(|&k| v.px(d[k])).collect();
        if pts.iter().all(|p| p.0.is_finite() && p.1.is_finite()) {
            draw_polyline(area, &pts, TEXT.to_rgba(), st.lw)?;
        }
    }
    Ok(())
}

/// A shape's title over its panel `v`, on two lines at most: the lines given (`\n`) kept,
/// each fitted to the panel; else wrapped.
fn draw_shape_title(area: &Area, title: &str, v: &MeshView, grid: &Grid, st: &Sty) -> Res<()> {
    let (fs, pad) = (st.fs, st.pad);
    let width = grid.pw + grid.hgap - pad;
    let (tl, tf) = if title.contains('\n') {
        let parts: Vec<(Vec<String>, f64)> = title
            .split('\n')
            .take(2)
            .map(|t| fit_text(t, fs, width, 1))
            .collect();
        let size = parts.iter().map(|p| p.1).fold(fs, f64::min);
        (parts.into_iter().map(|p| p.0.join(" ")).collect(), size)
    } else {
        fit_text(title, fs, width, 2)
    };
    let py0 = v.r.y0;
    for (k, line) in tl.iter().enumerate() {
        let from_bottom = (tl.len() - 1 - k) as f64;
        draw_text(
            area,
            line,
            (
                v.r.cx(),
                py0 - 0.6 * pad - DESC * tf - from_bottom * 1.15 * (CAP + DESC) * tf,
            ),
            tf,
            HA::Center,
            VA::Baseline,
            false,
            TEXT,
        )?;
    }
    Ok(())
}
