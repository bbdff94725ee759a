# Resident memory across scene loads and unloads (issue 30, item 4):
#   python3 docs/bench/unload_rss.py ADDR PID ROUNDS SCENE [SCENE...]
# against a gistreamd of pid PID serving the named scenes. First a warm-up
# (the bundled cornell_box loaded, rendered 64x64 by both solvers, so that
# their shaders are compiled, unloaded) and its RSS, the start; then per round: each scene loaded, rendered 64x64 by
# `direct` and `implicit_visibility`, RSS read while loaded, every scene
# unloaded, RSS read again once it has not fallen for 2 s (at most 20 s). Prints one line per reading and the
# last unloaded RSS against the start.
import os, sys, time
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../build/python"))
from gistream import client as gc

addr, pid, rounds, scenes = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4:]


def rss_mb():
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("VmRSS"):
            return int(line.split()[1]) / 1024.0
    return 0.0


def settled_rss_mb():
    """RSS once it has stopped falling: retired solvers end their background
    jobs first."""
    last, deadline = rss_mb(), time.time() + 20
    while time.time() < deadline:
        time.sleep(2)
        now = rss_mb()
        if now >= last - 1:
            return now
        last = now
    return last


c = gc.Client(addr, timeout=600)
warm = c.load_scene(name="cornell_box").scene_id
for solver in ("direct", "implicit_visibility"):
    c.render(warm, solver=solver, size=(64, 64), refine_samples=1)
c.unload_scene(warm)
start = settled_rss_mb()
print(f"start (after a warm-up render): {start:.0f} MB")
for r in range(rounds):
    ids = [c.load_scene(name=s).scene_id for s in scenes]
    for i in ids:
        for solver in ("direct", "implicit_visibility"):
            c.render(i, solver=solver, size=(64, 64), refine_samples=1)
    loaded = rss_mb()
    for i in ids:
        c.unload_scene(i)
    after = settled_rss_mb()
    print(f"round {r + 1}: loaded {loaded:.0f} MB, unloaded {after:.0f} MB")
print(f"unloaded / start: {after / start:.3f}")
