#!/usr/bin/env python3
"""Generate the bundled glTF 2.0 scenes in scenes/ (standard library only).

    python3 tools/make_scenes.py [OUT_DIR]      # default: <repo>/scenes

Every file is a self-contained .gltf (one base64 data: URI buffer). Units are
metres, Y is up. Every primitive is indexed and has POSITION and NORMAL, with
normals facing the visible side and triangles wound counter-clockwise when
seen from that side. Materials are diffuse (metallic 0, roughness 1); area
lights are emissive materials with KHR_materials_emissive_strength; punctual
lights use KHR_lights_punctual (candela for point/spot, lux for directional,
shining down the node's -Z). Cameras look down their node's -Z.
"""
import base64
import json
import math
import os
import struct
import sys

# ---------------------------------------------------------------- vector math


def add(a, b): return tuple(x + y for x, y in zip(a, b))
def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def mul(a, s): return tuple(x * s for x in a)
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def lerp(a, b, t): return add(mul(a, 1.0 - t), mul(b, t))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(a):
    return mul(a, 1.0 / math.sqrt(dot(a, a)))


def angle_between(a, b):
    return math.acos(max(-1.0, min(1.0, dot(normalize(a), normalize(b)))))


def look_at(eye, target, up=(0.0, 1.0, 0.0)):
    """Quaternion [x, y, z, w] turning the node's -Z toward target (+Y kept up)."""
    z = normalize(sub(eye, target))             # local +Z points away from target
    x = normalize(cross(up, z))
    y = cross(z, x)
    m = [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]]
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = 2.0 * math.sqrt(tr + 1.0)
        q = ((m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, 0.25 * s)
    else:
        i = max(range(3), key=lambda k: m[k][k])
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(1.0 + m[i][i] - m[j][j] - m[k][k])
        q = [0.0] * 4
        q[i] = 0.25 * s
        q[j] = (m[j][i] + m[i][j]) / s
        q[k] = (m[k][i] + m[i][k]) / s
        q[3] = (m[k][j] - m[j][k]) / s
    return [round(c, 9) for c in normalize(q)]


def mm(*p):
    return tuple(c * 0.001 for c in p)

# ---------------------------------------------------------------- mesh builder


class Mesh:
    def __init__(self):
        self.pos, self.nrm, self.idx = [], [], []

    def quad(self, p00, p10, p11, p01, nu, nv, toward=None, away=None, keep=None):
        """Bilinear patch P(u,v) through the four corners, split into nu x nv cells
        of two triangles. Normals face `toward` a point or `away` from one.
        keep(cell_centre) -> bool drops cells (holes); unused vertices are not emitted."""
        def P(u, v): return lerp(lerp(p00, p10, u), lerp(p01, p11, u), v)
        def N(u, v): return normalize(cross(sub(lerp(p10, p11, v), lerp(p00, p01, v)),
                                            sub(lerp(p01, p11, u), lerp(p00, p10, u))))
        c = P(0.5, 0.5)
        side = sub(toward, c) if toward is not None else sub(c, away)
        flip = dot(N(0.5, 0.5), side) < 0
        remap = {}

        def vert(i, j):
            if (i, j) not in remap:
                remap[(i, j)] = len(self.pos)
                self.pos.append(P(i / nu, j / nv))
                n = N(i / nu, j / nv)
                self.nrm.append(mul(n, -1.0) if flip else n)
            return remap[(i, j)]

        for j in range(nv):
            for i in range(nu):
                if keep and not keep(P((i + 0.5) / nu, (j + 0.5) / nv)):
                    continue
                a, b, c_, d = vert(i, j), vert(i + 1, j), vert(i + 1, j + 1), vert(i, j + 1)
                for t in ((a, b, c_), (a, c_, d)):
                    self.idx.extend((t[0], t[2], t[1]) if flip else t)
        return self

    def box(self, lo, hi, n, inward=False):
        """Axis-aligned box from 6 quads, n x n cells per face, normals out (or in)."""
        (x0, y0, z0), (x1, y1, z1) = lo, hi
        ctr = mul(add(lo, hi), 0.5)
        faces = [((x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)),   # -Y
                 ((x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1)),   # +Y
                 ((x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)),   # -Z
                 ((x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)),   # +Z
                 ((x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)),   # -X
                 ((x1, y0, z0), (x1, y0, z1), (x1, y1, z1), (x1, y1, z0))]   # +X
        for f in faces:
            self.quad(*f, n, n, **({'toward': ctr} if inward else {'away': ctr}))
        return self

# ---------------------------------------------------------------- glTF writer


class Gltf:
    def __init__(self, name):
        self.name = name
        self.blob = bytearray()
        self.doc = {"asset": {"version": "2.0", "generator": "gistream tools/make_scenes.py"},
                    "scene": 0, "scenes": [{"name": name, "nodes": []}], "nodes": [],
                    "meshes": [], "materials": [], "accessors": [], "bufferViews": [],
                    "buffers": []}
        self.ext_used = set()
        self.lights = []
        self.stats = [0, 0]     # vertices, triangles

    def _view(self, data, target):
        while len(self.blob) % 4:
            self.blob.append(0)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.blob),
                                        "byteLength": len(data), "target": target})
        self.blob.extend(data)
        return len(self.doc["bufferViews"]) - 1

    def _accessor(self, acc):
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def material(self, name, albedo, emissive=None, strength=None, metallic=0.0, roughness=1.0):
        mat = {"name": name, "pbrMetallicRoughness": {
            "baseColorFactor": list(albedo) + [1.0], "metallicFactor": metallic,
            "roughnessFactor": roughness}}
        if emissive:
            mat["emissiveFactor"] = list(emissive)
            mat["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": strength}}
            self.ext_used.add("KHR_materials_emissive_strength")
        self.doc["materials"].append(mat)
        return len(self.doc["materials"]) - 1

    def mesh(self, name, mesh, material):
        nv = len(mesh.pos)
        pos = struct.pack("<%df" % (3 * nv), *[c for p in mesh.pos for c in p])
        f32 = struct.unpack("<%df" % (3 * nv), pos)   # min/max of the stored float32 values
        lo = [min(f32[k::3]) for k in range(3)]
        hi = [max(f32[k::3]) for k in range(3)]
        nrm = struct.pack("<%df" % (3 * nv), *[c for n in mesh.nrm for c in n])
        short = nv <= 0xFFFF
        idx = struct.pack("<%d%s" % (len(mesh.idx), "H" if short else "I"), *mesh.idx)
        a_pos = self._accessor({"bufferView": self._view(pos, 34962), "componentType": 5126,
                                "count": nv, "type": "VEC3", "min": lo, "max": hi})
        a_nrm = self._accessor({"bufferView": self._view(nrm, 34962), "componentType": 5126,
                                "count": nv, "type": "VEC3"})
        a_idx = self._accessor({"bufferView": self._view(idx, 34963),
                                "componentType": 5123 if short else 5125,
                                "count": len(mesh.idx), "type": "SCALAR"})
        self.doc["meshes"].append({"name": name, "primitives": [{
            "attributes": {"POSITION": a_pos, "NORMAL": a_nrm}, "indices": a_idx,
            "material": material, "mode": 4}]})
        self.stats[0] += nv
        self.stats[1] += len(mesh.idx) // 3
        return len(self.doc["meshes"]) - 1

    def floats(self, values, kind, target=None, bounds=False):
        """An accessor of float32 `values` (flat) of glTF type `kind` (SCALAR, VEC3,
        VEC4, MAT4); bounds: min/max (required for POSITION and animation input)."""
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4, "MAT4": 16}[kind]
        data = struct.pack("<%df" % len(values), *values)
        f32 = struct.unpack("<%df" % len(values), data)
        acc = {"bufferView": self._view(data, target) if target else self._view_plain(data),
               "componentType": 5126, "count": len(values) // width, "type": kind}
        if bounds:
            acc["min"] = [min(f32[k::width]) for k in range(width)]
            acc["max"] = [max(f32[k::width]) for k in range(width)]
        return self._accessor(acc)

    def _view_plain(self, data):
        """A buffer view without a target (skins, animations)."""
        view = self._view(data, 0)
        del self.doc["bufferViews"][view]["target"]
        return view

    def deforming_mesh(self, name, mesh, material, joints=None, weights=None, targets=(),
                       target_names=()):
        """A mesh like mesh(), plus JOINTS_0 (unsigned short) / WEIGHTS_0 per vertex and
        morph targets [(position deltas, normal deltas or None)], default weights 0."""
        index = self.mesh(name, mesh, material)
        prim = self.doc["meshes"][index]["primitives"][0]
        if joints is not None:
            data = struct.pack("<%dH" % (4 * len(joints)), *[j for js in joints for j in js])
            prim["attributes"]["JOINTS_0"] = self._accessor({
                "bufferView": self._view(data, 34962), "componentType": 5123,
                "count": len(joints), "type": "VEC4"})
            prim["attributes"]["WEIGHTS_0"] = self.floats(
                [w for ws in weights for w in ws], "VEC4", 34962)
        if targets:
            prim["targets"] = []
            for dp, dn in targets:
                t = {"POSITION": self.floats([c for v in dp for c in v], "VEC3", 34962, True)}
                if dn is not None:
                    t["NORMAL"] = self.floats([c for v in dn for c in v], "VEC3", 34962)
                prim["targets"].append(t)
            self.doc["meshes"][index]["weights"] = [0.0] * len(targets)
            self.doc["meshes"][index]["extras"] = {"targetNames": list(target_names)}
        return index

    def animation(self, name, channels):
        """channels: [(node index, path, key times, flat output values)], LINEAR."""
        anim = {"name": name, "samplers": [], "channels": []}
        for node, path, times, values in channels:
            kind = {"rotation": "VEC4", "translation": "VEC3", "scale": "VEC3",
                    "weights": "SCALAR"}[path]
            anim["samplers"].append({"input": self.floats(times, "SCALAR", bounds=True),
                                     "output": self.floats(values, kind),
                                     "interpolation": "LINEAR"})
            anim["channels"].append({"sampler": len(anim["samplers"]) - 1,
                                     "target": {"node": node, "path": path}})
        self.doc.setdefault("animations", []).append(anim)

    def node(self, name, mesh=None, material=None, translation=None, rotation=None, **extra):
        assert all(n["name"] != name for n in self.doc["nodes"]), name
        node = {"name": name}
        if mesh is not None:
            node["mesh"] = self.mesh(name, mesh, material)
        if translation is not None:
            node["translation"] = [float(c) for c in translation]
        if rotation is not None:
            node["rotation"] = [float(c) for c in rotation]
        node.update(extra)
        self.doc["nodes"].append(node)
        self.doc["scenes"][0]["nodes"].append(len(self.doc["nodes"]) - 1)
        return node

    def camera(self, name, translation, rotation, yfov, znear):
        self.doc.setdefault("cameras", []).append({"name": name, "type": "perspective",
                                                   "perspective": {"yfov": yfov, "znear": znear}})
        return self.node(name, translation=translation, rotation=rotation,
                         camera=len(self.doc["cameras"]) - 1)

    def light(self, name, kind, intensity, translation=None, rotation=None, spot=None):
        light = {"name": name, "type": kind, "color": [1.0, 1.0, 1.0], "intensity": intensity}
        if spot:
            light["spot"] = spot
        self.lights.append(light)
        self.ext_used.add("KHR_lights_punctual")
        return self.node(name, translation=translation, rotation=rotation,
                         extensions={"KHR_lights_punctual": {"light": len(self.lights) - 1}})

    def write(self, path):
        doc = dict(self.doc)
        if self.lights:
            doc["extensions"] = {"KHR_lights_punctual": {"lights": self.lights}}
        if self.ext_used:
            doc["extensionsUsed"] = sorted(self.ext_used)
        doc["buffers"] = [{"name": self.name, "byteLength": len(self.blob),
                           "uri": "data:application/octet-stream;base64,"
                                  + base64.b64encode(bytes(self.blob)).decode("ascii")}]
        with open(path, "w") as f:
            json.dump(doc, f, indent=1)
            f.write("\n")
        print("%-22s %6d vertices %6d triangles %3d nodes" %
              (os.path.basename(path), self.stats[0], self.stats[1], len(doc["nodes"])))

# ---------------------------------------------------------------- scenes


# Cornell box light quad: measured at y = 548.8 mm, x 213..343, z 227..332; we
# hang it 0.5 mm below the ceiling. The node sits at the quad's centre.
CORNELL_LIGHT_T = (0.278, 0.5483, 0.2795)
CORNELL_LIGHT_HALF = (0.065, 0.0525)


def cornell_room(g, walls_n):
    """The Cornell box's materials and five walls (the light and camera come after
    the contents, cornell_light_and_camera); returns the white material."""
    white = g.material("white", (0.725, 0.71, 0.68))
    red = g.material("red", (0.63, 0.065, 0.05))
    green = g.material("green", (0.14, 0.45, 0.091))
    g.material("light", (0.78, 0.78, 0.78), emissive=(1.0, 0.85, 0.43), strength=17.0)

    inside = mm(278.0, 274.4, 279.6)
    walls = [  # name, material, measured corners (mm)
        ("floor", white, [(552.8, 0, 0), (0, 0, 0), (0, 0, 559.2), (549.6, 0, 559.2)]),
        ("ceiling", white, [(556, 548.8, 0), (556, 548.8, 559.2), (0, 548.8, 559.2), (0, 548.8, 0)]),
        ("back_wall", white, [(549.6, 0, 559.2), (0, 0, 559.2), (0, 548.8, 559.2), (556, 548.8, 559.2)]),
        ("left_wall", red, [(552.8, 0, 0), (549.6, 0, 559.2), (556, 548.8, 559.2), (556, 548.8, 0)]),
        ("right_wall", green, [(0, 0, 559.2), (0, 0, 0), (0, 548.8, 0), (0, 548.8, 559.2)]),
    ]
    for name, mat, q in walls:
        g.node(name, Mesh().quad(*[mm(*p) for p in q], walls_n, walls_n, toward=inside), mat)
    return white


def cornell_light_and_camera(g, light_n):
    """The Cornell box's ceiling light quad and published camera."""
    lamp = 3   # the "light" material, fourth of cornell_room's
    hx, hz = CORNELL_LIGHT_HALF   # local coordinates around the node origin, facing down
    g.node("light", Mesh().quad((-hx, 0, -hz), (hx, 0, -hz), (hx, 0, hz), (-hx, 0, hz), light_n,
                                light_n, toward=(0, -1, 0)), lamp, translation=CORNELL_LIGHT_T)
    # Published camera: (278, 273, -800) mm looking along +Z, 35 mm lens, 25 mm film.
    g.camera("camera", (0.278, 0.273, -0.800), (0.0, 1.0, 0.0, 0.0), math.radians(39.3), 0.01)


def cornell_box(out, walls_n=24, blocks_n=6, scene_name="cornell_box", light_n=2):
    """Cornell University Program of Computer Graphics "Cornell Box Data" (mm -> m).

    walls_n / blocks_n / light_n: quads per wall / block face / light edge
    (tools/make_tessellations.py writes other tessellations of the same box under
    other names; cornell_box_coarse is the one-quad-per-face version)."""
    g = Gltf(scene_name)
    white = cornell_room(g, walls_n)
    blocks = [  # measured faces: top, then the four sides
        ("short_block", [
            [(130, 165, 65), (82, 165, 225), (240, 165, 272), (290, 165, 114)],
            [(290, 0, 114), (290, 165, 114), (240, 165, 272), (240, 0, 272)],
            [(130, 0, 65), (130, 165, 65), (290, 165, 114), (290, 0, 114)],
            [(82, 0, 225), (82, 165, 225), (130, 165, 65), (130, 0, 65)],
            [(240, 0, 272), (240, 165, 272), (82, 165, 225), (82, 0, 225)]]),
        ("tall_block", [
            [(423, 330, 247), (265, 330, 296), (314, 330, 456), (472, 330, 406)],
            [(423, 0, 247), (423, 330, 247), (472, 330, 406), (472, 0, 406)],
            [(472, 0, 406), (472, 330, 406), (314, 330, 456), (314, 0, 456)],
            [(314, 0, 456), (314, 330, 456), (265, 330, 296), (265, 0, 296)],
            [(265, 0, 296), (265, 330, 296), (423, 330, 247), (423, 0, 247)]]),
    ]
    for block, faces in blocks:
        top = [mm(*p) for p in faces[0]]
        cx, cy, cz = mul(tuple(map(sum, zip(*top))), 0.25)
        centre = (cx, cy * 0.5, cz)                            # middle of the block
        m = Mesh()
        for q in faces:
            m.quad(*[mm(*p) for p in q], blocks_n, blocks_n, away=centre)
        g.node(block, m, white)

    cornell_light_and_camera(g, light_n)
    g.write(os.path.join(out, scene_name + ".gltf"))


def cornell_box_coarse(out):
    """The same box with one quad per wall, block face and light: 64 vertices and
    32 triangles, as the common OBJ versions of the Cornell box are (a test of
    coarse meshes for the vertex-based solvers)."""
    cornell_box(out, 1, 1, "cornell_box_coarse", light_n=1)


def indirect_room(out):
    """Two 4 x 3 x 4 m rooms side by side along X, joined by a doorway.

    Room A: x 0..4, divider (solid, 0.25 m thick): x 4..4.25, room B: x 4.25..8.25;
    z 0..4 (south..north), y 0..3. Doorway through the divider at z 2.75..3.75,
    y 0..2.25 (near the north end). Everything lies on a 0.25 m grid, so where
    surfaces meet, their vertices coincide along the common edge.

    The spot lamp in room A points south-west, down at the orange west wall and
    the floor. Why none of its light reaches the doorway: the lamp sits at
    x = 3.0 < 4 and its axis makes an angle beta = 44.7 deg with -X. A direction
    toward any point with x >= 3.0 has a non-negative x component, so it is at
    least 90 deg from -X and at least 90 - 44.7 = 45.3 deg from the axis, which
    is more than the 0.6 rad = 34.4 deg outer cone. The whole doorway (x >= 4)
    is therefore dark, and room B gets no direct light at all.

    The camera in room B looks north-west at the divider and the doorway.
    Through the doorway it sees only the north part of room A (the rays enter
    room A heading north-west); check_indirect_only() traces those rays and
    asserts that every room-A point they reach is also outside the cone, so
    every pixel the camera sees is lit only indirectly.
    """
    g = Gltf("indirect_room")
    white = g.material("white", (0.7, 0.7, 0.7))
    orange = g.material("orange", (0.8, 0.4, 0.1))
    blue = g.material("blue", (0.15, 0.3, 0.7))

    X0, XA, XB, X1, H, D = 0.0, 4.0, 4.25, 8.25, 3.0, 4.0
    DZ0, DZ1, DH = 2.75, 3.75, 2.25                      # doorway
    n = lambda length: max(1, round(length / 0.25))     # 0.25 m cells
    mid = (XA + XB) / 2

    def in_door(p): return DZ0 < p[2] < DZ1 and p[1] < DH
    def in_divider(p): return XA < p[0] < XB

    g.node("floor", Mesh().quad((X0, 0, 0), (X1, 0, 0), (X1, 0, D), (X0, 0, D), n(X1), n(D),
                                toward=(0, 1, 0), keep=lambda p: not in_divider(p) or DZ0 < p[2] < DZ1),
           white)
    g.node("ceiling", Mesh().quad((X0, H, 0), (X1, H, 0), (X1, H, D), (X0, H, D), n(X1), n(D),
                                  toward=(0, 0, 0), keep=lambda p: not in_divider(p)), white)
    for name, mat, x0, x1 in (("room_a_south_wall", white, X0, XA), ("room_b_south_wall", white, XB, X1)):
        g.node(name, Mesh().quad((x0, 0, 0), (x1, 0, 0), (x1, H, 0), (x0, H, 0), n(x1 - x0), n(H),
                                 toward=(x0, 0, 1)), mat)
    for name, mat, x0, x1 in (("room_a_north_wall", white, X0, XA), ("room_b_north_wall", blue, XB, X1)):
        g.node(name, Mesh().quad((x0, 0, D), (x1, 0, D), (x1, H, D), (x0, H, D), n(x1 - x0), n(H),
                                 toward=(x0, 0, 0)), mat)
    g.node("room_a_west_wall", Mesh().quad((X0, 0, 0), (X0, 0, D), (X0, H, D), (X0, H, 0), n(D), n(H),
                                           toward=(1, 0, 0)), orange)
    g.node("room_b_east_wall", Mesh().quad((X1, 0, 0), (X1, 0, D), (X1, H, D), (X1, H, 0), n(D), n(H),
                                           toward=(0, 0, 0)), white)
    div = Mesh()
    for x, inside in ((XA, (0, 0, 0)), (XB, (X1, 0, 0))):           # the two faces, with the hole
        div.quad((x, 0, 0), (x, 0, D), (x, H, D), (x, H, 0), n(D), n(H), toward=inside,
                 keep=lambda p: not in_door(p))
    div.quad((XA, 0, DZ0), (XB, 0, DZ0), (XB, DH, DZ0), (XA, DH, DZ0), 1, n(DH), toward=(mid, 0, D))
    div.quad((XA, 0, DZ1), (XB, 0, DZ1), (XB, DH, DZ1), (XA, DH, DZ1), 1, n(DH), toward=(mid, 0, 0))
    div.quad((XA, DH, DZ0), (XB, DH, DZ0), (XB, DH, DZ1), (XA, DH, DZ1), 1, n(DZ1 - DZ0),
             toward=(mid, 0, 3.0))                                  # lintel underside
    g.node("divider", div, white)

    lamp_pos, lamp_aim, outer = (3.0, 2.7, 1.5), (0.5, 0.3, 0.9), 0.6
    cam_pos, cam_aim = (7.9, 1.6, 0.35), (4.5, 1.0, 3.3)
    check_indirect_only(lamp_pos, sub(lamp_aim, lamp_pos), outer, cam_pos,
                        room_a=((X0, 0, 0), (XA, H, D)), door=(XA, XB, DZ0, DZ1, DH))
    g.light("lamp", "spot", 200.0, lamp_pos, look_at(lamp_pos, lamp_aim),
            spot={"innerConeAngle": 0.45, "outerConeAngle": outer})
    g.camera("camera", cam_pos, look_at(cam_pos, cam_aim), math.radians(60.0), 0.05)
    g.write(os.path.join(out, "indirect_room.gltf"))


def check_indirect_only(lamp, axis, outer, cam, room_a, door, steps=60):
    """Assert the spot's cone misses the doorway and every room-A point the
    camera can see through it (room A is a convex empty box, so a point there
    is directly lit iff it lies inside the cone)."""
    xa, xb, z0, z1, dh = door
    (ax0, ay0, az0), (ax1, ay1, az1) = room_a
    assert lamp[0] < xa and math.degrees(angle_between(axis, (-1, 0, 0))) + math.degrees(outer) < 90
    worst = math.pi
    for i in range(steps + 1):
        for j in range(steps + 1):
            p = (xa, dh * j / steps, z0 + (z1 - z0) * i / steps)      # doorway, room-A side
            worst = min(worst, angle_between(sub(p, lamp), axis))
            d = sub(p, cam)
            t = (xb - cam[0]) / d[0]                                  # must also clear room-B side
            q = add(cam, mul(d, t))
            if not (z0 <= q[2] <= z1 and q[1] <= dh):
                continue
            # exit point of the ray from room A's box (x < xa side, then walls/floor/ceiling)
            ts = [(ax0 - cam[0]) / d[0]]
            for k, lo, hi in ((1, ay0, ay1), (2, az0, az1)):
                if d[k] > 0: ts.append((hi - cam[k]) / d[k])
                if d[k] < 0: ts.append((lo - cam[k]) / d[k])
            hit = add(cam, mul(d, min(ts)))
            worst = min(worst, angle_between(sub(hit, lamp), axis))
    assert worst > outer, "lamp cone reaches what the camera sees through the doorway"
    return worst


def furnace(out):
    """White furnace: closed 2 m cube, inward normals, albedo 0.5, emission 1.
    Radiance everywhere: L = E / (1 - rho) = 1 / (1 - 0.5) = 2."""
    g = Gltf("furnace")
    mat = g.material("furnace", (0.5, 0.5, 0.5), emissive=(1.0, 1.0, 1.0), strength=1.0)
    g.node("furnace", Mesh().box((-1, -1, -1), (1, 1, 1), 16, inward=True), mat)
    g.camera("camera", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), math.radians(60.0), 0.01)
    g.write(os.path.join(out, "furnace.gltf"))


