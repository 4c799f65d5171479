#!/usr/bin/env python3
"""Runs the shipped scenarios with two softway binaries and compares what they write.

    python3 bench/same_results.py OLD_BINARY NEW_BINARY [SCENARIO ...]

Each scenario runs shortened by `--set` (the same settings on both sides, so the arithmetic
is the same), into a folder of each binary's; then every `summary.json` is compared value by
value (the provenance and timing entries aside: version, commit, wall times, memory) and
every CSV byte for byte. Exit 1 when anything differs, naming the file and the first
difference. A refactoring that leaves the arithmetic alone must pass it bit for bit.
"""
import json
import math
import pathlib
import subprocess
import sys
import tempfile

# The shortened runs: (scenario, command, extra arguments).
CASES = [
    ("sdof.toml", "run", []),
    ("bar-impact.toml", "run", []),
    ("bar-impact-mesh.toml", "run", []),
    ("compare-bar.toml", "compare", []),
    ("compare-two-bars.toml", "compare", []),
    ("wheel.toml", "run", ["--set", "rolling.turns=0.25"]),
    ("wheel-paper-mesh.toml", "run", ["--set", "rolling.turns=0.25"]),
    ("wheel-traction.toml", "run", ["--set", "rolling.turns=0.25"]),
    ("wheel-zone.toml", "run", ["--set", "rolling.turns=0.1"]),
    ("wheel-plastic.toml", "run", ["--set", "rolling.turns=0.25"]),
    ("wheel-on-block.toml", "run", []),
    ("wheel-gmsh.toml", "run", ["--set", "rolling.turns=0.25"]),
    ("track-moving-load.toml", "run", []),
    ("track.toml", "run", ["--set", "vehicle.travel_bays=2"]),
    ("track-traction.toml", "run", ["--set", "vehicle.travel_bays=2"]),
    ("creep-curve.toml", "run", ["--set", "rolling.turns=0.25"]),
    ("polygon.toml", "grow", ["--passes", "2"]),
]

# Timings: entries and columns that differ between two runs of the same arithmetic.
TIMINGS = {"build_s", "loop_s", "wear_bookkeeping_s", "wall_s", "wall_time_s",
           "time_per_metre_s", "time_per_step_us", "steps_per_s"}

# Entries that differ between two builds or two runs of the same arithmetic.
IGNORED = TIMINGS | {
    "softway_version", "softway_git_commit", "peak_rss_mib", "wall_time_s", "wall_s",
    "elapsed_s", "seconds", "reference_wall_s", "steps_per_second", "time_per_step_s",
    "scenario_path", "path", "time_per_step_us", "steps_per_s",
}


def differ(a, b, where):
    """The first difference of two JSON values, or None."""
    if isinstance(a, dict) and isinstance(b, dict) and "scalar_names" in a:
        # A checkpoint's pass: its scalars by name (the timings aside).
        a, b = dict(a), dict(b)
        for d in (a, b):
            d["scalar_values"] = [v for n, v in zip(d["scalar_names"], d["scalar_values"])
                                  if n not in TIMINGS]
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k in IGNORED or "wall" in k or k.endswith("_time_s") and "cpu" in k:
                continue
            if k not in a or k not in b:
                return f"{where}.{k}: only in {'new' if k in b else 'old'}"
            d = differ(a[k], b[k], f"{where}.{k}")
            if d:
                return d
        return None
    if isinstance(a, list) and isinstance(b, list):
        # A list of [name, value] pairs: the timings aside.
        if len(a) == 2 and isinstance(a[0], str) and a[0] in TIMINGS:
            return None
        if len(a) != len(b):
            return f"{where}: {len(a)} against {len(b)} entries"
        for i, (x, y) in enumerate(zip(a, b)):
            d = differ(x, y, f"{where}[{i}]")
            if d:
                return d
        return None
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return None
    return None if a == b else f"{where}: {a!r} against {b!r}"


def untimed(path):
    """The CSV's rows without its timing columns; with the scalar values of a checkpoint's
    timing entries aside."""
    import csv
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return rows
    keep = [i for i, h in enumerate(rows[0]) if h not in TIMINGS]
    return [[r[i] for i in keep if i < len(r)] for r in rows]


def csv_differ(a, b, where):
    """The first differing row of two CSV files (timing columns aside), or None."""
    ra, rb = untimed(a), untimed(b)
    if len(ra) != len(rb):
        return f"{where}: {len(ra)} against {len(rb)} rows"
    for i, (x, y) in enumerate(zip(ra, rb)):
        if x != y:
            return f"{where}: row {i}: {x} against {y}"
    return None


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    old, new = sys.argv[1], sys.argv[2]
    only = set(sys.argv[3:])
    root = pathlib.Path(__file__).resolve().parent.parent
    bad = 0
    with tempfile.TemporaryDirectory() as tmp:
        for scenario, command, extra in CASES:
            if only and scenario not in only:
                continue
            outs = []
            for name, binary in (("old", old), ("new", new)):
                out = pathlib.Path(tmp) / name / scenario
                args = [binary, command, str(root / "scenarios" / scenario), "--out", str(out),
                        "--yes"] + extra
                p = subprocess.run(args, capture_output=True, text=True)
                if p.returncode != 0:
                    print(f"{scenario}: {name} exits {p.returncode}: {p.stderr.strip()[-300:]}")
                outs.append((out, p.returncode))
            (a, ra), (b, rb) = outs
            if ra != rb:
                bad += 1
                continue
            files_a = sorted(p.relative_to(a) for p in a.rglob("*") if p.is_file())
            files_b = sorted(p.relative_to(b) for p in b.rglob("*") if p.is_file())
            if files_a != files_b:
                print(f"{scenario}: other files: {set(files_a) ^ set(files_b)}")
                bad += 1
                continue
            same = True
            for f in files_a:
                if f.suffix == ".json":
                    d = differ(json.loads((a / f).read_text()), json.loads((b / f).read_text()), str(f))
                elif f.suffix == ".csv":
                    d = csv_differ(a / f, b / f, str(f))
                else:
                    continue
                if d:
                    print(f"{scenario}: {d}")
                    same = False
            bad += not same
            print(f"{scenario}: {'same' if same else 'DIFFERENT'} ({len(files_a)} files)")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
