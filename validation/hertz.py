"""Hertz's elliptic point contact (Johnson, Contact Mechanics 1985, Sec. 4.2, Eq. 4.39) by
scipy's complete elliptic integrals (scipy.special.ellipk / ellipe, parameter m = e^2) and a
root finder, independent of softway's arithmetic-geometric mean and bisection. It prints the
eccentricity, semi-axes, peak pressure and approach of the cases that tests/hertz*.rs and
src/contact/hertz.rs check:

  1. a rigid sphere R = 0.1 m on steel (E = 210 GPa, nu = 0.3, E* = E / (1 - nu^2)), P = 1 kN;
  2. a rigid body of radii 0.46 m (along x) and 0.30 m (across, y) on steel, P = 10, 50, 100 kN;
  3. the same radii, two steel bodies (E* = E / (2 (1 - nu^2))), P = 100 kN (the rail's case);
  4. the half-space's axial displacement at depth z under case 2's pressure at 100 kN
     (Boussinesq's kernel, Johnson Eq. 3.21c, integrated by scipy's dblquad).

python validation/hertz.py
"""
import numpy as np
from scipy.special import ellipk, ellipe
from scipy.optimize import brentq
from scipy.integrate import dblquad

E, NU = 210e9, 0.3


def hertz(rx, ry, e_star, p):
    A, B = 0.5 / max(rx, ry), 0.5 / min(rx, ry)  # A <= B: a along the smaller curvature

    def ratio(e):
        m = e * e
        k, ee = ellipk(m), ellipe(m)
        return (ee / (1 - m) - k) / (k - ee)

    if abs(B / A - 1) < 1e-12:
        r = 0.5 / A
        a = (3 * p * r / (4 * e_star)) ** (1 / 3)
        return dict(e=0.0, a=a, b=a, p0=3 * p / (2 * np.pi * a * a), delta=a * a / r)
    e = brentq(lambda e: ratio(e) - B / A, 1e-3, 1 - 1e-9, xtol=1e-16, rtol=1e-15)
    m = e * e
    k, ee = ellipk(m), ellipe(m)
    a = (3 * p * (k - ee) / (2 * np.pi * m * e_star * A)) ** (1 / 3)
    b = a * np.sqrt(1 - m)
    p0 = 3 * p / (2 * np.pi * a * b)
    delta = p0 * b * k / e_star
    return dict(e=e, a=a, b=b, p0=p0, delta=delta)


def axial(h, z, nu, g):
    """u_z(0, 0, z) of the half-space under Hertz's pressure of h (x = a s cos t, y = b s sin t)."""
    a, b, p0 = h["a"], h["b"], h["p0"]

    def f(s, t):
        x, y = a * s * np.cos(t), b * s * np.sin(t)
        rho = np.sqrt(x * x + y * y + z * z)
        return p0 * np.sqrt(1 - s * s) * (z * z / rho**3 + 2 * (1 - nu) / rho) * a * b * s

    v, _ = dblquad(f, 0, 2 * np.pi, 0, 1, epsabs=0, epsrel=1e-11)
    return v / (4 * np.pi * g)


rigid = E / (1 - NU**2)
g = E / (2 * (1 + NU))
print("sphere R=0.1 P=1e3:", hertz(0.1, 0.1, rigid, 1e3))
for p in (10e3, 50e3, 100e3):
    print(f"rigid 0.46/0.30 P={p:g}:", hertz(0.46, 0.30, rigid, p))
print("two steel bodies 0.46/0.30 P=1e5:", hertz(0.46, 0.30, E / (2 * (1 - NU**2)), 100e3))
h = hertz(0.46, 0.30, rigid, 100e3)
for z in (1e-3, 1e-2, 1e-1):
    print(f"axial displacement z={z:g}: {axial(h, z, NU, g):.12e}",
          f"(point load {100e3 * (3 - 2 * NU) / (4 * np.pi * g * z):.12e})")