def glossy_box(out):
    """After the antiradiance paper's glossy box (Dachsbacher et al. 2007,
    Fig. 15): a glossy gold cube (metallic 1, roughness 0.3) turned 30
    degrees on the floor of a closed diffuse room (4 x 3 x 4 m, grey 0.6,
    a red and a green side wall), lit by one spot light from the ceiling
    aimed at the cube. Materials with metallic 0 and roughness 1 are
    Lambertian (README, material model)."""
    g = Gltf("glossy_box")
    grey = g.material("grey", (0.6, 0.6, 0.6))
    red = g.material("red", (0.6, 0.15, 0.12))
    green = g.material("green", (0.15, 0.5, 0.15))
    gold = g.material("gold", (1.0, 0.78, 0.34), metallic=1.0, roughness=0.3)
    x0, x1, y1, z0, z1, n = -2.0, 2.0, 3.0, -2.0, 2.0, 12
    inside = (0.0, 1.5, 0.0)
    walls = (("floor", grey, [(x0, 0, z1), (x1, 0, z1), (x1, 0, z0), (x0, 0, z0)]),
             ("ceiling", grey, [(x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1)]),
             ("back", grey, [(x0, 0, z0), (x1, 0, z0), (x1, y1, z0), (x0, y1, z0)]),
             ("front", grey, [(x1, 0, z1), (x0, 0, z1), (x0, y1, z1), (x1, y1, z1)]),
             ("left", red, [(x0, 0, z1), (x0, 0, z0), (x0, y1, z0), (x0, y1, z1)]),
             ("right", green, [(x1, 0, z0), (x1, 0, z1), (x1, y1, z1), (x1, y1, z0)]))
    for name, mat, q in walls:
        g.node(name, Mesh().quad(*q, n, n, toward=inside), mat)
    half = math.radians(30.0) / 2.0
    g.node("cube", Mesh().box((-0.5, 0.0, -0.5), (0.5, 1.0, 0.5), 6), gold,
           translation=(0.0, 0.0, -0.3), rotation=(0.0, math.sin(half), 0.0, math.cos(half)))
    lamp, aim = (0.6, 2.9, 1.2), (0.0, 0.5, -0.3)
    g.light("spot", "spot", 80.0, lamp, look_at(lamp, aim),
            spot={"innerConeAngle": 0.35, "outerConeAngle": 0.5})
    eye = (0.0, 1.5, 1.9)
    g.camera("camera", eye, look_at(eye, (0.0, 0.6, -0.5)), math.radians(60.0), 0.01)
    g.write(os.path.join(out, "glossy_box.gltf"))


