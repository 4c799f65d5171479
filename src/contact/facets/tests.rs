use super::*;
use crate::contact::search::Motion;
use crate::mesh::generators::box_mesh;

const FIXED: Placed = Placed {
    motion: Motion::Fixed,
    first_dof: 0,
};

/// A small deterministic generator of numbers in `[0, 1)` (xorshift64*).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The positions of a facet's nodes.
fn corners(coords: &[f64], f: &Facet) -> Vec<Vector> {
    f.nodes().iter().map(|&i| point(coords, i)).collect()
}

/// The point of facet `f` at `(xi, eta)` and its outward unit normal, computed here from
/// the facet's definition (a triangle's cross product; the bilinear map's derivatives).
fn on_facet(coords: &[f64], f: &Facet, xi: f64, eta: f64) -> (Vector, Vector) {
    let x = corners(coords, f);
    let w = f.weights(xi, eta);
    let at = std::array::from_fn(|d| (0..x.len()).map(|i| w[i] * x[i][d]).sum());
    let (a, b) = match f {
        Facet::Tri(_) => (sub(x[1], x[0]), sub(x[2], x[0])),
        Facet::Quad(_) => {
            // d/dxi and d/deta of the weights (1-xi)(1-eta), xi(1-eta), xi eta, (1-xi) eta.
            let dxi = [-(1.0 - eta), 1.0 - eta, eta, -eta];
            let deta = [-(1.0 - xi), -xi, xi, 1.0 - xi];
            (
                std::array::from_fn(|d| (0..4).map(|i| dxi[i] * x[i][d]).sum()),
                std::array::from_fn(|d| (0..4).map(|i| deta[i] * x[i][d]).sum()),
            )
        }
    };
    (at, unit(cross(a, b)))
}

/// Every box's facets point out of the box along the axis of the face they lie on, there
/// are `2 (nx ny + ny nz + nz nx)` squares' worth of them, and they close the box: by the
/// divergence theorem, `sum A n = 0` and `sum (x_c . A n) / 3 = V` (exact for plane facets,
/// `x_c` a facet's centroid). The 10-node tetrahedra give the 4-node ones' facets, on the
/// grid's corner nodes only. A region (the face `z1`) keeps its facets alone.
#[test]
fn the_facets_of_a_box_point_out_and_close_it() {
    let (size, n) = ([0.3, 0.2, 0.1], [3, 2, 2]);
    let squares = 2 * (n[0] * n[1] + n[1] * n[2] + n[2] * n[0]);
    let grid_nodes = (n[0] + 1) * (n[1] + 1) * (n[2] + 1);
    for (kind, per_square) in [
        (CellKind::Hex8, 1),
        (CellKind::Tet4, 2),
        (CellKind::Tet10, 2),
    ] {
        let mesh = box_mesh(kind, size, n).unwrap();
        let facets = surface_facets(&mesh, None).unwrap();
        assert_eq!(facets.len(), squares * per_square, "{kind:?}");
        let (mut sum_a, mut volume) = ([0.0; 3], 0.0);
        for f in &facets {
            assert!(f.nodes().iter().all(|&i| i < grid_nodes), "{kind:?} {f:?}");
            let x = corners(&mesh.coords, f);
            let c: Vector =
                std::array::from_fn(|d| x.iter().map(|p| p[d]).sum::<f64>() / x.len() as f64);
            let a = area_vector(f, |i| point(&mesh.coords, i));
            let normal = unit(a);
            // The face of the box the facet lies on, and its outward axis.
            let mut expected = [0.0; 3];
            for d in 0..3 {
                if x.iter().all(|p| p[d] == 0.0) {
                    expected[d] = -1.0;
                } else if x.iter().all(|p| p[d] == size[d]) {
                    expected[d] = 1.0;
                }
            }
            assert_eq!(
                dot(expected, expected),
                1.0,
                "{kind:?}: {x:?} not on one face"
            );
            assert!(
                (0..3).all(|d| (normal[d] - expected[d]).abs() < 1e-14),
                "{kind:?}: {normal:?} against {expected:?}"
            );
            for d in 0..3 {
                sum_a[d] += a[d];
            }
            volume += dot(c, a) / 3.0;
        }
        let v = size[0] * size[1] * size[2];
        assert!(sum_a.iter().all(|s| s.abs() < 1e-15), "{kind:?} {sum_a:?}");
        assert!((volume / v - 1.0).abs() < 1e-13, "{kind:?} {volume} vs {v}");
        let top = surface_facets(&mesh, mesh.node_set("z1")).unwrap();
        assert_eq!(top.len(), n[0] * n[1] * per_square, "{kind:?}");
        for f in &top {
            let a = unit(area_vector(f, |i| point(&mesh.coords, i)));
            assert!((a[2] - 1.0).abs() < 1e-14, "{kind:?} {a:?}");
        }
    }
}

