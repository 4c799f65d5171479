//! The coefficients of a constraint row on at most [`MAX_TERMS`] dofs
//! ([`crate::contact::rows`]).

/// Most dofs one row acts on: a node against a quadrilateral facet in 3D, five nodes of
/// three components ([`crate::contact::facets`]).
pub const MAX_TERMS: usize = 15;

/// The coefficients of a row on at most [`MAX_TERMS`] dofs. The dofs are kept as `u32`
/// (a model of more than 4e9 dofs is far beyond any factorization): a row is copied with
/// every pair's state in every step, and its size is what the copies cost.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Terms {
    len: u32,
    dof: [u32; MAX_TERMS],
    coef: [f64; MAX_TERMS],
}

impl Default for Terms {
    fn default() -> Self {
        Self {
            len: 0,
            dof: [0; MAX_TERMS],
            coef: [0.0; MAX_TERMS],
        }
    }
}

impl Terms {
    /// Adds `coef` on `dof`.
    ///
    /// # Panics
    /// Beyond [`MAX_TERMS`] terms.
    pub fn push(&mut self, dof: usize, coef: f64) {
        let k = self.len as usize;
        assert!(k < MAX_TERMS, "a row acts on at most {MAX_TERMS} dofs");
        self.dof[k] = u32::try_from(dof).expect("a dof index below 2^32");
        self.coef[k] = coef;
        self.len += 1;
    }

    /// `*self = *src`, copying only the terms in use: the same value, since the unused
    /// entries of every row are zero (a row is made by [`Terms::default`] and
    /// [`Terms::push`] alone). A pair's state carries up to two rows and is recorded every
    /// step; a whole copy moves all [`MAX_TERMS`] of each.
    pub fn assign(&mut self, src: &Terms) {
        let (n, m) = (src.len as usize, self.len as usize);
        self.dof[..n].copy_from_slice(&src.dof[..n]);
        self.coef[..n].copy_from_slice(&src.coef[..n]);
        if m > n {
            self.dof[n..m].fill(0);
            self.coef[n..m].fill(0.0);
        }
        self.len = src.len;
    }

    /// The `(dof, coefficient)` pairs.
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        (0..self.len as usize).map(|i| (self.dof[i] as usize, self.coef[i]))
    }

    /// `c . x`.
    pub fn dot(&self, x: &[f64]) -> f64 {
        let mut s = 0.0;
        for i in 0..self.len as usize {
            s += self.coef[i] * x[self.dof[i] as usize];
        }
        s
    }

    /// The same row on relabelled nodes of a model of `dim` (2 or 3) unknowns per node: the
    /// terms of node `m` move to node `node(m)` with their coefficients turned by the
    /// rotation `rot` (row-major; its leading `dim x dim` block); `None` when a node has no
    /// new label. Nodes from `turned` on (another body's, in a frame that does not turn)
    /// move as `node` says with their coefficients as they are.
    pub fn relabel(
        &self,
        dim: usize,
        node: impl Fn(usize) -> Option<usize>,
        rot: [[f64; 3]; 3],
        turned: usize,
    ) -> Option<Terms> {
        let mut out = Terms::default();
        let mut seen = [usize::MAX; MAX_TERMS];
        let mut k = 0;
        let len = self.len as usize;
        for i in 0..len {
            let m = self.dof[i] as usize / dim;
            if seen[..k].contains(&m) {
                continue;
            }
            seen[k] = m;
            k += 1;
            let mut c = [0.0; 3];
            for j in 0..len {
                if self.dof[j] as usize / dim == m {
                    c[self.dof[j] as usize % dim] += self.coef[j];
                }
            }
            let n = node(m)?;
            for (comp, r) in rot.iter().enumerate().take(dim) {
                let mut v = 0.0;
                if m < turned {
                    for q in 0..dim {
                        v += r[q] * c[q];
                    }
                } else {
                    v = c[comp];
                }
                out.push(dim * n + comp, v);
            }
        }
        Some(out)
    }

    /// `y[dof] += s c` for every term.
    pub fn scatter(&self, s: f64, y: &mut [f64]) {
        for i in 0..self.len as usize {
            y[self.dof[i] as usize] += self.coef[i] * s;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::PairMode;

    fn row(n: usize, seed: f64) -> Terms {
        let mut t = Terms::default();
        for i in 0..n {
            t.push(3 * i + 1, seed + i as f64);
        }
        t
    }

    /// Assigning by the terms in use gives the value a whole copy gives (all fields, the
    /// unused entries included), whether the row grows, shrinks or empties.
    #[test]
    fn assigning_the_terms_in_use_equals_a_whole_copy() {
        for (a, b) in [(0, 0), (0, 6), (6, 0), (15, 4), (4, 15), (9, 9)] {
            let src = row(b, 2.5);
            let mut dst = row(a, -7.0);
            dst.assign(&src);
            assert_eq!(dst, src, "{a} -> {b} terms");
            assert_eq!(format!("{dst:?}"), format!("{src:?}"));
        }
    }

    /// A row on a turned body's node and another body's: the first node's terms move and
    /// turn, the second's move as the map says with their coefficients kept; a node without
    /// a label drops the row.
    #[test]
    fn a_relabelled_row_turns_only_the_turned_bodys_terms() {
        let mut t = Terms::default();
        // Node 1 (turned) along x, node 5 (the other body's) along (0, 1, 2).
        t.push(3, 1.0);
        t.push(16, 1.0);
        t.push(17, 2.0);
        let (c, s) = (0.6_f64, 0.8_f64);
        let rot = [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]];
        let r = t
            .relabel(3, |m| Some(if m == 1 { 2 } else { m }), rot, 4)
            .unwrap();
        let mut x = vec![0.0; 18];
        r.scatter(1.0, &mut x);
        assert_eq!(&x[6..9], &[c, -s, 0.0]);
        assert_eq!(&x[15..18], &[0.0, 1.0, 2.0]);
        assert!(t.relabel(3, |m| (m == 1).then_some(2), rot, 4).is_none());
    }

    /// A mode assigned equals the source for every pair of variants.
    #[test]
    fn assigning_a_mode_equals_a_whole_copy() {
        let modes = [
            PairMode::Free,
            PairMode::Hold,
            PairMode::Brake {
                q: 0.5,
                terms: row(6, 1.0),
                w: -0.1,
            },
            PairMode::Brake {
                q: -2.0,
                terms: row(15, 3.0),
                w: 0.0,
            },
        ];
        for a in &modes {
            for b in &modes {
                let mut dst = *a;
                dst.assign(b);
                assert_eq!(&dst, b);
            }
        }
    }
}