def dynamic_block(out):
    """6 x 6 m floor, back wall, a movable 0.5 m block, a point light and a sun."""
    g = Gltf("dynamic_block")
    floor = g.material("floor", (0.7, 0.7, 0.7))
    wall = g.material("wall", (0.6, 0.6, 0.6))
    block = g.material("block", (0.8, 0.3, 0.2))
    g.node("floor", Mesh().quad((-3, 0, -3), (3, 0, -3), (3, 0, 3), (-3, 0, 3), 32, 32,
                                toward=(0, 1, 0)), floor)
    g.node("back_wall", Mesh().quad((-3, 0, -3), (3, 0, -3), (3, 3, -3), (-3, 3, -3), 32, 16,
                                    toward=(0, 0, 0)), wall)
    # Block origin at its centre; translation puts its bottom face on the floor.
    g.node("block", Mesh().box((-0.25, -0.25, -0.25), (0.25, 0.25, 0.25), 4), block,
           translation=(0.0, 0.25, 0.0))
    g.light("point_light", "point", 30.0, (1.5, 3.0, 1.5))
    sun_dir = normalize((-0.5, -1.0, -0.4))          # down, toward -X and the back wall
    g.light("sun", "directional", 1.0, (0.0, 5.0, 0.0), look_at((0, 0, 0), sun_dir))
    cam = (0.0, 2.5, 5.0)
    g.camera("camera", cam, look_at(cam, (0, 0, 0)), math.radians(45.0), 0.05)
    g.write(os.path.join(out, "dynamic_block.gltf"))


