"""One elastic half-space (G1, nu) pressed and rolled on a RIGID one: the coupled normal and
tangential problems of Kalker's exact theory, discretized as halfspace.py does (same grid,
piecewise-constant tractions, collocation at the cell centres, upwind slip, block Gauss-Seidel
for Coulomb's law), with the cross influence coefficients that quasi-identity drops.

Conventions (those of halfspace.py). p >= 0 is the pressure and q = (q_x, q_y) the tangential
traction acting ON THE ELASTIC BODY (exerted by the rigid one); u is the displacement of the
elastic body's surface (the rigid body's is zero), u_z counted positive INTO the elastic body,
so the gap is h - delta + u_z. The elastic body rolls in +x (its material passes through the
contact from x = +a to x = -a); xi, eta, phi are the creepages of the elastic body relative to
the rigid one, s = w - du/dx the slip. F = sum(q) dA is the force on the elastic body.

Point loads on the surface of the half-space z >= 0 (z into the body), at field-minus-load
offset (X, Y), rho = |(X, Y)| (Johnson 1985, Eqs. 3.19 (Boussinesq) and 3.86 (Cerruti) at z = 0):

    normal load P (into the body):  u_z = (1 - nu) P / (2 pi G1 rho)
                                     u_x = -(1 - 2 nu) P X / (4 pi G1 rho^2)   (towards the load)
    tangential load Q_x:             u_x = Q_x / (2 pi G1) [(1 - nu)/rho + nu X^2/rho^3]
                                     u_y = Q_x / (2 pi G1) nu X Y / rho^3
                                     u_z = +(1 - 2 nu) Q_x X / (4 pi G1 rho^2)

The two cross kernels are each other's mirror (Betti: K_xz(X) = K_zx(-X)); the sign of u_z
under Q_x follows from Boussinesq's inward u_x by that reciprocity. For two bodies the cross
coefficient is ((1 - 2 nu1)/G1 - (1 - 2 nu2)/G2) / (4 pi); the rigid body (G2 -> oo) adds
nothing, so here it is (1 - 2 nu)/(4 pi G1) = K / (pi G), with Kalker's combined modulus
G = 2 / (1/G1 + 1/G2) = 2 G1 and difference parameter K = (G/4) ((1 - 2 nu1)/G1 -
(1 - 2 nu2)/G2) = (1 - 2 nu)/2 (Dundurs' beta = (1 - 2 nu) / (2 (1 - nu))). The direct
coefficients are halfspace.py's with G = 2 G1: an elastic body on a rigid one is, apart from
the coupling, the quasi-identical pair of combined modulus 2 G1 and the same nu
(1/E* = (1 - nu^2)/E). Swapping which body is elastic changes nothing once p, q, u and the
creepages are those of the elastic body.

The rectangle integrals of the cross kernel (corner sums as in halfspace.rect_integrals):

    int int X/rho^2 dX dY = X atan(Y/X) + Y ln rho,   int int Y/rho^2 = Y atan(X/Y) + X ln rho

Solvers (class ElasticOnRigid):
- stick(): vanishing creepage / full adhesion (mu = oo): the joint linear system in (p, q,
  delta) on an active set of contact cells, the set updated as in halfspace.solve_normal;
  Kalker's linear theory of the coupled problem.
- coulomb(): Coulomb friction, the Panagiotopoulos process as CONTACT does it: the normal
  problem with the current q's normal displacement, then the tangential problem (Gauss-Seidel
  of halfspace.Rolling) with the new p as bound mu p and the new p's tangential displacement
  as an extra rigid slip, until p and q stop changing.
"""
import numpy as np
from scipy.linalg import lu_factor, lu_solve
from halfspace import Grid, Rolling, ellipse_cells, hertz, normal_matrix, tangential_matrix


def difference_parameters(nu):
    """Kalker's K and Dundurs' beta for an elastic body (nu) on a rigid one."""
    return (1 - 2 * nu) / 2, (1 - 2 * nu) / (2 * (1 - nu))


def _xatan(X, Y):
    """X atan(Y/X), 0 at X = 0 (its limit)."""
    Xs = np.where(X == 0, 1.0, X)
    return np.where(X == 0, 0.0, X * np.arctan(Y / Xs))


