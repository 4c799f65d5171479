"""The reference a 3D creep sweep of softway draws (`rolling.reference_curve`): the coupled
creep curve of an elastic wheel on a rigid crown (coupled.py, the case of
creep_curve_coupled.py: steel, nu = 0.3, a circle, R = R_c, mu = 0.3), written in softway's
convention, and the creepages at Q/(mu N) = -0.5, 0, +0.5 on a ladder of cells with their
Richardson limits.

Conventions. coupled.py's xi is the elastic body's creepage with its material passing the
contact from +a to -a (xi > 0 brakes it) and Fx the force on it; softway's `rolling.creepage`
is (omega rho - V) / (omega rho) (> 0: the wheel drives) and Q the creep force, positive when
the wheel drives. So xi_softway = -xi and Q / (mu N) = Fx / (mu Fz) = -(-Fx / (mu Fz)). On
the half-space the creepage is referred to the undeformed radius (softway's
`traction.creepage_undeformed`) and, with mu and nu fixed, the curve depends on xi R / (mu a)
alone (the friction's saturation creepage and the pressure's tangential strain both scale
as a / R): the file's first column.

    python rolling3d_reference.py csv              # rolling3d_reference.csv from creep_curve_coupled.csv (32 cells)
    python rolling3d_reference.py curve [n]        # rolling3d_reference.csv solved on n x n cells (54: 20 min)
    python rolling3d_reference.py ladder [n ...]   # the target creepages on 24, 36, 54 cells (7 min)
"""
import os
import sys
import time
import numpy as np
from coupled import make, steel_case

MU = 0.3
here = os.path.dirname(os.path.abspath(__file__))
TARGETS = (-0.5, 0.0, 0.5)


def write_reference(x, y, n, how):
    o = np.argsort(x)
    path = os.path.join(here, "rolling3d_reference.csv")
    with open(path, "w") as f:
        f.write("# The coupled creep curve of an elastic steel wheel (nu = 0.3) on a rigid crown, R = R_c\n"
                f"# (a circle), Coulomb mu = 0.3: validation/halfspace3d/coupled.py on {n} x {n} cells (on 32 x 32\n"
                "# equal to CONTACT's to its four printed digits: creep_curve_coupled.csv, README.md). In\n"
                "# softway's convention: the creepage on the undeformed radius in units of mu a / R, Q / (mu N).\n"
                f"# Written by rolling3d_reference.py {how}.\n")
        f.write("creepage_mu_a_R,traction_ratio\n")
        for i in o:
            f.write(f"{x[i]:.6f},{y[i]:.6f}\n")
    print(f"wrote {path} ({len(o)} points)")


def write_csv():
    d = np.loadtxt(os.path.join(here, "creep_curve_coupled.csv"), delimiter=",", skiprows=1)
    case = steel_case(0.3)
    unit = MU * case["hz"]["a"] / case["R"]
    write_reference(-d[:, 0] / unit, -d[:, 4], 32, "csv")


def solve_curve(n):
    """The coupled curve on n x n cells at softway's creepages x (mu a / R), warm-started
    outwards from free rolling."""
    case = steel_case(0.3)
    force, unit = case["force"], MU * case["hz"]["a"] / case["R"]
    model = make(case, n, box=1.1, coupled=True)
    xs = np.unique(np.round(np.concatenate([np.linspace(-1.0, 1.6, 27), [-2.0, -1.5, -1.25, 1.8, 2.1, 2.6]]), 6))
    k = int(np.argmin(np.abs(xs - 0.3)))
    out = {}
    for branch in (xs[k:], xs[:k][::-1]):
        state = None if not out else out[xs[k]][1]
        for x in branch:
            t = time.time()
            st = model.coulomb(-unit * x, 0.0, 0.0, MU, force, state=state)
            state = st
            y = model.forces(st["p"], st["q"])[0] / (MU * force)
            out[x] = (y, st)
            print(f"  x = {x:+.4f} mu a / R: Q/(mu N) = {y:+.5f}  ({time.time() - t:.0f} s)", flush=True)
    x = np.array(sorted(out))
    write_reference(x, np.array([out[v][0] for v in x]), n, f"curve {n}")


def target_creepages(n, guesses=None):
    """softway's creepage (undeformed radius, mu a / R) at Q/(mu N) = TARGETS on n x n cells:
    the secant method on Fx(xi)."""
    case = steel_case(0.3)
    force, unit = case["force"], MU * case["hz"]["a"] / case["R"]
    model = make(case, n, box=1.1, coupled=True)
    out, state = [], None
    for k, tgt in enumerate(TARGETS):
        # coupled.py's xi = -unit * x
        g = guesses[k] if guesses is not None else {-0.5: 0.1, 0.0: 0.31, 0.5: 0.55}[tgt]
        x0, x1 = g - 0.02, g + 0.02

        def ratio(x):
            nonlocal state
            st = model.coulomb(-unit * x, 0.0, 0.0, MU, force, state=state)
            state = st
            return model.forces(st["p"], st["q"])[0] / (MU * force) - tgt

        f0, f1 = ratio(x0), ratio(x1)
        for _ in range(30):
            x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
            x0, f0 = x1, f1
            x1, f1 = x2, ratio(x2)
            if abs(f1) < 1e-6:
                break
        out.append(x1)
    return out


def ladder(ns):
    rows = []
    for n in ns:
        t = time.time()
        xs = target_creepages(n)
        rows.append(xs)
        print(f"{n} x {n} cells: creepage at Q/(mu N) = -0.5 / 0 / +0.5: "
              + " / ".join(f"{x:.5f}" for x in xs) + f"  (mu a / R; {time.time() - t:.0f} s)", flush=True)
    rows = np.array(rows)
    if len(ns) >= 3 and all(ns[i + 1] * ns[i - 1] == ns[i] ** 2 for i in range(1, len(ns) - 1)):
        x1, x2, x3 = rows[-3], rows[-2], rows[-1]
        r = ns[-1] / ns[-2]
        p = np.log(np.abs((x1 - x2) / (x2 - x3))) / np.log(r)
        lim = x3 + (x3 - x2) / (r**p - 1)
        print("observed order: " + " / ".join(f"{v:.2f}" for v in p))
        print("Richardson limit: " + " / ".join(f"{v:.5f}" for v in lim))
        print("finest - limit: " + " / ".join(f"{v:+.5f}" for v in x3 - lim))


if __name__ == "__main__":
    if sys.argv[1:2] == ["csv"]:
        write_csv()
    elif sys.argv[1:2] == ["curve"]:
        solve_curve(int(sys.argv[2]) if len(sys.argv) > 2 else 54)
    elif sys.argv[1:2] == ["ladder"]:
        ladder([int(a) for a in sys.argv[2:]] or [24, 36, 54])
    else:
        print(__doc__)
