"""The longitudinal creep curve of one elastic body on a rigid one, coupled (coupled.py: the
Panagiotopoulos process, the cross influence coefficients kept) beside the uncoupled model of the
same pair (cross coefficients dropped; its curve is odd in xi and solved for xi >= 0 only), for a case the FE model can run: a steel wheel
(E = 2.05e11 Pa, nu = 0.3) of radius R = 0.1 m along the rolling direction on a rigid crown of
radius 0.1 m across it (A = B = 5 /m, a/b = 1), Coulomb mu = 0.3, the normal load from Hertz
(E* = E/(1 - nu^2), the elastic body alone) for the contact radius a = 1.5 mm.

xi is the creepage of the elastic body relative to the rigid one (xi > 0: the wheel's surface
slides forwards, braking) and Fx the force on the elastic body; with coupling the curve is not
odd in xi (the pressure's tangential displacement gives a traction at xi = 0), so it runs from
-1.6 to +1.6 times the saturation creepage 3 mu Fz / (G c^2 C11) (G = 2 G1, Kalker's C11 of the
quasi-identical table) and the free-rolling creepage (Fx = 0) is found by the secant method.

Writes creep_curve_coupled.csv and creep_curve_coupled.png beside this file.
python creep_curve_coupled.py [n_cells_per_axis]     (default 32; about 10 minutes)
python creep_curve_coupled.py plot                   (the figure again from the csv)
"""
import os
import sys
import time
import numpy as np
from coupled import make, steel_case
from halfspace import kalker_table

MU = 0.3
here = os.path.dirname(os.path.abspath(__file__))


def branch(model, xs, force, state=None):
    rows, states = [], []
    for xi in xs:
        t = time.time()
        st = model.coulomb(xi, 0.0, 0.0, MU, force, state=state)
        fx, fy, mz, fz = model.forces(st["p"], st["q"])
        ncon = (st["p"] > 0).sum()
        rows.append((xi, fx, fy, mz, -fx / (MU * force), st["stick"].sum() / ncon, st["outer"],
                     st["sweeps"]))
        if model.touches_edge(st["p"]):
            print("  warning: the contact reaches the candidate set's border")
        print(f"  {'coupled' if model.coupled else 'uncoupled'} xi = {xi:+.4e}  -Fx/(mu Fz) = {rows[-1][4]:+.5f}  "
              f"Fy = {fy:+.1e} N  Mz = {mz:+.1e} N m  stick {rows[-1][5]:.3f}  {st['outer']} outer, "
              f"{st['sweeps']} sweeps  {time.time() - t:.1f} s", flush=True)
        states.append(st)
        state = st
    return rows, states


def curve(model, xs, force):
    """xs sorted; solved outwards from the creepage nearest zero, warm-started."""
    k = int(np.argmin(np.abs(xs)))
    up, sup = branch(model, xs[k:], force)
    down, sdown = branch(model, xs[:k][::-1], force, state=sup[0])
    rows = down[::-1] + up
    states = sdown[::-1] + sup
    return np.array(rows), states


def free_rolling(model, force, x0, x1, state, tol=1e-4):
    """Secant iteration for Fx(xi) = 0 (Coulomb, mu = MU)."""
    f = {}
    for x in (x0, x1):
        st = model.coulomb(x, 0, 0, MU, force, state=state)
        f[x] = model.forces(st["p"], st["q"])[0]
    for _ in range(20):
        x2 = x1 - f[x1] * (x1 - x0) / (f[x1] - f[x0])
        st = model.coulomb(x2, 0, 0, MU, force, state=st)
        f[x2] = model.forces(st["p"], st["q"])[0]
        x0, x1 = x1, x2
        if abs(f[x2]) < tol * MU * force:
            break
    return x2, st


