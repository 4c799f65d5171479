#!/usr/bin/env python3
"""Peer comparison of softway's space-time step (issue 11): one command, one ratio.

    python bench/peers/peers.py scenarios/wheel-paper-mesh.toml [--softway target/release/softway]

Runs `softway matrix SCENARIO --out DIR`, which writes the step's matrices (A, B, K in
Matrix Market), the state and load of the step, the fixed dofs, the sizes of softway's
factors and softway's own time for one free step (matrix.json), then times the same step
with the peers, factor once and solve per step, each step being

    b = B v0 - h K u0 + h f,  b[fixed] = 0,  v1 = A^-1 b

(with `time.coriolis = "extrapolated"` in the scenario, A and B hold the symmetric part of C
and the Coriolis term is on the right-hand side: `b -= h G (v0 + alpha h a0)`, from G.mtx and
a0.mtx; A is then symmetric and CHOLMOD solves the same step as softway)

- scipy's SuperLU (`scipy.sparse.linalg.splu`) on A, COLAMD and MMD(A^T + A) orderings:
  the exact step (A is unsymmetric when the wheel spins: Coriolis);
- CHOLMOD through cholespy (if installed) on A when A is symmetric; on an unsymmetric A on
  its symmetric part (A + A^T)/2 instead, a bound for a Cholesky peer and not the same step
  (marked so).

Each time is the median over five rounds of many steps, in this process, single-threaded
(OMP/MKL/OpenBLAS threads set to 1). Prints a table with the nnz of each factor and the
ratio softway / peer. Needs numpy and scipy; cholespy optional
(`pip install numpy scipy cholespy`). Not part of CI.
"""
import argparse
import json
import resource
import os
import subprocess
import sys
import tempfile
import time

for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

import numpy as np  # noqa: E402
import scipy.io  # noqa: E402
import scipy.sparse as sp  # noqa: E402
import scipy.sparse.linalg as spla  # noqa: E402