def cross_integrals(X, Y, dx, dy):
    """Integrals of X/rho^2 and Y/rho^2 over the source cell (dx x dy), for field points at
    offsets (X, Y) from the cell's centre (no field point on a cell's corner)."""
    ix = 0.0
    iy = 0.0
    for sx, sy, sign in ((0.5, 0.5, 1), (-0.5, 0.5, -1), (0.5, -0.5, -1), (-0.5, -0.5, 1)):
        Xc, Yc = X + sx * dx, Y + sy * dy
        lr = 0.5 * np.log(Xc * Xc + Yc * Yc)
        ix = ix + sign * (_xatan(Xc, Yc) + Yc * lr)
        iy = iy + sign * (_xatan(Yc, Xc) + Xc * lr)
    return ix, iy


class _SubRolling(Rolling):
    """halfspace.Rolling on a subset of cells, with a given slip matrix D and an extra rigid
    slip w_extra (the pressure's -d u/dx); its Gauss-Seidel solve is Rolling.solve unchanged."""

    def __init__(self, grid, G, nu, idx, D, w_extra):
        self.grid, self.G, self.nu = grid, G, nu
        self.idx = np.asarray(idx)
        self.n = n = len(self.idx)
        self.D = D
        self.x, self.y = grid.x[self.idx], grid.y[self.idx]
        self.Mx = -np.diag(D)[:n].copy()
        self.My = -np.diag(D)[n:].copy()
        self.order = np.lexsort((self.x, self.y))
        self.w_extra = w_extra

    def rigid_slip(self, xi, eta, phi):
        return Rolling.rigid_slip(self, xi, eta, phi) + self.w_extra


