use super::*;

/// The pattern of an `m x m x m` grid of nodes with `per` unknowns each, every node coupled
/// to its 26 neighbours (the pattern of trilinear hexahedra).
fn grid3(m: usize, per: usize) -> Pattern {
    let node = |x: usize, y: usize, z: usize| x + m * (y + m * z);
    let n = per * m * m * m;
    let (mut cp, mut ri) = (vec![0usize], Vec::new());
    for z in 0..m {
        for y in 0..m {
            for x in 0..m {
                let mut col = Vec::new();
                for dz in -1i64..=1 {
                    for dy in -1i64..=1 {
                        for dx in -1i64..=1 {
                            let (a, b, c) = (x as i64 + dx, y as i64 + dy, z as i64 + dz);
                            let inside = |v: i64| (0..m as i64).contains(&v);
                            if inside(a) && inside(b) && inside(c) {
                                let o = node(a as usize, b as usize, c as usize);
                                col.extend((0..per).map(|d| per * o + d));
                            }
                        }
                    }
                }
                col.sort_unstable();
                for _ in 0..per {
                    ri.extend_from_slice(&col);
                    cp.push(ri.len());
                }
            }
        }
    }
    Pattern::new_checked(n, n, cp, None, ri)
}

/// A node's three unknowns are one vertex of the compressed graph, of weight 3, and the
/// compressed graph is the node graph: 26 neighbours inside, 7 at a corner.
#[test]
fn the_unknowns_of_a_node_are_one_vertex() {
    let m = 6;
    let (g, mptr, members) = Graph::compressed(&grid3(m, 3));
    assert_eq!(g.n(), m * m * m);
    assert!(g.vwt.iter().all(|&w| w == 3));
    for v in 0..g.n() {
        let mine = &members[mptr[v]..mptr[v + 1]];
        assert!(mine.iter().all(|&i| i / 3 == mine[0] / 3));
    }
    let degrees: Vec<usize> = (0..g.n()).map(|v| g.ptr[v + 1] - g.ptr[v]).collect();
    assert_eq!(degrees.iter().copied().max(), Some(26));
    assert_eq!(degrees.iter().copied().min(), Some(7));
    assert!((Graph::unknowns_per_vertex(&grid3(m, 3)) - 3.0).abs() < 1e-12);
    assert!((Graph::unknowns_per_vertex(&grid3(m, 2)) - 2.0).abs() < 1e-12);
}

/// The separator of a cube of nodes separates (no edge joins the two sides), the sides are
/// balanced within 35/65, and it is no larger than twice a plane cut across the cube
/// (`m^2` nodes: the least separator of the 26-neighbour grid is a plane, Lipton, Rose and
/// Tarjan 1979 bound it by `O(n^{2/3})`).
#[test]
fn a_cube_is_separated_by_about_a_plane() {
    for m in [12, 17] {
        let (g, _, _) = Graph::compressed(&grid3(m, 1));
        let side = separator(&g, &mut Rng(7));
        for v in 0..g.n() {
            for e in g.ptr[v]..g.ptr[v + 1] {
                let u = g.adj[e];
                assert!(side[v] + side[u] != 1, "{m}: an edge {v}-{u} from A to B");
            }
        }
        let count = |s: u8| side.iter().filter(|&&x| x == s).count();
        let (a, b, s) = (count(0), count(1), count(2));
        assert!(20 * a.min(b) >= 7 * (a + b), "{m}: sides {a} and {b}");
        assert!(
            s <= 2 * m * m,
            "{m}: a separator of {s} nodes against a plane's {}",
            m * m
        );
    }
}

/// The ordering is a permutation, and its factor's fill on a cube of nodes with three
/// unknowns each is below AMD's.
#[test]
fn nested_dissection_is_a_permutation_with_less_fill_than_amd() {
    let pattern = grid3(14, 3);
    let n = pattern.ncols();
    let (fwd, inv) = nested_dissection(&pattern).unwrap();
    let mut seen = vec![false; n];
    for (p, &i) in fwd.iter().enumerate() {
        assert!(!seen[i]);
        seen[i] = true;
        assert_eq!(inv[i], p);
    }
    let (_, amd_inv) =
        super::super::lu::column_ordering(&pattern, super::super::Ordering::Amd).unwrap();
    let nd = super::super::split::factor_entries(&pattern, &inv);
    let amd = super::super::split::factor_entries(&pattern, &amd_inv);
    assert!(nd < amd, "nested dissection {nd} against AMD {amd}");
}
