#!/usr/bin/env python3
"""Samples per frame of a refining view (issue 27): one gistreamd, one
continuous session on the Cornell box per solver and size; after the first
picture has rested, a camera move, then the frames and milliseconds until
the view rests again with all its refine_samples, and the samples each
frame showed. Run once with --budget-ms (frames without an update shade
as many samples as it allows; 0: the server's --frame-budget-ms) and once
with a budget of a microsecond (one sample a frame, as before).

    PYTHONPATH=build/python python3 docs/bench/refine_frames.py [--gistreamd build/gistreamd]
        [--solvers direct,antiradiance] [--sizes 64,128] [--fps 10] [--refine 16] [--budget-ms 0]
"""
import argparse
import time

import gistream
from local_server import local_gistreamd


def after_move(client, scene_id, solver, size, args, budget_ms):
    """(frames, ms, samples per frame) from a camera move to the rest."""
    with client.session(scene_id, solver=solver, size=(size, size), format="png", fps=args.fps,
                        refine_samples=args.refine, frame_budget_ms=budget_ms) as session:
        for _ in session.frames(10**6):  # the first picture, until it rests
            pass
        seq = session.update(camera=gistream.look_at((0.33, 0.29, -0.75), (0.278, 0.27, 0.28)))
        start = time.monotonic()
        samples = []
        for frame in session.frames(10**6):
            if frame.last_update_seq < seq:
                continue
            if frame.stats.get("at_rest", 0.0) == 1.0:
                return len(samples), (time.monotonic() - start) * 1e3, samples
            samples.append(int(frame.stats.get("refine_samples", 0)))
    return None


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--gistreamd", default="build/gistreamd")
    p.add_argument("--scenes", default="scenes")
    p.add_argument("--solvers", default="direct,antiradiance")
    p.add_argument("--sizes", default="64,128")
    p.add_argument("--fps", type=float, default=10.0)
    p.add_argument("--refine", type=int, default=16)
    p.add_argument("--budget-ms", type=float, default=0.0)
    args = p.parse_args()
    with local_gistreamd(args.gistreamd, args.scenes) as (address, server_pid):
        with gistream.Client(address) as client:
            scene = client.load_scene("cornell_box")
            print("| solver | size | budget | frames to rest | ms | samples shown per frame |")
            print("|---|---|---|---|---|---|")
            for solver in args.solvers.split(","):
                for size in (int(s) for s in args.sizes.split(",")):
                    for name, budget in ((f"{args.budget_ms:g} ms" if args.budget_ms else "server's",
                                          args.budget_ms), ("1 us", 1e-3)):
                        got = after_move(client, scene.scene_id, solver, size, args, budget)
                        if got is None:
                            print(f"| {solver} | {size} | {name} | (stream ended) | | |")
                            continue
                        frames, ms, samples = got
                        print(f"| {solver} | {size}x{size} | {name} | {frames} | {ms:.0f} | "
                              f"{' '.join(map(str, samples))} |", flush=True)


if __name__ == "__main__":
    main()