def tube_mesh(base, length, radius, rings, sides):
    """An open tube along +Y from `base` with a capped top: ring r at height
    length * r / (rings - 1), outward normals; the cap's centre vertex last."""
    m = Mesh()
    for r in range(rings):
        y = length * r / (rings - 1)
        for k in range(sides):
            a = 2.0 * math.pi * k / sides
            n = (math.cos(a), 0.0, math.sin(a))
            m.pos.append(add(base, (radius * n[0], y, radius * n[2])))
            m.nrm.append(n)
    for r in range(rings - 1):
        for k in range(sides):
            a, b = r * sides + k, r * sides + (k + 1) % sides
            m.idx.extend((a, a + sides, b, b, a + sides, b + sides))
    top = len(m.pos)
    m.pos.append(add(base, (0.0, length, 0.0)))
    m.nrm.append((0.0, 1.0, 0.0))
    for k in range(sides):
        a, b = (rings - 1) * sides + k, (rings - 1) * sides + (k + 1) % sides
        m.idx.extend((a, top, b))
    return m


def bending_tube(out):
    """A skinned, segmented tube standing in a Cornell box (walls, light and camera
    of cornell_box, no blocks), bending back and forth: issue 18's deforming scene
    after the papers' animated characters.

    The tube (radius 7 cm, 33 cm tall, 16 rings of 20 sides, capped) is skinned to
    three joints along its axis (base, 1/3, 2/3 of the height); each vertex blends
    the two joints around its height linearly (JOINTS_0 / WEIGHTS_0). Animation
    "bend": the middle and upper joints turn about Z by 0, +30, 0, -30, 0 degrees
    at 0, 1, 2, 3, 4 s (LINEAR), so the tube sways left and right every 4 s."""
    g = Gltf("bending_tube")
    cornell_room(g, 12)
    tube = g.material("tube", (0.8, 0.45, 0.15))
    base, length, radius, rings, sides = (0.278, 0.0, 0.30), 0.33, 0.07, 16, 20
    m = tube_mesh(base, length, radius, rings, sides)
    seg = length / 3.0
    joints, weights = [], []
    for p in m.pos:
        h = min(max((p[1] - base[1]) / seg, 0.0), 2.0)   # joint coordinate 0..2
        j = min(int(h), 1)
        t = h - j
        joints.append((j, j + 1, 0, 0))
        weights.append((1.0 - t, t, 0.0, 0.0))
    nodes = g.doc["nodes"]
    mesh = g.deforming_mesh("tube", m, tube, joints, weights)
    # Joint nodes: the root at the tube's base (a scene root), the others its
    # descendants, seg apart; the skinned mesh node stays at the origin (glTF
    # ignores its transform) and its vertices are in world space at bind time.
    first = len(nodes)
    nodes.append({"name": "joint_base", "translation": list(base), "children": [first + 1]})
    nodes.append({"name": "joint_middle", "translation": [0.0, seg, 0.0], "children": [first + 2]})
    nodes.append({"name": "joint_upper", "translation": [0.0, seg, 0.0]})
    g.doc["scenes"][0]["nodes"].append(first)
    ibm = []
    for k in range(3):   # inverse of each joint's bind (world) transform: a translation
        ibm += [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -base[0], -(base[1] + k * seg), -base[2], 1]
    g.doc["skins"] = [{"name": "tube_skin", "joints": [first, first + 1, first + 2],
                       "skeleton": first, "inverseBindMatrices": g.floats(ibm, "MAT4")}]
    nodes.append({"name": "tube", "mesh": mesh, "skin": 0})
    g.doc["scenes"][0]["nodes"].append(len(nodes) - 1)
    times = [0.0, 1.0, 2.0, 3.0, 4.0]
    rot = []
    for deg in (0.0, 30.0, 0.0, -30.0, 0.0):
        h = math.radians(deg) / 2.0
        rot += [0.0, 0.0, round(math.sin(h), 9), round(math.cos(h), 9)]
    g.animation("bend", [(first + 1, "rotation", times, rot), (first + 2, "rotation", times, rot)])
    cornell_light_and_camera(g, 2)
    g.write(os.path.join(out, "bending_tube.gltf"))


