"""Checks of coupled.py (an elastic body on a rigid one, the normal and tangential problems
coupled), about 25 s. Run with `python -m pytest validation/halfspace3d` (from this folder:
`python -m pytest test_coupled.py`)."""
import numpy as np
from coupled import ElasticOnRigid, cross_integrals, make, steel_case
from halfspace import Grid, Rolling, solve_normal

MU = 0.3


def test_cross_integrals_match_quadrature():
    n = 2000
    s = (np.arange(n) + 0.5) / n
    for X0, Y0, dx, dy in ((0.7, -1.9, 1.0, 2.0), (0.2, 0.1, 1.0, 1.0), (-2.5, 0.3, 0.5, 1.5)):
        xs, ys = np.meshgrid(X0 - (s - 0.5) * dx, Y0 - (s - 0.5) * dy, indexing="ij")
        r2 = xs**2 + ys**2
        ix, iy = cross_integrals(np.array([X0]), np.array([Y0]), dx, dy)
        area = dx * dy / n**2
        assert abs(ix[0] - (xs / r2).sum() * area) < 1e-5 * abs(ix[0])
        assert abs(iy[0] - (ys / r2).sum() * area) < 1e-5 * abs(iy[0])
    # odd in (X, Y) (Betti: u_z from q_x is minus the transpose of u_x from p); zero on the cell
    X, Y = np.array([1.0, -3.0, 0.0]), np.array([2.0, 1.0, 0.0])
    a, b = cross_integrals(X, Y, 1.0, 1.0), cross_integrals(-X, -Y, 1.0, 1.0)
    assert np.allclose(a[0], -b[0], atol=1e-14) and np.allclose(a[1], -b[1], atol=1e-14)
    assert abs(a[0][2]) < 1e-14 and abs(a[1][2]) < 1e-14


def test_uniform_pressure_pulls_the_surface_inwards():
    # Johnson Eq. 3.35: under a uniform pressure p on a circle of radius 1, u_r = -(1 - 2 nu) p r
    # / (4 G) inside (towards the centre); the model's tangential displacement from p
    G, nu, p = 1.0, 0.3, 1.0
    g = Grid.box(1.2, 1.2, 48, 48)
    load = np.hypot(g.x, g.y) < 1
    X = g.x[:, None] - g.x[None, load]
    Y = g.y[:, None] - g.y[None, load]
    ix, iy = cross_integrals(X, Y, g.dx, g.dy)
    k = -(1 - 2 * nu) / (4 * np.pi * G)
    ux, uy = k * ix.sum(axis=1) * p, k * iy.sum(axis=1) * p
    inner = np.hypot(g.x, g.y) < 0.6
    ref = -(1 - 2 * nu) * p / (4 * G)
    assert np.abs(ux[inner] - ref * g.x[inner]).max() < 0.02 * abs(ref)
    assert np.abs(uy[inner] - ref * g.y[inner]).max() < 0.02 * abs(ref)


def _case(nu):
    case = steel_case(nu)
    hz = case["hz"]
    return case, np.sqrt(hz["a"] * hz["b"])


def test_nu_half_gives_the_uncoupled_halfspace_numbers():
    # nu = 0.5: no coupling; the coupled solver must give halfspace.py's numbers for the
    # combined modulus G = 2 G1 (an elastic body on a rigid one), normal and tangential
    for nu in (0.5, 0.3):
        case, c = _case(nu)
        hz = case["hz"]
        g = Grid.box(1.1 * hz["a"], 1.1 * hz["b"], 14, 14)
        m = ElasticOnRigid(g, case["G1"], nu, case["A"], case["B"], coupled=(nu == 0.5))
        if nu == 0.5:
            assert np.abs(m.Azt).max() == 0 and np.abs(m.Dtp).max() == 0
        p_ref, d_ref = solve_normal(g, case["A"], case["B"], 2 * case["G1"], nu, force=case["force"])
        p, d = m.normal(m.h, case["force"])
        assert np.allclose(p, p_ref, rtol=0, atol=1e-9 * p_ref.max()) and abs(d / d_ref - 1) < 1e-9
        idx = np.flatnonzero(p_ref > 0)
        roll = Rolling(g, 2 * case["G1"], nu, idx)
        ref = roll.linear_coefficients(hz["a"], hz["b"])
        r = m.linear_coefficients(case["force"], c, 1e-5, halvings=0)
        row = r["rows"][0][1]
        assert np.allclose([row["C11"], row["C22"], row["C23"]], ref, rtol=1e-8)
        assert abs(r["xi_free"]) < 1e-12
        st = m.coulomb(1e-3, 0.0, 0.0, MU, case["force"], tol=1e-11)
        q_ref, _, _, _ = roll.solve(1e-3, 0.0, 0.0, MU * p_ref[idx], tol=1e-11)
        fx_ref = roll.forces(q_ref)[0]
        assert abs(m.forces(st["p"], st["q"])[0] / fx_ref - 1) < 1e-7


