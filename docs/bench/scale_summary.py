#!/usr/bin/env python3
"""Tabulates docs/bench/scale.sh's output directory: per scene and solver,
the first frame's total ms with proxies and with full_detail=true, the
shadow_maps (or voxelize) stage, and the RMS difference of the proxy image
from the full-detail one (idiff -a, linear radiance).

    /usr/bin/python3 docs/bench/scale_summary.py OUT_DIR
"""
import glob
import os
import re
import subprocess
import sys


def parse(path):
    text = open(path).read()
    total = re.search(r", ([0-9.]+) ms\n", text)
    stages = {m.group(1): float(m.group(2))
              for m in re.finditer(r"^\s+(\w+)\s+\|\s+([0-9.]+)\s", text, re.M)}
    return (float(total.group(1)) if total else None), stages


def rms_difference(a, b):
    """idiff's RMS error of EXR a against b (linear radiance, all channels)."""
    run = subprocess.run(["idiff", "-a", a, b], capture_output=True, text=True)
    m = re.search(r"RMS error = ([0-9.e+-]+)", run.stdout)
    return float(m.group(1)) if m else None


SOLVERS = ("implicit_visibility", "antiradiance", "sh_probes", "pathtrace", "direct", "avg")


def main():
    out = sys.argv[1]
    rows = []
    for full in sorted(glob.glob(os.path.join(out, "*_full.txt"))):
        base = full[:-len("_full.txt")]
        name = os.path.basename(base)
        solver = next(s for s in SOLVERS if name.endswith("_" + s))
        scene = name[:-len(solver) - 1]
        t_full, s_full = parse(full)
        t_proxy, s_proxy = parse(base + "_proxies.txt")
        err = rms_difference(base + "_proxies.exr", base + "_full.exr")
        stage = "voxelize" if solver == "avg" else "shadow_maps"
        rows.append((scene, solver, t_proxy, t_full, s_proxy.get(stage), s_full.get(stage), err))
    print("| scene | solver | first frame, proxies (ms) | first frame, full detail (ms) |"
          " shadow_maps/voxelize, proxies | full detail | RMS difference proxies vs full |")
    print("| --- | --- | ---: | ---: | ---: | ---: | ---: |")
    for r in rows:
        print("| %s | %s | %s | %s | %s | %s | %s |" % (
            r[0], r[1], *["%.0f" % v if v is not None else "-" for v in r[2:6]],
            "%.2e" % r[6] if r[6] is not None else "-"))


if __name__ == "__main__":
    main()
