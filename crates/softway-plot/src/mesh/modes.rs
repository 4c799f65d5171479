//! Mode shapes: the deformed mesh of each mode over its outline at rest.

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

pub(crate) fn render_mode_shapes(
    frames: &[ModeShape],
    cols: usize,
    size: (u32, u32),
) -> Res<Vec<u8>> {
    if frames.is_empty() {
        return Err(Fail::Empty("no mode shapes".into()));
    }
    for (i, f) in frames.iter().enumerate() {
        if f.displacement.len() != f.points.len() {
            return Err(Fail::Draw(format!(
                "shape {i}: {} displacements for {} points",
                f.displacement.len(),
                f.points.len()
            )));
        }
        check_triangles(f.points, f.triangles, &format!("shape {i}"))?;
    }
    let n = frames.len();
    let cols = if cols == 0 {
        (n as f64).sqrt().ceil() as usize
    } else {
        cols.min(n)
    };
    let rows = n.div_ceil(cols);
    let unit = unit_scale(frames[0].length_unit_scale);
    let deformed: Vec<Vec<[f64; 2]>> = frames
        .iter()
        .map(|f| {
            f.points
                .iter()
                .zip(f.displacement)
                .map(|(p, d)| {
                    if d[0].is_finite() && d[1].is_finite() {
                        [p[0] + d[0], p[1] + d[1]]
                    } else {
                        [f64::NAN, f64::NAN]
                    }
                })
                .collect()
        })
        .collect();
    let mut bb0: Option<[f64; 4]> = None;
    for (f, d) in frames.iter().zip(&deformed) {
        for b in [
            mesh_bbox(f.points, f.triangles, unit),
            mesh_bbox(d, f.triangles, unit),
        ]
        .into_iter()
        .flatten()
        {
            bb0 = Some(match bb0 {
                None => b,
                Some(a) => [
                    a[0].min(b[0]),
                    a[1].max(b[1]),
                    a[2].min(b[2]),
                    a[3].max(b[3]),
                ],
            });
        }
    }
    let bb = pad_bbox(
        bb0.ok_or_else(|| Fail::Empty("no shape has a drawable triangle".into()))?,
        0.03,
    );
    // Each node's displacement over the largest of its panel, 0 to 1.
    let rel: Vec<Vec<f64>> = frames
        .iter()
        .map(|f| {
            let mags: Vec<f64> = f.displacement.iter().map(|d| d[0].hypot(d[1])).collect();
            let top = mags
                .iter()
                .filter(|m| m.is_finite())
                .fold(0.0f64, |a, &m| a.max(m));
            mags.iter()
                .map(|m| if top > 0.0 { m / top } else { 0.0 })
                .collect()
        })
        .collect();
    // The material lines carried by the displacement (`None`: a break).
    let lines: Vec<Vec<Vec<Option<[f64; 2]>>>> = frames
        .iter()
        .map(|f| {
            f.lines
                .iter()
                .map(|l| {
                    l.iter()
                        .map(|&q| {
                            displacement_at(q, f.points, f.triangles, f.displacement)
                                .map(|d| [q[0] + d[0], q[1] + d[1]])
                        })
                        .collect()
                })
                .collect()
        })
        .collect();
    let loops: Vec<Vec<Vec<usize>>> = frames
        .iter()
        .map(|f| boundary_loops(f.points, f.triangles))
        .collect();
    let vr = (0.0, 1.0);
    let (dx, dy) = (bb[1] - bb[0], bb[3] - bb[2]);
    let xl = axis_label("x", &frames[0].length_unit);
    let yl = axis_label("y", &frames[0].length_unit);
    let cb_label = frames[0].colorbar_label.clone();

    render(size, |area, fig| {
        let st = Sty::new(fig, (fig.out.0 / cols as f64, fig.out.1 / rows as f64));
        let (fs, fl, pad, tick) = (st.fs, st.fl, st.pad, st.tick);
        // Two lines of title per panel.
        let line_h = 1.15 * (CAP + DESC) * fs;
        let title_band = if frames.iter().any(|f| !f.title.is_empty()) {
            2.0 * line_h + 0.6 * pad
        } else {
            0.5 * CAP * fs
        };
        let hgap = 1.6 * fs;
        let vgap = 1.2 * pad;
        let top = pad;
        let note_text = &frames[0].note;
        let (note, nf) = fit_text(note_text, 0.85 * fs, fig.w - 2.0 * pad, 3);
        let note_h = if note_text.is_empty() {
            0.0
        } else {
            note.len() as f64 * 1.15 * (CAP + DESC) * nf + 0.5 * pad
        };
        let bottom = tick + 0.6 * pad + CAP * fs + pad + (CAP + DESC) * fl + pad + note_h;
        let mut left_w = pad + (CAP + DESC) * fl + 0.8 * pad + 3.0 * fs + 0.6 * pad + tick;
        let mut cb_w = 6.0 * fs;
        let mut layout = None;
        for _ in 0..3 {
            let avail_w = fig.w - left_w - cb_w - pad - (cols - 1) as f64 * hgap;
            let avail_h =
                fig.h - top - bottom - rows as f64 * title_band - (rows - 1) as f64 * vgap;
            if avail_w <= 20.0 * cols as f64 || avail_h <= 20.0 * rows as f64 {
                return Err(Fail::Draw(
                    "the image is too small for this many shapes".into(),
                ));
            }
            let s = (avail_w / (cols as f64 * dx)).min(avail_h / (rows as f64 * dy));
            let (pw, ph) = (dx * s, dy * s);
            let gw = cols as f64 * pw + (cols - 1) as f64 * hgap;
            let gh = rows as f64 * (title_band + ph) + (rows - 1) as f64 * vgap;
            let x0 = left_w + 0.5 * (avail_w + (cols - 1) as f64 * hgap - gw);
            let y0 = top + 0.5 * (fig.h - top - bottom - gh);
            let xt = linear_ticks(bb[0], bb[1], pw, fs, true);
            let yt = linear_ticks(bb[2], bb[3], ph, fs, false);
            let ct = linear_ticks(vr.0, vr.1, gh - title_band, fs, false);
            let new_left =
                pad + (CAP + DESC) * fl + 0.8 * pad + yt.max_label_w(fs) + 0.6 * pad + tick;
            let new_cb = colorbar_width(&ct, &cb_label, &st);
            let done = (new_left - left_w).abs() < 1.0 && (new_cb - cb_w).abs() < 1.0;
            left_w = new_left;
            cb_w = new_cb;
            layout = Some((x0, y0, pw, ph, gw, gh, xt, yt, ct));
            if done {
                break;
            }
        }
        let Some((x0, y0, pw, ph, gw, gh, xt, yt, ct)) = layout else {
            return Err(Fail::Draw("layout failed".into()));
        };
        for (i, f) in frames.iter().enumerate() {
            let (r, c) = (i / cols, i % cols);
            let px0 = x0 + c as f64 * (pw + hgap);
            let py0 = y0 + r as f64 * (title_band + ph + vgap) + title_band;
            let v = MeshView {
                bb,
                r: Rect::new(px0, py0, px0 + pw, py0 + ph),
                unit,
            };
            let m = &rel[i];
            let d = &deformed[i];
            audit::with_clip(v.r, || -> Res<()> {
                let size_px = fill_triangles(area, &v, d, f.triangles, |t| {
                    let tri = f.triangles[t];
                    viridis((m[tri[0]] + m[tri[1]] + m[tri[2]]) / 3.0)
                })?;
                draw_edges(
                    area,
                    &v,
                    d,
                    f.triangles,
                    size_px >= 10.0 * fig.k,
                    false,
                    WHITE.mix(0.35),
                    &st,
                )?;
                // The undeformed outline, dashed grey; the deformed one, solid and dark.
                for l in &loops[i] {
                    let pts: Vec<Pt> = l.iter().map(|&k| v.px(f.points[k])).collect();
                    for dash in crate::geom::dash_polyline(&pts, 1.2 * fs, 0.6 * fs) {
                        draw_polyline(area, &dash, RGBColor(120, 120, 120).to_rgba(), st.lw)?;
                    }
                }
                for l in &lines[i] {
                    for run in l.split(|q| q.is_none()) {
                        let pts: Vec<Pt> = run.iter().flatten().map(|&q| v.px(q)).collect();
                        if pts.len() > 1 {
                            draw_polyline(area, &pts, RGBColor(30, 30, 30).to_rgba(), st.thin)?;
                        }
                    }
                }
                for l in &loops[i] {
                    let pts: Vec<Pt> = l.iter().map(|&k| v.px(d[k])).collect();
                    if pts.iter().all(|p| p.0.is_finite() && p.1.is_finite()) {
                        draw_polyline(area, &pts, TEXT.to_rgba(), st.lw)?;
                    }
                }
                Ok(())
            })?;
            let bottom_of_column = i + cols >= n;
            draw_mesh_axes(area, &v, &xt, &yt, bottom_of_column, c == 0, &st)?;
            // Lines given (`\n`) are kept, each fitted to the panel; else wrapped.
            let (tl, tf) = if f.title.contains('\n') {
                let parts: Vec<(Vec<String>, f64)> = f
                    .title
                    .split('\n')
                    .take(2)
                    .map(|t| fit_text(t, fs, pw + hgap - pad, 1))
                    .collect();
                let size = parts.iter().map(|p| p.1).fold(fs, f64::min);
                (parts.into_iter().map(|p| p.0.join(" ")).collect(), size)
            } else {
                fit_text(&f.title, fs, pw + hgap - pad, 2)
            };
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
        }
        let grid_bottom = y0 + gh;
        draw_text(
            area,
            &xl,
            (
                x0 + 0.5 * gw,
                grid_bottom + tick + 0.6 * pad + CAP * fs + pad,
            ),
            fl,
            HA::Center,
            VA::Top,
            false,
            TEXT,
        )?;
        let ylx = x0 - tick - 0.6 * pad - yt.max_label_w(fs) - 0.8 * pad - (CAP + DESC) * fl;
        draw_text(
            area,
            &yl,
            (ylx, y0 + title_band + 0.5 * (gh - title_band)),
            fl,
            HA::Center,
            VA::Top,
            true,
            TEXT,
        )?;
        let cb = Rect::new(
            x0 + gw + 1.2 * fs,
            y0 + title_band,
            x0 + gw + 2.3 * fs,
            grid_bottom,
        );
        if !note_text.is_empty() {
            draw_note(area, &note, nf, fig, &st)?;
        }
        draw_colorbar(area, cb, vr, &ct, &cb_label, (false, false), &st)
    })
}
