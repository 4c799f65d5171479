"""Quasi-static, steady-state rolling contact of two elastic half-spaces: Kalker's exact theory
discretized as CONTACT does it (J.J. Kalker, "Three-dimensional elastic bodies in rolling
contact", Kluwer 1990, ch. 5; E.A.H. Vollebregt, "User guide for CONTACT", sec. "the
discretization").

- A rectangular grid of cells (dx x dy) over the potential contact area; tractions piecewise
  constant per cell; displacements collocated at the cell centres.
- Influence coefficients: the surface displacement of a half-space under a uniform traction on
  a rectangle, from the Boussinesq and Cerruti point-load solutions (Johnson, "Contact
  Mechanics" 1985, Eqs. 3.20 and 3.86; Love 1929 for the pressure) integrated in closed form.
  For a point load of unit size on ONE body, at distance rho = sqrt(X^2 + Y^2):

      u_z = (1 - nu) / (2 pi G) / rho                                   (normal load)
      u_x = 1 / (2 pi G) [ (1 - nu) / rho + nu X^2 / rho^3 ]            (load along x)
      u_y = 1 / (2 pi G) nu X Y / rho^3                                 (load along x)

  Two bodies of the same material ("quasi-identity", Kalker 1990 sec. 1.4) carrying equal and
  opposite tractions: the displacement difference u = u(1) - u(2) is twice one body's, i.e.
  1 / (pi G) times the brackets above, and the normal and tangential problems decouple (the
  tangential traction does not move the surfaces normally and vice versa).
  The rectangle integrals follow from the antiderivatives (corner sums of F(X, Y)):

      int int 1/rho       = X ln(Y + rho) + Y ln(X + rho)
      int int X^2/rho^3   = Y ln(X + rho)
      int int Y^2/rho^3   = X ln(Y + rho)
      int int X Y/rho^3   = -rho

- Normal problem (Kalker's NORM, an active set): find p >= 0 on the cells with the gap
  g = h(x, y) - delta + (A p) >= 0, p g = 0, for the undeformed separation
  h = A x^2 + B y^2 and either the approach delta or the total force sum(p) dx dy prescribed
  (delta then an unknown of the linear system on the active set).
- Tangential problem, steady rolling (Kalker 1990 sec. 5.2; CONTACT's steady-state scheme):
  the body rolls in +x, material passes through the contact from the leading edge x = +a to
  the trailing edge with speed V. The slip (velocity divided by V) is

      s = w - du/dx,   w = (xi - phi y, eta + phi x)  (longitudinal, lateral creepage, spin)

  discretized upwind in time: s_I = w_I - (u(x_I + dx, y_I) - u(x_I, y_I)) / dx, both u's
  from the influence coefficients (the first at the centre of the upstream cell). Coulomb's
  law per cell with the traction bound g_I = mu p_I: stick |q_I| <= g_I and s_I = 0, or slip
  q_I = -g_I s_I / |s_I|. Solved by block Gauss-Seidel over the cells, leading edge first, each
  cell's 2 x 2 local problem exact (stick, or slip with the direction from a scalar equation),
  as Kalker's TANGCF and CONTACT's GaussSeidel/ConvexGS do.

Units are SI throughout (m, Pa, N). Kalker's creep coefficients: F_x = -G c^2 C11 xi,
F_y = -G c^2 (C22 eta + c C23 phi), c = sqrt(a b) (Kalker 1967; Johnson 1985 Eq. 8.42).
"""
import numpy as np
from scipy.special import ellipk, ellipe
from scipy.optimize import brentq


# ------------------------------------------------------------------ Hertz (Johnson Eq. 4.39)
def hertz(A, B, e_star, force):
    """Hertz's ellipse for h = A x^2 + B y^2 and 1/E* = sum (1 - nu_i^2)/E_i.
    Returns a (semi-axis along x), b (along y), p0, delta (approach)."""
    lo, hi = min(A, B), max(A, B)
    if abs(hi / lo - 1) < 1e-12:
        r = 0.5 / A
        a = (3 * force * r / (4 * e_star)) ** (1 / 3)
        return dict(a=a, b=a, p0=3 * force / (2 * np.pi * a * a), delta=a * a / r)

    def ratio(e):
        m = e * e
        k, ee = ellipk(m), ellipe(m)
        return (ee / (1 - m) - k) / (k - ee)

    e = brentq(lambda e: ratio(e) - hi / lo, 1e-4, 1 - 1e-12, xtol=1e-16, rtol=1e-15)
    m = e * e
    k, ee = ellipk(m), ellipe(m)
    major = (3 * force * (k - ee) / (2 * np.pi * m * e_star * lo)) ** (1 / 3)
    minor = major * np.sqrt(1 - m)
    p0 = 3 * force / (2 * np.pi * major * minor)
    delta = p0 * minor * k / e_star
    a, b = (major, minor) if A <= B else (minor, major)
    return dict(a=a, b=b, p0=p0, delta=delta)


