"""Small checks of halfspace.py (under a minute): Hertz's normal problem and Kalker's C11.
Not part of .ci/run; run with `python -m pytest validation/halfspace3d`."""
import numpy as np
from halfspace import (Grid, Rolling, contact_measures, ellipse_cells, hertz, kalker_table,
                       normal_matrix, rect_integrals, solve_normal)

G, NU, F = 82e9, 0.28, 10e3
A, B = 1 / (2 * 0.46), 1 / (2 * 0.3)


def test_rectangle_integral_matches_quadrature():
    # integral of 1/rho and X^2/rho^3 over a 1 x 2 cell seen from an offset (0.7, -1.9)
    n = 2000
    s = (np.arange(n) + 0.5) / n
    xs, ys = np.meshgrid(0.7 - (s - 0.5) * 1.0, -1.9 - (s - 0.5) * 2.0, indexing="ij")
    rho = np.hypot(xs, ys)
    i1, ixx, iyy, ixy = rect_integrals(np.array([0.7]), np.array([-1.9]), 1.0, 2.0)
    area = 2.0 / n**2
    assert abs(i1[0] - (1 / rho).sum() * area) < 1e-5 * i1[0]
    assert abs(ixx[0] - (xs**2 / rho**3).sum() * area) < 1e-5 * abs(ixx[0])
    assert abs(ixy[0] - (xs * ys / rho**3).sum() * area) < 1e-5 * abs(ixy[0])


def test_hertz_normal_problem_within_one_percent():
    h = hertz(A, B, G / (1 - NU), F)
    g = Grid.box(1.25 * h["a"], 1.25 * h["b"], 40, 40)
    p, delta = solve_normal(g, A, B, G, NU, force=F)
    m = contact_measures(g, p)
    assert abs(m["force"] / F - 1) < 1e-10
    assert abs(m["area"] / (np.pi * h["a"] * h["b"]) - 1) < 0.01
    assert abs(m["a"] / h["a"] - 1) < 0.01 and abs(m["b"] / h["b"] - 1) < 0.01
    assert abs(m["pmax"] / h["p0"] - 1) < 0.01
    assert abs(delta / h["delta"] - 1) < 0.01
    # the gap closes on the contact set and is open elsewhere
    gap = A * g.x**2 + B * g.y**2 - delta + normal_matrix(g, G, NU) @ p
    assert np.abs(gap[p > 0]).max() < 1e-9 * delta and gap[p == 0].min() > -1e-12 * delta


def test_kalker_c11_circle_within_two_percent():
    g = Grid.box(1.0, 1.0, 32, 32)
    r = Rolling(g, 1.0, 0.25, ellipse_cells(g, 1.0, 1.0))
    c11, c22, c23 = r.linear_coefficients(1.0, 1.0)
    ref = kalker_table(0.25, 1.0)
    assert abs(c11 / ref[0] - 1) < 0.02
    assert abs(c22 / ref[1] - 1) < 0.03
    assert abs(c23 / ref[2] - 1) < 0.03


def test_coulomb_solver_full_stick_and_full_slip():
    g = Grid.box(1.0, 1.0, 12, 12)
    r = Rolling(g, 1.0, 0.25, ellipse_cells(g, 1.0, 1.0))
    big = np.full(r.n, 1.0)  # far above the full-stick traction (about 6e-3)
    q, s, stick, _ = r.solve(1e-3, 0.0, 0.0, big, tol=1e-12)
    assert np.allclose(q, r.full_stick(1e-3, 0.0, 0.0), rtol=0, atol=1e-8 * np.abs(q).max())
    bound = np.full(r.n, 1e-6)
    q, s, stick, _ = r.solve(1.0, 0.0, 0.0, bound, tol=1e-12)
    assert not stick.any()
    assert np.allclose(np.hypot(q[:r.n], q[r.n:]), bound)
