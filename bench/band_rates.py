#!/usr/bin/env python3
"""Growth rates of several `softway grow` studies over one window of real passes.

    python3 bench/band_rates.py N1 N2 OUT_DIR [OUT_DIR ...]

For each one-third-octave band of each study's `bands.csv` (its levels after every
simulated pass) the level at N1 and at N2 real passes (linear between passes; the real
passes of a simulated pass are the study's `passes_per_pass`, from its `summary.json`) and
the rate between them, dB per 1e5 real passes, one column per study. Studies of different
`growth.passes_per_pass` or rims compared over the same window are a convergence check of
the wear step or of the mesh; a study that does not reach N2 shows `-`. Standard library
only.
"""
import csv
import json
import sys
from pathlib import Path


def levels(study: Path):
    ppp = json.loads((study / "summary.json").read_text())["passes_per_pass"]
    out = {}
    with open(study / "bands.csv", newline="") as f:
        for row in csv.DictReader(f):
            ls = [float(row[k]) for k in row if k.startswith("level_after_")]
            out[round(1e3 * float(row["centre_wavelength_m"]), 1)] = (ppp, ls)
    return out


def at(ppp, ls, n):
    k = n / ppp
    i = int(k)
    if i >= len(ls) - 1:
        return ls[-1] if abs(k - (len(ls) - 1)) < 1e-9 else None
    return ls[i] + (k - i) * (ls[i + 1] - ls[i])


def main(argv):
    if len(argv) < 4:
        sys.exit(__doc__)
    n1, n2 = float(argv[1]), float(argv[2])
    if not n2 > n1 >= 0:
        sys.exit("band_rates: need 0 <= N1 < N2")
    studies = [Path(a) for a in argv[3:]]
    data = [levels(s) for s in studies]
    print("band_mm," + ",".join(s.name for s in studies))
    for band in sorted(data[0]):
        cells = []
        for d in data:
            if band not in d:
                cells.append("-")
                continue
            ppp, ls = d[band]
            a, b = at(ppp, ls, n1), at(ppp, ls, n2)
            cells.append("-" if a is None or b is None else f"{(b - a) / (n2 - n1) * 1e5:.1f}")
        print(f"{band}," + ",".join(cells))


if __name__ == "__main__":
    main(sys.argv)
