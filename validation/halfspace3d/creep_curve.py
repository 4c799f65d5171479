"""The longitudinal creep curve Fx / (mu Fz) against the creepage xi, from vanishing creepage to
full slip, for the Hertzian case of scenarios/press-hertz.toml: two steel bodies (G = 82 GPa,
nu = 0.28), Fz = 10 kN, A = 1/(2 x 0.46 m) along the rolling direction x, B = 1/(2 x 0.3 m)
across, Coulomb friction mu = 0.3, steady rolling, no lateral creepage or spin.

The normal problem is solved on the grid (halfspace.solve_normal, the force prescribed), the
tangential one on the cells it puts in contact (halfspace.Rolling.solve), each creepage warm
started from the previous one. Secondary, labelled curves: the linear theory Fx = -G c^2 C11 xi
with Kalker's tabulated C11, and the cubic saturation F/(mu Fz) = 1 - (1 - x)^3,
x = G c^2 C11 xi / (3 mu Fz) (Johnson and Vermeulen 1964's form with Kalker's C11; the law
Shen, Hedrick and Elkins 1983 build on), which is not an independent 3D solution.

Writes creep_curve.csv and creep_curve.png next to the given output prefix (default: this
folder). python creep_curve.py [n_cells_per_axis] [out_prefix]   (default 40; about 2 minutes)
"""
import os
import sys
import time
import numpy as np
from halfspace import Grid, Rolling, contact_measures, hertz, kalker_table, solve_normal

G, NU, FZ, MU = 82e9, 0.28, 10e3, 0.3
A, B = 1 / (2 * 0.46), 1 / (2 * 0.3)


def run(n=40):
    h = hertz(A, B, G / (1 - NU), FZ)
    grid = Grid.box(1.08 * h["a"], 1.08 * h["b"], n, n)
    p, delta = solve_normal(grid, A, B, G, NU, force=FZ)
    m = contact_measures(grid, p)
    idx = np.flatnonzero(p > 0)
    roll = Rolling(grid, G, NU, idx)
    bound = MU * p[idx]
    c2 = h["a"] * h["b"]
    c11 = kalker_table(NU, h["a"] / h["b"])[0]
    xi_sat = 3 * MU * FZ / (G * c2 * c11)
    xs = xi_sat * np.concatenate([np.linspace(0, 0.2, 5)[1:], np.linspace(0.25, 1.0, 16),
                                  [1.1, 1.25, 1.5, 2.0]])
    rows, fields = [], {}
    q = None
    for xi in xs:
        t = time.time()
        q, s, stick, sweeps = roll.solve(xi, 0.0, 0.0, bound, q0=q, tol=1e-9)
        fx, fy, mz = roll.forces(q)
        rows.append((xi, fx, fy, mz, -fx / (MU * FZ), stick.mean(), sweeps))
        print(f"xi = {xi:.4e}  -Fx/(mu Fz) = {-fx / (MU * FZ):.5f}  Fy = {fy:+.2e} N  "
              f"stick {stick.mean():.3f}  {sweeps} sweeps  {time.time() - t:.1f} s", flush=True)
        fields[xi] = (q.copy(), stick.copy())
    return dict(h=h, grid=grid, p=p, m=m, idx=idx, roll=roll, rows=np.array(rows), c11=c11,
                xi_sat=xi_sat, c2=c2, fields=fields)


def write(r, prefix):
    rows = r["rows"]
    hdr = ("creepage_xi [-],Fx [N],Fy [N],Mz [N m],minus_Fx_over_mu_Fz [-],"
           "stick_fraction_of_contact_cells [-],gauss_seidel_sweeps [-]")
    np.savetxt(prefix + ".csv", rows, delimiter=",", header=hdr, comments="",
               fmt=["%.6e", "%.6e", "%.6e", "%.6e", "%.6f", "%.4f", "%d"])


