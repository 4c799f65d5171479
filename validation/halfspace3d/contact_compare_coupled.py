"""The coupled creep curve of creep_curve_coupled.py (steel E = 2.05e11 Pa, nu = 0.3, on a rigid
body, A = B = 1/(2 x 100 mm), a = 1.5 mm, mu = 0.3) run by CONTACT (github eve70a/CONTACT,
built with gfortran as README.md says) with dissimilar materials: module 3, Hertzian steady
rolling (IPOTCN = -2: A1 = 1/200 /mm, a/b = 1), n x n cells over 1.1 times Hertz's box (the grid
of creep_curve_coupled.py), DQ = DX, Coulomb mu = 0.3, units mm and N/mm^2, POISS 0.3 and
GG = G1 for the elastic body, a shear modulus 1e7 times larger for the "rigid" one, and the
Panagiotopoulos process (MAXOUT = 50) that CONTACT needs for dissimilar materials (Ak != 0).

CONTACT's forces and creepages are those of its body 1. The case is run twice: the elastic body
as body 1 (compared with the csv as it is) and as body 2 (then body 1's creepage and force are
minus the elastic body's, so CONTACT's curve is compared with -Fx(-xi)).

python contact_compare_coupled.py PATH/TO/contact_linux64 [workdir] [n]   (default n = 32)
"""
import os
import re
import subprocess
import sys
import numpy as np
from coupled import steel_case

here = os.path.dirname(os.path.abspath(__file__))
MU = 0.3


def write_input(path, xis, case, elastic_body=1, n=32, scale=1.1, big=1e7, mu=MU, matfile=False):
    """xis: creepages xi, or tuples (xi, eta, phi) with phi in 1/m."""
    hz = case["hz"]
    a, b = hz["a"], hz["b"]
    dq = 2 * scale * a / n
    g1 = case["G1"] / 1e6  # N/mm^2
    gg = (g1, big * g1) if elastic_body == 1 else (big * g1, g1)
    nu = case["nu"]
    lines = [f"% steel (E = {case['E']:.3e} Pa, nu = {nu}) on a rigid body, body {elastic_body} elastic; "
             f"Fn = {case['force']:.2f} N, A = B = 1/(2 x {1e3 * case['R']:.0f} mm), mu = {MU}"]
    for k, cr in enumerate(xis):
        xi, eta, phi = (cr, 0.0, 0.0) if np.ndim(cr) == 0 else cr
        first = k == 0
        lines += [" 3 MODULE",
                  "  203100     P-B-T-N-F-S        PVTIME, BOUND , TANG  , NORM , FORCE, STRESS",
                  ("  022020" if first else "  100000") + "     L-D-C-M-Z-E        FRCLAW, DISCNS, INFLCF, MATER, RZNORM, EXRHS",
                  ((" 0001341" if first else " 0101341") if matfile else (" 0000341" if first else " 0100341")) + "   H-G-I-A-O-W-R  HEAT, GAUSEI, IESTIM, MATFIL, OUTPUT, FLOW, RETURN"]
        if first:
            lines.append("   300  200    5   50      1e-6    MAXGS , MAXIN , MAXNR , MAXOUT, EPS")
        lines.append(f" {case['force']:.4f}      {xi:.7e}     {eta:.7e}     {phi / 1e3:.7e}    FN, CKSI, CETA, CPHI")
        if first:
            lines += [f"   {mu:.3f}      {mu:.3f}                                 FSTAT, FKIN",
                      f"   0.000      {1e3 * dq:.8f}      10000.                     CHI, DQ, VELOC",
                      f"   {nu:.3f}      {nu:.3f}      {gg[0]:.6e}     {gg[1]:.6e}          POISS 1,2,  GG 1,2",
                      "   -2                                               IPOTCN",
                      f"   {n}   {n}    {case['A'] / 1e3:.9f}     {a / b:.6f}      {scale:.3f}           MX,MY,A1,AOB,SCALE"]
        lines.append("")
    lines[-1] = " 0 MODULE"
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def read_mat(path):
    """Forces (N) and contact cells of one case from CONTACT's .mat file (tractions in N/mm^2
    to six digits, per element in contact)."""
    lines = open(path).read().splitlines()
    k = next(i for i, l in enumerate(lines) if l.lstrip().startswith("%   MX"))
    v = lines[k + 1].split()
    dx, dy = float(v[4]), float(v[5])
    k = next(i for i, l in enumerate(lines) if l.lstrip().startswith("%    I    IGS"))
    data = np.array([[float(t) for t in l.split()] for l in lines[k + 1:] if l.strip() and not l.lstrip().startswith("%")])
    pn, px, py = data[:, 4], data[:, 5], data[:, 6]
    return px.sum() * dx * dy, py.sum() * dx * dy, pn.sum() * dx * dy, int((pn > 0).sum())