/// Ericson's triangle against the regions worked by hand on the unit right triangle in
/// `z = 0`: the face (the point's own `x, y`, the gap its height), the vertices, the
/// edges (the foot of the perpendicular), the hypotenuse `x + y = 1` (foot
/// `((1 + x - y) / 2, (1 - x + y) / 2)`); and on random triangles and points, no point of
/// a fine barycentric grid is closer than the answer.
#[test]
fn a_triangle_s_closest_point_is_exact_in_every_region() {
    let (a, b, c) = ([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    let cases: [(Vector, (f64, f64)); 7] = [
        ([0.2, 0.3, 0.5], (0.2, 0.3)),
        ([0.2, 0.3, -0.5], (0.2, 0.3)),
        ([-0.5, -0.5, 0.1], (0.0, 0.0)),
        ([2.0, -1.0, 0.0], (1.0, 0.0)),
        ([-0.2, 3.0, 1.0], (0.0, 1.0)),
        ([0.4, -0.3, 0.2], (0.4, 0.0)),
        ([0.9, 0.5, -0.2], (0.7, 0.3)),
    ];
    for (p, (xi, eta)) in cases {
        let got = closest_on_triangle(p, a, b, c);
        assert!(
            (got.0 - xi).abs() < 1e-15 && (got.1 - eta).abs() < 1e-15,
            "{p:?}: {got:?} against {:?}",
            (xi, eta)
        );
    }
    let mut rng = Rng(7);
    let r3 = |rng: &mut Rng| -> Vector { std::array::from_fn(|_| 2.0 * rng.next() - 1.0) };
    for _ in 0..200 {
        let x = [r3(&mut rng), r3(&mut rng), r3(&mut rng)];
        let p = r3(&mut rng).map(|v| 2.0 * v);
        let (xi, eta) = closest_on_triangle(p, x[0], x[1], x[2]);
        assert!(xi >= 0.0 && eta >= 0.0 && xi + eta <= 1.0 + 1e-15);
        let d = |xi: f64, eta: f64| {
            let r = sub(triangle_point(&x, xi, eta), p);
            dot(r, r).sqrt()
        };
        let best = d(xi, eta);
        let m = 60;
        for i in 0..=m {
            for j in 0..=m - i {
                let g = d(i as f64 / m as f64, j as f64 / m as f64);
                assert!(g >= best - 1e-12, "grid {g} closer than {best}");
            }
        }
    }
}

/// Points on the normal of the saddle `z = x y` (exactly the bilinear quadrilateral on
/// the unit square with corners `(0,0,0), (1,0,0), (1,1,1), (0,1,0)`) at a distance `d`
/// below its least radius of curvature (`1` at the origin, larger elsewhere): the closest
/// point is the foot `q`, its parameters `q`'s `(x, y)`, the normal
/// `(-y, -x, 1) / sqrt(1 + x^2 + y^2)` and the gap `d`.
#[test]
fn a_curved_quadrilateral_s_closest_point_is_the_foot_of_the_normal() {
    let x = [[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 1.0], [0.0, 1.0, 0.0]];
    for &(u, v) in &[
        (0.5f64, 0.5f64),
        (0.2, 0.7),
        (0.9, 0.1),
        (0.35, 0.35),
        (0.05, 0.95),
    ] {
        let l = (1.0 + u * u + v * v).sqrt();
        let n = [-v / l, -u / l, 1.0 / l];
        for d in [0.2, 0.05, -0.05, -0.2] {
            let p = [u + d * n[0], v + d * n[1], u * v + d * n[2]];
            let (xi, eta) = closest_on_quad(p, &x);
            assert!(
                (xi - u).abs() < 1e-12 && (eta - v).abs() < 1e-12,
                "({u}, {v}) d {d}: ({xi}, {eta})"
            );
            let nn = quad_normal(&x, xi, eta);
            assert!((0..3).all(|k| (nn[k] - n[k]).abs() < 1e-12), "{nn:?} {n:?}");
            let gap = dot(nn, sub(p, quad_point(&x, xi, eta)));
            assert!((gap - d).abs() < 1e-12, "gap {gap} against {d}");
        }
    }
    // Outside the square: the closest point is on an edge (a straight line): beyond the
    // edge xi = 1 (the line from (1,0,0) to (1,1,1)), at its parameter 1/2.
    let p = [1.5, 0.5, 0.5];
    let (xi, eta) = closest_on_quad(p, &x);
    assert!(
        (xi - 1.0).abs() < 1e-15 && (eta - 0.5).abs() < 1e-12,
        "({xi}, {eta})"
    );
}

/// The surface nodes of `mesh` (a box of side `2 r` at the origin's corner) pushed onto the
/// sphere of radius `r` about the box's centre: a sphere-like set of curved facets.
fn sphere_like(kind: CellKind, r: f64, n: usize) -> Mesh {
    let mut mesh = box_mesh(kind, [2.0 * r; 3], [n; 3]).unwrap();
    let on_surface: Vec<usize> = (0..mesh.n_nodes())
        .filter(|&i| {
            mesh.point(i)
                .iter()
                .any(|&c| c.abs() < 1e-12 || (c - 2.0 * r).abs() < 1e-12)
        })
        .collect();
    for i in on_surface {
        let p: Vector = std::array::from_fn(|d| mesh.coords[3 * i + d] - r);
        let s = r / dot(p, p).sqrt();
        for d in 0..3 {
            mesh.coords[3 * i + d] = r + s * p[d];
        }
    }
    mesh
}

/// On sphere-like facets (curved quadrilaterals, plane triangles), a point off each facet
/// along its own normal at a point `q` inside it finds that facet at `q`'s parameters with
/// the gap its distance, outside (positive) and inside (negative).
#[test]
fn points_on_the_normals_of_sphere_like_facets_find_their_foot() {
    let r = 0.5;
    for kind in [CellKind::Hex8, CellKind::Tet4] {
        let mesh = sphere_like(kind, r, 4);
        let mut s = FacetSearch::on_mesh(&mesh, None, FIXED, 0.1).unwrap();
        s.update(0.0, &vec![0.0; mesh.n_dofs()]);
        let params: &[(f64, f64)] = match kind {
            CellKind::Hex8 => &[(0.5, 0.5), (0.3, 0.6), (0.7, 0.25)],
            _ => &[(1.0 / 3.0, 1.0 / 3.0), (0.2, 0.5), (0.5, 0.3)],
        };
        for (k, f) in s.facets().iter().enumerate() {
            for &(xi, eta) in params {
                let (q, n) = on_facet(&mesh.coords, f, xi, eta);
                // Outward: away from the sphere's centre.
                assert!(dot(n, sub(q, [r; 3])) > 0.0, "{kind:?} facet {k}");
                for d in [0.01, -0.01] {
                    let p = std::array::from_fn(|c| q[c] + d * n[c]);
                    let t = s.find(p).expect("within reach");
                    assert_eq!(t.segment, k, "{kind:?} ({xi}, {eta}) d {d}");
                    assert!(
                        (t.xi - xi).abs() < 1e-11 && (t.eta - eta).abs() < 1e-11,
                        "{kind:?} facet {k}: ({}, {}) against ({xi}, {eta})",
                        t.xi,
                        t.eta
                    );
                    assert!((t.gap - d).abs() < 1e-13, "gap {} against {d}", t.gap);
                    assert!((0..3).all(|c| (t.normal[c] - n[c]).abs() < 1e-12));
                }
            }
        }
    }
}

/// Nodes exactly on the box's surface where facets meet: on an edge between two top
/// facets, on a vertex of four, on the box's corner (three faces): a gap of zero, the
/// closest point the node itself. Beyond the box's edge `x = 1, z = 1` the closest point
/// is on that edge: the distance `hypot(a, b)` from both the top and the side facet, and
/// the top's (the larger gap, `b`) is taken.
#[test]
fn a_node_on_an_edge_or_a_vertex_has_a_zero_gap() {
    for kind in [CellKind::Hex8, CellKind::Tet4] {
        let mesh = box_mesh(kind, [1.0; 3], [2; 3]).unwrap();
        let mut s = FacetSearch::on_mesh(&mesh, None, FIXED, 0.2).unwrap();
        s.update(0.0, &vec![0.0; mesh.n_dofs()]);
        for p in [
            [0.5, 0.25, 1.0],
            [0.5, 0.5, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 0.3, 0.7],
        ] {
            let t = s.find(p).unwrap();
            assert!(t.gap.abs() < 1e-15, "{kind:?} {p:?}: {}", t.gap);
            let (q, _) = on_facet(&mesh.coords, &s.facets()[t.segment], t.xi, t.eta);
            assert!((0..3).all(|d| (q[d] - p[d]).abs() < 1e-15), "{q:?} {p:?}");
        }
        let (a, b) = (0.01, 0.02);
        let t = s.find([1.0 + a, 0.3, 1.0 + b]).unwrap();
        assert!((t.gap - b).abs() < 1e-15, "{kind:?} gap {}", t.gap);
        assert_eq!(t.normal, [0.0, 0.0, 1.0]);
        let (q, _) = on_facet(&mesh.coords, &s.facets()[t.segment], t.xi, t.eta);
        assert!(
            (q[0] - 1.0).abs() < 1e-15 && (q[1] - 0.3).abs() < 1e-15 && (q[2] - 1.0).abs() < 1e-15,
            "{q:?}"
        );
        // Planar: a point above the top at height h has the gap h.
        let t = s.find([0.61, 0.13, 1.07]).unwrap();
        assert!((t.gap - 0.07).abs() < 1e-15 && t.normal == [0.0, 0.0, 1.0]);
        assert!(s.find([0.61, 0.13, 1.3]).is_none(), "beyond the reach");
    }
}

/// The hierarchy misses nothing: on a deformed, moving sphere-like surface, the search
/// answers every random point as trying every facet does (the same facet, or one at the
/// same distance with the same gap).
#[test]
fn the_hierarchy_finds_what_trying_every_facet_finds() {
    let mut rng = Rng(12345);
    for (kind, n) in [
        (CellKind::Hex8, 6),
        (CellKind::Tet4, 4),
        (CellKind::Tet10, 3),
    ] {
        let mesh = sphere_like(kind, 0.5, n);
        let master = Placed {
            motion: Motion::Translating {
                origin: [0.1, -0.2, 0.3],
                velocity: [2.0, 1.0, -0.5],
            },
            first_dof: 6,
        };
        let mut s = FacetSearch::on_mesh(&mesh, None, master, 0.15).unwrap();
        let mut u = vec![0.0; 6 + mesh.n_dofs()];
        for v in u.iter_mut().skip(6) {
            *v = 0.01 * (rng.next() - 0.5);
        }
        s.update(0.05, &u);
        let (mut found, mut trials) = (0, 0);
        for _ in 0..3000 {
            // Around the sphere's centre at t: (0.5 + 0.1 + 0.1, 0.5 - 0.2 + 0.05, ...).
            let c = [0.7, 0.35, 0.775];
            let p: Vector = std::array::from_fn(|d| c[d] + 1.4 * (rng.next() - 0.5));
            let (fast, brute) = (s.find(p), s.find_brute(p));
            trials += 1;
            match (fast, brute) {
                (None, None) => {}
                (Some(a), Some(b)) => {
                    found += 1;
                    let same = a.segment == b.segment || (a.gap - b.gap).abs() < 1e-15;
                    assert!(same, "{kind:?} {p:?}: {a:?} against {b:?}");
                }
                _ => panic!("{kind:?} {p:?}: {fast:?} against {brute:?}"),
            }
        }
        assert!(
            found > trials / 10,
            "{kind:?}: {found} of {trials} near the surface"
        );
    }
}

/// The row's gap `c . (X + u) - o` is the search's gap; its rate at fixed displacements is
/// `-w` (a translating master, a slave frame turning about z); the tangential rows are
/// orthogonal to the normal row on the slave node's dofs.
#[test]
fn the_row_gives_the_search_s_gap_and_w_its_rate() {
    let mesh = sphere_like(CellKind::Hex8, 0.5, 3);
    let master = Placed {
        motion: Motion::Translating {
            origin: [0.0, 0.0, -1.0],
            velocity: [3.0, -1.0, 2.0],
        },
        first_dof: 3,
    };
    let slave = Placed {
        motion: Motion::Rotating {
            centre: [0.4, 0.5, 0.0],
            omega: 20.0,
            angle0: 0.3,
        },
        first_dof: 0,
    };
    let mut s = FacetSearch::on_mesh(&mesh, None, master, 0.2).unwrap();
    let mut u = vec![0.0; 3 + mesh.n_dofs()];
    let mut rng = Rng(99);
    for v in u.iter_mut() {
        *v = 1e-3 * (rng.next() - 0.5);
    }
    let t = 0.01;
    s.update(t, &u);
    // A slave node just above the sphere's top at t: the sphere's centre is at
    // (0.5 + 0.03, 0.5 - 0.01, 0.5 - 1 + 0.02), its top at z = 0.02; the node's frame
    // turns about z.
    let ground = [0.56, 0.47, 0.02 + 0.03];
    let back = slave.motion.rotate_back(t, sub(ground, [0.4, 0.5, 0.0]));
    let x_ref: Vec<f64> = (0..3).map(|c| back[c] - u[c]).collect();
    let target = s.find(ground).unwrap();
    let row = s.normal_row_for_test(&target, slave, &x_ref, t, &u);
    let mut x_all: Vec<f64> = x_ref.clone();
    x_all.extend(&mesh.coords);
    let x_all: Vec<f64> = x_all.iter().zip(&u).map(|(a, b)| a + b).collect();
    let g = row.terms.dot(&x_all) - row.offset;
    assert!((g - target.gap).abs() < 1e-15, "{g} against {}", target.gap);
    let gap_at = |tt: f64| {
        let xa = slave.motion.place(tt, std::array::from_fn(|c| x_all[c]));
        let f = s.facets()[target.segment];
        let w = f.weights(target.xi, target.eta);
        let mut xf = [0.0; 3];
        for (&m, wm) in f.nodes().iter().zip(w) {
            let p = master
                .motion
                .place(tt, std::array::from_fn(|c| x_all[3 + 3 * m + c]));
            for c in 0..3 {
                xf[c] += wm * p[c];
            }
        }
        dot(target.normal, sub(xa, xf))
    };
    let dt = 1e-7;
    let rate = (gap_at(t + dt) - gap_at(t - dt)) / (2.0 * dt);
    assert!((rate + row.w).abs() < 1e-7, "rate {rate}, w {}", row.w);
    for k in 0..2 {
        let tr = s.tangent_row(&target, k, slave, 0, &x_ref, t, &u).unwrap();
        let on_node = |r: &SearchedRow| -> Vec<f64> {
            r.terms
                .iter()
                .filter(|&(d, _)| d < 3)
                .map(|(_, c)| c)
                .collect()
        };
        let (cn, ct) = (on_node(&row), on_node(&tr));
        let d: f64 = cn.iter().zip(&ct).map(|(a, b)| a * b).sum();
        assert!(d.abs() < 1e-15, "tangent {k}: {d}");
    }
    assert!(s.tangent_row(&target, 2, slave, 0, &x_ref, t, &u).is_none());
}

/// A master whose material turns under its mesh ([`MaterialSpin`]) gives its tangential rows
/// the surface velocity of a master whose frame really turns, at the instant the two
/// coincide (the turning frame's drift, [`Motion::Rotating`], is the same field); its normal
/// rows stay those of the master at rest, whose geometry it keeps.
#[test]
fn a_material_spin_slides_the_tangential_rows_as_a_turning_frame_does() {
    let mesh = sphere_like(CellKind::Hex8, 0.5, 3);
    let (centre, omega) = ([0.3, 0.6, -0.2], 7.0);
    let place = |motion| Placed {
        motion,
        first_dof: 3,
    };
    let turning = FacetSearch::on_mesh(
        &mesh,
        None,
        place(Motion::Rotating {
            centre,
            omega,
            angle0: 0.0,
        }),
        0.2,
    )
    .unwrap();
    let at_rest = FacetSearch::on_mesh(
        &mesh,
        None,
        place(Motion::Translating {
            origin: centre,
            velocity: [0.0; 3],
        }),
        0.2,
    )
    .unwrap();
    let spun = at_rest.clone().with_spin(Some(MaterialSpin {
        axis: [0.0, 0.0, 1.0],
        pivot: centre,
        rate: omega,
    }));
    let slave = Placed {
        motion: Motion::Translating {
            origin: [0.0; 3],
            velocity: [1.0, -2.0, 0.5],
        },
        first_dof: 0,
    };
    let mut u = vec![0.0; 3 + mesh.n_dofs()];
    let mut rng = Rng(7);
    for v in u.iter_mut() {
        *v = 1e-3 * (rng.next() - 0.5);
    }
    let mut searches = [turning, at_rest, spun];
    for s in searches.iter_mut() {
        s.update(0.0, &u);
    }
    // Points just off the sphere's top and sides (its centre at centre + (0.5, 0.5, 0.5)).
    for ground in [[0.85, 1.12, 0.85], [1.33, 1.05, 0.32], [0.78, 0.57, 0.25]] {
        let x_ref: Vec<f64> = (0..3).map(|c| ground[c] - u[c]).collect();
        let target = searches[0].find(ground).unwrap();
        assert_eq!(searches[2].find(ground), Some(target));
        let mut slid: f64 = 0.0;
        for k in 0..2 {
            let [tt, tr, ts] = [0, 1, 2].map(|i| {
                searches[i]
                    .tangent_row(&target, k, slave, 0, &x_ref, 0.0, &u)
                    .unwrap()
            });
            assert!(
                (ts.w - tt.w).abs() < 1e-12 * (1.0 + tt.w.abs()),
                "tangent {k} at {ground:?}: spun {}, turning {}",
                ts.w,
                tt.w
            );
            slid = slid.max((ts.w - tr.w).abs());
            assert_eq!(
                ts.terms.iter().collect::<Vec<_>>(),
                tt.terms.iter().collect::<Vec<_>>()
            );
        }
        assert!(slid > 0.1, "the spin slides the rows at {ground:?}: {slid}");
        let [nr, ns] =
            [1, 2].map(|i| searches[i].normal_row_for_test(&target, slave, &x_ref, 0.0, &u));
        assert_eq!(nr.w.to_bits(), ns.w.to_bits());
        assert_eq!(nr.offset.to_bits(), ns.offset.to_bits());
    }
}

impl FacetSearch {
    /// The normal row of slave node 0.
    fn normal_row_for_test(
        &self,
        target: &Target,
        slave: Placed,
        x_ref: &[f64],
        t: f64,
        u: &[f64],
    ) -> SearchedRow {
        MasterSurface::normal_row(self, target, slave, 0, x_ref, t, u)
    }
}

#[test]
fn bad_surfaces_and_searches_are_refused() {
    let planar = crate::mesh::generators::rectangle(1.0, 1.0, 2, 2).unwrap();
    assert!(matches!(
        surface_facets(&planar, None),
        Err(FacetError::Cells(_))
    ));
    let mesh = box_mesh(CellKind::Hex8, [1.0; 3], [1; 3]).unwrap();
    assert_eq!(
        surface_facets(&mesh, Some(&[0, 99])).unwrap_err(),
        FacetError::Region { node: 99, nodes: 8 }
    );
    let facets = surface_facets(&mesh, None).unwrap();
    let reference = mesh.coords.clone();
    for reach in [f64::NAN, 0.0, -1.0, f64::INFINITY] {
        assert!(matches!(
            FacetSearch::new(FIXED, reference.clone(), facets.clone(), reach),
            Err(FacetError::Reach(_))
        ));
    }
    let bad = |f: Facet| FacetSearch::new(FIXED, reference.clone(), vec![f], 0.1).unwrap_err();
    assert!(matches!(
        bad(Facet::Tri([0, 1, 1])),
        FacetError::Facet { .. }
    ));
    assert!(matches!(
        bad(Facet::Tri([0, 1, 8])),
        FacetError::Facet { .. }
    ));
    // Three nodes on a line: no area.
    let mut line = reference.clone();
    line[3 * 2..3 * 3].copy_from_slice(&[2.0, 0.0, 0.0]);
    assert!(matches!(
        FacetSearch::new(FIXED, line, vec![Facet::Tri([0, 1, 2])], 0.1),
        Err(FacetError::Facet { .. })
    ));
    assert_eq!(
        FacetSearch::new(FIXED, reference.clone(), Vec::new(), 0.1).unwrap_err(),
        FacetError::Empty
    );
    assert_eq!(
        FacetSearch::new(FIXED, vec![0.0; 4], facets, 0.1).unwrap_err(),
        FacetError::Reference(4)
    );
    // A face of three cells.
    let mut doubled = mesh.clone();
    let c = doubled.cells.connectivity().to_vec();
    let flat: Vec<usize> = c.iter().chain(&c).copied().collect();
    doubled.cells = crate::mesh::Cells::from_flat(CellKind::Hex8, &flat);
    assert!(
        surface_facets(&doubled, None).unwrap().is_empty(),
        "two copies: every face inner"
    );
    let tripled: Vec<usize> = c.iter().chain(&c).chain(&c).copied().collect();
    doubled.cells = crate::mesh::Cells::from_flat(CellKind::Hex8, &tripled);
    assert!(matches!(
        surface_facets(&doubled, None),
        Err(FacetError::NonManifold { cells: 3, .. })
    ));
}

/// Placing the facets and rebuilding the hierarchy reuses the buffers [`FacetSearch::new`]
/// sized: their addresses do not change over updates of a moving, deforming surface.
#[test]
fn an_update_allocates_nothing() {
    let mesh = sphere_like(CellKind::Hex8, 0.5, 5);
    let mut s = FacetSearch::on_mesh(&mesh, None, FIXED, 0.1).unwrap();
    let mut u = vec![0.0; mesh.n_dofs()];
    s.update(0.0, &u);
    let addresses = |s: &FacetSearch| (s.boxes.as_ptr(), s.bvh.addresses(), s.placed.as_ptr());
    let before = addresses(&s);
    let mut rng = Rng(3);
    for k in 1..20 {
        for v in u.iter_mut() {
            *v = 0.05 * (rng.next() - 0.5);
        }
        s.update(k as f64, &u);
        assert_eq!(addresses(&s), before);
    }
}
