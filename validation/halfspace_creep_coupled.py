"""The coupled creep curve of `scenarios/creep-curve-coupled.toml` on a half-space, the pressure
solved with the traction (no Goodman simplification).

`halfspace_creep.py` holds the pressure at Hertz's. On a steel roller against a rigid plane
the coupling also runs the other way: the traction q tilts the surface,

    du_z/dx = -C int p(s) / (x - s) ds + K q(x),
    K = (1 - 2 nu)(1 + nu) / E,   C = 2 (1 - nu^2) / (pi E)

(Johnson, Contact Mechanics, 1985, Eq. 2.25b; z into the roller), so that the pressure that
fits the plane moves with the traction. Here both are solved, on a strip of constant-traction
cells over [-1.5 a, 1.5 a] (a Hertz's half-width of the load P):

- normal, for a given q: the displacement form of the condition, collocated at the cells'
  midpoints, C sum_j L_ij p_j = x_i^2 / (2 R) + K int_{-inf}^{x_i} q - D in the contact set,
  L_ij = int_cell_j ln|x_i - s| ds, the approach D unknown, sum_j p_j dx = P; the set
  found by an active-set loop (cells with p < 0 leave it, cells that would overlap the plane
  join it);
- tangential, for a given p: `halfspace_creep.Strip.solve`'s regularized Coulomb law by
  Newton's method, on the same cells (continued below 1e-3 of the creepage scale as far as
  Newton converges; the solves stopped there are counted and printed);
- for a contact set the pressure is an affine map of the traction (the normal condition is
  linear in both), so the two are one Newton solve; the set is then updated until it holds
  (alternating the two problems instead cycles near full slip: a cell at the stick-slip
  boundary flips each time).

    python validation/halfspace_creep_coupled.py [cells ...]   (numpy; 150, 300, 600 cells
                                                               by default: about an hour)

Checks inside: with q = 0 the pressure is Hertz's (peak and half-width); with the coupling
left out of the pressure (the Goodman simplification) the curve is `halfspace_creep.py`'s.
"""

import sys

import numpy as np

import halfspace_creep as hs
from halfspace_creep import A, C, K, MU, P0, R

LOAD = 0.5 * np.pi * A * P0  # Hertz: P' = pi a p0 / 2 per metre


