#!/usr/bin/env python3
"""Residual against global pass, symmetric vs asymmetric (the paper's Fig. 5),
as an SVG with the standard library only. The numbers are the frame stats
residual_1... of

  gistream render --scene SCENE --solver antiradiance --param iterations=16 ...
  gistream render --scene SCENE --solver antiradiance --param scheme=asymmetric --param iterations=3 ...

at 64x64 (docs/RESULTS.md, antiradiance, Convergence)."""
import math

DATA = {
    "cornell_box symmetric": ("#1f77b4", "", [1.56013, 0.753828, 0.333628, 0.13272, 0.0602552, 0.0269757, 0.0129457,
                                              0.00606954, 0.00297265, 0.00142066, 0.000700945, 0.000339003,
                                              0.00016785, 8.19043e-05, 4.06673e-05, 1.99844e-05]),
    "cornell_box asymmetric": ("#d62728", "", [0.990229, 0.141863, 0.00623954, 0.000212006, 0.50285, 0.487833,
                                               0.0688297, 0.0035827, 0.000218195, 0.238962, 0.24046, 0.0367499,
                                               0.00195777, 9.18805e-05, 0.120377]),
    "indirect_room symmetric": ("#1f77b4", "6,4", [1.75677, 1.23057, 0.708079, 0.43616, 0.272687, 0.177576, 0.116275,
                                                   0.0766225, 0.0504765, 0.0333346, 0.0220203, 0.0145651,
                                                   0.00963981, 0.00638632, 0.00423408, 0.00280964]),
    "indirect_room asymmetric": ("#d62728", "6,4", [1.06506, 0.0951074, 0.00138829, 6.08981e-05, 0.641934, 0.680352,
                                                    0.0617583, 0.000690148, 0.406823, 0.437896, 0.044448,
                                                    0.000497246, 0.261383]),
}
W, H, L, R, T, B = 640, 400, 70, 200, 20, 50
LO, HI = -5.0, 1.0  # log10 range


def xy(i, v):
    x = L + (i - 1) / 15.0 * (W - L - R)
    y = T + (HI - math.log10(max(v, 10 ** LO))) / (HI - LO) * (H - T - B)
    return x, y


out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
       f'<rect width="{W}" height="{H}" fill="white"/>']
for e in range(int(LO), int(HI) + 1):
    _, y = xy(1, 10 ** e)
    out.append(f'<line x1="{L}" y1="{y:.1f}" x2="{W - R}" y2="{y:.1f}" stroke="#ddd"/>')
    out.append(f'<text x="{L - 8}" y="{y + 4:.1f}" text-anchor="end">1e{e}</text>')
for i in range(1, 17, 3):
    x, _ = xy(i, 1)
    out.append(f'<text x="{x:.1f}" y="{H - B + 18}" text-anchor="middle">{i}</text>')
out.append(f'<text x="{(L + W - R) / 2}" y="{H - 10}" text-anchor="middle">global pass</text>')
out.append(f'<text x="15" y="{(T + H - B) / 2}" transform="rotate(-90 15 {(T + H - B) / 2})" '
           'text-anchor="middle">residual |dI_ex| / |I_ex(0)|</text>')
for k, (name, (colour, dash, values)) in enumerate(DATA.items()):
    pts = " ".join(f"{x:.1f},{y:.1f}" for x, y in (xy(i + 1, v) for i, v in enumerate(values)))
    d = f' stroke-dasharray="{dash}"' if dash else ""
    out.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="2"{d}/>')
    ly = T + 20 + 20 * k
    out.append(f'<line x1="{W - R + 10}" y1="{ly}" x2="{W - R + 40}" y2="{ly}" stroke="{colour}" stroke-width="2"{d}/>')
    out.append(f'<text x="{W - R + 45}" y="{ly + 4}">{name}</text>')
out.append("</svg>")
with open(__file__.replace("convergence_plot.py", "convergence.svg"), "w") as f:
    f.write("\n".join(out) + "\n")
