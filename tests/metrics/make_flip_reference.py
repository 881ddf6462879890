#!/usr/bin/python3
"""Independent reference values for fovlab's LDR-FLIP (metrics/flip.cpp).

Written straight from the equations of Andersson, Nilsson, Akenine-Moeller, Oskarsson, Astrom,
Fairchild, "FLIP: A Difference Evaluator for Alternating Images", Proc. ACM Comput. Graph.
Interact. Tech. 3(2), article 15, 2020 (with the erratum on research.nvidia.com: the achromatic
channel is normalised by division by 116, not 100), and deliberately built differently from the
C++ code: full two-dimensional kernels applied with scipy.ndimage.correlate (mode 'nearest' =
replicated borders) instead of separable passes, matrices inverted by numpy, and the whole
pipeline vectorised. Only NumPy and SciPy are used; no FLIP package.

Run:  /usr/bin/python3 tests/metrics/make_flip_reference.py \
          > tests/metrics/flip_reference.inc
"""
import math
import sys

import numpy as np
import scipy
from scipy import ndimage

# ---- constants (where in the paper, after each) --------------------------------------------
# sRGB <-> linear (IEC 61966-2-1), linear sRGB -> XYZ (D65) as exact fractions.
M_RGB2XYZ = np.array([
    [10135552 / 24577794, 8788810 / 24577794, 4435075 / 24577794],
    [2613072 / 12288897, 8788810 / 12288897, 887015 / 12288897],
    [1425312 / 73733382, 8788810 / 73733382, 70074185 / 73733382],
])
M_XYZ2RGB = np.linalg.inv(M_RGB2XYZ)
WHITE = M_RGB2XYZ @ np.ones(3)  # XYZ of linear RGB (1, 1, 1): the reference white
# CSF parameters (a1, b1, a2, b2) of the three opponent channels (paper, spatial filtering, table).
CSF = {
    "A": (1.0, 0.0047, 0.0, 1e-5),
    "RG": (1.0, 0.0053, 0.0, 1e-5),
    "BY": (34.1, 0.04, 13.5, 0.025),
}
QC = 0.7     # colour exponent (paper)
PC = 0.4     # redistribution break point, fraction of cmax (paper)
PT = 0.95    # error assigned at the break point (paper)
W_DEG = 0.082  # edge/point detector: peak-to-trough width in degrees (paper)
QF = 0.5     # feature exponent (paper)


def srgb_to_linear(v):
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def to_xyz(rgb_lin):  # (..., 3)
    return rgb_lin @ M_RGB2XYZ.T


def xyz_to_ycxcz(xyz):
    n = xyz / WHITE
    return np.stack([116 * n[..., 1] - 16, 500 * (n[..., 0] - n[..., 1]), 200 * (n[..., 1] - n[..., 2])], -1)


def ycxcz_to_xyz(o):
    y = (o[..., 0] + 16) / 116
    return np.stack([y + o[..., 1] / 500, y, y - o[..., 2] / 200], -1) * WHITE


def xyz_to_lab(xyz):
    d = 6 / 29
    t = xyz / WHITE
    f = np.where(t > d ** 3, np.cbrt(t), t / (3 * d * d) + 4 / 29)
    return np.stack([116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]), 200 * (f[..., 1] - f[..., 2])], -1)


def hunt(lab):
    return np.stack([lab[..., 0], 0.01 * lab[..., 0] * lab[..., 1], 0.01 * lab[..., 0] * lab[..., 2]], -1)


def hyab(p, q):
    d = p - q
    return np.abs(d[..., 0]) + np.hypot(d[..., 1], d[..., 2])


def csf_kernel(ppd, channel):
    a1, b1, a2, b2 = CSF[channel]
    b_max = max(max(v[1], v[3]) for v in CSF.values())
    r = int(math.ceil(3 * math.sqrt(b_max / (2 * math.pi ** 2)) * ppd))
    g = np.arange(-r, r + 1) / ppd
    x, y = np.meshgrid(g, g)
    d2 = x * x + y * y
    s = a1 * math.sqrt(math.pi / b1) * np.exp(-math.pi ** 2 * d2 / b1)
    if a2 != 0.0:
        s = s + a2 * math.sqrt(math.pi / b2) * np.exp(-math.pi ** 2 * d2 / b2)
    return s / s.sum()


def detector_kernel(ppd, point):
    sd = 0.5 * W_DEG * ppd
    r = int(math.ceil(3 * sd))
    x, y = np.meshgrid(np.arange(-r, r + 1, dtype=float), np.arange(-r, r + 1, dtype=float))
    g = np.exp(-(x * x + y * y) / (2 * sd * sd))
    k = (x * x / (sd * sd) - 1) * g if point else -x * g
    pos, neg = k[k > 0].sum(), -k[k < 0].sum()
    return np.where(k > 0, k / pos, np.where(k < 0, k / neg, 0.0))


