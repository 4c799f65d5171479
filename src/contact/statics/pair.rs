//! The rows of two elastic bodies in static contact ([`super`], Two elastic bodies): each
//! slave node of one body against the master facet of the other that the facet search
//! finds for it in the undeformed configuration ([`FacetSearch::find`]), frozen (small
//! deformation).

use super::Row;
use crate::contact::facets::FacetSearch;

/// A slave node's row against the master surface, with what the search found.
#[derive(Debug, Clone, PartialEq)]
pub struct FacetRow {
    /// The row (its first node the slave node, in the model's numbering).
    pub row: Row,
    /// The gap in the undeformed configuration, m.
    pub gap: f64,
}

/// The rows of the `slaves` (nodes of the model, reference positions `x`, three per node)
/// against the facets of `search`, whose master body's node `i` is the model's node
/// `master_first_node + i` (the search placed once, undeformed); a slave node with no facet
/// within the search's reach has no row. The offsets are 0: the gap is the bodies' own
/// ([`Row::node_to_facet`]).
pub fn facet_rows(
    x: &[f64],
    slaves: &[usize],
    search: &FacetSearch,
    master_first_node: usize,
) -> Vec<FacetRow> {
    let mut rows = Vec::with_capacity(slaves.len());
    for &s in slaves {
        let Some(p) = x.get(3 * s..3 * s + 3) else {
            continue;
        };
        let Some(t) = search.find([p[0], p[1], p[2]]) else {
            continue;
        };
        let facet = search.facets()[t.segment];
        let w = facet.weights(t.xi, t.eta);
        let nodes: Vec<(usize, f64)> = facet
            .nodes()
            .iter()
            .zip(w)
            .map(|(&i, wi)| (master_first_node + i, wi))
            .collect();
        rows.push(FacetRow {
            row: Row::node_to_facet(s, &nodes, t.normal, 0.0),
            gap: t.gap,
        });
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::search::{Motion, Placed};
    use crate::contact::statics::{FactorChoice, Statics};
    use crate::linalg::Pattern;

    /// Two unit springs in series, a slave node above a master facet of four nodes each
    /// on a spring to the ground: pressed together by an offset `o` (a closure), the
    /// contact force is `k_s k_m / (k_s + k_m) o` by the springs in series, and the
    /// weights `+1, -1/4 x 4` sum to 0.
    #[test]
    fn a_slave_node_pressed_on_a_facet_carries_the_force_of_springs_in_series() {
        // Master: a unit square facet at z = 0 (nodes 0..4), slave node 4 at its centre,
        // z = 0.001 above it.
        let master = vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0];
        let facets = vec![crate::contact::facets::Facet::Quad([0, 1, 2, 3])];
        let placed = Placed {
            motion: Motion::Fixed,
            first_dof: 0,
        };
        let mut search = FacetSearch::new(placed, master.clone(), facets, 0.1).unwrap();
        let n = 15;
        search.update(0.0, &vec![0.0; n]);
        let mut x = master;
        x.extend([0.5, 0.5, 0.001]);
        let rows = facet_rows(&x, &[4], &search, 0);
        assert_eq!(rows.len(), 1);
        assert!((rows[0].gap - 0.001).abs() < 1e-15);
        let sum: f64 = rows[0].row.nodes.iter().map(|n| n.1).sum();
        assert!(sum.abs() < 1e-15, "weights sum {sum}");
        // K: every dof on a spring to the ground, k_s = 3 on the slave, k_m = 1 on each
        // master node (the facet's four in parallel through weights 1/4: 4 x (1/4)^2 = 1/4
        // of a unit spring, a compliance 4 x 1/16 x 1 = 1/4).
        let pattern = Pattern::new_checked(n, n, (0..=n).collect(), None, (0..n).collect());
        let k: Vec<f64> = (0..n).map(|i| if i >= 12 { 3.0 } else { 1.0 }).collect();
        let mut row = rows[0].row.clone();
        let o = 0.003;
        row.offset = o;
        let mut st = Statics::new(
            &pattern,
            &k,
            &[],
            &vec![0.0; n],
            3,
            vec![row],
            FactorChoice::Lu,
        )
        .unwrap();
        let sol = st.solve(&x).unwrap();
        assert!(sol.converged && sol.active.len() == 1);
        // Closing the gap g0 - o = -0.002 through the compliance 1/3 + 1/4.
        let expected = (o - 0.001) / (1.0 / 3.0 + 0.25);
        let lam = sol.active[0].1;
        assert!((lam / expected - 1.0).abs() < 1e-12, "{lam} vs {expected}");
        // The slave moves up by lam / 3 and each master node down by lam / 4 / 1.
        assert!((sol.u[14] - lam / 3.0).abs() < 1e-15);
        assert!((sol.u[2] + lam / 4.0).abs() < 1e-15);
    }
}
