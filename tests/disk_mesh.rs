//! The graded disk (`disk_graded`) and the mesh quality report (`quality`): rim, validity,
//! area, watertightness, angles, symmetry, size and grading, for 72 to 1,440 rim nodes.

use std::collections::HashMap;
use std::f64::consts::{PI, TAU};

use softway::mesh::generators::{disk_graded, disk_rings, DiskOptions, MeshError};
use softway::mesh::{quality, Cells, Mesh};

/// Wheel radius of the paper, m.
const R: f64 = 0.1;
/// The rim node counts a user asks for.
const RIMS: [usize; 5] = [72, 144, 288, 576, 1440];

fn graded(rim_nodes: usize) -> Mesh {
    disk_graded(R, rim_nodes, DiskOptions::default()).unwrap()
}

fn tris(mesh: &Mesh) -> &[[usize; 3]] {
    match &mesh.cells {
        Cells::Tri3(t) => t,
        _ => panic!("expected triangles"),
    }
}

fn signed_area(m: &Mesh, t: [usize; 3]) -> f64 {
    let [a, b, c] = t.map(|i| m.point(i));
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

fn norm(p: &[f64]) -> f64 {
    p[0].hypot(p[1])
}

/// The distinct node radii, increasing (radii within 1e-9 R merged).
fn ring_radii(mesh: &Mesh) -> Vec<f64> {
    let mut r: Vec<f64> = mesh.points().map(norm).collect();
    r.sort_by(f64::total_cmp);
    r.dedup_by(|a, b| (*a - *b).abs() < 1e-9 * R);
    r
}

/// Checks that `mesh` is a watertight, consistently oriented disk whose boundary is the rim
/// polygon: every edge in at most two triangles (once in each direction), the edges of one
/// triangle exactly the rim's consecutive pairs, counter-clockwise, every node used.
fn check_watertight(mesh: &Mesh, label: &str) {
    let mut directed: HashMap<(usize, usize), usize> = HashMap::new();
    let mut used = vec![false; mesh.n_nodes()];
    for t in tris(mesh) {
        for v in 0..3 {
            let (a, b) = (t[v], t[(v + 1) % 3]);
            used[a] = true;
            *directed.entry((a, b)).or_insert(0) += 1;
        }
    }
    assert!(used.iter().all(|&u| u), "{label}: a node in no triangle");
    let mut boundary = Vec::new();
    for (&(a, b), &count) in &directed {
        assert_eq!(
            count, 1,
            "{label}: directed edge {a}->{b} in {count} triangles"
        );
        if !directed.contains_key(&(b, a)) {
            boundary.push((a, b));
        }
    }
    boundary.sort_unstable();
    let rim = mesh.node_set("rim").unwrap();
    let mut polygon: Vec<(usize, usize)> = (0..rim.len())
        .map(|i| (rim[i], rim[(i + 1) % rim.len()]))
        .collect();
    polygon.sort_unstable();
    assert_eq!(
        boundary, polygon,
        "{label}: boundary is not the rim polygon"
    );
    let q = quality(mesh);
    assert_eq!(q.boundary_edges, rim.len(), "{label}");
    assert_eq!(q.non_manifold_edges, 0, "{label}");
}

#[test]
fn default_grading_is_1_15() {
    assert_eq!(DiskOptions::default().grading, 1.15);
    assert_eq!(DiskOptions::DEFAULT_GRADING, 1.15);
    assert_eq!(DiskOptions::MAX_GRADING, 2.0);
}

#[test]
fn rim_has_exactly_the_requested_nodes_on_the_circle() {
    for n in RIMS {
        let m = graded(n);
        let rim = m.node_set("rim").unwrap();
        assert_eq!(rim.len(), n);
        assert_eq!(quality(&m).rim_nodes, n);
        // Counter-clockwise from the positive x axis, at the rim pitch.
        for (i, &node) in rim.iter().enumerate() {
            let p = m.point(node);
            assert!(
                (norm(p) - R).abs() < 1e-12 * R,
                "n = {n}: rim node {i} off the circle"
            );
            let angle = p[1].atan2(p[0]).rem_euclid(TAU);
            let expect = TAU * i as f64 / n as f64;
            assert!(
                (angle - expect).abs() < 1e-12,
                "n = {n}: rim node {i} at {angle}"
            );
        }
        // No other node on the circle; the centre node at the origin.
        let on_circle = m.points().filter(|&p| norm(p) > R * (1.0 - 1e-9)).count();
        assert_eq!(on_circle, n);
        assert_eq!(m.node_set("centre"), Some(&[0][..]));
        assert_eq!(m.point(0), [0.0, 0.0]);
        assert_eq!(m.node_set("all").unwrap().len(), m.n_nodes());
    }
}

#[test]
fn no_inverted_or_degenerate_triangle_and_area_of_the_rim_polygon() {
    for n in RIMS {
        let m = graded(n);
        let mut total = 0.0;
        for &t in tris(&m) {
            let a = signed_area(&m, t);
            assert!(a > 0.0, "n = {n}: triangle {t:?} has area {a}");
            total += a;
        }
        let q = quality(&m);
        assert_eq!((q.inverted, q.degenerate), (0, 0), "n = {n}");
        // The inscribed n-gon: pi R^2 sin(2 pi / n) n / (2 pi).
        let polygon = PI * R * R * (TAU / n as f64).sin() * n as f64 / TAU;
        assert!(
            ((total - polygon) / polygon).abs() < 1e-12,
            "n = {n}: area {total} vs {polygon}"
        );
        assert!(((q.area - polygon) / polygon).abs() < 1e-12, "n = {n}");
    }
}

#[test]
fn watertight_disk_bounded_by_the_rim_polygon() {
    for n in RIMS {
        let m = graded(n);
        check_watertight(&m, &format!("graded n = {n}"));
        // Euler: a disk of N nodes, n of them on the boundary, has 2N - 2 - n triangles.
        assert_eq!(m.cells.len(), 2 * m.n_nodes() - 2 - n, "n = {n}");
    }
    check_watertight(&disk_rings(R, 8).unwrap(), "disk_rings(8)");
}

/// Measured with the default grading (1.15): smallest angle 39.0-41.0 degrees, largest
/// 93.8-94.6, largest aspect ratio R_c / (2 r_i) 1.271-1.287.
#[test]
fn angles_and_aspect_ratios_are_bounded() {
    for n in RIMS {
        let q = quality(&graded(n));
        eprintln!(
            "rim {n}: {} nodes, {} triangles, angles {:.1}-{:.1} deg, aspect max {:.3} \
             mean {:.3}, symmetry {}",
            q.nodes,
            q.triangles,
            q.min_angle_deg,
            q.max_angle_deg,
            q.max_aspect,
            q.mean_aspect,
            q.symmetry_order
        );
        assert!(q.min_angle_deg > 38.0, "n = {n}: {}", q.min_angle_deg);
        assert!(q.max_angle_deg < 96.0, "n = {n}: {}", q.max_angle_deg);
        assert!(q.max_aspect < 1.3, "n = {n}: {}", q.max_aspect);
    }
}

#[test]
fn graded_disks_have_no_rotational_symmetry_hexagonal_ones_six() {
    for n in RIMS {
        assert_eq!(quality(&graded(n)).symmetry_order, 1, "n = {n}");
    }
    assert_eq!(quality(&disk_rings(0.1, 8).unwrap()).symmetry_order, 6);
    assert_eq!(quality(&disk_rings(0.1, 12).unwrap()).symmetry_order, 6);
}

/// Observed law (default grading): N / n = 3.6, 5.0, 6.0, 6.6, 7.5 for n = 72 ... 1,440
/// rim nodes, growing by about 0.9 per doubling of n (logarithmically), where a uniform
/// mesh would grow like n / (4 pi): fewer than 8 nodes per rim node up to 1,440.
#[test]
fn node_count_grows_like_the_rim_count() {
    let mut last_ratio = 0.0;
    let mut counts = Vec::new();
    for n in RIMS {
        let nodes = graded(n).n_nodes();
        let ratio = nodes as f64 / n as f64;
        assert!(ratio > 3.0 && ratio < 8.0, "n = {n}: {nodes} nodes");
        assert!(
            ratio > last_ratio,
            "n = {n}: N / n = {ratio} after {last_ratio}"
        );
        last_ratio = ratio;
        counts.push(nodes);
    }
    // 20 times the rim, at most 50 times the nodes (a uniform disk: 400 times).
    assert!(counts[4] < 50 * counts[0], "{counts:?}");
    // Uniform spacing (grading 1) costs about n^2 / (4 pi) nodes.
    let uniform = disk_graded(
        R,
        288,
        DiskOptions {
            grading: 1.0,
            ..Default::default()
        },
    )
    .unwrap();
    let expect = 288.0 * 288.0 / (4.0 * PI);
    assert!((uniform.n_nodes() as f64 / expect - 1.0).abs() < 0.05);
}

#[test]
fn rim_pitch_equals_the_radial_spacing_at_the_rim_and_grading_is_geometric() {
    for n in RIMS {
        let m = graded(n);
        let r = ring_radii(&m);
        let pitch = TAU * R / n as f64;
        let rim_gap = r[r.len() - 1] - r[r.len() - 2];
        assert!(
            (rim_gap / pitch - 1.0).abs() < 0.2,
            "n = {n}: gap {rim_gap} pitch {pitch}"
        );
        // Gaps grow inwards by one ratio, close to the requested 1.15.
        let gaps: Vec<f64> = r.windows(2).map(|w| w[1] - w[0]).collect();
        let ratio = gaps[gaps.len() - 2] / gaps[gaps.len() - 1];
        assert!((ratio - 1.15).abs() < 0.03, "n = {n}: ratio {ratio}");
        for w in gaps.windows(2) {
            assert!(
                (w[0] / w[1] - ratio).abs() < 1e-9 * ratio,
                "n = {n}: {gaps:?}"
            );
        }
    }
}

#[test]
fn grading_trades_nodes_for_uniformity() {
    let mut last = usize::MAX;
    for g in [1.0, 1.1, 1.15, 1.3, 1.5, 2.0] {
        let m = disk_graded(
            R,
            144,
            DiskOptions {
                grading: g,
                ..Default::default()
            },
        )
        .unwrap();
        let q = quality(&m);
        assert_eq!((q.inverted, q.degenerate), (0, 0), "grading {g}");
        assert!(q.min_angle_deg > 20.0, "grading {g}: {}", q.min_angle_deg);
        assert_eq!(q.symmetry_order, 1, "grading {g}");
        check_watertight(&m, &format!("grading {g}"));
        assert!(m.n_nodes() < last, "grading {g}: {} nodes", m.n_nodes());
        last = m.n_nodes();
    }
}

#[test]
fn every_rim_count_from_3_to_300_gives_a_valid_disk() {
    for n in 3..=300 {
        let m = graded(n);
        let q = quality(&m);
        assert_eq!(
            (q.inverted, q.degenerate, q.rim_nodes),
            (0, 0, n),
            "n = {n}"
        );
        let polygon = 0.5 * n as f64 * R * R * (TAU / n as f64).sin();
        assert!(((q.area - polygon) / polygon).abs() < 1e-12, "n = {n}");
        check_watertight(&m, &format!("n = {n}"));
        // Below 10 rim nodes the disk is a fan of the centre and the rim (order n).
        let order = if n < 10 { n } else { 1 };
        assert_eq!(q.symmetry_order, order, "n = {n}");
        // Measured from 3 to 2,000 rim nodes: 24.4 degrees at n = 10 (one ring of 7 nodes,
        // 5 sharing a factor with the rim), 30 at n = 3 (the fan), at least 35.2 from 11 on.
        let bound = if n >= 11 { 35.0 } else { 24.0 };
        assert!(q.min_angle_deg > bound, "n = {n}: {}", q.min_angle_deg);
    }
}

#[test]
fn deterministic_and_scaled_with_the_radius() {
    assert_eq!(graded(288), graded(288));
    let a = graded(144);
    let b = disk_graded(2.0 * R, 144, DiskOptions::default()).unwrap();
    assert_eq!(a.cells, b.cells);
    for (p, q) in a.points().zip(b.points()) {
        assert!((2.0 * p[0] - q[0]).abs() < 1e-12 && (2.0 * p[1] - q[1]).abs() < 1e-12);
    }
}

#[test]
fn bad_arguments_are_named() {
    let d = DiskOptions::default();
    for r in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            disk_graded(r, 72, d),
            Err(MeshError::InvalidLength { name: "radius", .. })
        ));
    }
    let e = disk_graded(R, 2, d).unwrap_err();
    assert_eq!(
        e,
        MeshError::CountBelow {
            name: "rim_nodes",
            value: 2,
            min: 3
        }
    );
    assert!(e.to_string().contains(">= 3"), "{e}");
    for g in [0.99, 2.01, f64::NAN, f64::INFINITY, -1.15] {
        let e = disk_graded(
            R,
            72,
            DiskOptions {
                grading: g,
                ..Default::default()
            },
        )
        .unwrap_err();
        assert!(
            matches!(
                e,
                MeshError::OutOfRange {
                    name: "grading",
                    ..
                }
            ),
            "{g}: {e}"
        );
        assert!(e.to_string().contains("[1, 2]"), "{e}");
    }
    for n in [usize::MAX, 49_999_999, 10_000_000] {
        assert!(
            matches!(
                disk_graded(R, n, d),
                Err(MeshError::TooLarge {
                    name: "rim_nodes",
                    ..
                })
            ),
            "n = {n}"
        );
    }
}