# ------------------------------------------------------------------ influence coefficients
def _ln_plus(s, t, rho):
    """ln(s + rho) with rho = sqrt(s^2 + t^2), without cancellation for s < 0."""
    out = np.empty_like(s)
    pos = s >= 0
    out[pos] = np.log(s[pos] + rho[pos])
    neg = ~pos
    out[neg] = np.log(t[neg] ** 2 / (rho[neg] - s[neg]))
    return out


def _prims(X, Y):
    rho = np.hypot(X, Y)
    lx = _ln_plus(X, Y, rho)
    ly = _ln_plus(Y, X, rho)
    return X * ly + Y * lx, Y * lx, X * ly, -rho  # 1/rho, X^2/rho^3, Y^2/rho^3, XY/rho^3


def rect_integrals(X, Y, dx, dy):
    """Integrals of 1/rho, X^2/rho^3, Y^2/rho^3, XY/rho^3 over the source cell, for field
    points at offsets (X, Y) from the cell's centre (arrays of any shape; the offsets must not
    put the field point on a cell edge)."""
    out = [0.0, 0.0, 0.0, 0.0]
    for sx, sy, sign in ((0.5, 0.5, 1), (-0.5, 0.5, -1), (0.5, -0.5, -1), (-0.5, -0.5, 1)):
        # offset of the field point from the corner: X - sx dx
        f = _prims(X + sx * dx, Y + sy * dy)
        for k in range(4):
            out[k] = out[k] + sign * f[k]
    return out


class Grid:
    """nx x ny cells of size dx x dy centred on (0, 0) + (x0, y0)."""

    def __init__(self, nx, ny, dx, dy, x0=0.0, y0=0.0):
        self.nx, self.ny, self.dx, self.dy = nx, ny, dx, dy
        xc = x0 + (np.arange(nx) - (nx - 1) / 2) * dx
        yc = y0 + (np.arange(ny) - (ny - 1) / 2) * dy
        self.X, self.Y = np.meshgrid(xc, yc, indexing="ij")  # cell (i, j): x index i
        self.x, self.y = self.X.ravel(), self.Y.ravel()

    @classmethod
    def box(cls, half_x, half_y, nx, ny):
        return cls(nx, ny, 2 * half_x / nx, 2 * half_y / ny)


def normal_matrix(grid, G, nu, idx=None):
    """A_zz[I, J]: the normal displacement difference at centre I from unit pressure on cell J."""
    x, y = (grid.x, grid.y) if idx is None else (grid.x[idx], grid.y[idx])
    X = x[:, None] - x[None, :]
    Y = y[:, None] - y[None, :]
    i1, _, _, _ = rect_integrals(X, Y, grid.dx, grid.dy)
    return (1 - nu) / (np.pi * G) * i1


def tangential_matrix(grid, G, nu, idx, shift=0.0):
    """2N x 2N matrix of the tangential displacement difference (u_x; u_y) at the centres of
    cells idx, moved by `shift` along x, from unit tractions (q_x; q_y) on cells idx."""
    x, y = grid.x[idx], grid.y[idx]
    X = (x[:, None] + shift) - x[None, :]
    Y = y[:, None] - y[None, :]
    i1, ixx, iyy, ixy = rect_integrals(X, Y, grid.dx, grid.dy)
    c = 1 / (np.pi * G)
    n = len(x)
    M = np.empty((2 * n, 2 * n))
    M[:n, :n] = c * ((1 - nu) * i1 + nu * ixx)
    M[:n, n:] = c * nu * ixy
    M[n:, :n] = c * nu * ixy
    M[n:, n:] = c * ((1 - nu) * i1 + nu * iyy)
    return M