def run(n=32):
    case = steel_case(0.3)
    hz, force = case["hz"], case["force"]
    c2 = hz["a"] * hz["b"]
    Gc = 2 * case["G1"]
    c11 = kalker_table(0.3, 1.0)[0]
    xi_sat = 3 * MU * force / (Gc * c2 * c11)
    f = np.concatenate([[0.0], np.linspace(0.05, 0.3, 6), np.linspace(0.4, 1.0, 7), [1.2, 1.6]])
    xs = xi_sat * np.unique(np.concatenate([-f, f]))
    out = dict(case=case, xi_sat=xi_sat, c11_table=c11, n=n)
    for cp in (True, False):
        t = time.time()
        model = make(case, n, box=1.1, coupled=cp)
        if cp:
            rows, states = curve(model, xs, force)
        else:  # odd in xi: solve xi >= 0 and mirror
            k = int(np.argmin(np.abs(xs)))
            up, sup = branch(model, xs[k:], force)
            up = np.array(up)
            down = up[1:][::-1].copy()
            down[:, :5] *= -1
            down[:, 5:] = up[1:][::-1, 5:]
            rows = np.vstack([down, up])
            states = [None] * (len(xs) - len(sup)) + sup
        out[cp] = dict(rows=rows, states=states, model=model, time=time.time() - t)
        if cp:
            k = int(np.argmin(np.abs(xs)))
            j = np.flatnonzero(np.sign(rows[:-1, 1]) != np.sign(rows[1:, 1]))[0]
            xf, st = free_rolling(model, force, rows[j, 0], rows[j + 1, 0], states[j])
            out["xi_free"], out["free_state"] = xf, st
            # slope of the mu = 0.3 curve at free rolling (central difference, +-xi_sat/100)
            e = xi_sat / 100
            fp = model.forces(*[model.coulomb(xf + e, 0, 0, MU, force, state=st)[k] for k in ("p", "q")])[0]
            fm = model.forces(*[model.coulomb(xf - e, 0, 0, MU, force, state=st)[k] for k in ("p", "q")])[0]
            out["slope_free"] = -(fp - fm) / (2 * e) / (Gc * c2)
    return out


def write(r, path):
    rc, ru = r[True]["rows"], r[False]["rows"]
    hdr = ("creepage_xi [-],Fx [N],Fy [N],Mz [N m],minus_Fx_over_mu_Fz [-],stick_fraction_of_contact_cells [-],"
           "panagiotopoulos_iterations [-],gauss_seidel_sweeps [-],"
           "uncoupled_minus_Fx_over_mu_Fz [-],uncoupled_stick_fraction [-]")
    data = np.column_stack([rc[:, :8], ru[:, 4], ru[:, 5]])
    np.savetxt(path, data, delimiter=",", header=hdr, comments="",
               fmt=["%.6e", "%.6e", "%.6e", "%.6e", "%.6f", "%.4f", "%d", "%d", "%.6f", "%.4f"])


def replot(path_csv, path_png, n=32):
    """The figure from the csv, with the two traction fields (xi = 0, free rolling) solved again."""
    data = np.loadtxt(path_csv, delimiter=",", skiprows=1)
    case = steel_case(0.3)
    model = make(case, n, box=1.1, coupled=True)
    rc = data[:, :8]
    ru = np.column_stack([data[:, 0], np.zeros((len(data), 3)), data[:, 8], data[:, 9]])
    s0 = model.coulomb(0.0, 0, 0, MU, case["force"])
    k = np.flatnonzero(np.sign(rc[:-1, 1]) != np.sign(rc[1:, 1]))[0]
    xf, sf = free_rolling(model, case["force"], rc[k, 0], rc[k + 1, 0], s0)
    states = [None] * len(rc)
    states[int(np.argmin(np.abs(rc[:, 0])))] = s0
    r = {True: dict(rows=rc, states=states, model=model), False: dict(rows=ru), "case": case,
         "xi_free": xf, "free_state": sf}
    plot(r, path_png)


