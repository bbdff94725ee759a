#!/usr/bin/env python3
"""Streams the bundled Cornell box with global illumination and saves the
frames: the Python counterpart of `gistream stream`.

    PYTHONPATH=build/python python3 python/examples/save_frames.py --server 127.0.0.1:50051
"""
import argparse
import math
import pathlib

import grpc

import gistream


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--server", default="127.0.0.1:50051")
    parser.add_argument("--solver", default="implicit_visibility")
    parser.add_argument("--frames", type=int, default=12)
    parser.add_argument("--out", default="out/python")
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    with gistream.Client(args.server) as client:
        scene = client.load_scene("cornell_box")
        print(f"scene {scene.scene_id}: {scene.triangle_count} triangles")
        with client.session(scene.scene_id, solver=args.solver, size=(320, 240), fps=10) as session:
            for i in range(args.frames):
                angle = math.radians(-104 + 28 * i / max(args.frames - 1, 1))
                eye = (0.278 + 1.08 * math.cos(angle), 0.274, 0.28 + 1.08 * math.sin(angle))
                seq = session.update(camera=gistream.look_at(eye, (0.278, 0.274, 0.28)))
                # The first frame that includes the update (frames before it
                # still show the previous camera).
                for frame in session.frames(1000, stop_at_rest=False):
                    if frame.last_update_seq >= seq and frame.image:
                        break
                path = out / f"frame_{i:03d}.jpg"
                path.write_bytes(frame.image)
                print(f"{path}: shows update {frame.last_update_seq}, {frame.total_ms:.1f} ms")
        try:
            client.unload_scene(scene.scene_id)
        except grpc.RpcError:
            pass  # still shared with another client, or the session is closing


if __name__ == "__main__":
    main()