# ------------------------------------------------------------------ normal problem
def solve_normal(grid, A, B, G, nu, force=None, delta=None, max_iter=200):
    """Active-set solution of the frictionless normal problem; returns (p per cell, delta)."""
    h = A * grid.x**2 + B * grid.y**2
    Azz = normal_matrix(grid, G, nu)
    dA = grid.dx * grid.dy
    if force is not None:
        e_star = G / (1 - nu)  # two identical bodies: 1/E* = 2 (1 - nu^2)/E = (1 - nu)/G
        d0 = hertz(A, B, e_star, force)["delta"]
    else:
        d0 = delta
    act = h < d0
    n = len(h)
    for _ in range(max_iter):
        S = np.flatnonzero(act)
        p = np.zeros(n)
        if force is None:
            pS = np.linalg.solve(Azz[np.ix_(S, S)], delta - h[S])
            d = delta
        else:
            m = len(S)
            K = np.zeros((m + 1, m + 1))
            K[:m, :m] = Azz[np.ix_(S, S)]
            K[:m, m] = -1.0
            K[m, :m] = dA
            rhs = np.concatenate([-h[S], [force]])
            sol = np.linalg.solve(K, rhs)
            pS, d = sol[:m], sol[m]
        p[S] = pS
        neg = pS < 0
        if neg.any():
            act[S[neg]] = False
            continue
        gap = h - d + Azz @ p
        pen = (~act) & (gap < -1e-12 * max(d, 1e-30))
        if pen.any():
            act[pen] = True
            continue
        return p, d
    raise RuntimeError("normal problem: active set did not settle")


def contact_measures(grid, p):
    """Area, semi-axes from the second moments of the contact set (an ellipse of semi-axes
    a, b has int x^2 dA = pi a^3 b / 4), peak pressure, total force."""
    dA = grid.dx * grid.dy
    c = p > 0
    area = c.sum() * dA
    ixx = (grid.x[c] ** 2).sum() * dA
    iyy = (grid.y[c] ** 2).sum() * dA
    a = np.sqrt(4 * ixx / area)
    b = np.sqrt(4 * iyy / area)
    return dict(area=area, a=a, b=b, pmax=p.max(), force=p.sum() * dA)