def plot(r, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update({"font.size": 9, "font.family": "serif", "mathtext.fontset": "cm"})
    rc, ru = r[True]["rows"], r[False]["rows"]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(7.4, 3.1), gridspec_kw=dict(width_ratios=[1.3, 1]))
    ax.axhline(0, color="0.6", lw=0.6)
    ax.axvline(0, color="0.6", lw=0.6)
    ax.plot(1e3 * ru[:, 0], ru[:, 4], "s--", color="tab:orange", ms=2.5, lw=1,
            label="uncoupled (quasi-identical model)")
    ax.plot(1e3 * rc[:, 0], rc[:, 4], "o-", color="tab:blue", ms=3, lw=1.2,
            label="coupled (elastic on rigid)")
    ax.plot([1e3 * r["xi_free"]], [0], "kx", ms=6, label=rf"free rolling, $\xi$ = {1e3 * r['xi_free']:.3f}$\times10^{{-3}}$")
    ax.set_xlabel(r"longitudinal creepage $\xi$ [$10^{-3}$]")
    ax.set_ylabel(r"$-F_x/(\mu F_z)$ [-]")
    ax.set_xlim(1e3 * rc[0, 0], 1e3 * rc[-1, 0])
    ax.set_ylim(-1.08, 1.08)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=7, frameon=False)
    hz, case = r["case"]["hz"], r["case"]
    ax.set_title(rf"(a) steel on rigid, $a$ = {1e3 * hz['a']:.1f} mm, $F_z$ = {case['force'] / 1e3:.2f} kN, $\mu$ = {MU}",
                 fontsize=8.5)
    # (b) centre line at zero creepage: pressure and traction, coupled
    m = r[True]["model"]
    k0 = int(np.argmin(np.abs(rc[:, 0])))
    st = r[True]["states"][k0]
    p, q = st["p"], st["q"]
    row = np.abs(m.y - m.y[np.argmin(np.abs(m.y))]) < 1e-12
    o = np.argsort(m.x[row])
    xr = 1e3 * m.x[row][o]
    bx.plot(xr, MU * p[row][o] / 1e6, "k-", lw=1, label=r"$\pm\mu p$ at $\xi$ = 0")
    bx.plot(xr, -MU * p[row][o] / 1e6, "k-", lw=1)
    bx.step(xr, q[:m.nC][row][o] / 1e6, where="mid", color="tab:blue", lw=1, label=r"$q_x$ at $\xi$ = 0")
    stk = st["stick"][row][o]
    bx.plot(xr[stk], q[:m.nC][row][o][stk] / 1e6, "o", color="tab:blue", ms=2, label="stick")
    sf = r["free_state"]
    bx.step(xr, sf["q"][:m.nC][row][o] / 1e6, where="mid", color="tab:red", lw=1,
            label=r"$q_x$ at free rolling")
    bx.set_xlabel(r"$x$ [mm] (rolling direction $\rightarrow$)")
    bx.set_ylabel("traction on the wheel [MPa]")
    bx.set_title(r"(b) centre line $y$ = 0, coupled", fontsize=8.5)
    bx.set_xlim(-1.1e3 * hz["a"], 1.1e3 * hz["a"])
    bx.set_ylim(-1.1 * MU * p.max() / 1e6, 1.75 * MU * p.max() / 1e6)
    bx.grid(alpha=0.3)
    bx.legend(fontsize=6.5, frameon=False, loc="upper center", ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=200)


if __name__ == "__main__":
    if sys.argv[1:2] == ["plot"]:  # the figure again from the csv (a minute)
        replot(os.path.join(here, "creep_curve_coupled.csv"), os.path.join(here, "creep_curve_coupled.png"))
        sys.exit()
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 32
    r = run(n)
    case, hz = r["case"], r["case"]["hz"]
    Gc, c2 = 2 * case["G1"], hz["a"] * hz["b"]
    print(f"pair: E = {case['E']:.3e} Pa, nu = {case['nu']}, G1 = {case['G1']:.4e} Pa (G = 2 G1), R = {case['R']} m, "
          f"Hertz load Fz = {case['force']:.2f} N for a = {1e3 * hz['a']:.4f} mm, p0 = {hz['p0'] / 1e6:.1f} MPa, "
          f"approach {1e6 * hz['delta']:.3f} um; mu = {MU}; {n} x {n} cells over 1.1 a x 1.1 b")
    print(f"saturation creepage 3 mu Fz/(G c^2 C11) = {r['xi_sat']:.4e} (C11 = {r['c11_table']:.3f}, table)")
    for cp in (True, False):
        rows = r[cp]["rows"]
        full = rows[(rows[:, 0] > 0) & (rows[:, 5] == 0), 0]
        fullm = rows[(rows[:, 0] < 0) & (rows[:, 5] == 0), 0]
        print(f"{'coupled' if cp else 'uncoupled'}: first full slip at xi = {full.min() if len(full) else float('nan'):.4e} "
              f"and {fullm.max() if len(fullm) else float('nan'):.4e} (of the points run); {r[cp]['time']:.0f} s")
    print(f"coupled, mu = {MU}: free rolling (Fx = 0) at xi = {r['xi_free']:.4e} = {r['xi_free'] / (hz['a'] / case['R']):+.4f} a/R; "
          f"slope there -dFx/dxi/(G c^2) = {r['slope_free']:.4f}")
    write(r, os.path.join(here, "creep_curve_coupled.csv"))
    plot(r, os.path.join(here, "creep_curve_coupled.png"))
