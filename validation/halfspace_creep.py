"""An independent half-space answer for the coupled creep curve of `scenarios/creep-curve-coupled.toml`.

Steady plane rolling of an elastic roller (plane strain, E, nu) on a rigid plane, Coulomb
friction mu, Hertz's pressure p(x) = p0 sqrt(1 - x^2/a^2) held fixed (the tangential traction's
effect on the pressure is left out, as in Bentall and Johnson's and Kalker's 2D solutions with
the "Goodman" simplification). The roller's surface is a half-plane:

    eps(x) = du_x/dx = -K p(x) - C int q(s) / (x - s) ds,
    K = (1 - 2 nu)(1 + nu) / E,   C = 2 (1 - nu^2) / (pi E)

(Johnson, Contact Mechanics, 1985, Eq. 2.25), q the traction on the roller along x. The slip
of the roller against the plane over the rolling speed is s(x) = xi + eps(x), with xi the
creepage on the undeformed radius (the one `creep_curve.csv` gives as `creepage_undeformed`).
Stick: s = 0 and |q| <= mu p; slip: q = -mu p sign(s).

The strip [-a, a] is cut into n equal cells of constant traction, collocated at their
midpoints (the principal value of the self cell is zero); Coulomb's law is regularized and
solved by Newton's method as the regularization is taken to zero (`Strip.solve`). Q(xi) is
monotone: free rolling and Q/(mu P) = +-0.5 by regula falsi. The
answers are printed for n = 100, 200, 400, 800 (0.2650, 0.6183, 0.8977 at 800; they move
by at most 7e-4 from 400 to 800, not monotonically: no Richardson step is taken).

    python validation/halfspace_creep.py        (numpy; about 10 minutes, most at n = 800)

Checks inside: mu -> 0 gives Bentall and Johnson's 0.9148 beta a / R; full slip gives
|Q| = mu P; without the coupling (K = 0) Carter's curve.
"""

import sys

import numpy as np

E, NU = 2.05e11, 0.3
R, A, MU = 0.1, 1e-3, 0.3
ESTAR = E / (1.0 - NU * NU)
P0 = A * ESTAR / (2.0 * R)  # Hertz, plane: p0 = a E* / (2 R)
K = (1.0 - 2.0 * NU) * (1.0 + NU) / E
C = 2.0 * (1.0 - NU * NU) / (np.pi * E)
BETA = (1.0 - 2.0 * NU) / (2.0 * (1.0 - NU))


class Strip:
    def __init__(self, n, mu=MU):
        self.n, self.mu = n, mu
        edges = np.linspace(-A, A, n + 1)
        self.dx = edges[1] - edges[0]
        self.x = 0.5 * (edges[:-1] + edges[1:])
        # Mean pressure over each cell (exact integral of the semi-ellipse).
        def prim(t):
            t = np.clip(t / A, -1.0, 1.0)
            return 0.5 * A * (t * np.sqrt(1.0 - t * t) + np.arcsin(t))

        self.p = P0 * (prim(edges[1:]) - prim(edges[:-1])) / self.dx
        self.load = self.p.sum() * self.dx
        # H[i, j] = int_cell j ds / (x_i - s) = ln|x_i - s_a| - ln|x_i - s_b|.
        xi = self.x[:, None]
        with np.errstate(divide="ignore"):
            self.H = np.log(np.abs(xi - edges[None, :-1])) - np.log(np.abs(xi - edges[None, 1:]))

    def solve(self, xi):
        """The traction q for the creepage xi, and Q / (mu P).

        Coulomb's law regularized, q = -mu p s / sqrt(s^2 + delta^2), solved by Newton's
        method with a backtracking line search while delta falls from the creepage scale
        mu a / R to 2e-5 of it by factors of 2, each level starting from the last one's answer
        (n = 200, free rolling: 0.6202 / 0.6184 / 0.6183 mu a / R at delta = 1e-3 / 1e-4 / 1e-5
        of the scale).
        """
        mu_p = self.mu * self.p
        base = xi - K * self.p
        q = np.zeros(self.n)
        CH = C * self.H
        scale = MU * A / R

        def residual(q, delta):
            s = base - CH @ q
            root = np.sqrt(s * s + delta * delta)
            return q + mu_p * s / root, s, root

        delta = scale
        while delta > 2e-5 * scale:
            for _ in range(500):
                f, s, root = residual(q, delta)
                norm = np.linalg.norm(f)
                if np.max(np.abs(f)) < 1e-10 * self.mu * P0:
                    break
                ds = mu_p * delta * delta / root**3
                step = np.linalg.solve(np.eye(self.n) - ds[:, None] * CH, -f)
                t = 1.0
                while t > 1e-6 and np.linalg.norm(residual(q + t * step, delta)[0]) > (1 - 1e-4 * t) * norm:
                    t *= 0.5
                q = q + t * step
            else:
                raise RuntimeError(f"Newton did not converge at delta {delta:e}")
            delta *= 0.5
        # softway's `traction_ratio` is the force on the base: the reaction of q.
        return q, -q.sum() * self.dx / (self.mu * self.load)

    def creepage_at(self, ratio):
        """The creepage at which Q / (mu P) = ratio: the curve rises monotonically from
        -1 to +1; a bracket is widened from the creepage scale, then closed by the Illinois
        variant of regula falsi."""
        unit = MU * A / R
        lo, hi = -unit, 2.0 * unit
        f_lo, f_hi = self.solve(lo)[1] - ratio, self.solve(hi)[1] - ratio
        while f_lo > 0.0:
            lo -= unit
            f_lo = self.solve(lo)[1] - ratio
        while f_hi < 0.0:
            hi += unit
            f_hi = self.solve(hi)[1] - ratio
        side = 0
        for _ in range(100):
            x = (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
            f = self.solve(x)[1] - ratio
            if abs(f) < 1e-9 or hi - lo < 1e-9 * unit:
                return x
            if f < 0.0:
                lo, f_lo = x, f
                if side == -1:
                    f_hi *= 0.5
                side = -1
            else:
                hi, f_hi = x, f
                if side == 1:
                    f_lo *= 0.5
                side = 1
        raise RuntimeError("regula falsi did not converge")


def main():
    unit = MU * A / R
    # Checks: full slip, and Bentall and Johnson's mu -> 0 limit.
    s = Strip(400)
    full = s.solve(10 * A / R)[1]
    print(f"full slip: Q/(mu P) = {full:+.6f}")
    global K
    k, K = K, 0.0
    carter = Strip(400).creepage_at(0.75) / unit
    K = k
    print(f"uncoupled (K = 0), Q/(mu P) = 0.75: xi = {carter:.4f} mu a / R (Carter 0.5)")
    bj = Strip(400, mu=1e-3).creepage_at(0.0) / (BETA * A / R)
    print(f"mu -> 0 free rolling: {bj:.4f} beta a / R (Bentall and Johnson 0.9148)")
    ratios = [-0.5, 0.0, 0.5]
    rows = []
    for n in [100, 200, 400, 800]:
        s = Strip(n)
        row = [s.creepage_at(r) / unit for r in ratios]
        rows.append(row)
        print(f"n = {n:5d}: xi / (mu a / R) = " + ", ".join(f"{v:.4f}" for v in row), flush=True)
    r = np.array(rows)
    print(
        "change from the last but one: "
        + ", ".join(f"{v:+.4f}" for v in r[-1] - r[-2])
        + " (mu a / R): the cells' error is below that, not of one sign"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
