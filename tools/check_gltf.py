#!/usr/bin/env python3
"""Structural checks for the bundled glTF scenes (standard library only).

    python3 tools/check_gltf.py scenes/*.gltf

Checks: valid JSON; each buffer is a base64 data: URI whose decoded size equals
byteLength; bufferViews lie inside their buffer; accessors fit their
bufferView and are aligned; every primitive is indexed triangles with
POSITION and NORMAL of equal count; POSITION has min/max matching the data;
indices < vertex count; normals unit length and agreeing with the triangle
winding (counter-clockwise seen from the normal's side); node names present
and unique; mesh/material/camera/light references valid; extensions listed in
extensionsUsed. Exits non-zero on the first file with errors.
"""
import base64
import json
import math
import struct
import sys

COMPONENTS = {5120: ("b", 1), 5121: ("B", 1), 5122: ("h", 2), 5123: ("H", 2),
              5125: ("I", 4), 5126: ("f", 4)}
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
PREFIX = "data:application/octet-stream;base64,"


def check(path):
    errors = []
    def err(msg): errors.append(msg)

    with open(path) as f:
        doc = json.load(f)
    if doc.get("asset", {}).get("version") != "2.0":
        err("asset.version is not 2.0")

    buffers = []
    for i, b in enumerate(doc.get("buffers", [])):
        uri = b.get("uri", "")
        if not uri.startswith(PREFIX):
            err("buffer %d: not an embedded base64 data URI" % i)
            buffers.append(b"")
            continue
        data = base64.b64decode(uri[len(PREFIX):], validate=True)
        if len(data) != b["byteLength"]:
            err("buffer %d: byteLength %d but %d bytes decoded" % (i, b["byteLength"], len(data)))
        buffers.append(data)

    views = doc.get("bufferViews", [])
    for i, v in enumerate(views):
        if v["buffer"] >= len(buffers) or v.get("byteOffset", 0) + v["byteLength"] > len(buffers[v["buffer"]]):
            err("bufferView %d: outside its buffer" % i)

    def read(ai):
        """Accessor ai as a list of tuples (after range and alignment checks)."""
        a = doc["accessors"][ai]
        fmt, size = COMPONENTS[a["componentType"]]
        width = WIDTH[a["type"]]
        v = views[a["bufferView"]]
        stride = v.get("byteStride", size * width)
        off = a.get("byteOffset", 0)
        need = off + stride * (a["count"] - 1) + size * width if a["count"] else 0
        if need > v["byteLength"]:
            err("accessor %d: needs %d bytes, bufferView has %d" % (ai, need, v["byteLength"]))
            return []
        start = v.get("byteOffset", 0) + off
        if start % size or stride % size:
            err("accessor %d: misaligned" % ai)
        data = buffers[v["buffer"]]
        return [struct.unpack_from("<%d%s" % (width, fmt), data, start + k * stride)
                for k in range(a["count"])]

    def cross(a, b):
        return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])

    stats = [0, 0]
    for mi, mesh in enumerate(doc.get("meshes", [])):
        for pi, prim in enumerate(mesh["primitives"]):
            where = "mesh %d (%s) primitive %d" % (mi, mesh.get("name"), pi)
            attrs = prim.get("attributes", {})
            if "POSITION" not in attrs or "NORMAL" not in attrs or "indices" not in prim:
                err(where + ": needs POSITION, NORMAL and indices")
                continue
            if prim.get("mode", 4) != 4:
                err(where + ": not TRIANGLES")
            if not 0 <= prim.get("material", -1) < len(doc.get("materials", [])):
                err(where + ": bad material")
            pa = doc["accessors"][attrs["POSITION"]]
            if "min" not in pa or "max" not in pa:
                err(where + ": POSITION without min/max")
            pos, nrm = read(attrs["POSITION"]), read(attrs["NORMAL"])
            ia = doc["accessors"][prim["indices"]]
            if ia["componentType"] not in (5123, 5125) or ia["type"] != "SCALAR":
                err(where + ": indices must be UNSIGNED_SHORT/INT scalars")
            idx = [i[0] for i in read(prim["indices"])]
            if not pos or len(pos) != len(nrm) or len(idx) % 3:
                err(where + ": bad counts")
                continue
            for k in range(3):
                vals = [p[k] for p in pos]
                if "min" in pa and (pa["min"][k] != min(vals) or pa["max"][k] != max(vals)):
                    err(where + ": POSITION min/max do not match the data")
                    break
            if max(idx) >= len(pos):
                err(where + ": index %d >= vertex count %d" % (max(idx), len(pos)))
                continue
            if any(abs(math.sqrt(sum(c * c for c in n)) - 1.0) > 1e-4 for n in nrm):
                err(where + ": normals not unit length")
            bad = 0
            for t in range(0, len(idx), 3):
                a, b, c = (pos[i] for i in idx[t:t + 3])
                g = cross([b[k] - a[k] for k in range(3)], [c[k] - a[k] for k in range(3)])
                if sum(g[k] * (nrm[idx[t]][k] + nrm[idx[t + 1]][k] + nrm[idx[t + 2]][k]) for k in range(3)) <= 0:
                    bad += 1
            if bad:
                err(where + ": %d triangles wound against their normals (or degenerate)" % bad)
            stats[0] += len(pos)
            stats[1] += len(idx) // 3

    lights = doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    used = set(doc.get("extensionsUsed", []))
    names = [n.get("name") for n in doc.get("nodes", [])]
    if None in names or "" in names or len(set(names)) != len(names):
        err("node names missing or not unique: %s" % names)
    for n in doc.get("nodes", []):
        if "mesh" in n and not 0 <= n["mesh"] < len(doc.get("meshes", [])):
            err("node %s: bad mesh" % n.get("name"))
        if "camera" in n and not 0 <= n["camera"] < len(doc.get("cameras", [])):
            err("node %s: bad camera" % n.get("name"))
        if "KHR_lights_punctual" in n.get("extensions", {}):
            if not 0 <= n["extensions"]["KHR_lights_punctual"]["light"] < len(lights):
                err("node %s: bad light" % n.get("name"))
    for scene in doc.get("scenes", []):
        if any(not 0 <= i < len(names) for i in scene.get("nodes", [])):
            err("scene references a missing node")
    present = set(doc.get("extensions", {}))
    for obj in doc.get("nodes", []) + doc.get("materials", []):
        present |= set(obj.get("extensions", {}))
    if present - used:
        err("extensions not in extensionsUsed: %s" % sorted(present - used))

    for e in errors:
        print("%s: %s" % (path, e))
    print("%s: %s (%d vertices, %d triangles; nodes: %s)" %
          (path, "FAIL" if errors else "ok", stats[0], stats[1], ", ".join(map(str, names))))
    return not errors


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    sys.exit(0 if all([check(p) for p in sys.argv[1:]]) else 1)
