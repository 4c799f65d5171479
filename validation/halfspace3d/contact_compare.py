"""The press-hertz creep curve of creep_curve.py run by CONTACT (github eve70a/CONTACT, built
with gfortran as README.md says) on the same grid: writes a CONTACT input (module 3, Hertzian
steady rolling, IPOTCN = -2: the curvature A = 1/(2 x 460 mm) and Hertz's a/b, 40 x 40 cells
over 1.08 times the ellipse's bounding box, DQ = DX, Coulomb mu = 0.3, units mm and N/mm^2)
for the creepages of creep_curve.csv, runs it and prints CONTACT's Fx/(mu Fz) beside ours.

python contact_compare.py PATH/TO/contact_linux64 [workdir]   (a few seconds)
"""
import os
import re
import subprocess
import sys
import numpy as np
from halfspace import hertz

here = os.path.dirname(os.path.abspath(__file__))


def write_input(path, xis, a, b, n=40, scale=1.08):
    dq = 2 * scale * a / n
    lines = ["% press-hertz: steel G = 82 GPa, nu = 0.28, Fn = 10 kN, A = 1/(2 x 460 mm), mu = 0.3"]
    for k, xi in enumerate(xis):
        first = k == 0
        lines += [" 3 MODULE",
                  "  203100     P-B-T-N-F-S        PVTIME, BOUND , TANG  , NORM , FORCE, STRESS",
                  ("  022020" if first else "  100000") + "     L-D-C-M-Z-E        FRCLAW, DISCNS, INFLCF, MATER, RZNORM, EXRHS",
                  (" 0000341" if first else " 0100341") + "   H-G-I-A-O-W-R  HEAT, GAUSEI, IESTIM, MATFIL, OUTPUT, FLOW, RETURN"]
        if first:
            lines.append("   300  200    5    1      1e-6    MAXGS , MAXIN , MAXNR , MAXOUT, EPS")
        lines.append(f" 10000.      {xi:.7e}     0.000      0.000           FN, CKSI, CETA, CPHI")
        if first:
            lines += ["   0.300      0.300                                 FSTAT, FKIN",
                      f"   0.000      {1e3 * dq:.6f}      10000.                     CHI, DQ, VELOC",
                      "   0.280      0.280      82000.     82000.          POISS 1,2,  GG 1,2",
                      "   -2                                               IPOTCN",
                      f"   {n}   {n}    {1 / 920:.9f}     {a / b:.6f}      {scale:.3f}           MX,MY,A1,AOB,SCALE"]
        lines.append("")
    lines[-1] = " 0 MODULE"
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main(exe, work):
    os.makedirs(work, exist_ok=True)
    rows = np.loadtxt(os.path.join(here, "creep_curve.csv"), delimiter=",", skiprows=1)
    h = hertz(1 / (2 * 0.46), 1 / (2 * 0.3), 82e9 / (1 - 0.28), 10e3)
    write_input(os.path.join(work, "presshertz.inp"), rows[:, 0], h["a"], h["b"])
    subprocess.run([os.path.abspath(exe), "2", "presshertz"], cwd=work, check=True,
                   stdout=subprocess.DEVNULL)
    out = open(os.path.join(work, "presshertz.out")).read()
    fx = [float(m.group(1)) for m in
          re.finditer(r"FX/FSTAT/FN.*\n\s+\S+\s+(\S+)", out)]
    ncon = [int(m.group(1)) for m in re.finditer(r"NPOT\s+NCON.*\n\s+\d+\s+(\d+)", out)]
    assert len(fx) == len(rows), (len(fx), len(rows))
    print(f"contact cells: CONTACT {ncon[0]}")
    print("   xi [-]     -Fx/(mu Fz): CONTACT   halfspace.py   difference")
    for r, f in zip(rows, fx):
        print(f"  {r[0]:.4e}        {-f:.4f}        {r[4]:.4f}      {r[4] + f:+.4f}")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else "/tmp/contact_presshertz")