class ElasticOnRigid:
    """An elastic half-space (shear modulus G1, Poisson's ratio nu) on a rigid one, undeformed
    separation h = A x^2 + B y^2, on the candidate cells `cand` of `grid` (default: all).
    coupled=False drops the cross coefficients (the quasi-identical model of the same pair)."""

    def __init__(self, grid, G1, nu, A, B, cand=None, coupled=True):
        self.grid, self.G1, self.nu, self.A, self.B = grid, G1, nu, A, B
        self.Gc = 2.0 * G1  # Kalker's combined modulus; the rigid body contributes nothing
        self.coupled = coupled
        self.cand = np.arange(grid.nx * grid.ny) if cand is None else np.asarray(cand)
        c = self.cand
        self.nC = nC = len(c)
        self.x, self.y = grid.x[c], grid.y[c]
        self.h = A * self.x**2 + B * self.y**2
        self.dA = grid.dx * grid.dy
        self.Azz = normal_matrix(grid, self.Gc, nu, idx=c)
        A1 = tangential_matrix(grid, self.Gc, nu, c, shift=grid.dx)
        A1 -= tangential_matrix(grid, self.Gc, nu, c)
        A1 /= grid.dx
        self.Dtt = A1  # s = w - Dtt q - Dtp p
        kz = (1 - 2 * nu) / (4 * np.pi * G1) if coupled else 0.0
        X = self.x[:, None] - self.x[None, :]
        Y = self.y[:, None] - self.y[None, :]
        ix, iy = cross_integrals(X, Y, grid.dx, grid.dy)
        self.Azt = kz * np.hstack([ix, iy])            # u_z at I from unit (q_x; q_y) at J
        Atz0 = -kz * np.vstack([ix, iy])               # (u_x; u_y) at I from unit p at J
        ix, iy = cross_integrals(X + grid.dx, Y, grid.dx, grid.dy)
        self.Dtp = (-kz * np.vstack([ix, iy]) - Atz0) / grid.dx
        del Atz0, ix, iy, X, Y
        self._lu = {}

    # -------------------------------------------------------------- measures
    def forces(self, p, q):
        n, dA = self.nC, self.dA
        fx, fy = q[:n].sum() * dA, q[n:].sum() * dA
        mz = (self.x * q[n:] - self.y * q[:n]).sum() * dA
        return fx, fy, mz, p.sum() * dA

    def rigid_slip(self, xi, eta, phi):
        return np.concatenate([xi - phi * self.y, eta + phi * self.x])

    def touches_edge(self, p):
        """True if a contact cell has a neighbour outside the candidate set (then the
        candidate set may be too small)."""
        ny = self.grid.ny
        inside = set(int(k) for k in self.cand)
        for k in self.cand[p > 0]:
            i, j = divmod(int(k), ny)
            for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                ii, jj = i + di, j + dj
                if not (0 <= ii < self.grid.nx and 0 <= jj < ny) or ii * ny + jj not in inside:
                    return True
        return False

    # -------------------------------------------------------------- normal problem
    def normal(self, h, force, act=None, max_iter=200):
        """Active set for p >= 0, gap = h - delta + Azz p >= 0, p gap = 0, sum p dA = force
        (h includes the tangential traction's normal displacement)."""
        act = (h < np.sort(h)[max(1, int(0.3 * self.nC))]) if act is None else act.copy()
        n = self.nC
        for _ in range(max_iter):
            S = np.flatnonzero(act)
            m = len(S)
            K = np.zeros((m + 1, m + 1))
            K[:m, :m] = self.Azz[np.ix_(S, S)]
            K[:m, m] = -1.0
            K[m, :m] = self.dA
            sol = np.linalg.solve(K, np.concatenate([-h[S], [force]]))
            p = np.zeros(n)
            p[S], d = sol[:m], sol[m]
            if (sol[:m] < 0).any():
                act[S[sol[:m] < 0]] = False
                continue
            gap = h - d + self.Azz @ p
            pen = (~act) & (gap < -1e-12 * abs(d))
            if pen.any():
                act[pen] = True
                continue
            return p, d
        raise RuntimeError("normal problem: active set did not settle")

    # -------------------------------------------------------------- full adhesion (mu = oo)
    def _factor(self, S):
        key = S.tobytes()
        if key not in self._lu:
            n, m = self.nC, len(S)
            S2 = np.concatenate([S, n + S])
            M = np.zeros((3 * m + 1, 3 * m + 1))
            M[:m, :m] = self.Azz[np.ix_(S, S)]
            M[:m, m:3 * m] = self.Azt[np.ix_(S, S2)]
            M[:m, 3 * m] = -1.0
            M[m:3 * m, :m] = self.Dtp[np.ix_(S2, S)]
            M[m:3 * m, m:3 * m] = self.Dtt[np.ix_(S2, S2)]
            M[3 * m, :m] = self.dA
            self._lu = {key: lu_factor(M, overwrite_a=True, check_finite=False)}  # keep one
        return self._lu[key]

    def stick(self, xi, eta, phi, force, act=None, max_iter=200, fixed=False):
        """No slip anywhere in the contact (mu = oo): Azz p + Azt q - delta = -h on the
        contact, Dtp p + Dtt q = w there, sum p dA = force; the contact set by an active set,
        or (fixed=True) all candidate cells, with no sign condition on p (Kalker's linear
        theory on a prescribed area). Returns dict(p, q, delta, act, iterations)."""
        n = self.nC
        if fixed:
            act = np.ones(n, bool)
        elif act is None:
            p0, _ = self.normal(self.h, force)
            act = p0 > 0
        act = act.copy()
        w = self.rigid_slip(xi, eta, phi)
        seen, single, best = set(), False, None
        for it in range(1, max_iter + 1):
            S = np.flatnonzero(act)
            m = len(S)
            S2 = np.concatenate([S, n + S])
            rhs = np.concatenate([-self.h[S], w[S2], [force]])
            sol = lu_solve(self._factor(S), rhs, check_finite=False)
            p = np.zeros(n)
            q = np.zeros(2 * n)
            p[S], q[S2], d = sol[:m], sol[m:3 * m], sol[3 * m]
            if fixed:
                return dict(p=p, q=q, delta=d, act=act, iterations=it)
            key = S.tobytes()
            if key in seen and single:
                # a cycle even one cell at a time (the coupled no-slip problem need not have a
                # complementary solution on the grid): accept the iterate with p >= 0 and the
                # smallest penetration seen, and report the penetration
                if best is not None:
                    return best
            single = single or key in seen  # a set seen before: change one cell at a time
            seen.add(key)
            if (p[S] < 0).any():
                if single:
                    act[S[np.argmin(p[S])]] = False
                else:
                    act[S[p[S] < 0]] = False
                continue
            gap = self.h - d + self.Azz @ p + self.Azt @ q
            pen = (~act) & (gap < -1e-12 * abs(d))
            if pen.any():
                if (p[S] >= 0).all() and single:
                    pmax_ = -gap[pen].min() / abs(d)
                    if best is None or pmax_ < best["penetration"]:
                        best = dict(p=p, q=q, delta=d, act=act.copy(), iterations=it, penetration=pmax_)
                if single:
                    act[np.argmin(np.where(pen, gap, np.inf))] = True
                else:
                    act[pen] = True
                continue
            return dict(p=p, q=q, delta=d, act=act, iterations=it, penetration=0.0)
        raise RuntimeError("full-stick problem: active set did not settle")

    def free_rolling_stick(self, force, tol=1e-10, max_iter=30):
        """Full adhesion: the creepage xi_free at which F_x = 0 (secant on the piecewise linear
        F_x(xi) of the active-set solution). Returns (xi_free, solution, F_x at xi = 0)."""
        s0 = self.stick(0.0, 0.0, 0.0, force)
        f0 = self.forces(s0["p"], s0["q"])[0]
        s1 = self.stick(1e-6, 0.0, 0.0, force, act=s0["act"])
        k = (self.forces(s1["p"], s1["q"])[0] - f0) / 1e-6
        x, st, f = 0.0, s0, f0
        for _ in range(max_iter):
            if abs(f) < tol * force:
                break
            x = x - f / k
            st = self.stick(x, 0.0, 0.0, force, act=st["act"])
            fn = self.forces(st["p"], st["q"])[0]
            e = 1e-6
            se = self.stick(x + e, 0.0, 0.0, force, act=st["act"])
            k = (self.forces(se["p"], se["q"])[0] - fn) / e
            f = fn
        return x, st, f0

    def linear_coefficients(self, force, c, xi0, halvings=1, fixed=False, about="free"):
        """Kalker's C11, C22, C23 of the coupled problem in full adhesion from central
        differences of the forces at xi_b +- xi0 (eta: +-xi0, phi: +-xi0/c about 0), normalized
        with the combined modulus G = 2 G1: F_x = -G c^2 C11 xi, F_y = -G c^2 (C22 eta + c C23
        phi). The base xi_b is the free-rolling creepage (about="free": F_x = 0, the tractions
        small) or 0 (about="zero"). Repeated with xi0 halved `halvings` times (equal results
        while the contact set stays: linear). fixed: the contact area is all the candidate
        cells (see stick). Returns a dict with rows [(xi0, {C11, C22, C23, ..._same_set})],
        fx0 (F_x at zero creepage), xi_free, base (the base solution)."""
        if fixed or about == "zero":
            base = self.stick(0.0, 0.0, 0.0, force, fixed=fixed)
            fx0 = self.forces(base["p"], base["q"])[0]
            xb = 0.0
        else:
            xb, base, fx0 = self.free_rolling_stick(force)
        fxb, fy0, mz0, _ = self.forces(base["p"], base["q"])
        out = dict(base=base, fx0=fx0, fy0=fy0, mz0=mz0, xi_base=xb, rows=[])
        gc2 = self.Gc * c * c
        for k in range(halvings + 1):
            e = xi0 / 2**k
            r = {}
            for name, args, j, norm in (("C11", (1, 0, 0), 0, gc2), ("C22", (0, 1, 0), 1, gc2),
                                        ("C23", (0, 0, 1 / c), 1, gc2 * c)):
                sp = self.stick(xb + e * args[0], e * args[1], e * args[2], force, act=base["act"], fixed=fixed)
                sm = self.stick(xb - e * args[0], -e * args[1], -e * args[2], force, act=base["act"], fixed=fixed)
                fp, fm = self.forces(sp["p"], sp["q"]), self.forces(sm["p"], sm["q"])
                step = e * max(args)  # xi0, eta0 = xi0 or phi0 = xi0 / c
                r[name] = -(fp[j] - fm[j]) / (2 * step) / norm
                r[name + "_same_set"] = (np.array_equal(sp["act"], base["act"])
                                         and np.array_equal(sm["act"], base["act"]))
                if name == "C22":
                    r["Fx_pm_eta"] = (fp[0], fm[0])
                    r["Fy_pm_eta"] = (fp[1], fm[1])
            out["rows"].append((e, r))
        c11 = out["rows"][-1][1]["C11"]
        out["xi_free"] = xb if about == "free" and not fixed else fxb / (gc2 * c11)
        return out

    # -------------------------------------------------------------- Coulomb friction
    def coulomb(self, xi, eta, phi, mu, force, state=None, tol=1e-9, outer_tol=1e-7,
                max_outer=200, inner_sweeps=25):
        """Steady rolling with Coulomb friction, the Panagiotopoulos process: the normal
        problem with the current q's normal displacement, then at most `inner_sweeps` Gauss-
        Seidel sweeps of the tangential problem with the new p (bound mu p, the p's tangential
        displacement as an extra rigid slip), repeated until the sweeps converge (change below
        tol mu max p) and p and q change by less than outer_tol (mu) max p. `state` (a previous
        result) warm-starts. Returns dict(p, q, delta, stick (per candidate cell, False outside
        the contact), outer, sweeps)."""
        n = self.nC
        q = np.zeros(2 * n) if state is None else state["q"].copy()
        p, d = self.normal(self.h + self.Azt @ q, force,
                           act=None if state is None else state["p"] > 0)
        pmax = p.max()
        sweeps = 0
        for outer in range(1, max_outer + 1):
            S = np.flatnonzero(p > 0)
            S2 = np.concatenate([S, n + S])
            w_extra = -(self.Dtp @ p)[S2]
            sub = _SubRolling(self.grid, self.Gc, self.nu, self.cand[S],
                              self.Dtt[np.ix_(S2, S2)], w_extra)
            qS, s, st, sw = sub.solve(xi, eta, phi, mu * p[S], q0=q[S2], tol=tol,
                                      max_sweeps=inner_sweeps if self.coupled else 100000)
            sweeps += sw
            inner_done = sw < inner_sweeps or not self.coupled
            qn = np.zeros(2 * n)
            qn[S2] = qS
            stick = np.zeros(n, bool)
            stick[S] = st
            if not self.coupled:  # p does not depend on q
                q = qn
                break
            pn, d = self.normal(self.h + self.Azt @ qn, force, act=p > 0)
            dq, dp = np.abs(qn - q).max(), np.abs(pn - p).max()
            q, p_old, p = qn, p, pn
            if inner_done and dp <= outer_tol * pmax and dq <= outer_tol * mu * pmax:
                p = p_old  # q was solved with this bound; p moved by less than outer_tol
                break
        else:
            raise RuntimeError("Panagiotopoulos process did not converge")
        return dict(p=p, q=q, delta=d, stick=stick, outer=outer, sweeps=sweeps)