/// With a hub (`DiskOptions::hub`, the wheel's clamped support) the graded disk is the
/// annulus from a ring on the hub's circle to the rim: the rim keeps its count, no node lies
/// inside the hub, the node set `"hub"` is exactly the circle of the hub's radius with at
/// least 12 nodes (so a clamp of the nodes within it holds that circle, not the centre alone
/// or a polygon of a few sides), the triangles keep their angles (40.1 to 40.7 degrees at
/// worst) and the mesh its symmetry order 1, and its area is the annulus's.
#[test]
fn a_hub_makes_the_graded_disk_an_annulus_clamped_on_its_circle() {
    for (rim, hub) in [
        (72, 0.01),
        (144, 0.01),
        (288, 0.01),
        (576, 0.01),
        (288, 0.04),
    ] {
        let m = disk_graded(
            R,
            rim,
            DiskOptions {
                hub: Some(hub),
                ..Default::default()
            },
        )
        .unwrap();
        let label = format!("{rim} rim nodes, hub {hub}");
        let q = quality(&m);
        assert_eq!(q.rim_nodes, rim, "{label}");
        assert_eq!(q.inverted + q.degenerate, 0, "{label}");
        eprintln!(
            "{label}: {} nodes, min angle {:.1} deg",
            q.nodes, q.min_angle_deg
        );
        assert!(q.min_angle_deg > 35.0, "{label}: {q:?}");
        assert_eq!(q.symmetry_order, 1, "{label}");
        let inner = m.node_set("hub").unwrap();
        assert!(
            inner.len() >= 12,
            "{label}: {} nodes on the hub",
            inner.len()
        );
        for &n in inner {
            assert!((norm(m.point(n)) - hub).abs() < 1e-12 * R, "{label}");
        }
        assert!(
            m.points().all(|p| norm(p) > hub * (1.0 - 1e-12)),
            "{label}: a node inside the hub"
        );
        let area: f64 = tris(&m).iter().map(|&t| signed_area(&m, t)).sum();
        // The polygons inscribed in the two circles.
        let polygon = |r: f64, n: usize| 0.5 * n as f64 * r * r * (TAU / n as f64).sin();
        let expect = polygon(R, rim) - polygon(hub, inner.len());
        assert!(
            (area / expect - 1.0).abs() < 1e-9,
            "{label}: {area} vs {expect}"
        );
    }
    // A hub that leaves no room for the graded band is refused, naming the parameter.
    let e = disk_graded(
        R,
        72,
        DiskOptions {
            hub: Some(0.099),
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("hub"), "{e}");
}

/// The rim's radial displacement of a hub-clamped disk (E = 210 GPa, plane stress) under a
/// radial rim load of polygon order `m` (`cos(m theta)` at each rim node), by order: the
/// amplitude of every order `0..=n/2` of the rim's `n` nodes (a DFT of `u_r` by rim angle).
fn rim_orders_under_load(mesh: Mesh, m: usize) -> Vec<f64> {
    use softway::linalg::{set_identity_rows, SparseLu};
    use softway::wheel::{Support, WheelModel, WheelSpec};
    let spec = WheelSpec {
        radius: R,
        support: Support::Hub { radius: 0.2 * R },
        ..WheelSpec::paper()
    };
    let wm = WheelModel::new(mesh, spec).unwrap();
    let n = wm.rim.len();
    let x = wm.mesh.reference_positions();
    let theta = |i: usize| x[2 * i + 1].atan2(x[2 * i]);
    let mut f = vec![0.0; x.len()];
    for &i in &wm.rim {
        let (s, c) = theta(i).sin_cos();
        let load = (m as f64 * theta(i)).cos();
        f[2 * i] = load * c;
        f[2 * i + 1] = load * s;
    }
    let mut fixed = vec![false; x.len()];
    for &d in &wm.fixed_dofs {
        fixed[d] = true;
        f[d] = 0.0;
    }
    let mut k = wm.k_elastic.clone();
    set_identity_rows(wm.model.pattern(), &mut k, &fixed);
    let mut lu = SparseLu::new(wm.model.pattern(), &k).unwrap();
    lu.solve_in_place(&mut f);
    let ur: Vec<(f64, f64)> = wm
        .rim
        .iter()
        .map(|&i| {
            let (s, c) = theta(i).sin_cos();
            (theta(i), f[2 * i] * c + f[2 * i + 1] * s)
        })
        .collect();
    (0..=n / 2)
        .map(|j| {
            let (mut re, mut im) = (0.0, 0.0);
            for &(t, u) in &ur {
                re += u * (j as f64 * t).cos();
                im += u * (j as f64 * t).sin();
            }
            2.0 * re.hypot(im) / n as f64
        })
        .collect()
}

/// The symmetric rim (`disk_symmetric_rim`): its band maps onto itself under a turn by one
/// rim pitch (nodes and triangles), its triangles are near equilateral, and it does not
/// couple polygon orders: a radial rim load of order `m` answers at order `m` alone but
/// for the interior's attenuated share, where the graded disk (rings of other counts and
/// turns) answers at other orders too.
#[test]
fn a_symmetric_rim_maps_onto_itself_and_does_not_couple_orders() {
    use softway::mesh::generators::disk_symmetric_rim;
    let (n, band) = (144usize, 0.25 * R);
    let opts = DiskOptions {
        hub: Some(0.2 * R),
        ..Default::default()
    };
    let sym = disk_symmetric_rim(R, n, band, opts).unwrap();
    let r_band = R - band;
    let pts: Vec<[f64; 2]> = (0..sym.n_nodes())
        .map(|i| [sym.point(i)[0], sym.point(i)[1]])
        .collect();
    let key = |p: [f64; 2]| {
        (
            (p[0] / R * 1e7).round() as i64,
            (p[1] / R * 1e7).round() as i64,
        )
    };
    let index: HashMap<(i64, i64), usize> =
        pts.iter().enumerate().map(|(i, &p)| (key(p), i)).collect();
    let turn = |p: [f64; 2]| {
        let (s, c) = (TAU / n as f64).sin_cos();
        [c * p[0] - s * p[1], s * p[0] + c * p[1]]
    };
    let in_band = |p: [f64; 2]| p[0].hypot(p[1]) >= r_band * (1.0 - 1e-9);
    let mut banded = 0;
    for &p in pts.iter().filter(|&&p| in_band(p)) {
        assert!(index.contains_key(&key(turn(p))), "{p:?} has no image");
        banded += 1;
    }
    let band_tris: Vec<[usize; 3]> = tris(&sym)
        .iter()
        .copied()
        .filter(|t| t.iter().all(|&i| in_band(pts[i])))
        .collect();
    let sorted = |mut t: [usize; 3]| {
        t.sort_unstable();
        t
    };
    let set: std::collections::HashSet<[usize; 3]> = band_tris.iter().map(|&t| sorted(t)).collect();
    for t in &band_tris {
        let image = sorted(t.map(|i| index[&key(turn(pts[i]))]));
        assert!(set.contains(&image), "{t:?} has no image");
    }
    assert_eq!(banded % n, 0);
    assert_eq!(band_tris.len(), 2 * n * (banded / n - 1));
    let q = quality(&sym);
    println!(
        "symmetric rim: {} nodes ({banded} in the band), smallest angle {:.1} deg",
        sym.n_nodes(),
        q.min_angle_deg
    );
    assert!(q.min_angle_deg > 35.0);
    // Order coupling: the largest answer at another order than the load's, over the answer
    // at the load's order.
    let leak = |u: &[f64], m: usize| {
        let other = u
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != m)
            .map(|(_, &v)| v)
            .fold(0.0, f64::max);
        other / u[m]
    };
    for m in [6usize, 18, 30] {
        let s = leak(
            &rim_orders_under_load(disk_symmetric_rim(R, n, band, opts).unwrap(), m),
            m,
        );
        let g = leak(
            &rim_orders_under_load(disk_graded(R, n, opts).unwrap(), m),
            m,
        );
        println!(
            "order {m}: leak to other orders {s:.2e} (symmetric rim) against {g:.2e} (graded)"
        );
        assert!(s < 0.1 * g, "order {m}: {s} against {g}");
    }
}

