"""Draws the wheel's and the rail's cross-section quadrilaterals written by
`cargo run --release --example wheel_rail_meshes -- OUT_DIR` (OUT_DIR/wheel_section.csv,
OUT_DIR/rail_section.csv) as OUT_DIR/wheel_section.png and OUT_DIR/rail_section.png, each
with a close-up of the contact region.

    python validation/plot_sections.py OUT_DIR
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import PolyCollection


def draw(csv, png, title, zoom, labels):
    q = np.loadtxt(csv, delimiter=",", skiprows=1).reshape(-1, 4, 2) * 1e3
    fig, axes = plt.subplots(1, 2, figsize=(13, 6.5))
    for ax, box in zip(axes, [None, zoom]):
        ax.add_collection(PolyCollection(q, facecolors="#dde6f0", edgecolors="k", linewidths=0.3))
        ax.set_aspect("equal")
        if box is None:
            ax.autoscale()
        else:
            ax.set_xlim(box[0], box[1])
            ax.set_ylim(box[2], box[3])
        ax.set_xlabel(labels[0])
        ax.set_ylabel(labels[1])
    axes[0].set_title(f"{title}: {len(q)} quadrilaterals")
    axes[1].set_title("close-up of the contact region")
    fig.tight_layout()
    fig.savefig(png, dpi=130)


out = sys.argv[1] if len(sys.argv) > 1 else "wheel_rail_meshes"
draw(f"{out}/wheel_section.csv", f"{out}/wheel_section.png", "S1002 wheel section",
     (-75, 65, 380, 500), ("y from the taping line (mm)", "r (mm)"))
draw(f"{out}/rail_section.csv", f"{out}/rail_section.png", "UIC60 section (upright)",
     (-40, 40, -50, 5), ("y (mm)", "z (mm)"))
print(f"written {out}/wheel_section.png, {out}/rail_section.png")