def morph_blob(out):
    """A morph-target sphere in a Cornell box (walls, light and camera of
    cornell_box): issue 18's morphing scene.

    The sphere (radius 10 cm, 24 x 16 segments) rests on the floor. Target 0
    "squash" makes it an ellipsoid 1.25 x 0.7 x 1.25 (position and normal deltas,
    the normals exact for the ellipsoid); target 1 "ripple" pushes it out by
    2 cm x cos(4 phi) sin(theta)^2 (positions only). Animation "pulse" drives the
    weights: (0, 0), (1, 0.5), (0, 1), (0, 0) at 0, 1, 2, 3 s (LINEAR)."""
    g = Gltf("morph_blob")
    cornell_room(g, 12)
    blob = g.material("blob", (0.25, 0.45, 0.8))
    r, c, nu, nv = 0.1, (0.30, 0.1, 0.27), 24, 16
    m = Mesh()
    grid = {}
    for j in range(nv + 1):
        theta = math.pi * j / nv
        for i in range(nu + 1):
            if (j in (0, nv)) and i > 0:
                grid[(i, j)] = grid[(0, j)]   # one pole vertex
                continue
            phi = 2.0 * math.pi * i / nu
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            if i == nu:
                grid[(i, j)] = grid[(0, j)]   # the seam closes
                continue
            grid[(i, j)] = len(m.pos)
            m.pos.append(add(c, mul(n, r)))
            m.nrm.append(n)
    for j in range(nv):
        for i in range(nu):
            a, b, d, e = grid[(i, j)], grid[(i + 1, j)], grid[(i, j + 1)], grid[(i + 1, j + 1)]
            if a != b:
                m.idx.extend((a, b, d))
            if d != e:
                m.idx.extend((b, e, d))
    sx, sy = 1.25, 0.7
    squash_p, squash_n, ripple_p = [], [], []
    for p, n in zip(m.pos, m.nrm):
        # The ellipsoid keeps the bottom on the floor: y scales about the sphere's base.
        q = (c[0] + (p[0] - c[0]) * sx, (c[1] - r) + (p[1] - (c[1] - r)) * sy,
             c[2] + (p[2] - c[2]) * sx)
        squash_p.append(sub(q, p))
        squash_n.append(sub(normalize((n[0] / sx, n[1] / sy, n[2] / sx)), n))
        phi = math.atan2(n[2], n[0])
        ripple_p.append(mul(n, 0.02 * math.cos(4.0 * phi) * (1.0 - n[1] * n[1])))
    mesh = g.deforming_mesh("blob", m, blob, targets=[(squash_p, squash_n), (ripple_p, None)],
                            target_names=["squash", "ripple"])
    node = g.node("blob")
    node["mesh"] = mesh
    index = len(g.doc["nodes"]) - 1
    g.animation("pulse", [(index, "weights", [0.0, 1.0, 2.0, 3.0],
                           [0.0, 0.0, 1.0, 0.5, 0.0, 1.0, 0.0, 0.0])])
    cornell_light_and_camera(g, 2)
    g.write(os.path.join(out, "morph_blob.gltf"))


