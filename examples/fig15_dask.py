"""Fig. 15 of Bajer (1998) through Dask: the paper's wheel (its 12-ring mesh, pinned
centre) rolled at several speeds, the oscillations of the contact force per turn and the
contact force against the speed, drawn with matplotlib (headless).

    python examples/fig15_dask.py                        # a LocalCluster of 2 processes
    python examples/fig15_dask.py --scheduler tcp://127.0.0.1:8786   # a running cluster
    python examples/fig15_dask.py --serial               # in this process, for timing

Writes out/fig15-dask/: sweep.nc (the gathered Dataset), each speed's folder (the command
line's files and point.nc, written by the worker that ran it) and fig15.png. Prints the
table and the wall time.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import softway  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default=str(ROOT / "scenarios/wheel-sweep-paper-mesh.toml"))
    ap.add_argument(
        "--speeds",
        default="250,300,350,400,450,520",
        help="omega values, rad/s (default: the scenario's [sweep] table's)",
    )
    ap.add_argument("--turns", type=int, default=2, help="turns per speed (the paper: 4)")
    ap.add_argument("--workers", type=int, default=2, help="LocalCluster worker processes")
    ap.add_argument("--scheduler", help="address of a running Dask scheduler")
    ap.add_argument("--serial", action="store_true", help="run in this process, no Dask")
    ap.add_argument("--out", default="out/fig15-dask")
    args = ap.parse_args()

    sc = softway.Scenario(args.scenario).with_values(**{"rolling.turns": args.turns})
    speeds = [float(x) for x in args.speeds.split(",")]
    grid = {"rolling.omega": speeds}
    out = Path(args.out)

    t0 = time.perf_counter()
    if args.serial:
        ds = softway.sweep(sc, grid, executor="serial", out=out, histories=["contact_force_N"])
        where = "serial, in this process"
    else:
        from dask.distributed import Client, LocalCluster

        if args.scheduler:
            client, cluster = Client(args.scheduler), None
            where = f"Dask scheduler {args.scheduler}"
        else:
            cluster = LocalCluster(
                n_workers=args.workers,
                threads_per_worker=1,
                processes=True,
                dashboard_address=":0",
            )
            client = Client(cluster)
            where = f"Dask LocalCluster, {args.workers} processes"
        try:
            ds = softway.sweep(
                sc, grid, executor=client.get_executor(), out=out, histories=["contact_force_N"]
            )
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    wall = time.perf_counter() - t0

    failed = ds["error"].values != ""
    if failed.any():
        raise SystemExit(f"{failed.sum()} points failed: {ds['error'].values[failed]}")

    omega = ds["rolling.omega"].values
    kmh = ds["speed_km_h"].values
    # The paper's count (peaks per turn, mean of the turns after the first; the first
    # carries the start of rolling).
    counts = []
    for s in ds["summary_json"].values:
        per_turn = json.loads(str(s))["oscillations_per_turn"]
        rest = per_turn[1:] or per_turn
        counts.append(float(np.mean(rest)))
    fixed = ds["fixed_frequency_cycles_per_turn"].values
    held = ds["bounce_frequency_hz"].values * 2 * math.pi / omega

    fig, (a, b) = plt.subplots(2, 1, figsize=(8, 8), sharex=True)
    a.plot(kmh, counts, "o-", label="peaks counted (the paper's rule)")
    a.plot(kmh, fixed, "s-", label="fixed-frequency component (the bounce), rolling")
    a.plot(kmh, held, "--", label="bounce with the contact held, $f_b\\,2\\pi/\\omega$")
    a.set_ylabel("oscillations per turn")
    a.set_title(
        f"Fig. 15: the paper's wheel at {len(speeds)} speeds, {args.turns} turns each ({where})"
    )
    a.grid(alpha=0.3)
    a.legend(fontsize=8)
    for name, style in (("max_contact_force", "o-"), ("mean_contact_force", "s-"),
                        ("min_contact_force", "v-")):
        b.plot(kmh, ds[name].values / 1e3, style, label=name.replace("_", " "))
    b.set_xlabel("rim speed [km/h]")
    b.set_ylabel("contact force [kN]")
    b.grid(alpha=0.3)
    b.legend(fontsize=8)
    fig.tight_layout()
    png = out / "fig15.png"
    fig.savefig(png, dpi=110)

    print(f"{'omega':>7} {'km/h':>7} {'peaks/turn':>10} {'fixed/turn':>10} {'max F [kN]':>10}")
    for w, v, c, f, m in zip(omega, kmh, counts, fixed, ds["max_contact_force"].values):
        print(f"{w:7.1f} {v:7.1f} {c:10.2f} {f:10.2f} {m / 1e3:10.1f}")
    print(f"{len(speeds)} runs in {wall:.1f} s ({where}); wrote {png} and {out / 'sweep.nc'}")


if __name__ == "__main__":
    main()
