"""Southwell coefficients of a uniform rotating cantilever (zero hub radius), by an
independent 1D Euler-Bernoulli beam model (Hermite elements, the centrifugal tension
N(x) = rho A Omega^2 (L^2 - x^2) / 2 in the geometric stiffness), for tests/rotating3d.rs.
Flapwise: omega^2 = omega_0^2 + K1 Omega^2; lagwise (spin softening -Omega^2 rho A too):
omega^2 = omega_0^2 + (K1 - 1) Omega^2. Published K1 = 1.1933 (Wright, Smith, Thresher and
Wang 1982, J. Appl. Mech. 49, Table 1, first mode, zero hub radius)."""
import numpy as np
from scipy.linalg import eigh

n, L = 200, 1.0
h = L / n
N = 2 * (n + 1)
K, M, G = (np.zeros((N, N)) for _ in range(3))
ke = np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
               [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]]) / h**3
me = h / 420 * np.array([[156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
                         [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]])
gp, gw = np.polynomial.legendre.leggauss(6)
for e in range(n):
    x0 = e * h
    ge = np.zeros((4, 4))
    for s, w in zip(gp, gw):
        xi = (s + 1) / 2
        x = x0 + xi * h
        dn = np.array([(-6 * xi + 6 * xi**2) / h, 1 - 4 * xi + 3 * xi**2,
                       (6 * xi - 6 * xi**2) / h, -2 * xi + 3 * xi**2])
        ge += w * h / 2 * (L * L - x * x) / 2 * np.outer(dn, dn)
    idx = slice(2 * e, 2 * e + 4)
    K[idx, idx] += ke
    M[idx, idx] += me
    G[idx, idx] += ge
free = slice(2, N)  # clamped at x = 0
Kf, Mf, Gf = K[free, free], M[free, free], G[free, free]
w0 = eigh(Kf, Mf, eigvals_only=True)[:3]
w1 = eigh(Kf + Gf, Mf, eigvals_only=True)[:3]  # EI = rho A = Omega = 1
print("omega_0 (EI = rho A = L = 1):", np.sqrt(w0), "(3.5160, 22.0345, 61.6972)")
print("Southwell K1..K3 (flap):", w1 - w0)
lam, phi = eigh(Kf, Mf)
for k in range(3):
    f = phi[:, k]
    print(f"mode {k + 1}: slope d(omega^2)/d(Omega^2) at 0 = phi^T G phi / phi^T M phi =",
          f @ Gf @ f / (f @ Mf @ f))
for om2 in (1.0, 12.36):
    w = eigh(Kf + om2 * Gf, Mf, eigvals_only=True)[:2]
    print(f"Omega^2 = {om2}: (omega^2 - omega_0^2)/Omega^2 =", (w - w0[:2]) / om2)