def cornell_orbit(out):
    """`make run` demo script: orbit outside the open front, light loops under the ceiling."""
    x, y, z = CORNELL_LIGHT_T
    loop = [(0, 0), (0.035, -0.035), (0, -0.07), (-0.035, -0.035), (0, 0)]   # diamond, back to start
    keys = [{"frame": f, "translation": [round(x + dx, 4), y, round(z + dz, 4)]}
            for f, (dx, dz) in zip((0, 9, 18, 27, 35), loop)]
    for k in keys:   # whole quad stays inside x, z in 0.15..0.40
        tx, _, tz = k["translation"]
        assert 0.15 <= tx - CORNELL_LIGHT_HALF[0] and tx + CORNELL_LIGHT_HALF[0] <= 0.40
        assert 0.15 <= tz - CORNELL_LIGHT_HALF[1] and tz + CORNELL_LIGHT_HALF[1] <= 0.40
    # The walls are single-sided sheets, so the camera must stay between the side
    # walls' planes (0 < x < 0.5528) or it sees a wall's back: with r = 1.08 that
    # allows +-14 deg around the canonical view (-90 deg), a 28 deg sweep.
    orbit = {"type": "camera_orbit", "target": [0.278, 0.274, 0.28], "radius": 1.08,
             "height": 0.274, "start_deg": -104, "end_deg": -76, "yfov_degrees": 39.3}
    for deg in (orbit["start_deg"], orbit["end_deg"]):
        a, r, (tx, _, tz) = math.radians(deg), orbit["radius"], orbit["target"]
        assert 0.0 < tx + r * math.cos(a) < 0.5528 and tz + r * math.sin(a) < 0.0
    doc = {"scene": "cornell_box", "solver": "direct", "params": {}, "size": [320, 320],
           "format": "jpeg", "frames": 36,
           "tracks": [orbit, {"type": "node_path", "node": "light", "keys": keys}]}
    # Same layout as the documented format: one line per setting, track and key.
    lines = ['  "%s": %s,' % (k, json.dumps(v)) for k, v in doc.items() if k != "tracks"]
    orbit, path = (json.dumps(t) for t in doc["tracks"])
    path = path.replace('"keys": [', '"keys": [\n      ').replace('}, {"frame"', '},\n      {"frame"')
    text = "{\n%s\n  \"tracks\": [\n    %s,\n    %s\n  ]\n}\n" % ("\n".join(lines), orbit, path)
    assert json.loads(text) == doc
    with open(os.path.join(out, "cornell_orbit.json"), "w") as f:
        f.write(text)
    print("cornell_orbit.json     36 frames, light keys at frames 0, 9, 18, 27, 35")


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scenes")
    os.makedirs(out, exist_ok=True)
    for make in (cornell_box, cornell_box_coarse, indirect_room, furnace, glossy_box,
                 dynamic_block, bending_tube, morph_blob, cornell_orbit):
        make(out)


if __name__ == "__main__":
    main()