# ------------------------------------------------------------------ tangential problem
class Rolling:
    """Steady rolling on the cells `idx` of `grid` (the contact area), traction bound mu p."""

    def __init__(self, grid, G, nu, idx):
        self.grid, self.G, self.nu = grid, G, nu
        self.idx = np.asarray(idx)
        self.n = len(self.idx)
        A0 = tangential_matrix(grid, G, nu, self.idx)
        A1 = tangential_matrix(grid, G, nu, self.idx, shift=grid.dx)
        # s = w - D q with D = (u(x + dx) - u(x)) / dx per unit traction
        self.D = (A1 - A0) / grid.dx
        self.x, self.y = grid.x[self.idx], grid.y[self.idx]
        # the local 2 x 2 block is diagonal (cross terms vanish by symmetry): s_I = b_I + M q_I
        n = self.n
        self.Mx = -np.diag(self.D)[:n].copy()
        self.My = -np.diag(self.D)[n:].copy()
        self.order = np.lexsort((self.x, self.y))  # line by line (y), trailing edge first (spectral radius < 1; leading first diverges)

    def rigid_slip(self, xi, eta, phi):
        return np.concatenate([xi - phi * self.y, eta + phi * self.x])

    def full_stick(self, xi, eta, phi):
        """Tractions (q_x; q_y) with no slip anywhere: D q = w."""
        return np.linalg.solve(self.D, self.rigid_slip(xi, eta, phi))

    def linear_coefficients(self, a, b):
        """Kalker's C11, C22, C23 of the full-stick (vanishing creepage) limit, c = sqrt(a b):
        F_x = -G c^2 C11 xi, F_y = -G c^2 (C22 eta + c C23 phi)."""
        from scipy.linalg import lu_factor, lu_solve
        lu = lu_factor(self.D, overwrite_a=False, check_finite=False)
        W = np.stack([self.rigid_slip(1, 0, 0), self.rigid_slip(0, 1, 0),
                      self.rigid_slip(0, 0, 1)], axis=1)
        Q = lu_solve(lu, W, check_finite=False)
        c2 = a * b
        fx, _, _ = self.forces(Q[:, 0])
        _, fy1, _ = self.forces(Q[:, 1])
        _, fy2, _ = self.forces(Q[:, 2])
        return -fx / (self.G * c2), -fy1 / (self.G * c2), -fy2 / (self.G * c2 ** 1.5)

    def spin_coefficients(self, a, b):
        """The spin's coefficients of the full-stick limit, c = sqrt(a b), in Kalker's form
        F_y = -G c^2 (C22 eta + c C23 phi), M_z = G c^3 (C23 eta - c C33 phi): C23 read from F_y
        at phi, C23 read from M_z at eta (the same in the exact theory: the coupling is
        antisymmetric) and C33."""
        from scipy.linalg import lu_factor, lu_solve
        lu = lu_factor(self.D, overwrite_a=False, check_finite=False)
        W = np.stack([self.rigid_slip(0, 1, 0), self.rigid_slip(0, 0, 1)], axis=1)
        Q = lu_solve(lu, W, check_finite=False)
        c = np.sqrt(a * b)
        _, _, mz_eta = self.forces(Q[:, 0])
        _, fy_phi, mz_phi = self.forces(Q[:, 1])
        G = self.G
        return -fy_phi / (G * c ** 3), mz_eta / (G * c ** 3), -mz_phi / (G * c ** 4)

    def forces(self, q):
        dA = self.grid.dx * self.grid.dy
        n = self.n
        fx, fy = q[:n].sum() * dA, q[n:].sum() * dA
        mz = (self.x * q[n:] - self.y * q[:n]).sum() * dA
        return fx, fy, mz

    def solve(self, xi, eta, phi, bound, q0=None, tol=1e-10, max_sweeps=5000):
        """Coulomb friction by block Gauss-Seidel; bound = mu p on the cells. Returns
        (q, slip s, stick mask, sweeps)."""
        n = self.n
        w = self.rigid_slip(xi, eta, phi)
        q = np.zeros(2 * n) if q0 is None else q0.copy()
        DT = np.ascontiguousarray(self.D.T)
        s = w - self.D @ q
        gmax = bound.max()
        for sweep in range(1, max_sweeps + 1):
            change = 0.0
            for I in self.order:
                g = bound[I]
                mx, my = self.Mx[I], self.My[I]
                qx, qy = q[I], q[n + I]
                bx, by = s[I] - mx * qx, s[n + I] - my * qy
                tx, ty = -bx / mx, -by / my  # stick traction
                if tx * tx + ty * ty <= g * g:
                    nx_, ny_ = tx, ty
                else:
                    # slip: b = (lam + g M) e, |e| = 1, lam >= 0
                    f = lambda lam: (bx / (lam + g * mx)) ** 2 + (by / (lam + g * my)) ** 2 - 1
                    hi = np.hypot(bx, by)
                    lam = brentq(f, 0.0, hi + 1e-300, xtol=1e-15 * hi + 1e-300) if f(0.0) > 0 else 0.0
                    ex, ey = bx / (lam + g * mx), by / (lam + g * my)
                    nrm = np.hypot(ex, ey)
                    nx_, ny_ = -g * ex / nrm, -g * ey / nrm
                dx_, dy_ = nx_ - qx, ny_ - qy
                if dx_ != 0.0 or dy_ != 0.0:
                    s -= DT[I] * dx_ + DT[n + I] * dy_
                    q[I], q[n + I] = nx_, ny_
                    change = max(change, abs(dx_), abs(dy_))
            if change <= tol * gmax:
                break
        qn = np.hypot(q[:n], q[n:])
        stick = qn < bound * (1 - 1e-9)
        return q, s, stick, sweep


def ellipse_cells(grid, a, b):
    """Cells whose centres lie inside the ellipse (x/a)^2 + (y/b)^2 < 1."""
    return np.flatnonzero((grid.x / a) ** 2 + (grid.y / b) ** 2 < 1)