/// `wheel.rim_band` builds the wheel on the symmetric rim (more nodes than the graded disk:
/// the band's rings carry the rim's count), and a band out of its range or without
/// `wheel.rim_nodes` is refused, naming the file and the key.
#[test]
fn the_rim_band_key_builds_the_symmetric_rim_and_names_its_range() {
    let dir = std::env::temp_dir().join(format!("softway-rim-band-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let base = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/polygon.toml"),
    )
    .unwrap();
    let run = |name: &str, text: String, extra: &[&str]| {
        let f = dir.join(name);
        std::fs::write(&f, text).unwrap();
        let mut args = vec!["matrix".to_string(), f.to_string_lossy().into_owned()];
        args.extend([
            "--out".into(),
            dir.join(format!("out-{name}"))
                .to_string_lossy()
                .into_owned(),
        ]);
        args.extend(extra.iter().map(|s| s.to_string()));
        std::process::Command::new(env!("CARGO_BIN_EXE_softway"))
            .args(&args)
            .output()
            .unwrap()
    };
    let dofs = |out: &std::process::Output, name: &str| -> f64 {
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let j: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join(format!("out-{name}")).join("matrix.json")).unwrap(),
        )
        .unwrap();
        j["dofs"].as_f64().or_else(|| j["n"].as_f64()).unwrap()
    };
    let graded = run("graded.toml", base.clone(), &["--steps", "20"]);
    let banded = run(
        "banded.toml",
        base.replace("[wheel]\n", "[wheel]\nrim_band = 0.02\n"),
        &["--steps", "20"],
    );
    let (g, b) = (dofs(&graded, "graded.toml"), dofs(&banded, "banded.toml"));
    println!("dofs: graded {g}, with a 20 mm symmetric band {b}");
    assert!(b > 1.5 * g, "{b} against {g}");
    for (name, text, words) in [
        (
            "deep.toml",
            base.replace("[wheel]\n", "[wheel]\nrim_band = 0.09\n"),
            vec!["wheel.rim_band", "at most"],
        ),
        (
            "zone.toml",
            base.replace(
                "[wheel]\n",
                "[wheel]\nrim_band = 0.02\nzone_rim_nodes = 576\n",
            ),
            vec!["wheel.rim_band", "wheel.zone_rim_nodes"],
        ),
        (
            "rings.toml",
            base.replace("[wheel]\n", "[wheel]\nrim_band = 0.02\n")
                .replace("rim_nodes = 288", "rings = 12"),
            vec!["wheel.rim_band", "wheel.rim_nodes"],
        ),
    ] {
        let out = run(name, text, &[]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {err}");
        for w in words.iter().chain([&name]) {
            assert!(err.contains(w), "{name}: `{w}` not in {err}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
