#!/usr/bin/env python3
"""Other tessellations of the Cornell box, for vertex-based solvers'
scaling and light-leak measurements (implicit_visibility in docs/RESULTS.md).

    python3 tools/make_tessellations.py OUT_DIR

writes OUT_DIR/cornell_box_t{12,24,52}.gltf: walls n x n quads, blocks
n/4 per face edge (t24 is the bundled cornell_box under another name):

    t12  ~1.0K vertices   t24  3624 vertices   t52  ~15.7K vertices

Not bundled: the scenes stay as tools/make_scenes.py writes them.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_scenes  # noqa: E402

VARIANTS = {12: 3, 24: 6, 52: 13}


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    for walls, blocks in VARIANTS.items():
        make_scenes.cornell_box(out, walls, blocks, f"cornell_box_t{walls}")


if __name__ == "__main__":
    main()
