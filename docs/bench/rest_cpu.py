#!/usr/bin/env python3
"""What an idle viewer costs the server (issue 27, "then rest"): one
gistreamd, one continuous session on the Cornell box (default solver
implicit_visibility, 128x128, 10 fps), measured twice for --seconds each
after --warmup: the camera still, then orbiting (a look-at update every
frame). Prints the server's CPU seconds (utime + stime from
/proc/PID/stat) in each window, the frames received and rendered, and the
ratio still / orbit.

    PYTHONPATH=build/python python3 docs/bench/rest_cpu.py [--gistreamd build/gistreamd]
        [--solver implicit_visibility] [--size 128] [--fps 10] [--seconds 10] [--warmup 8]
"""
import argparse
import math
import os
import threading
import time

import gistream
from local_server import local_gistreamd

TICKS = os.sysconf("SC_CLK_TCK")


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICKS  # utime, stime


def rendered(client):
    return client.status().frames_rendered


def measure(client, pid, scene_id, args, orbit):
    """CPU seconds, frames received and frames rendered over the window."""
    received = [0]
    stop = threading.Event()
    with client.session(scene_id, solver=args.solver, size=(args.size, args.size),
                        fps=args.fps) as session:
        def reader():
            for _ in session.frames(10**9, stop_at_rest=False):
                received[0] += 1
                if stop.is_set():
                    return
        t = threading.Thread(target=reader, daemon=True)
        t.start()
        start = time.monotonic()
        window = None
        i = 0
        while time.monotonic() - start < args.warmup + args.seconds:
            now = time.monotonic() - start
            if window is None and now >= args.warmup:
                window = (cpu_seconds(pid), received[0], rendered(client), time.monotonic())
            if orbit:
                angle = math.radians(-104 + 3.0 * i)
                eye = (0.278 + 1.08 * math.cos(angle), 0.274, 0.28 + 1.08 * math.sin(angle))
                session.update(camera=gistream.look_at(eye, (0.278, 0.274, 0.28)))
                i += 1
            time.sleep(1.0 / args.fps)
        cpu = cpu_seconds(pid) - window[0]
        frames = received[0] - window[1]
        renders = rendered(client) - window[2]
        seconds = time.monotonic() - window[3]
        stop.set()
        t.join(timeout=5.0)  # (at the next frame: keep-alives come every second)
    return cpu, frames, renders, seconds


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--gistreamd", default="build/gistreamd")
    p.add_argument("--scenes", default="scenes")
    p.add_argument("--solver", default="implicit_visibility")
    p.add_argument("--size", type=int, default=128)
    p.add_argument("--fps", type=float, default=10.0)
    p.add_argument("--seconds", type=float, default=10.0)
    p.add_argument("--warmup", type=float, default=8.0)
    args = p.parse_args()
    with local_gistreamd(args.gistreamd, args.scenes) as (address, server_pid):
        with gistream.Client(address) as client:
            scene = client.load_scene("cornell_box")
            rows = []
            for name, orbit in (("still", False), ("orbit", True)):
                cpu, frames, renders, seconds = measure(client, server_pid, scene.scene_id, args, orbit)
                rows.append((name, cpu, frames, renders, seconds))
                print(f"{name:6s} server CPU {cpu:6.2f} s over {seconds:5.1f} s, "
                      f"{frames} frames received, {renders} rendered", flush=True)
            still, orbit = rows[0][1], rows[1][1]
            print(f"still / orbit CPU: {still / orbit * 100.0:.1f} %" if orbit > 0 else "orbit used no CPU")


if __name__ == "__main__":
    main()