def steel_case(nu=0.3, E=2.05e11, R=0.1, a=1.5e-3):
    """The FE model's pair: a steel wheel of radius R along x on a rigid crown of radius R
    across (A = B = 1/(2R), a circle), the load that gives Hertz's contact radius a."""
    G1 = E / (2 * (1 + nu))
    e_star = E / (1 - nu**2)  # the elastic body alone
    A = B = 1 / (2 * R)
    force = 4 * e_star * a**3 / (3 * R)
    h = hertz(A, B, e_star, force)
    return dict(E=E, nu=nu, G1=G1, e_star=e_star, A=A, B=B, R=R, force=force, hz=h)


def make(case, n, box=1.1, coupled=True):
    """Grid of n x n cells over box x Hertz's bounding box; candidates: the cells inside the
    box's inscribed ellipse (box = 1: Hertz's ellipse cells, as kalker_coefficients.py)."""
    h = case["hz"]
    g = Grid.box(box * h["a"], box * h["b"], n, n)
    cand = ellipse_cells(g, box * h["a"], box * h["b"])
    return ElasticOnRigid(g, case["G1"], case["nu"], case["A"], case["B"], cand, coupled)


if __name__ == "__main__":
    # a quick look: the FE model's pair at 20 x 20 cells
    for nu in (0.25, 0.3):
        case = steel_case(nu)
        hz = case["hz"]
        c = np.sqrt(hz["a"] * hz["b"])
        for cp in (False, True):
            m = make(case, 20, coupled=cp)
            r = m.linear_coefficients(case["force"], c, 1e-6)
            e, row = r["rows"][-1]
            print(f"nu = {nu} coupled = {cp}: C11 {row['C11']:.4f} C22 {row['C22']:.4f} "
                  f"C23 {row['C23']:.4f}  xi_free {r['xi_free']:.3e}")