def test_lateral_problem_is_mirror_symmetric():
    # eta -> -eta is the mirror y -> -y: F_x even, F_y odd, and F_y opposes eta
    case, c = _case(0.3)
    m = make(case, 12)
    r = m.linear_coefficients(case["force"], c, 1e-5, halvings=0)
    row = r["rows"][0][1]
    fxp, fxm = row["Fx_pm_eta"]
    fyp, fym = row["Fy_pm_eta"]
    assert abs(fxp - fxm) < 1e-9 * abs(fxp) + 1e-9 and abs(fyp + fym) < 1e-9 * abs(fyp)
    assert fyp < 0 and row["C22"] > 0 and row["C23"] > 0 and row["C11"] > 0
    assert abs(r["fy0"]) < 1e-8 * case["force"] and abs(r["mz0"]) < 1e-8 * case["force"] * c
    # Coulomb friction, lateral creepage
    sp = m.coulomb(0.0, 1e-3, 0.0, MU, case["force"], tol=1e-11)
    sm = m.coulomb(0.0, -1e-3, 0.0, MU, case["force"], tol=1e-11)
    fp, fm = m.forces(sp["p"], sp["q"]), m.forces(sm["p"], sm["q"])
    assert abs(fp[0] - fm[0]) < 1e-6 * MU * case["force"]
    assert abs(fp[1] + fm[1]) < 1e-6 * MU * case["force"] and fp[1] < 0


def test_coulomb_creep_force_matches_contact():
    # CONTACT (eve70a/CONTACT d431cdb, gfortran build; contact_compare_coupled.py's input with
    # 16 x 16 cells) prints -Fx/(mu Fz) = 0.4632 at xi = 0 and -0.2991 at xi = -2e-3 (elastic
    # body 1, G2 = 1e7 G1), with 164 and 166 cells in contact
    case, c = _case(0.3)
    m = make(case, 16)
    st = None
    for xi, ref, ncon in ((0.0, 0.4632, 164), (-2e-3, -0.2991, 166)):
        st = m.coulomb(xi, 0.0, 0.0, MU, case["force"], state=st)
        f = -m.forces(st["p"], st["q"])[0] / (MU * case["force"])
        assert abs(f - ref) < 6e-5 and (st["p"] > 0).sum() == ncon


def test_coupled_c11_small_grid_near_finest_rung():
    # Hertz's area fixed (coupled_coefficients.py hertz-area): 64 cells give C11, C22, C23 =
    # 4.5377, 3.8376, 1.5112 for nu = 0.3; 16 cells within 5 % (the rungs still drift by
    # +0.5 % of the uncoupled value per halving, see README)
    case, c = _case(0.3)
    m = make(case, 16, box=1.0)
    r = m.linear_coefficients(case["force"], c, 1e-5, halvings=1, fixed=True)
    (_, r1), (_, r2) = r["rows"]
    for k, ref in (("C11", 4.5377), ("C22", 3.8376), ("C23", 1.5112)):
        assert abs(r1[k] / r2[k] - 1) < 1e-9  # linear: halving xi0 changes nothing
        assert abs(r2[k] / ref - 1) < 0.05
