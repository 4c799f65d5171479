"""Kalker's linear creep coefficients C11, C22, C23 from the full-stick limit of the steady
rolling problem of halfspace.py (vanishing creepage: no slip anywhere, so the traction solves
D q = w on the contact ellipse), on a ladder of grids with n x n cells over the ellipse's
bounding box (the cells whose centres lie inside the ellipse), with a Richardson limit.

Reference: Kalker 1990 ("Three-dimensional elastic bodies in rolling contact", Table E.3; the
same values as Johnson 1985 Table 8.1 after Kalker 1967), as tabulated in CONTACT's
src/m_hertz.f90 (eve70a/CONTACT, subroutine linrol); for nu = 0.28, and a/b between the table's
rows, CONTACT's interpolation (linear in the row, a parabola in nu of the reciprocals).

Cases: nu = 0.25 with a/b = 1 and a/b = 0.5 (table entries, no interpolation), and the steel
case of scenarios/press-hertz.toml (G = 82 GPa, nu = 0.28, 10 kN, A = 1/(2 0.46 m),
B = 1/(2 0.3 m)) with Hertz's a/b. The coefficients do not depend on G or the load.

python kalker_coefficients.py [n ...]      (default 10 20 40 80; about 3 minutes on 2 cores)
"""
import sys
import time
import numpy as np
from halfspace import Grid, Rolling, ellipse_cells, hertz, kalker_table


def ladder(a, b, nu, ns, method="linear_coefficients"):
    """Per grid of n x n cells: (n, cells, coefficients of Rolling.<method>(a, b)..., seconds)."""
    rows = []
    for n in ns:
        t = time.time()
        g = Grid.box(a, b, n, n)
        idx = ellipse_cells(g, a, b)
        r = Rolling(g, 1.0, nu, idx)
        rows.append((n, len(idx)) + tuple(getattr(r, method)(a, b)) + (time.time() - t,))
        del r
    return rows


def richardson(v, ratio=2.0):
    """Limit and observed order from the last three rungs (grid ratio 2)."""
    v0, v1, v2 = v[-3:]
    d1, d2 = v1 - v0, v2 - v1
    if d1 * d2 <= 0 or abs(d2) >= abs(d1):
        return float("nan"), float("nan")
    p = np.log(d1 / d2) / np.log(ratio)
    return v2 + d2 / (ratio ** p - 1), p


def main(ns):
    G, nu_s, F = 82e9, 0.28, 10e3
    h = hertz(1 / (2 * 0.46), 1 / (2 * 0.3), G / (1 - nu_s), F)
    cases = [("nu=0.25 a/b=1", 1.0, 1.0, 0.25),
             ("nu=0.25 a/b=0.5", 0.5, 1.0, 0.25),
             ("press-hertz nu=0.28 a/b=%.4f" % (h["a"] / h["b"]), h["a"], h["b"], nu_s)]
    out = []
    for name, a, b, nu in cases:
        ref = kalker_table(nu, a / b)
        rows = ladder(a, b, nu, ns)
        print(f"\n{name}: Kalker (Table E.3) C11 = {ref[0]:.3f}, C22 = {ref[1]:.3f}, C23 = {ref[2]:.3f}")
        print("    n  cells      C11      C22      C23   time/s")
        for r in rows:
            print(f"  {r[0]:3d}  {r[1]:5d}  {r[2]:7.4f}  {r[3]:7.4f}  {r[4]:7.4f}  {r[5]:6.1f}")
        for k, lab in enumerate(("C11", "C22", "C23")):
            v = [r[2 + k] for r in rows]
            lim, p = richardson(v) if len(v) >= 3 else (float("nan"), float("nan"))
            print(f"  {lab}: finest {v[-1]:.4f} ({100 * (v[-1] / ref[k] - 1):+.2f} %), Richardson "
                  f"{lim:.4f} ({100 * (lim / ref[k] - 1):+.2f} %, observed order {p:.2f}); table {ref[k]:.3f}")
            out.append((name, lab, v[-1], lim, p, ref[k]))
    return out


if __name__ == "__main__":
    ns = [int(s) for s in sys.argv[1:]] or [10, 20, 40, 80]
    main(ns)
