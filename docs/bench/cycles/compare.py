#!/usr/bin/env python3
"""gistream's pathtrace against Cycles, within noise (issue 29).

  compare.py GISTREAM.exr GISTREAM_OTHER_SEED.exr CYCLES.exr [BLOCKS]

Prints the mean ratio gistream / Cycles per channel over the picture, the
luminance ratio per block (BLOCKS x BLOCKS, default 8), and the same
figures between the two gistream renders, which differ by noise only: a
difference between the renderers is within noise when it is no larger
than that one (relMSE, and the spread of the blocks' ratios). Needs
oiiotool (OpenImageIO's tools); no numpy.
"""
import array
import math
import os
import subprocess
import sys
import tempfile


def load(path):
    """(width, height, rows of RGB floats, top row first)."""
    with tempfile.TemporaryDirectory() as tmp:
        fits = os.path.join(tmp, "image.fits")
        subprocess.run(["oiiotool", path, "--ch", "R,G,B", "-d", "float", "-o", fits],
                       check=True)
        data = open(fits, "rb").read()
    cards = [data[i:i + 80].decode() for i in range(0, 2880, 80)]
    key = lambda k: int(next(c for c in cards if c.startswith(k)).split("=")[1].split("/")[0])
    w, h = key("NAXIS2"), key("NAXIS3")
    a = array.array("f")
    a.frombytes(data[2880:2880 + w * h * 12])
    a.byteswap()  # FITS is big-endian
    return w, h, [a[(h - 1 - y) * w * 3:(h - y) * w * 3] for y in range(h)]


def rel_mse(a, b):
    """Mean over pixels and channels of (a - b)^2 / (b^2 + 0.01)."""
    _, _, ra = a
    w, h, rb = b
    total = 0.0
    for y in range(h):
        for i in range(w * 3):
            total += (ra[y][i] - rb[y][i]) ** 2 / (rb[y][i] ** 2 + 0.01)
    return total / (w * h * 3)


def channel_means(img):
    w, h, rows = img
    return [sum(rows[y][x * 3 + c] for y in range(h) for x in range(w)) / (w * h)
            for c in range(3)]


def block_ratios(a, b, n):
    w, h, ra = a
    _, _, rb = b
    bw, bh = w // n, h // n
    out = []
    for by in range(n):
        row = []
        for bx in range(n):
            sa = sb = 0.0
            for y in range(by * bh, (by + 1) * bh):
                for x in range(bx * bw, (bx + 1) * bw):
                    sa += sum(ra[y][x * 3:x * 3 + 3])
                    sb += sum(rb[y][x * 3:x * 3 + 3])
            row.append(sa / sb if sb > 0 else float("nan"))
        out.append(row)
    return out


def spread(blocks):
    """RMS of (ratio - 1) over the blocks."""
    values = [r for row in blocks for r in row if not math.isnan(r)]
    return math.sqrt(sum((r - 1) ** 2 for r in values) / max(len(values), 1))


def main():
    gistream, other, cycles = (load(p) for p in sys.argv[1:4])
    n = int(sys.argv[4]) if len(sys.argv) > 4 else 8
    mg, mc = channel_means(gistream), channel_means(cycles)
    ratio = [a / b if b > 0 else float("nan") for a, b in zip(mg, mc)]
    noise_blocks = block_ratios(gistream, other, n)
    blocks = block_ratios(gistream, cycles, n)
    print("mean ratio gistream / cycles (R G B): " + " ".join(f"{r:.4f}" for r in ratio))
    print(f"relMSE gistream vs cycles {rel_mse(gistream, cycles):.4g}, "
          f"gistream vs gistream (other seed) {rel_mse(gistream, other):.4g}")
    print(f"blocks' ratio RMS off 1: vs cycles {spread(blocks):.4f}, "
          f"vs other seed {spread(noise_blocks):.4f}")
    print(f"luminance ratio gistream / cycles per block ({n}x{n}, top row first):")
    for row in blocks:
        print(" ".join(f"{r:.3f}" for r in row))


if __name__ == "__main__":
    main()