def linear(exe, work, case, n, xi_b=0.0, xi0=1e-5, mu=1e3, big=1e7):
    """C11, C22, C23 of CONTACT with full adhesion (mu = 1e3) from central differences about
    (xi_b, 0, 0), the forces from its .mat files (six digits), normalized as coupled.py
    (G = 2 G1, c of Hertz). big = 1: a quasi-identical pair of the same combined modulus."""
    hz = case["hz"]
    c = np.sqrt(hz["a"] * hz["b"])
    cases = [(xi_b + xi0, 0, 0), (xi_b - xi0, 0, 0), (xi_b, xi0, 0), (xi_b, -xi0, 0),
             (xi_b, 0, xi0 / c), (xi_b, 0, -xi0 / c), (xi_b, 0, 0), (0, 0, 0)]
    name = f"lin{n}_{big:g}"
    for f in os.listdir(work):
        if f.startswith(name + "."):
            os.remove(os.path.join(work, f))
    cs = dict(case)
    if big == 1:
        cs["G1"] = 2 * case["G1"]  # G1 = G2 = 2 G1: combined modulus 2 G1, Ak = 0
    write_input(os.path.join(work, name + ".inp"), cases, cs, 1, n, big=big, mu=mu, matfile=True)
    subprocess.run([os.path.abspath(exe), "2", name], cwd=work, check=True, stdout=subprocess.DEVNULL)
    F = [read_mat(os.path.join(work, f"{name}.{k + 1:04d}.mat")) for k in range(len(cases))]
    g = 2 * case["G1"] * c * c
    c11 = -(F[0][0] - F[1][0]) / (2 * xi0) / g
    c22 = -(F[2][1] - F[3][1]) / (2 * xi0) / g
    c23 = -(F[4][1] - F[5][1]) / (2 * xi0 / c) / (g * c)
    return dict(C11=c11, C22=c22, C23=c23, fx_b=F[6][0], ncon=F[6][3], fx0=F[7][0])


def run(exe, work, name, xis, case, elastic_body, n):
    write_input(os.path.join(work, name + ".inp"), xis, case, elastic_body, n)
    subprocess.run([os.path.abspath(exe), "2", name], cwd=work, check=True, stdout=subprocess.DEVNULL)
    out = open(os.path.join(work, name + ".out")).read()
    fx = [float(m.group(1)) for m in re.finditer(r"FX/FSTAT/FN.*\n\s+\S+\s+(\S+)", out)]
    ncon = [int(m.group(1)) for m in re.finditer(r"NPOT\s+NCON.*\n\s+\d+\s+(\d+)", out)]
    ak = re.search(r"AK\s*=?\s*([-+0-9.Ee]+)", out)
    assert len(fx) == len(xis), (len(fx), len(xis))
    return np.array(fx), ncon, out


def main(exe, work, n=32):
    os.makedirs(work, exist_ok=True)
    rows = np.loadtxt(os.path.join(here, "creep_curve_coupled.csv"), delimiter=",", skiprows=1)
    case = steel_case(0.3)
    xis = rows[:, 0]
    fx1, ncon1, _ = run(exe, work, "coupled_b1", xis, case, 1, n)
    fx2, ncon2, _ = run(exe, work, "coupled_b2", -xis, case, 2, n)
    print(f"contact cells at the first creepage: CONTACT {ncon1[0]} (elastic body 1), {ncon2[0]} (elastic body 2)")
    print("   xi [-]      -Fx/(mu Fz): coupled.py  CONTACT (b1)  CONTACT (b2)   diff b1   diff b2   uncoupled")
    d1, d2 = [], []
    for r, f1, f2 in zip(rows, fx1, fx2):
        d1.append(r[4] + f1)
        d2.append(r[4] - f2)
        print(f"  {r[0]:+.4e}        {r[4]:+.4f}      {-f1:+.4f}       {f2:+.4f}      {d1[-1]:+.4f}   {d2[-1]:+.4f}    {r[8]:+.4f}")
    print(f"max |difference|: {np.abs(d1).max():.4f} (body 1 elastic), {np.abs(d2).max():.4f} (body 2 elastic)")
    # full adhesion: the linear coefficients about coupled.py's free-rolling creepage
    from coupled import make
    hz = case["hz"]
    c = np.sqrt(hz["a"] * hz["b"])
    print("\nfull adhesion (CONTACT: mu = 1e3), n x n cells over 1.1 a x 1.1 b, linearized about the")
    print("free-rolling creepage xi_f of coupled.py (+-1e-5); uncoupled: CONTACT with G1 = G2 = 2 G1 (Ak = 0)")
    print("    n  model       contact cells   C11 coupled.py / CONTACT   C22                 C23                 "
          "Fx(xi_f) [N]   Fx(0) [N]")
    for m in sorted({16, n}):
        for cp in (False, True):
            r = make(case, m, coupled=cp).linear_coefficients(case["force"], c, 1e-5, halvings=0)
            k = r["rows"][0][1]
            ct = linear(exe, work, case, m, xi_b=r["xi_base"], big=1e7 if cp else 1)
            print(f"  {m:3d}  {'coupled  ' if cp else 'uncoupled'}   {int((r['base']['p'] > 0).sum())} / {ct['ncon']}     "
                  f"     {k['C11']:.4f} / {ct['C11']:.4f}     {k['C22']:.4f} / {ct['C22']:.4f}   "
                  f"{k['C23']:.4f} / {ct['C23']:.4f}   {ct['fx_b']:+.2f}        {r['fx0']:.1f} / {ct['fx0']:.1f}"
                  f"   (xi_f = {r['xi_base']:.4e})")
    return rows, fx1, fx2


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else "/tmp/contact_coupled",
         int(sys.argv[3]) if len(sys.argv) > 3 else 32)
