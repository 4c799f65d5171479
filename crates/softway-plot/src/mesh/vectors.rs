//! Vector fields on a mesh: arrows at a subset of the nodes over the mesh's outline.

use super::grid::{bbox_union, grid_shape, Grid, GridSpec, Note};
use super::*;

/// Evenly spread subset of the nodes used by drawable triangles: in each
/// cell of a grid of about `n_across` cells over the larger extent, the
/// node closest to the cell centre.
pub(super) fn arrow_nodes(
    points: &[[f64; 2]],
    triangles: &[[usize; 3]],
    unit: f64,
    bb: [f64; 4],
    n_across: f64,
) -> Vec<usize> {
    let cell = (bb[1] - bb[0]).max(bb[3] - bb[2]) / n_across;
    if cell.is_nan() || cell <= 0.0 {
        return Vec::new();
    }
    let nx = ((bb[1] - bb[0]) / cell).ceil().max(1.0) as usize;
    let ny = ((bb[3] - bb[2]) / cell).ceil().max(1.0) as usize;
    let mut used = vec![false; points.len()];
    for t in triangles.iter().filter(|t| tri_ok(points, t)) {
        for &n in t {
            used[n] = true;
        }
    }
    let mut best: HashMap<(usize, usize), (f64, usize)> = HashMap::new();
    for (n, p) in points.iter().enumerate().filter(|(n, _)| used[*n]) {
        let (x, y) = (p[0] * unit - bb[0], p[1] * unit - bb[2]);
        let (i, j) = (
            ((x / cell) as usize).min(nx - 1),
            ((y / cell) as usize).min(ny - 1),
        );
        let (cx, cy) = ((i as f64 + 0.5) * cell, (j as f64 + 0.5) * cell);
        let d = (x - cx).powi(2) + (y - cy).powi(2);
        let e = best.entry((i, j)).or_insert((f64::INFINITY, n));
        if d < e.0 {
            *e = (d, n);
        }
    }
    let mut nodes: Vec<usize> = best.into_values().map(|(_, n)| n).collect();
    nodes.sort_unstable();
    nodes
}

/// Black arrow with a thin white halo (visible on dark and light colours).
pub(super) fn draw_arrow(area: &Area, from: Pt, to: Pt, st: &Sty) -> Res<()> {
    let (dx, dy) = (to.0 - from.0, to.1 - from.1);
    let len = (dx * dx + dy * dy).sqrt();
    if len < 0.3 * st.fs {
        return Ok(());
    }
    let (ux, uy) = (dx / len, dy / len);
    let head = (0.35 * len).min(0.5 * st.fs);
    let half = 0.42 * head;
    let base = (to.0 - head * ux, to.1 - head * uy);
    let shaft = 1.1 * st.thin;
    let halo = 0.4 * st.thin + 0.5;
    let tri = |grow: f64| {
        [
            (to.0 + grow * 1.6 * ux, to.1 + grow * 1.6 * uy),
            (
                base.0 - (half + grow) * uy - grow * ux,
                base.1 + (half + grow) * ux - grow * uy,
            ),
            (
                base.0 + (half + grow) * uy - grow * ux,
                base.1 - (half + grow) * ux - grow * uy,
            ),
        ]
    };
    let white = WHITE.mix(0.6);
    draw_polyline(
        area,
        &[(from.0 - halo * ux, from.1 - halo * uy), base],
        white,
        shaft + 2.0 * halo,
    )?;
    fill_polygon_rgba(area, &tri(halo), white)?;
    draw_polyline(area, &[from, base], BLACK.to_rgba(), shaft)?;
    fill_polygon(area, &tri(0.0), BLACK)
}

