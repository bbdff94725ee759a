#!/usr/bin/env python3
"""Real-sized scenes for issue 19 (proxy geometry): cost against triangle count.

    python3 tools/make_scale_scenes.py [--atrium-only] OUT_DIR [atrium_detail ...]

writes into OUT_DIR:
  cornell_box_x4 / _x16 / _x64   the bundled Cornell box with 4x, 16x, 64x the
                                 triangles (walls and blocks subdivided; same
                                 picture): ~26K, ~104K, ~415K triangles
  atrium_d<D>                    a Sponza/Sibenik-like atrium at detail D
                                 (default 3 and 6: ~150K and ~590K triangles)

The atrium: a 16 x 24 x 10 m hall, two storeys of 8 columns per long side
(one instanced column mesh), arches between them (one instanced arch mesh),
an upper gallery slab along each side, and a skylight (an emissive panel in
the roof's opening) as its only light. Detail D sets the column's 16D
segments x 8D rings, the arch's 16D steps, and the walls' 8D x 8D quads.
These files are many MB at the larger sizes: generated at bench time, not
bundled (docs/bench/scale.sh).
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_scenes  # noqa: E402
from make_scenes import Gltf, Mesh  # noqa: E402

CORNELL_SCALES = {4: (48, 12), 16: (96, 24), 64: (192, 48)}  # walls_n, blocks_n


def column(d, radius=0.35, height=4.0):
    """A faceted cylinder, 16d segments x 8d rings, normals out, open ends."""
    m = Mesh()
    seg, rings = 16 * d, 8 * d
    for i in range(seg):
        a0, a1 = 2 * math.pi * i / seg, 2 * math.pi * (i + 1) / seg
        p0 = (radius * math.cos(a0), 0.0, radius * math.sin(a0))
        p1 = (radius * math.cos(a1), 0.0, radius * math.sin(a1))
        m.quad(p0, p1, (p1[0], height, p1[2]), (p0[0], height, p0[2]), 1, rings,
               away=(0.0, height * 0.5, 0.0))
    return m


def arch(d, span, depth=0.7, thickness=0.4):
    """A semicircular arch of inner radius span/2 springing at y = 0 between
    x = -span/2 and span/2, `depth` deep along z: intrados (facing the centre),
    and the front and back faces between the intrados and extrados."""
    m = Mesh()
    r, steps = span * 0.5, 16 * d
    for k in range(steps):
        t0, t1 = math.pi * k / steps, math.pi * (k + 1) / steps
        i0 = (r * math.cos(t0), r * math.sin(t0))
        i1 = (r * math.cos(t1), r * math.sin(t1))
        o0 = ((r + thickness) * math.cos(t0), (r + thickness) * math.sin(t0))
        o1 = ((r + thickness) * math.cos(t1), (r + thickness) * math.sin(t1))
        hz = depth * 0.5
        m.quad((i0[0], i0[1], -hz), (i1[0], i1[1], -hz), (i1[0], i1[1], hz), (i0[0], i0[1], hz),
               1, 4 * d, toward=(0.0, 0.0, 0.0))
        for z, far in ((-hz, (0.0, 0.0, 1.0)), (hz, (0.0, 0.0, -1.0))):
            m.quad((i0[0], i0[1], z), (o0[0], o0[1], z), (o1[0], o1[1], z), (i1[0], i1[1], z),
                   2 * d, 1, away=far)
    return m


def atrium(out, d):
    name = "atrium_d%d" % d
    g = Gltf(name)
    stone = g.material("stone", (0.72, 0.68, 0.6))
    floor_m = g.material("floor", (0.55, 0.5, 0.45))
    red = g.material("banner", (0.6, 0.08, 0.06))
    sky = g.material("skylight", (0.8, 0.8, 0.8), emissive=(1.0, 0.95, 0.85), strength=40.0)
    W, L, H = 16.0, 24.0, 10.0          # x, z, y
    n = 8 * d
    ctr = (0.0, H * 0.5, 0.0)
    hx, hz = W * 0.5, L * 0.5
    g.node("floor", Mesh().quad((-hx, 0, -hz), (hx, 0, -hz), (hx, 0, hz), (-hx, 0, hz), n, n,
                                toward=ctr), floor_m)
    # The roof with a 4 x 8 m opening in the middle for the skylight.
    g.node("roof", Mesh().quad((-hx, H, -hz), (hx, H, -hz), (hx, H, hz), (-hx, H, hz), n, n,
                               toward=ctr, keep=lambda p: abs(p[0]) > 2.0 or abs(p[2]) > 4.0),
           stone)
    walls = Mesh()
    walls.quad((-hx, 0, -hz), (hx, 0, -hz), (hx, H, -hz), (-hx, H, -hz), n, n, toward=ctr)
    walls.quad((-hx, 0, hz), (hx, 0, hz), (hx, H, hz), (-hx, H, hz), n, n, toward=ctr)
    g.node("end_walls", walls, stone)
    sides = Mesh()
    sides.quad((-hx, 0, -hz), (-hx, 0, hz), (-hx, H, hz), (-hx, H, -hz), n, n, toward=ctr)
    sides.quad((hx, 0, -hz), (hx, 0, hz), (hx, H, hz), (hx, H, -hz), n, n, toward=ctr)
    g.node("side_walls", sides, red)
    # Upper gallery: a slab along each long side at 4.5 m, 3 m deep.
    for s, x0, x1 in (("west", -hx, -hx + 3.0), ("east", hx - 3.0, hx)):
        g.node("gallery_" + s, Mesh().box((x0, 4.3, -hz), (x1, 4.6, hz), 4 * d), stone)
    # Skylight: an emissive panel in the opening, facing down.
    g.node("skylight", Mesh().quad((-2.0, H, -4.0), (2.0, H, -4.0), (2.0, H, 4.0), (-2.0, H, 4.0),
                                   2, 4, toward=(0.0, 0.0, 0.0)), sky)
    # Two storeys of 8 columns per side (one mesh, instanced), arches between.
    col = g.mesh("column", column(d), stone)
    spacing = L / 8.0
    span = spacing - 0.7
    arc = g.mesh("arch", arch(d, span), stone)
    for storey, y in ((0, 0.0), (1, 4.6)):
        for side, x in (("w", -hx + 3.0), ("e", hx - 3.0)):
            for i in range(8):
                z = -hz + spacing * (i + 0.5)
                g.doc["nodes"].append({"name": "column_%d%s%d" % (storey, side, i), "mesh": col,
                                       "translation": [x, y, z]})
                g.doc["scenes"][0]["nodes"].append(len(g.doc["nodes"]) - 1)
                if i < 7:  # arch springing from the column tops, spanning along z
                    g.doc["nodes"].append({
                        "name": "arch_%d%s%d" % (storey, side, i), "mesh": arc,
                        "translation": [x, y + 4.0 - 0.3 - span * 0.5 + 0.3, z + spacing * 0.5],
                        "rotation": [0.0, math.sin(math.pi / 4), 0.0, math.cos(math.pi / 4)]})
                    g.doc["scenes"][0]["nodes"].append(len(g.doc["nodes"]) - 1)
    # The count printed: every instance's triangles (32 columns, 28 arches).
    g.stats[1] += 31 * (len(column(d).idx) // 3) + 27 * (len(arch(d, span).idx) // 3)
    g.camera("camera", (0.0, 1.7, -hz + 1.0), (0.0, 1.0, 0.0, 0.0), math.radians(60.0), 0.05)
    g.write(os.path.join(out, name + ".gltf"))


def main():
    args = sys.argv[1:]
    atrium_only = "--atrium-only" in args  # docs/bench/atrium.sh: no Cornell boxes
    args = [a for a in args if a != "--atrium-only"]
    if not args or args[0].startswith("-"):  # no OUT_DIR, or -h / --help
        sys.exit(__doc__)
    out = args[0]
    os.makedirs(out, exist_ok=True)
    details = [int(a) for a in args[1:]] or [3, 6]
    for scale, (walls_n, blocks_n) in CORNELL_SCALES.items():
        if not atrium_only:
            make_scenes.cornell_box(out, walls_n, blocks_n, "cornell_box_x%d" % scale)
    for d in details:
        atrium(out, d)


if __name__ == "__main__":
    main()
