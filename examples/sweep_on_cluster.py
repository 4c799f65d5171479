"""A 4-speed sweep of the mesh-converged wheel (scenarios/wheel-sweep.toml: 288 rim nodes,
four turns) serially in this process and on a running Dask cluster, with the wall times,
their ratio, and a check that both give the same Dataset bit for bit.

Start a cluster from the command line (here on this machine, two worker processes of one
thread each), then give the script its address:

    dask scheduler --host 127.0.0.1 --port 8786 --no-dashboard &
    dask worker tcp://127.0.0.1:8786 --nworkers 1 --nthreads 1 --no-dashboard &
    dask worker tcp://127.0.0.1:8786 --nworkers 1 --nthreads 1 --no-dashboard &
    python examples/sweep_on_cluster.py tcp://127.0.0.1:8786
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

import xarray as xr

import softway

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scheduler", help="the Dask scheduler's address, e.g. tcp://127.0.0.1:8786")
    ap.add_argument("--scenario", default=str(ROOT / "scenarios/wheel-sweep.toml"))
    ap.add_argument("--speeds", default="250,310,380,460", help="omega values, rad/s")
    ap.add_argument("--turns", type=int, default=None, help="turns per speed (default: the scenario's)")
    ap.add_argument("--skip-serial", action="store_true")
    ap.add_argument("--rounds", type=int, default=1, help="alternated rounds (medians)")
    args = ap.parse_args()

    from dask.distributed import Client

    sc = softway.Scenario(args.scenario)
    if args.turns is not None:
        sc = sc.with_values(**{"rolling.turns": args.turns})
    grid = {"rolling.omega": [float(x) for x in args.speeds.split(",")]}
    client = Client(args.scheduler)
    workers = client.scheduler_info()["workers"]
    print(
        f"{len(workers)} workers: "
        + ", ".join(f"{a} ({w.get('nthreads', '?')} thread)" for a, w in workers.items())
    )
    times: dict[str, list[float]] = {"cluster": [], "serial": []}
    results = {}
    # Alternated rounds, so that a load that comes and goes on a shared machine falls on
    # both alike; the medians are compared.
    for _ in range(args.rounds):
        for how in ("serial", "cluster"):
            if how == "serial" and args.skip_serial:
                continue
            load = os.getloadavg()[0]
            t0 = time.perf_counter()
            results[how] = softway.sweep(
                sc, grid, executor="serial" if how == "serial" else client.get_executor(),
                progress=False,
            )
            times[how].append(time.perf_counter() - t0)
            print(f"{how:>7}: {times[how][-1]:6.1f} s (load average before: {load:.2f})")
    client.close()
    t_cluster = statistics.median(times["cluster"])
    print(f"{sc.name}, {len(grid['rolling.omega'])} speeds on the cluster: {t_cluster:.1f} s (median)")
    if args.skip_serial:
        return
    t_serial = statistics.median(times["serial"])
    print(f"{sc.name}, {len(grid['rolling.omega'])} speeds serially: {t_serial:.1f} s (median)")
    on_cluster = results["cluster"]
    xr.testing.assert_identical(on_cluster, results["serial"])
    print(f"ratio serial / cluster: {t_serial / t_cluster:.2f}; the same Dataset, bit for bit")
    print(on_cluster[["speed_km_h", "mean_contact_force", "max_contact_force"]].to_dataframe())


if __name__ == "__main__":
    main()
