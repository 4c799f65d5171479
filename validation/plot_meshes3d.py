"""Draws the boundary faces of the wheel and rail meshes written by
`cargo run --release --example wheel_rail_meshes -- OUT_DIR` (OUT_DIR/wheel.vtu, rail.vtu),
the wheel lifted by its nominal radius so that its running circle touches the rail's crown
(the frames of the generators put both contact points at y = 0), as OUT_DIR/meshes3d.png:
the whole pair, and a close-up of the contact region seen along the rail.

    python validation/plot_meshes3d.py OUT_DIR
"""
import base64
import re
import sys
from collections import Counter

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

DTYPES = {"Float64": "<f8", "UInt64": "<u8", "UInt8": "<u1", "Int64": "<i8"}


def read_vtu(path):
    """Points and hexahedra of a binary (UInt64 header, uncompressed) VTU file."""
    text = open(path).read()
    arrays = {}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="(\w+)"[^>]*>([^<]*)</DataArray>', text):
        raw = base64.b64decode(m.group(3).strip())
        n = int(np.frombuffer(raw[:8], "<u8")[0])
        arrays[m.group(2)] = np.frombuffer(raw[8:8 + n], DTYPES[m.group(1)])
    return arrays["Points"].reshape(-1, 3), arrays["connectivity"].reshape(-1, 8).astype(np.int64)


FACES = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


def boundary(hexes):
    """The faces of exactly one hexahedron."""
    faces = [tuple(h[list(f)]) for h in hexes for f in FACES]
    count = Counter(tuple(sorted(f)) for f in faces)
    return [f for f in faces if count[tuple(sorted(f))] == 1]


out = sys.argv[1] if len(sys.argv) > 1 else "wheel_rail_meshes"
wp, wh = read_vtu(f"{out}/wheel.vtu")
rp, rh = read_vtu(f"{out}/rail.vtu")
wp = wp + [0.0, 0.0, 0.46]
wf, rf = boundary(wh), boundary(rh)
fig = plt.figure(figsize=(14, 7))
for k, (box, view) in enumerate([(None, (20, -60)), ((-0.04, 0.04, -0.05, 0.05, -0.03, 0.04), (0, 0))]):
    ax = fig.add_subplot(1, 2, k + 1, projection="3d")
    for pts, faces, colour in [(rp, rf, "#c8d2dc"), (wp, wf, "#e8d8c0")]:
        polys = pts[np.array(faces)]
        if box is not None:
            c = polys.mean(axis=1)
            inside = (
                (c[:, 0] > box[0]) & (c[:, 0] < box[1]) & (c[:, 1] > box[2]) & (c[:, 1] < box[3])
                & (c[:, 2] > box[4]) & (c[:, 2] < box[5])
            )
            polys = polys[inside]
        ax.add_collection3d(Poly3DCollection(polys * 1e3, facecolors=colour, edgecolors="k", linewidths=0.1))
    lim = np.array(box if box is not None else (-0.5, 0.5, -0.5, 0.5, -0.2, 0.95)) * 1e3
    ax.set_xlim(lim[0], lim[1]); ax.set_ylim(lim[2], lim[3]); ax.set_zlim(lim[4], lim[5])
    ax.set_box_aspect((lim[1] - lim[0], lim[3] - lim[2], lim[5] - lim[4]))
    ax.view_init(*view)
    ax.set_xlabel("x along the rail (mm)"); ax.set_ylabel("y (mm)"); ax.set_zlabel("z (mm)")
axes = fig.get_axes()
axes[0].set_title(f"wheel {len(wh)} and rail {len(rh)} hexahedra")
axes[1].set_title("the contact region seen along the rail")
fig.tight_layout()
fig.savefig(f"{out}/meshes3d.png", dpi=120)
print(f"written {out}/meshes3d.png")
