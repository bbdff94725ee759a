# Another client beside a scene whose cost is in its draws (issue 30):
#   python3 docs/bench/heavy_neighbour.py ADDR HEAVY_SCENE
# The light client's cost solo, then beside a heavy one: a 32x32 `direct`
# Render of the bundled cornell_box (median of 5; 1 sample per pixel), and
# a 32x32 10 fps stream of it under an orbiting camera (p50 / p95 interval
# over 40 frames). The heavy client streams HEAVY_SCENE (e.g.
# many_primitives_65536 from tools/make_cost_scenes.py) at 64x64, 10 fps,
# its camera moved after every frame so that it never rests. Prints each
# figure and its ratio to solo (the target: within 3x).
import math, os, statistics, sys, threading, time
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../build/python"))
from gistream import client as gc

addr, heavy_scene = sys.argv[1], sys.argv[2]


def orbit(i, radius, height, centre=(0.0, 0.0, 0.0)):
    a = 0.15 * i
    eye = (centre[0] + radius * math.sin(a), centre[1] + height, centre[2] + radius * math.cos(a))
    return gc.look_at(eye, centre)


def light_figures(c, scene):
    renders = []
    for _ in range(5):
        t = time.monotonic()
        c.render(scene, solver="direct", size=(32, 32), refine_samples=1)
        renders.append(1000 * (time.monotonic() - t))
    intervals = []
    with c.session(scene, solver="direct", size=(32, 32), fps=10, refine_samples=1) as s:
        last = None
        for i, _ in enumerate(s.frames(41, stop_at_rest=False)):
            now = time.monotonic()
            if last is not None:
                intervals.append(1000 * (now - last))
            last = now
            s.update(camera=orbit(i, 3.5, 1.0, (0.0, 1.0, 0.0)))
    intervals.sort()
    return statistics.median(renders), intervals[len(intervals) // 2], intervals[int(0.95 * (len(intervals) - 1))]


light = gc.Client(addr, timeout=600)
cornell = light.load_scene(name="cornell_box").scene_id
light_figures(light, cornell)  # warm-up: shaders compiled
solo = light_figures(light, cornell)
print(f"solo:   render {solo[0]:.0f} ms, stream p50 {solo[1]:.0f} ms p95 {solo[2]:.0f} ms")

heavy = gc.Client(addr, timeout=600)
t = time.monotonic()
heavy_id = heavy.load_scene(name=heavy_scene).scene_id
print(f"heavy scene loaded in {time.monotonic() - t:.1f} s")
stop = threading.Event()
heavy_frames = []


def run_heavy():
    with heavy.session(heavy_id, solver="direct", size=(64, 64), fps=10, refine_samples=1) as s:
        i = 0
        for _ in s.frames(10**6, stop_at_rest=False):
            heavy_frames.append(time.monotonic())
            i += 1
            s.update(camera=orbit(i, 0.3, 2.0))
            if stop.is_set():
                return


th = threading.Thread(target=run_heavy)
th.start()
while len(heavy_frames) < 3:
    time.sleep(0.1)
beside = light_figures(light, cornell)
stop.set()
th.join()
gaps = sorted(1000 * (b - a) for a, b in zip(heavy_frames, heavy_frames[1:]))
print(f"beside: render {beside[0]:.0f} ms, stream p50 {beside[1]:.0f} ms p95 {beside[2]:.0f} ms "
      f"(heavy stream: {len(heavy_frames)} frames, p50 interval {gaps[len(gaps) // 2]:.0f} ms)")
print(f"ratios: render {beside[0] / solo[0]:.2f}, stream p95 {beside[2] / solo[2]:.2f}")