class Coupled:
    def __init__(self, n, window=1.5, mu=MU, coupled=True):
        self.n, self.mu, self.coupled = n, mu, coupled
        edges = np.linspace(-window * A, window * A, n + 1)
        self.dx = edges[1] - edges[0]
        self.x = 0.5 * (edges[:-1] + edges[1:])
        xi = self.x[:, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            self.H = np.log(np.abs(xi - edges[None, :-1])) - np.log(np.abs(xi - edges[None, 1:]))

            def f(t):
                at = np.abs(t)
                return np.where(at > 0.0, t * np.log(np.where(at > 0.0, at, 1.0)) - t, 0.0)

            self.L = f(xi - edges[None, :-1]) - f(xi - edges[None, 1:])
        self.active = np.abs(self.x) < A
        self.stalled = 0  # solves whose continuation stopped early (below 1e-3 of the scale)
        # int_{-inf}^{x_i} q ds = cum @ q: the cells before, and half of its own.
        self.cum = self.dx * (np.tril(np.ones((n, n)), -1) + 0.5 * np.eye(n))
        self.hertz = P0 * np.sqrt(np.clip(1.0 - (self.x / A) ** 2, 0.0, None))

    def affine(self, act):
        """The pressure for the contact set `act` as an affine map of the traction,
        p = p0 + T q: the displacement form in the set, C sum_j L_ij p_j = x_i^2 / (2 R) +
        K int_{-inf}^{x_i} q - D, and sum_j p_j dx = P, with D unknown."""
        idx = np.flatnonzero(act)
        m = len(idx)
        M = np.zeros((m + 1, m + 1))
        M[:m, :m] = C * self.L[np.ix_(idx, idx)]
        M[:m, m] = 1.0
        M[m, :m] = self.dx
        Minv = np.linalg.inv(M)
        p0 = np.zeros(self.n)
        p0[idx] = (Minv @ np.concatenate([self.x[idx] ** 2 / (2.0 * R), [LOAD]]))[:m]
        T = np.zeros((self.n, self.n))
        if self.coupled:
            T[idx, :] = Minv[:m, :m] @ (K * self.cum[idx, :])
        return p0, T

    def settle_set(self, p):
        """The contact set after the pressure p on the current one: the most negative cell
        leaves it, else the most overlapping cell outside joins it; None if it holds."""
        act = self.active
        idx = np.flatnonzero(act)
        if p[idx].min() < 0.0:
            new = act.copy()
            new[idx[np.argmin(p[idx])]] = False
            return new
        q = self.q
        rhs = self.x**2 / (2.0 * R) + (K * (self.cum @ q) if self.coupled else 0.0)
        d = np.mean((rhs - C * (self.L @ p))[idx])
        gap = rhs - d - C * (self.L @ p)
        gap[act] = 0.0
        if gap.min() < -1e-12 * A * A / R:
            new = act.copy()
            new[np.argmin(gap)] = True
            return new
        return None

    def solve(self, xi):
        """The traction and pressure for the creepage xi, and Q / (mu P): for a contact set,
        the regularized Coulomb law (`halfspace_creep.Strip.solve`'s) with the pressure p0 +
        T q solved by Newton's method (its Jacobian carries T); the set then updated until it
        holds."""
        CH = C * self.H
        scale = MU * A / R
        q = np.zeros(self.n)
        for _ in range(4 * self.n):
            p0, T = self.affine(self.active)

            def residual(q, delta):
                p = p0 + T @ q
                s = xi - K * p - CH @ q
                root = np.sqrt(s * s + delta * delta)
                return q + self.mu * p * s / root, p, s, root

            delta = scale
            while delta > 2e-5 * scale:
                q_level = q
                for _ in range(500):
                    f, p, s, root = residual(q, delta)
                    norm = np.linalg.norm(f)
                    if np.max(np.abs(f)) < 1e-10 * self.mu * P0:
                        break
                    ds = self.mu * p * delta * delta / root**3
                    J = np.eye(self.n) + (self.mu * s / root)[:, None] * T - ds[:, None] * (K * T + CH)
                    step = np.linalg.solve(J, -f)
                    t = 1.0
                    while t > 1e-6 and np.linalg.norm(residual(q + t * step, delta)[0]) > (1 - 1e-4 * t) * norm:
                        t *= 0.5
                    q = q + t * step
                else:
                    # On fine strips the last levels can stall (the law is nearly a step);
                    # below 1e-3 of the scale the answer has settled (Strip.solve's
                    # docstring: 1e-4 of the scale is within 1e-4 of the limit).
                    if delta > 1e-3 * scale:
                        raise RuntimeError(f"Newton did not converge at delta {delta:e}")
                    self.stalled += 1
                    q = q_level
                    break
                delta *= 0.5
            p = p0 + T @ q
            self.q = q
            new = self.settle_set(p)
            if new is None:
                self.p = p
                return q, -q.sum() * self.dx / (self.mu * LOAD)
            self.active = new
        raise RuntimeError("the contact set did not settle")

    def normal(self, q):
        """The pressure for the traction q (the contact set settled)."""
        self.q = q
        for _ in range(4 * self.n):
            p0, T = self.affine(self.active)
            p = p0 + T @ q
            new = self.settle_set(p)
            if new is None:
                return p
            self.active = new
        raise RuntimeError("the contact set did not settle")

    creepage_at = hs.Strip.creepage_at


def main():
    unit = MU * A / R
    s = Coupled(300)
    p = s.normal(np.zeros(s.n))
    inside = np.abs(s.x) < 0.9 * A
    print(
        f"q = 0: peak pressure {p.max() / P0:.4f} p0, contact cells {s.active.sum()} "
        f"({s.active.sum() * s.dx / (2 * A):.3f} of 2a), "
        f"largest difference from Hertz's inside 0.9 a {np.abs(p - s.hertz)[inside].max() / P0:.2e} p0"
    )
    ratios = [-0.5, 0.0, 0.5]
    for n in [int(v) for v in sys.argv[1:]] or [150, 300, 600]:
        row_g = [Coupled(n, coupled=False).creepage_at(r) / unit for r in ratios]
        c = Coupled(n)
        row_c = [c.creepage_at(r) / unit for r in ratios]
        print(
            f"n = {n:4d} over 3a: Goodman "
            + ", ".join(f"{v:.4f}" for v in row_g)
            + "; coupled "
            + ", ".join(f"{v:.4f}" for v in row_c)
            + (f" ({c.stalled} solves stopped below 1e-3 of the scale)" if c.stalled else ""),
            flush=True,
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