def kalker_table(nu, aob):
    """Kalker's C11, C22, C23 for an elliptical area (Kalker 1990, Table E.3; as tabulated and
    interpolated in CONTACT's src/m_hertz.f90, subroutine linrol: linear in g = min(a/b, b/a)
    between rows, a parabola in nu through nu = 0, 0.25, 0.5 of the reciprocals)."""
    t1 = [  # a/b = 0.1 .. 1.0 (a < b): C11(nu=0,.25,.5), C22(...), C23(...)
        [2.51, 3.31, 4.85, 2.51, 2.52, 2.53, .334, .473, .731],
        [2.59, 3.37, 4.81, 2.59, 2.63, 2.66, .483, .603, .809],
        [2.68, 3.44, 4.80, 2.68, 2.75, 2.81, .607, .715, .889],
        [2.78, 3.53, 4.82, 2.78, 2.88, 2.98, .720, .823, .977],
        [2.88, 3.62, 4.83, 2.88, 3.01, 3.14, .827, .929, 1.07],
        [2.98, 3.72, 4.91, 2.98, 3.14, 3.31, .930, 1.03, 1.18],
        [3.09, 3.81, 4.97, 3.09, 3.28, 3.48, 1.03, 1.14, 1.29],
        [3.19, 3.91, 5.05, 3.19, 3.41, 3.65, 1.13, 1.25, 1.40],
        [3.29, 4.01, 5.12, 3.29, 3.54, 3.82, 1.23, 1.36, 1.51],
        [3.40, 4.12, 5.20, 3.40, 3.67, 3.98, 1.33, 1.47, 1.63]]
    t2 = [  # b/a = 0.1 .. 1.0 (a > b)
        [10.7, 11.7, 12.9, 10.7, 12.8, 16.0, 12.2, 14.6, 18.0],
        [6.96, 7.78, 8.82, 6.96, 8.14, 9.79, 5.72, 6.63, 7.89],
        [5.57, 6.34, 7.34, 5.57, 6.40, 7.51, 3.79, 4.32, 5.01],
        [4.84, 5.57, 6.57, 4.84, 5.48, 6.31, 2.88, 3.24, 3.70],
        [4.37, 5.10, 6.11, 4.37, 4.90, 5.56, 2.35, 2.62, 2.96],
        [4.06, 4.78, 5.80, 4.06, 4.50, 5.04, 2.01, 2.23, 2.50],
        [3.82, 4.54, 5.58, 3.82, 4.21, 4.67, 1.76, 1.95, 2.18],
        [3.65, 4.36, 5.42, 3.65, 3.99, 4.39, 1.58, 1.75, 1.94],
        [3.51, 4.22, 5.30, 3.51, 3.81, 4.16, 1.44, 1.59, 1.77],
        [3.40, 4.12, 5.20, 3.40, 3.67, 3.98, 1.33, 1.47, 1.63]]
    tab = np.array(t1 if aob <= 1 else t2)
    g = aob if aob <= 1 else 1 / aob
    if not 0.1 <= g <= 1:
        raise ValueError("outside the table")
    r = 10 * g - 1
    i = min(int(np.floor(r + 1e-9)), 8)
    f = r - i
    row = (1 - f) * tab[i] + f * tab[i + 1]
    out = []
    for k in range(3):
        c0, c1, c2 = row[3 * k: 3 * k + 3]
        cc = ((nu - 0.25) * (nu - 0.5) * 8 / c0 - (nu - 0.5) * nu * 16 / c1
              + nu * (nu - 0.25) * 8 / c2)
        out.append(1 / cc)
    return tuple(out)


if __name__ == "__main__":
    # Hertz's ellipse of scenarios/press-hertz.toml on a grid ladder (box 1.25 a x 1.25 b)
    import sys
    G, NU, F = 82e9, 0.28, 10e3
    A, B = 1 / (2 * 0.46), 1 / (2 * 0.3)
    h = hertz(A, B, G / (1 - NU), F)
    print(f"Hertz: a = {1e3 * h['a']:.4f} mm, b = {1e3 * h['b']:.4f} mm, "
          f"p0 = {h['p0'] / 1e6:.2f} MPa, approach {1e6 * h['delta']:.3f} um")
    print("  n x n   area/Hertz   a/Hertz   b/Hertz   pmax/p0   approach/Hertz")
    for n in [int(s) for s in sys.argv[1:]] or [20, 40, 60]:
        g = Grid.box(1.25 * h["a"], 1.25 * h["b"], n, n)
        p, d = solve_normal(g, A, B, G, NU, force=F)
        m = contact_measures(g, p)
        print(f"  {n:3d}     {m['area'] / (np.pi * h['a'] * h['b']):.4f}     {m['a'] / h['a']:.4f}    "
              f"{m['b'] / h['b']:.4f}    {m['pmax'] / h['p0']:.4f}    {d / h['delta']:.4f}")
