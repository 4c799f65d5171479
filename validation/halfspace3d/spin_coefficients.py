"""Kalker's spin coefficients C23 and C33 from the full-stick limit of halfspace.py's steady
rolling problem (nu = 0.25, a/b = 1; Kalker's form F_y = -G c^2 (C22 eta + c C23 phi),
M_z = G c^3 (C23 eta - c C33 phi)), on a ladder of grids with a Richardson limit: C23 read
from F_y at the spin and from M_z at the lateral creepage (antisymmetric coupling: the same
number in the exact theory), and C33, the reference of the elastic rail's spin runs
(docs/src/solids3d.md, "Spin on the elastic rail"). Table E.3 gives C23 = 1.47 here.

python spin_coefficients.py [n ...]      (default 16 32 64; about a minute)
"""
import sys
from halfspace import kalker_table
from kalker_coefficients import ladder, richardson


def main(ns, a=1.0, b=1.0, nu=0.25):
    ref = kalker_table(nu, a / b)
    print(f"nu = {nu}, a/b = {a / b}: Kalker (Table E.3) C23 = {ref[2]:.3f}")
    print("    n  cells  C23 (F_y, phi)  C23 (M_z, eta)      C33   time/s")
    rows = ladder(a, b, nu, ns, "spin_coefficients")
    for n, cells, *v, secs in rows:
        print(f"  {n:3d}  {cells:5d}  {v[0]:14.4f}  {v[1]:14.4f}  {v[2]:7.4f}  {secs:7.1f}")
    if len(rows) >= 3:
        for k, lab in enumerate(("C23 (F_y, phi)", "C23 (M_z, eta)", "C33")):
            lim, p = richardson([row[2 + k] for row in rows])
            print(f"  {lab}: finest {rows[-1][2 + k]:.4f}, Richardson {lim:.4f} (observed order {p:.2f})")


if __name__ == "__main__":
    main([int(s) for s in sys.argv[1:]] or [16, 32, 64])
