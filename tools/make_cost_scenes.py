#!/usr/bin/env python3
"""Scenes whose cost is in their draw calls, not their triangles (issue 30).

    python3 tools/make_cost_scenes.py OUT_DIR [N]

writes into OUT_DIR (N = 65536 by default, a square number):
  many_primitives_<N>.gltf  one mesh of N primitives, each with its own
                            material: a floor of sqrt(N) x sqrt(N) tiles,
                            10 triangles each
  many_instances_<N>.gltf   N nodes instancing one 10-triangle tile mesh
Each has a white floor tile grid 2 x 2 m at y = 0, a point light 1 m above
its centre and a camera looking down at it. The triangle count (10 N) is far
below the import limit: what such a file costs is submission (primitives,
nodes, materials), which gistreamd's cost limits bound (README: "Cost
limits").
"""
import base64
import json
import math
import os
import struct
import sys


def tile(x0, z0, size):
    """A strip of 5 quads along x (10 triangles, 12 vertices) facing +y."""
    pos, idx = [], []
    for i in range(6):
        x = x0 + size * i / 5
        pos += [(x, 0.0, z0), (x, 0.0, z0 + size)]
    for i in range(5):
        a, b, c, d = 2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3
        idx += [a, b, c, c, b, d]
    return pos, idx


def write(path, doc, blob):
    doc["buffers"] = [{"byteLength": len(blob), "uri": os.path.basename(path)[:-5] + ".bin"}]
    with open(path[:-5] + ".bin", "wb") as f:
        f.write(blob)
    with open(path, "w") as f:
        json.dump(doc, f, separators=(",", ":"))


def common(doc):
    doc["asset"] = {"version": "2.0", "generator": "gistream tools/make_cost_scenes.py"}
    doc["extensionsUsed"] = ["KHR_lights_punctual"]
    doc["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "point", "color": [1, 1, 1], "intensity": 20.0}]}}
    doc["cameras"] = [{"type": "perspective",
                       "perspective": {"yfov": 0.9, "znear": 0.05, "zfar": 20.0, "aspectRatio": 1.0}}]
    # Looking down (-y) from 2.2 m: rotation of -90 degrees about x.
    s = math.sqrt(0.5)
    return [{"name": "light", "translation": [0, 1, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "camera", "camera": 0, "translation": [0, 2.2, 0], "rotation": [-s, 0, 0, s]}]


def many_primitives(out, n):
    side = int(math.isqrt(n))
    size = 2.0 / side
    blob = bytearray()
    accessors, views, prims, materials = [], [], [], []
    for k in range(side * side):
        i, j = divmod(k, side)
        pos, idx = tile(-1 + i * size, -1 + j * size, size)
        off = len(blob)
        for p in pos:
            blob += struct.pack("<3f", *p)
        views.append({"buffer": 0, "byteOffset": off, "byteLength": 12 * len(pos)})
        accessors.append({"bufferView": len(views) - 1, "componentType": 5126, "count": len(pos),
                          "type": "VEC3",
                          "min": [min(p[a] for p in pos) for a in range(3)],
                          "max": [max(p[a] for p in pos) for a in range(3)]})
        off = len(blob)
        for v in idx:
            blob += struct.pack("<H", v)
        while len(blob) % 4:
            blob += b"\0"
        views.append({"buffer": 0, "byteOffset": off, "byteLength": 2 * len(idx)})
        accessors.append({"bufferView": len(views) - 1, "componentType": 5123,
                          "count": len(idx), "type": "SCALAR"})
        shade = 0.5 + 0.3 * ((i + j) % 2)
        materials.append({"pbrMetallicRoughness": {"baseColorFactor": [shade, shade, shade, 1],
                                                   "metallicFactor": 0.0, "roughnessFactor": 1.0}})
        prims.append({"attributes": {"POSITION": len(accessors) - 2},
                      "indices": len(accessors) - 1, "material": k})
    doc = {}
    nodes = common(doc) + [{"name": "floor", "mesh": 0}]
    doc.update(scene=0, scenes=[{"nodes": list(range(len(nodes)))}], nodes=nodes,
               meshes=[{"primitives": prims}], materials=materials, accessors=accessors,
               bufferViews=views)
    path = os.path.join(out, f"many_primitives_{n}.gltf")
    write(path, doc, bytes(blob))
    return path


def many_instances(out, n):
    side = int(math.isqrt(n))
    size = 2.0 / side
    pos, idx = tile(0.0, 0.0, size)
    blob = bytearray()
    for p in pos:
        blob += struct.pack("<3f", *p)
    off = len(blob)
    for v in idx:
        blob += struct.pack("<H", v)
    while len(blob) % 4:
        blob += b"\0"
    doc = {}
    nodes = common(doc)
    tiles = [{"mesh": 0, "translation": [-1 + i * size, 0, -1 + j * size]}
             for i in range(side) for j in range(side)]
    nodes += [{"name": "floor", "children": list(range(len(nodes) + 1, len(nodes) + 1 + len(tiles)))}]
    nodes += tiles
    doc.update(scene=0, scenes=[{"nodes": [0, 1, 2]}], nodes=nodes,
               meshes=[{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
               materials=[{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1],
                                                    "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
               accessors=[{"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3",
                           "min": [min(p[a] for p in pos) for a in range(3)],
                           "max": [max(p[a] for p in pos) for a in range(3)]},
                          {"bufferView": 1, "componentType": 5123, "count": len(idx), "type": "SCALAR"}],
               bufferViews=[{"buffer": 0, "byteOffset": 0, "byteLength": 12 * len(pos)},
                            {"buffer": 0, "byteOffset": off, "byteLength": 2 * len(idx)}])
    path = os.path.join(out, f"many_instances_{n}.gltf")
    write(path, doc, bytes(blob))
    return path


def main():
    out = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 65536
    if math.isqrt(n) ** 2 != n:
        sys.exit("N must be a square number")
    os.makedirs(out, exist_ok=True)
    for path in (many_primitives(out, n), many_instances(out, n)):
        print(path, os.path.getsize(path) + os.path.getsize(path[:-5] + ".bin"), "bytes")


if __name__ == "__main__":
    main()
