//! Mass redistribution (Khenous, Laborde & Renard 2008): the contact nodes carry no mass,
//! so an impact takes no kinetic energy from them; contact is then enforced exactly.

use crate::linalg::Pattern;
use crate::model::LinearModel;

/// Makes the dofs of `nodes` massless (Khenous, Laborde & Renard 2008): their rows and
/// columns of `M` are zeroed and the mass removed is added to the diagonal of the
/// neighbouring dofs of the same direction (those coupled in the pattern, contact dofs
/// excluded), so the total mass in each direction is kept. Returns the massless dofs.
pub fn redistribute_mass(model: &mut LinearModel, dim: usize, nodes: &[usize]) -> Vec<usize> {
    let n = model.n();
    let mut contact = vec![false; n];
    for &nd in nodes {
        for c in 0..dim {
            contact[dim * nd + c] = true;
        }
    }
    let pattern: Pattern = model.pattern().clone();
    let cp = pattern.col_ptr();
    let ri = pattern.row_idx();
    let mut dofs = Vec::new();
    for d in 0..n {
        if !contact[d] {
            continue;
        }
        dofs.push(d);
        // Removed: row d plus column d, the diagonal once.
        let mut removed = 0.0;
        for j in 0..n {
            for p in cp[j]..cp[j + 1] {
                let i = ri[p];
                if i == d || j == d {
                    removed += model.m[p];
                    model.m[p] = 0.0;
                }
            }
        }
        let neighbours: Vec<usize> = (cp[d]..cp[d + 1])
            .map(|p| ri[p])
            .filter(|&i| i != d && !contact[i] && i % dim == d % dim)
            .collect();
        if neighbours.is_empty() {
            continue;
        }
        let share = removed / neighbours.len() as f64;
        for &j in &neighbours {
            for p in cp[j]..cp[j + 1] {
                if ri[p] == j {
                    model.m[p] += share;
                }
            }
        }
    }
    dofs
}