def plot(r, prefix):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update({"font.size": 9, "font.family": "serif", "mathtext.fontset": "cm"})
    rows, xi_sat, c11, c2 = r["rows"], r["xi_sat"], r["c11"], r["c2"]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(7.2, 3.0), gridspec_kw=dict(width_ratios=[1.25, 1]))
    xx = np.linspace(0, rows[-1, 0], 400)
    lin = G * c2 * c11 * xx / (MU * FZ)
    x = np.minimum(xx / xi_sat, 1)
    ax.plot(1e3 * xx, np.minimum(lin, 1.2), ":", color="0.5", lw=1, label=r"linear theory, Kalker's $C_{11}$")
    ax.plot(1e3 * xx, 1 - (1 - x) ** 3, "--", color="tab:orange", lw=1,
            label=r"$1-(1-\tilde\xi)^3$ (Johnson-Vermeulen form)")
    ax.plot(1e3 * rows[:, 0], rows[:, 4], "o-", color="tab:blue", ms=3, lw=1.2,
            label="half-space, Kalker's exact theory")
    ax.set_xlabel(r"longitudinal creepage $\xi$ [$10^{-3}$]")
    ax.set_ylabel(r"$-F_x/(\mu F_z)$")
    ax.set_ylim(0, 1.08)
    ax.set_xlim(0, 1e3 * rows[-1, 0])
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=7, frameon=False)
    ax.set_title(r"(a) creep curve, $F_z$ = 10 kN, $\mu$ = 0.3", fontsize=9)
    # (b) the traction on the centre line y ~ 0 for three creepages
    grid, idx, p = r["grid"], r["idx"], r["p"]
    n = len(idx)
    yc = grid.y[idx]
    row = np.abs(yc - yc[np.argmin(np.abs(yc))]) < 1e-12
    xr = grid.x[idx][row]
    o = np.argsort(xr)
    a = r["h"]["a"]
    bx.plot(1e3 * xr[o], MU * p[idx][row][o] / 1e6, "k-", lw=1, label=r"$\mu p$")
    keys = sorted(r["fields"])
    colours = ["tab:green", "tab:blue", "tab:red"]
    for target, col in zip((0.15, 0.4, 0.65), colours):
        xi = min(keys, key=lambda k: abs(k / r["xi_sat"] - target))
        q, stick = r["fields"][xi]
        qx = -q[:n][row][o] / 1e6
        bx.step(1e3 * xr[o], qx, where="mid", color=col, lw=1,
                label=rf"$-q_x$, $\xi$ = {1e3 * xi:.2f}$\times10^{{-3}}$")
        st = stick[row][o]
        bx.plot(1e3 * xr[o][st], qx[st], "o", color=col, ms=2)
    bx.set_xlabel(r"$x$ [mm] (rolling direction $\rightarrow$)")
    bx.set_ylabel("traction [MPa]")
    bx.set_title(r"(b) centre line; dots: stick", fontsize=9)
    bx.set_xlim(-1.08e3 * a, 1.08e3 * a)
    bx.set_ylim(0, 1.5 * MU * p.max() / 1e6)
    bx.grid(alpha=0.3)
    bx.legend(fontsize=6.5, frameon=False, loc="upper center", ncol=2)
    fig.tight_layout()
    fig.savefig(prefix + ".png", dpi=200)


if __name__ == "__main__":
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 40
    prefix = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "creep_curve")
    r = run(n)
    m, h = r["m"], r["h"]
    print(f"normal problem: area {m['area'] / (np.pi * h['a'] * h['b']):.4f} x Hertz's, a {m['a'] / h['a']:.4f}, "
          f"b {m['b'] / h['b']:.4f}, peak {m['pmax'] / h['p0']:.4f} x p0; saturation creepage "
          f"3 mu Fz / (G c^2 C11) = {r['xi_sat']:.4e}")
    write(r, prefix)
    plot(r, prefix)
