"""How much of the light a glossy object reflects into the room each
solver delivers (issue 29, item 6), against `pathtrace`.

Renders SCENE (default scenes/glossy_box.gltf) and a copy with MATERIAL
(default gold) made black and Lambertian, at SIZE px, with each solver at
its defaults and `pathtrace` at SPP. The room is every pixel that is not
the object (not black in the path-traced black copy). Prints per solver:
the object's contribution (glossy - black, summed over the room) over the
reference's, the room's mean luminance over the reference's, and the same
contribution in 4 x 4 image blocks.

    python3 docs/bench/glossy_room.py [--size 64] [--spp 4096] [--solvers a,b] [--out DIR]
                                      [--param KEY=VALUE]...  (every solver but pathtrace)

Needs build/gistreamd, build/gistream and oiiotool (images are read as
FITS, so no numpy is needed)."""
import argparse
import json
import os
import struct
import subprocess
import sys

sys.path.insert(0, os.path.dirname(__file__))
from local_server import local_gistreamd  # noqa: E402


def read_fits(path):
    """Rows top first of (r, g, b) from oiiotool's float FITS."""
    data = open(path, "rb").read()
    keys, i = {}, 0
    while True:
        card = data[i:i + 80].decode("latin1")
        i += 80
        if card[:8].strip() == "END":
            break
        if card[8:10] == "= ":
            keys[card[:8].strip()] = card[10:].split("/")[0].strip()
    c, w, h = int(keys["NAXIS1"]), int(keys["NAXIS2"]), int(keys["NAXIS3"])
    vals = struct.unpack(">%df" % (c * w * h), data[len(data) - 4 * c * w * h:])
    rows = [[vals[(y * w + x) * c:(y * w + x) * c + 3] for x in range(w)] for y in range(h)]
    return rows[::-1]  # FITS rows are bottom-up


def lum(p):
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", default="scenes/glossy_box.gltf")
    ap.add_argument("--material", default="gold")
    ap.add_argument("--size", type=int, default=64)
    ap.add_argument("--spp", type=int, default=4096)
    ap.add_argument("--solvers", default="sh_probes,avg,implicit_visibility,antiradiance")
    ap.add_argument("--out", default="out/glossy_room")
    ap.add_argument("--param", action="append", default=[],
                    help="KEY=VALUE for every solver but pathtrace (repeatable)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    doc = json.load(open(args.scene))
    for m in doc["materials"]:
        if m.get("name") == args.material:
            m["pbrMetallicRoughness"] = {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0,
                                         "roughnessFactor": 1}
    black = os.path.join(args.out, "black.gltf")
    json.dump(doc, open(black, "w"))
    variants = {"glossy": args.scene, "black": black}
    solvers = args.solvers.split(",")
    with local_gistreamd() as (address, _):
        def render(variant, solver, params):
            exr = os.path.join(args.out, "%s_%s.exr" % (solver, variant))
            cmd = ["build/gistream", "--server", address, "render", "--scene", variants[variant],
                   "--solver", solver, "--size", "%dx%d" % (args.size, args.size), "--format",
                   "exr", "--out", exr]
            for p in params:
                cmd += ["--param", p]
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
            fits = exr[:-4] + ".fits"
            subprocess.run(["oiiotool", exr, "-d", "float", "-o", fits], check=True)
            return read_fits(fits)
        images = {}
        for v in variants:
            images[("pathtrace", v)] = render(v, "pathtrace", ["spp=%d" % args.spp])
            for s in solvers:
                images[(s, v)] = render(v, s, args.param)
    n = args.size
    room = [[lum(images[("pathtrace", "black")][y][x]) > 0 for x in range(n)] for y in range(n)]

    def sums(solver):
        g, b = images[(solver, "glossy")], images[(solver, "black")]
        blocks = [[0.0] * 4 for _ in range(4)]
        total = mean = count = 0
        for y in range(n):
            for x in range(n):
                if not room[y][x]:
                    continue
                d = lum(g[y][x]) - lum(b[y][x])
                blocks[y * 4 // n][x * 4 // n] += d
                total += d
                mean += lum(g[y][x])
                count += 1
        return total, mean / max(count, 1), blocks

    ref_total, ref_mean, ref_blocks = sums("pathtrace")
    print("room: %d of %d pixels; the object's contribution is %.1f %% of the room's light" %
          (sum(map(sum, room)), n * n, 100 * ref_total / (ref_mean * sum(map(sum, room)))))
    print("| solver | object's light (x reference) | room mean (x reference) | 4 x 4 blocks (x reference) |")
    print("|---|---|---|---|")
    for s in solvers:
        total, mean, blocks = sums(s)
        cells = " / ".join(" ".join("%.2f" % (blocks[i][j] / ref_blocks[i][j]
                                              if abs(ref_blocks[i][j]) > 1e-9 else 0)
                                    for j in range(4)) for i in range(4))
        print("| %s | %.3f | %.3f | %s |" % (s, total / ref_total, mean / ref_mean, cells))


if __name__ == "__main__":
    main()
