#!/usr/bin/env python3
"""A peer for softway's 3D Cholesky: CHOLMOD (cholespy) and SuperLU on the same matrices.

    cargo run --release --example solver3d_ladder -- --kind hex8 --cells 18,24 --mtx DIR
    /work/venv-peers/bin/python bench/peers/solver3d.py DIR/A_hex8_18.mtx ... [--splu-max N]

For each Matrix Market file written by the ladder (the step matrix M + c K of a box):

- CHOLMOD through cholespy (CholeskySolverD): cholespy calls cholmod_analyze with one
  ordering method, CHOLMOD_NESDIS (CHOLMOD's nested dissection on METIS's node separators),
  and a simplicial LL' factorization, then solves with its own triangular sweeps; the time
  of the constructor (ordering, analysis, factorization, the copies into its solve layout)
  and of one solve (median of five). cholespy does not report nnz(L).
- scipy's SuperLU (splu) with MMD on A^T + A and no pivoting off the diagonal
  (diag_pivot_thresh 0: the Cholesky-like LU of an SPD matrix), up to --splu-max unknowns
  (default 30,000: it is slow in 3D): factor time, nnz(L + U), a solve.

Single-threaded (OMP/OpenBLAS/MKL threads 1). Prints a Markdown table. Not part of CI.
"""
import argparse
import os
import sys
import time

for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

import numpy as np  # noqa: E402
import scipy.io  # noqa: E402
import scipy.sparse as sp  # noqa: E402
import scipy.sparse.linalg as spla  # noqa: E402


def median_time(f, rounds=5):
    ts = []
    for _ in range(rounds):
        t = time.perf_counter()
        f()
        ts.append(time.perf_counter() - t)
    ts.sort()
    return ts[len(ts) // 2]


def peak_mb():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mtx", nargs="+")
    ap.add_argument("--splu-max", type=int, default=30000)
    args = ap.parse_args()
    try:
        from cholespy import CholeskySolverD, MatrixType
    except ImportError:
        CholeskySolverD = None
    load = open("/proc/loadavg").read().split()[:3]
    print(f"load average {' '.join(load)}")
    print("| matrix | dofs | nnz(A) | peer | ordering | factor s | nnz(L) | solve ms | residual | peak MB (process) |")
    print("|---|---:|---:|---|---|---:|---:|---:|---:|---:|")
    for path in args.mtx:
        A = sp.csc_matrix(scipy.io.mmread(path))
        n = A.shape[0]
        b = 1.0 + (np.arange(n) % 7).astype(np.float64)
        name = os.path.basename(path)
        if CholeskySolverD is not None:
            t = time.perf_counter()
            s = CholeskySolverD(n, A.indptr.astype(np.int32), A.indices.astype(np.int32),
                                A.data.astype(np.float64), MatrixType.CSC)
            tf = time.perf_counter() - t
            x = np.zeros(n)
            ts = median_time(lambda: s.solve(b, x))
            r = np.linalg.norm(A @ x - b) / np.linalg.norm(b)
            print(f"| {name} | {n} | {A.nnz} | CHOLMOD (cholespy) | NESDIS (METIS) | {tf:.2f} | | "
                  f"{ts * 1e3:.1f} | {r:.1e} | {peak_mb():.0f} |", flush=True)
            del s
        if n <= args.splu_max:
            t = time.perf_counter()
            lu = spla.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                           options=dict(SymmetricMode=True))
            tf = time.perf_counter() - t
            x = lu.solve(b)
            ts = median_time(lambda: lu.solve(b))
            r = np.linalg.norm(A @ x - b) / np.linalg.norm(b)
            print(f"| {name} | {n} | {A.nnz} | SuperLU | MMD(A^T+A) | {tf:.2f} | "
                  f"{lu.L.nnz + lu.U.nnz} (L+U) | {ts * 1e3:.1f} | {r:.1e} | {peak_mb():.0f} |", flush=True)
            del lu
    return 0


if __name__ == "__main__":
    sys.exit(main())
