"""A growth study from Python: the polygonal wear of the paper's wheel
(scenarios/polygon.toml) pass by pass, its band spectrum per pass and growth rates drawn
with matplotlib.

    python examples/grow_from_python.py                      # 20 passes (a few minutes)
    python examples/grow_from_python.py --passes 40 --resume # go on to 40
    python examples/grow_from_python.py --quick              # 96 rim nodes, 3 passes: seconds

Ctrl-C stops the pass under way within a step; the finished passes stay in the study's
checkpoint and --resume goes on from them (the same bits as a study run without a stop).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import softway

ROOT = Path(__file__).resolve().parents[1]
#: scenarios/polygon.toml shrunk to run in seconds (python/tests/test_grow.py's study).
QUICK = {"wheel.rim_nodes": 96, "time.h": 1e-5, "rolling.settle_time": 1.5e-3}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--passes", type=int, default=None)
    ap.add_argument("--resume", action="store_true")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default="out/polygon-grow-py")
    a = ap.parse_args()
    overrides = QUICK if a.quick else {}
    passes = a.passes if a.passes is not None else (3 if a.quick else None)
    try:
        g = softway.grow(ROOT / "scenarios/polygon.toml", passes=passes, out=a.out,
                         resume=a.resume, **overrides)
    except softway.GrowthInterrupted as e:
        g = e.result
        print(f"interrupted: {g.summary['passes']} passes kept; --resume goes on")
    for line in g.lines:
        print(line)

    import matplotlib.pyplot as plt

    b = g.bands
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 8), constrained_layout=True)
    for k in b["after_passes"].values:
        ax1.semilogx(b["wavelength"] * 1e3, b["level_db"].sel(after_passes=k),
                     color=plt.cm.viridis(k / max(1, b.sizes["after_passes"] - 1)),
                     label=f"after {k} passes" if k in (0, b.sizes["after_passes"] - 1) else None)
    ax1.set_xlabel("band centre wavelength (mm)")
    ax1.set_ylabel("roughness level (dB re 1 um)")
    ax1.legend()
    ax2.semilogx(b["wavelength"] * 1e3, b["rate_db_per_1e5"], "o-")
    ax2.axhline(0.0, color="k", lw=0.5)
    ax2.set_xlabel("band centre wavelength (mm)")
    ax2.set_ylabel("growth rate (dB per 1e5 passes)")
    from matplotlib.ticker import NullFormatter, ScalarFormatter

    for ax in (ax1, ax2):
        ax.xaxis.set_major_formatter(ScalarFormatter())
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_xticks([10, 20, 50, 100, 200, 500])
        ax.grid(True, which="both", lw=0.3)
    png = Path(a.out) / "bands_from_python.png"
    fig.savefig(png, dpi=100)
    print(f"    {png}")


if __name__ == "__main__":
    main()