def correlate(img2d, kernel):
    return ndimage.correlate(img2d, kernel, mode="nearest")


def cmax():
    g = hunt(xyz_to_lab(to_xyz(np.array([0.0, 1.0, 0.0]))))
    b = hunt(xyz_to_lab(to_xyz(np.array([0.0, 0.0, 1.0]))))
    return hyab(g, b) ** QC


def flip(ref_srgb, test_srgb, ppd):
    c_max = cmax()
    outs = []
    opp = [xyz_to_ycxcz(to_xyz(srgb_to_linear(im))) for im in (ref_srgb, test_srgb)]
    pre = []
    for o in opp:
        f = np.stack([correlate(o[..., i], csf_kernel(ppd, ch)) for i, ch in enumerate(("A", "RG", "BY"))], -1)
        lin = np.clip(ycxcz_to_xyz(f) @ M_XYZ2RGB.T, 0.0, 1.0)
        pre.append(hunt(xyz_to_lab(to_xyz(lin))))
    e = hyab(pre[0], pre[1]) ** QC
    pcc = PC * c_max
    color = np.where(e < pcc, PT / pcc * e, PT + (e - pcc) / (c_max - pcc) * (1 - PT))
    mags = []
    for o in opp:
        yn = (o[..., 0] + 16) / 116
        m = {}
        for name, point in (("edge", False), ("point", True)):
            k = detector_kernel(ppd, point)
            m[name] = np.hypot(correlate(yn, k), correlate(yn, k.T))
        mags.append(m)
    fd = np.maximum(np.abs(mags[0]["edge"] - mags[1]["edge"]), np.abs(mags[0]["point"] - mags[1]["point"]))
    feature = (fd / math.sqrt(2)) ** QF
    return color ** (1 - feature), color, feature


# ---- the synthetic image pairs (the C++ test builds the same ones) --------------------------
W, H = 24, 20


def code(v):
    """An 8-bit code value as the float the C++ test stores: float(k / 255.0), then widened."""
    return float(np.float32(v / 255.0))


def img(fn):
    a = np.zeros((H, W, 3))
    for y in range(H):
        for x in range(W):
            for c in range(3):
                a[y, x, c] = fn(x, y, c)
    return a


def pattern(x, y, c):
    return code((x * 37 + y * 91 + c * 53 + ((x * y) % 7) * 11) % 256)


def pattern_patched(x, y, c):
    if 4 <= x < 10 and 3 <= y < 8:
        return code((x * 13 + y * 29 + c * 71) % 256)
    return pattern(x, y, c)


def checker(x, y, c):
    return 1.0 if (x + y) % 2 == 0 else 0.0


def grey_half(x, y, c):
    return 0.5


def red(x, y, c):
    return 1.0 if c == 0 else 0.0


def red_with_green_square(x, y, c):
    if 9 <= x < 15 and 7 <= y < 13:
        return 1.0 if c == 1 else 0.0
    return red(x, y, c)


def step(at):
    return lambda x, y, c: code(200) if x >= at else code(40)


CASES = [
    # name, reference, test, ppd
    ("pattern_patch_67ppd", pattern, pattern_patched, 67.0),
    ("pattern_patch_10ppd", pattern, pattern_patched, 10.0),
    ("checker_vs_grey_20ppd", checker, grey_half, 20.0),
    ("checker_vs_grey_67ppd", checker, grey_half, 67.0),
    ("red_green_square_30ppd", red, red_with_green_square, 30.0),
    ("step_shift_40ppd", step(11), step(12), 40.0),
]
PIXELS = [(0, 0), (5, 4), (9, 7), (12, 10), (23, 19), (11, 15)]


def main():
    print("// Generated by tests/metrics/make_flip_reference.py -- do not edit; regenerate with")
    print("//   /usr/bin/python3 tests/metrics/make_flip_reference.py > "
          "tests/metrics/flip_reference.inc")
    print(f"// Python {sys.version.split()[0]}, NumPy {np.__version__}, SciPy {scipy.__version__}: an independent")
    print("// re-implementation of LDR-FLIP from the paper's equations (2-D kernels, scipy.ndimage.correlate with")
    print("// replicated borders). Image pairs: 24x20, defined in the script and rebuilt by flip_test.cpp.")
    print(f"constexpr double kReferenceCmax = {cmax():.17g};  // HyAB(Hunt(green), Hunt(blue))^qc")
    print("// {case, pixels_per_degree, mean FLIP, {x, y, FLIP at (x, y)} x 6}")
    print("const FlipReferenceCase kFlipReference[] = {")
    for name, rf, tf, ppd in CASES:
        err, _, _ = flip(img(rf), img(tf), ppd)
        px = ", ".join(f"{{{x}, {y}, {err[y, x]:.17g}}}" for x, y in PIXELS)
        print(f"    {{\"{name}\", {ppd!r}, {err.mean():.17g}, {{{px}}}}},")
    print("};")


if __name__ == "__main__":
    main()