pub(crate) fn render_vector_fields(
    frames: &[MeshVectorField],
    cols: usize,
    size: (u32, u32),
    opts: &MeshOptions,
) -> Res<Vec<u8>> {
    check_per_point(
        frames
            .iter()
            .map(|f| (f.vectors.len(), f.points, f.triangles)),
        ("no frames", "frame", "vectors"),
    )?;
    let n = frames.len();
    let (cols, rows) = grid_shape(n, cols);
    let unit = unit_scale(frames[0].length_unit_scale);
    let bb0 = bbox_union(
        frames
            .iter()
            .filter_map(|f| mesh_bbox(f.points, f.triangles, unit)),
    );
    // Arrows are centred on their node and at most 1/8 of the panel width
    // long: a margin of 7.5 % keeps them inside the frame.
    let bb = pad_bbox(
        bb0.ok_or_else(|| Fail::Empty("no frame has a drawable triangle".into()))?,
        0.075,
    );
    let mags: Vec<Vec<f64>> = frames
        .iter()
        .map(|f| f.vectors.iter().map(|v| v[0].hypot(v[1])).collect())
        .collect();
    let max_mag = mags
        .iter()
        .flatten()
        .filter(|m| m.is_finite())
        .fold(0.0f64, |a, &m| a.max(m));
    let vr = match opts.value_range {
        Some(_) => value_range(std::iter::empty(), opts.value_range),
        None => None,
    }
    .unwrap_or((0.0, if max_mag > 0.0 { max_mag } else { 1.0 }));
    let xl = axis_label("x", &frames[0].length_unit);
    let yl = axis_label("y", &frames[0].length_unit);
    let cb_label = frames[0].colorbar_label.clone();

    render(size, |area, fig| {
        let st = Sty::new(fig, (fig.out.0 / cols as f64, fig.out.1 / rows as f64));
        let (fs, pad) = (st.fs, st.pad);
        let title_band = if frames.iter().any(|f| !f.title.is_empty()) {
            (CAP + DESC) * fs + 0.6 * pad
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
            hgap: 1.2 * fs,
            what: "frames",
        };
        let grid = Grid::fit(fig, &st, &spec, &note)?;
        let arrow_scale = if max_mag > 0.0 {
            grid.pw / 8.0 / max_mag
        } else {
            0.0
        };
        let field = FieldStyle {
            vr,
            arrow_scale,
            opts,
        };
        for (i, f) in frames.iter().enumerate() {
            let v = grid.view(i, bb, unit);
            audit::with_clip(v.r, || draw_field(area, &v, f, &mags[i], &field, fig, &st))?;
            grid.draw_axes(area, &v, (i, n), &st)?;
            let (tl, tf) = fit_text(&f.title, fs, grid.pw + grid.hgap - pad, 1);
            draw_text(
                area,
                &tl.join(" "),
                (v.r.cx(), v.r.y0 - 0.6 * pad - DESC * fs),
                tf,
                HA::Center,
                VA::Baseline,
                false,
                TEXT,
            )?;
        }
        // Shared axis labels and colour bar.
        let cb = grid.draw_labels(area, (&xl, &yl), &st)?;
        draw_arrow_key(area, &grid, max_mag, arrow_scale, &cb_label, &st)?;
        note.draw(area, fig, &st)?;
        let over = opts
            .value_range
            .is_some_and(|_| mags.iter().flatten().any(|&m| m > vr.1 * (1.0 + 1e-9)));
        draw_colorbar(area, cb, vr, &grid.ct, &cb_label, (false, over), &st)
    })
}

/// How the frames' fields are drawn: the colour bar's range, pixels per unit of the
/// vectors, the options.
struct FieldStyle<'a> {
    vr: (f64, f64),
    arrow_scale: f64,
    opts: &'a MeshOptions,
}

/// One frame in its panel `v`: the mesh coloured by the vectors' magnitudes `m`, its edges,
/// the overlay, and an arrow at an even subset of the nodes.
fn draw_field(
    area: &Area,
    v: &MeshView,
    f: &MeshVectorField,
    m: &[f64],
    field: &FieldStyle,
    fig: &Fig,
    st: &Sty,
) -> Res<()> {
    let vr = field.vr;
    let size_px = fill_triangles(area, v, f.points, f.triangles, |t| {
        let tri = f.triangles[t];
        let mean = (m[tri[0]] + m[tri[1]] + m[tri[2]]) / 3.0;
        if mean.is_finite() {
            viridis((mean - vr.0) / (vr.1 - vr.0))
        } else {
            NO_DATA
        }
    })?;
    let inner = match field.opts.edges {
        EdgeMode::Always => true,
        EdgeMode::Never => false,
        EdgeMode::Auto => size_px >= 10.0 * fig.k,
    };
    draw_edges(
        area,
        v,
        f.points,
        f.triangles,
        inner,
        true,
        WHITE.mix(0.35),
        st,
    )?;
    for seg in &f.overlay {
        let (a, b) = (v.px(seg[0]), v.px(seg[1]));
        if a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite() {
            draw_polyline(area, &[a, b], OVERLAY.to_rgba(), 2.5 * st.thin)?;
        }
    }
    for node in arrow_nodes(f.points, f.triangles, v.unit, v.bb, 12.0) {
        let vec = f.vectors[node];
        if !(vec[0].is_finite() && vec[1].is_finite()) {
            continue;
        }
        let c = v.px(f.points[node]);
        let s = field.arrow_scale;
        let (hx, hy) = (0.5 * vec[0] * s, -0.5 * vec[1] * s);
        draw_arrow(area, (c.0 - hx, c.1 - hy), (c.0 + hx, c.1 + hy), st)?;
    }
    Ok(())
}

/// The arrows' scale: an arrow of a round value, bottom left under the grid.
fn draw_arrow_key(
    area: &Area,
    grid: &Grid,
    max_mag: f64,
    arrow_scale: f64,
    cb_label: &str,
    st: &Sty,
) -> Res<()> {
    let (fs, fl, pad, tick) = (st.fs, st.fl, st.pad, st.tick);
    let key = round_below(0.5 * max_mag);
    if key > 0.0 && arrow_scale > 0.0 {
        let len = key * arrow_scale;
        let y = grid.bottom() + tick + 0.6 * pad + CAP * fs + pad + 0.5 * CAP * fl;
        let label = "arrows:";
        let x = grid.x0;
        draw_text(area, label, (x, y), fs, HA::Left, VA::Center, false, TEXT)?;
        let ax = x + text_w(label, fs) + 0.5 * fs;
        draw_arrow(area, (ax, y), (ax + len, y), st)?;
        let unit = unit_of(cb_label);
        draw_text(
            area,
            &format!("{} {unit}", fmt_value(key)),
            (ax + len + 0.5 * fs, y),
            fs,
            HA::Left,
            VA::Center,
            false,
            TEXT,
        )?;
    }
    Ok(())
}