def median_step_us(step, reps):
    rounds = []
    for _ in range(5):
        t = time.perf_counter()
        for _ in range(reps):
            step()
        rounds.append((time.perf_counter() - t) / reps * 1e6)
    rounds.sort()
    return rounds[2]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenario")
    ap.add_argument("--softway", default=None,
                    help="the softway binary [default: target/release/softway, else cargo run --release]")
    ap.add_argument("--dir", default=None, help="where softway writes the matrices [default: a temporary folder]")
    ap.add_argument("--steps", type=int, default=None,
                    help="softway's timed steps per round (softway matrix --steps) [default: softway's]")
    ap.add_argument("--no-superlu", action="store_true",
                    help="leave SuperLU out (a large 3D matrix: its LU takes minutes and gigabytes)")
    ap.add_argument("--superlu-orderings", default="COLAMD,MMD_AT_PLUS_A",
                    help="SuperLU's column orderings, comma-separated [default: COLAMD,MMD_AT_PLUS_A]; "
                         "on a large 3D matrix COLAMD's fill alone takes gigabytes (86,400 unknowns: "
                         "152M entries against MMD's 33M)")
    args = ap.parse_args()

    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(os.path.dirname(here))
    out = args.dir or tempfile.mkdtemp(prefix="softway-peers-")
    exe = args.softway
    if exe is None:
        target = os.environ.get("CARGO_TARGET_DIR", os.path.join(root, "target"))
        cand = os.path.join(target, "release", "softway")
        exe = cand if os.path.exists(cand) else None
    cmd = [exe] if exe else ["cargo", "run", "--quiet", "--release", "--"]
    steps = ["--steps", str(args.steps)] if args.steps else []
    subprocess.run(cmd + ["matrix", os.path.abspath(args.scenario), "--out", os.path.abspath(out)] + steps, check=True, cwd=root,
                   stdout=subprocess.DEVNULL)

    info = json.load(open(os.path.join(out, "matrix.json")))
    A = sp.csc_matrix(scipy.io.mmread(os.path.join(out, "A.mtx")))
    B = sp.csr_matrix(scipy.io.mmread(os.path.join(out, "B.mtx")))
    K = sp.csr_matrix(scipy.io.mmread(os.path.join(out, "K.mtx")))
    u0 = np.asarray(scipy.io.mmread(os.path.join(out, "u0.mtx"))).ravel()
    v0 = np.asarray(scipy.io.mmread(os.path.join(out, "v0.mtx"))).ravel()
    f = np.asarray(scipy.io.mmread(os.path.join(out, "f.mtx"))).ravel()
    fixed_txt = open(os.path.join(out, "fixed.txt")).read().split()
    fixed = np.array([int(d) for d in fixed_txt], dtype=np.int64)
    h = info["h_s"]
    n = A.shape[0]
    hf = h * f
    hK = (h * K).tocsr()
    g_path = os.path.join(out, "G.mtx")
    if os.path.exists(g_path):
        hG = (h * sp.csr_matrix(scipy.io.mmread(g_path))).tocsr()
        a0 = np.asarray(scipy.io.mmread(os.path.join(out, "a0.mtx"))).ravel()
        ah = info["alpha"] * h
    else:
        hG = None

    def rhs():
        b = B @ v0 - hK @ u0 + hf
        if hG is not None:
            b -= hG @ (v0 + ah * a0)
        b[fixed] = 0.0
        return b

    reps = int(min(20000, max(20, 2_000_000 // (A.nnz + 1))))
    rows = []  # (peer, nnz of factors, us per step, exact step?)
    ref = None
    factor_s = {}
    for spec in () if args.no_superlu else [o.strip() for o in args.superlu_orderings.split(",") if o.strip()]:
        t0 = time.perf_counter()
        lu = spla.splu(A, permc_spec=spec)
        factor_s[f"scipy splu (SuperLU, {spec})"] = time.perf_counter() - t0
        x = lu.solve(rhs())
        if ref is None:
            ref = x
        us = median_step_us(lambda: lu.solve(rhs()), reps)
        rows.append((f"scipy splu (SuperLU, {spec})", lu.L.nnz + lu.U.nnz, us, True))
    resid = None if ref is None else np.abs(A @ ref - rhs()).max() / np.abs(rhs()).max()

    try:
        from cholespy import CholeskySolverD, MatrixType
        sym = abs(A - A.T).max() <= 1e-14 * abs(A).max()
        S = A if sym else ((A + A.T) * 0.5).tocsc()
        S = S.tocoo()
        t0 = time.perf_counter()
        solver = CholeskySolverD(n, S.row.astype(np.int32), S.col.astype(np.int32),
                                 S.data.astype(np.float64), MatrixType.COO)
        chol_factor_s = time.perf_counter() - t0
        xb = np.empty(n)

        def chol_step():
            b = rhs()
            solver.solve(b, xb)
        us = median_step_us(chol_step, reps)
        label = "CHOLMOD (cholespy)" + ("" if sym else " on (A+A^T)/2: no Coriolis, a bound")
        rows.append((label, None, us, sym))
        factor_s[label] = chol_factor_s
        if ref is None:
            ref = np.empty(n)
            solver.solve(rhs(), ref)
            resid = np.abs(A @ ref - rhs()).max() / np.abs(rhs()).max()
    except ImportError:
        print("cholespy not installed: no CHOLMOD row (pip install cholespy)", file=sys.stderr)

    sw = info["softway_step_us"]
    print(f"{info['n']} dofs, nnz(A) = {info['nnz_a']}, h = {h:g} s, A symmetric: {info['symmetric']}, "
          f"coriolis {info.get('coriolis', 'implicit')}; "
          f"residual of the first peer {float('nan') if resid is None else resid:.1e}")
    sw_factor = info.get("factor_s")
    if sw_factor is not None:
        print(f"softway's factor ({info['factor']}, ordering {info.get('factor_ordering', '?')}): "
              f"{sw_factor:.2f} s, peak memory {info.get('peak_rss_mib') or 0:.0f} MiB; "
              + "; ".join(f"{k}: factor {v:.2f} s" for k, v in factor_s.items())
              + f"; this process's peak memory {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MiB")
    print(f"{'solver':58} {'nnz(factors)':>13} {'us/step':>9} {'softway/peer':>13}")
    for name, nnz in info["factor_nnz"]:
        mark = " (used)" if name == info["factor"] else ""
        print(f"{'softway ' + name + mark:58} {nnz:>13}")
    print(f"{'softway (its factor, matrix.json)':58} {'':>13} {sw:>9.1f} {1.0:>13.2f}")
    best = None
    for name, nnz, us, exact in rows:
        nz = "" if nnz is None else str(nnz)
        print(f"{name:58} {nz:>13} {us:>9.1f} {sw / us:>13.2f}")
        if exact and (best is None or us < best[1]):
            best = (name, us)
    if best:
        print(f"ratio softway / best exact peer ({best[0]}): {sw / best[1]:.2f}")


if __name__ == "__main__":
    main()
