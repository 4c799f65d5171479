"""Kalker's linear creep coefficients C11, C22, C23 of an elastic body on a rigid one, coupled
(coupled.py, the cross influence coefficients kept) against uncoupled (the same solver with them
dropped: the quasi-identical model of the same pair), on a ladder of grids.

The pair is the FE model's: steel E = 2.05e11 Pa, radius R = 0.1 m along x on a rigid crown of
radius 0.1 m across (A = B = 5 /m, a/b = 1), the load from Hertz (E* of the elastic body alone)
for a = 1.5 mm; nu = 0.25 and nu = 0.3. n x n cells over 1.1 a x 1.1 b (the candidates: the
cells inside the 1.1-scaled ellipse), the contact set from the problem itself (active set),
linearized about the free-rolling creepage (F_x = 0, where the tractions are small): mode
"free-rolling". Mode "hertz-area" (the default): n x n cells over Hertz's bounding box, the
contact area fixed to the cells inside Hertz's ellipse (as kalker_coefficients.py; the pressure
there free of a sign condition), linearized about zero creepage, so coupled and uncoupled share
one area and the change is not mixed with the staircase of the contact set.
Full adhesion (mu = oo): F from central differences at +-xi0 (eta0 = xi0, phi0 = xi0 / c)
and again at xi0 / 2; the contact set is checked to be the same at all of them (then the forces
are exactly linear and both differences agree to round-off).
Normalization as in halfspace.py / kalker_coefficients.py with Kalker's combined modulus
G = 2 / (1/G1 + 1/G2) = 2 G1 and c = sqrt(a b) of Hertz's ellipse:
F_x = -G c^2 C11 xi, F_y = -G c^2 (C22 eta + c C23 phi) (uncoupled: Kalker's table values).
Also F_x at zero creepage and the free-rolling creepage xi_free (F_x = 0) of the coupled problem.

python coupled_coefficients.py [hertz-area|free-rolling] [n ...]
    hertz-area: default 8 16 32 64, about 6 minutes and 2 GB;
    free-rolling 8 16 24 32: about 6 minutes (the contact set's active set needs many
    factorizations of the joint (3m + 1)-system, so 48 and 64 cells are out of reach here)
"""
import sys
import time
import numpy as np
from coupled import difference_parameters, make, steel_case
from halfspace import kalker_table
from kalker_coefficients import richardson

XI0 = 1e-5


MODES = {"hertz-area": dict(box=1.0, fixed=True, about="zero"),
         "free-rolling": dict(box=1.1, fixed=False, about="free")}


def ladder(nu, ns, mode):
    box, fixed, about = MODES[mode]["box"], MODES[mode]["fixed"], MODES[mode]["about"]
    case = steel_case(nu)
    hz = case["hz"]
    c = np.sqrt(hz["a"] * hz["b"])
    rows = []
    for n in ns:
        t = time.time()
        res = {}
        for cp in (False, True):
            m = make(case, n, box=box, coupled=cp)
            r = m.linear_coefficients(case["force"], c, XI0, halvings=1, fixed=fixed, about=about)
            (e1, r1), (e2, r2) = r["rows"]
            same = all(r1[k + "_same_set"] and r2[k + "_same_set"] for k in ("C11", "C22", "C23"))
            lin = max(abs(r1[k] / r2[k] - 1) for k in ("C11", "C22", "C23"))
            if not fixed and m.touches_edge(r["base"]["p"]):
                print("  warning: the contact reaches the candidate set's border")
            res[cp] = dict(C11=r2["C11"], C22=r2["C22"], C23=r2["C23"], same=same, lin=lin,
                           ncon=int((r["base"]["p"] > 0).sum()), fx0=r["fx0"],
                           xi_free=r["xi_free"], fy0=r["fy0"], mz0=r["mz0"],
                           pmin=r["base"]["p"][r["base"]["act"]].min() / hz["p0"])
            del m
        rows.append((n, res, time.time() - t))
        u, k = res[False], res[True]
        print(f"  n = {n:3d}: cells {u['ncon']}/{k['ncon']}  uncoupled {u['C11']:.4f} {u['C22']:.4f} "
              f"{u['C23']:.4f}  coupled {k['C11']:.4f} {k['C22']:.4f} {k['C23']:.4f}  "
              f"xi_free {k['xi_free']:.4e} ({k['xi_free'] / (hz['a'] / case['R']):+.4f} a/R)  "
              f"same set {u['same'] and k['same']}, halving changes C by {max(u['lin'], k['lin']):.1e}, "
              f"min p/p0 {k['pmin']:+.3f}  "
              f"{time.time() - t:.0f} s", flush=True)
    return case, rows


def main(ns, modes=("hertz-area",)):
    out = {}
    for mode, nu in [(md, nu) for md in modes for nu in (0.25, 0.3)]:
        K, beta = difference_parameters(nu)
        ref = kalker_table(nu, 1.0)
        print(f"\n[{mode}] nu = {nu}: K = {K:.4f}, Dundurs beta = {beta:.4f}; Kalker's table (quasi-identical) "
              f"C11 {ref[0]:.3f} C22 {ref[1]:.3f} C23 {ref[2]:.3f}")
        case, rows = ladder(nu, ns, mode)
        hz = case["hz"]
        print(f"  pair: E = {case['E']:.3e} Pa, G1 = {case['G1']:.4e} Pa, G = 2 G1, Fz = {case['force']:.1f} N, "
              f"a = b = {1e3 * hz['a']:.4f} mm, p0 = {hz['p0'] / 1e6:.1f} MPa, p0/G1 = {hz['p0'] / case['G1']:.5f}")
        print("     n    C11 unc   C11 cpl   change    C22 unc   C22 cpl   change    C23 unc   C23 cpl   change"
              "   xi_free      xi_free/(a/R)  -Fx(0)/Fz")
        for n, res, _ in rows:
            u, k = res[False], res[True]
            line = f"  {n:4d}"
            for key in ("C11", "C22", "C23"):
                line += f"   {u[key]:.4f}    {k[key]:.4f}   {100 * (k[key] / u[key] - 1):+.2f} %"
            line += (f"   {k['xi_free']:.4e}   {k['xi_free'] / (hz['a'] / case['R']):+.5f}"
                     f"       {-k['fx0'] / case['force']:.5f}")
            print(line)
        if len(rows) >= 3 and mode == "hertz-area":
            for key in ("C11", "C22", "C23"):
                vu = [r[1][False][key] for r in rows]
                vk = [r[1][True][key] for r in rows]
                ch = [r[1][True][key] / r[1][False][key] - 1 for r in rows]
                lu, pu = richardson(vu)
                lk, pk = richardson(vk)
                print(f"  {key}: Richardson uncoupled {lu:.4f} (order {pu:.2f}), coupled {lk:.4f} (order {pk:.2f}); "
                      f"change on the rungs {', '.join(f'{100 * x:+.2f}' for x in ch)} %; table {ref[('C11', 'C22', 'C23').index(key)]:.3f}")
            xf = [r[1][True]["xi_free"] / (hz["a"] / case["R"]) for r in rows]
            lx, px = richardson(xf)
            print(f"  xi_free/(a/R): rungs {', '.join(f'{x:+.5f}' for x in xf)}; Richardson {lx:+.5f} (order {px:.2f})")
        out[mode, nu] = (case, rows)
    return out


if __name__ == "__main__":
    args = sys.argv[1:]
    modes = [a for a in args if a in MODES] or ["hertz-area"]
    main([int(a) for a in args if a not in MODES] or [8, 16, 32, 64], modes)
