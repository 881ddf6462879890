#!/usr/bin/env python3
"""An independent check of fovlab's four sampling models (Ye et al. 2022, sections 3 and 5.1).

Pure Python (no numpy): the sample positions and the sampling density of RMFR, KFR, the hyperbolic
layers and the linear fall-off are computed here from the papers' equations, and compared with what
`fovlab render` writes for the same display and gaze:
  --density-out D.exr  fovlab's CPU density, stored as grey g = clamp(1 + log2(density) / 8, 0, 1)
  --mask-out M.exr     the GPU's listed samples, binned into the pixel holding each (white: >= 1)
  --stats-json S.json  the samples the GPU shaded.
Reported per model and case: the largest relative density difference where the grey is not clamped,
the pixels whose occupancy differs, and the shaded counts.

Equations (written from the papers, not from fovlab's source):
  RMFR (Ye et al. 2022, eq. 3-7, per axis, in shares of the screen; X = x / W, gaze c, phi = f / W):
    g(t) = phi t / (phi + t); buffer to screen: U >= c: X = c + g^-1((U - c) / (1 - c) g(1 - c)),
    else X = c - g^-1((c - U) / c g(c)), g^-1(s) = phi s / (phi - s); buffer w = round(W / sigma).
    Density: (w / W) dU/dX (h / H) dV/dY with U(X) the forward map (eq. 4 with the gaze, not the
    pixel, divided by W), differentiated here numerically.
  KFR (Meng et al. 2018, as Ye et al. 2022 section 5.1 sets it): u = w (ln r / L)^alpha,
    v = h theta / 2 pi, L = ln(largest gaze-to-corner distance); the density is the Jacobian
    |du dv / dx dy|, computed here by finite differences of the forward map.
  Hyperbolic (Guenter et al. 2012; Ye et al. 2022 section 5.1): pixel sizes 1, 2, s3 within
    r1 = 10, r2 = 20 degrees and beyond; density 1 / s^2 of the zone.
  Linear (Weier et al. 2016; Ye et al. 2022 section 5.1): p = 1 up to r1, linear to p_min at r2.
  Eccentricity: the angle at the eye between the rays to the gaze and to the pixel centre, the
  eye on the display's axis at the viewing distance.
Where the papers are silent, fovlab's documented decisions (docs/foveation.md) are taken as stated
there: which KFR and hyperbolic samples are shaded (within a spacing / two layer pixels of where
they are read), the hyperbolic grids aligned to multiples of their pixel size, the linear model's
per-pixel thresholds (lowbias32 hash).

Usage: python3 scripts/bench/check_sampling_positions.py [--fovlab build/release/fovlab] [--out DIR]
Exit status 1 when a difference exceeds its tolerance.
"""
import argparse
import json
import math
import os
import struct
import subprocess
import sys
import zlib

# --- A minimal OpenEXR reader: one part, scanlines, FLOAT channels, NONE or ZIP(S) compression ---------


def read_exr(path):
    data = open(path, "rb").read()
    if data[:4] != b"\x76\x2f\x31\x01":
        raise SystemExit(f"{path}: not an OpenEXR file")
    pos = 8
    header = {}
    while data[pos] != 0:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        pos = end + 1
        end = data.index(b"\0", pos)
        kind = data[pos:end].decode()
        pos = end + 1
        (size,) = struct.unpack_from("<i", data, pos)
        pos += 4
        header[name] = (kind, data[pos:pos + size])
        pos += size
    pos += 1
    channels = []
    raw = header["channels"][1]
    i = 0
    while raw[i] != 0:
        end = raw.index(b"\0", i)
        name = raw[i:end].decode()
        (pixel_type,) = struct.unpack_from("<i", raw, end + 1)
        if pixel_type != 2:
            raise SystemExit(f"{path}: channel {name} is not FLOAT")
        channels.append(name)
        i = end + 1 + 16
    compression = header["compression"][1][0]
    xmin, ymin, xmax, ymax = struct.unpack("<4i", header["dataWindow"][1])
    width, height = xmax - xmin + 1, ymax - ymin + 1
    lines = {0: 1, 2: 1, 3: 16}.get(compression)
    if lines is None:
        raise SystemExit(f"{path}: compression {compression} not supported (NONE, ZIPS, ZIP only)")
    chunks = (height + lines - 1) // lines
    offsets = struct.unpack_from(f"<{chunks}Q", data, pos)
    values = {name: [0.0] * (width * height) for name in channels}
    for offset in offsets:
        y, size = struct.unpack_from("<ii", data, offset)
        block = data[offset + 8:offset + 8 + size]
        rows = min(lines, ymax + 1 - y)
        expected = rows * width * 4 * len(channels)
        if compression != 0 and size < expected:
            t = zlib.decompress(block)
            d = bytearray(len(t))
            previous = t[0]
            d[0] = previous
            for k in range(1, len(t)):
                previous = (previous + t[k] - 128) & 0xFF
                d[k] = previous
            half = (len(d) + 1) // 2
            out = bytearray(len(d))
            out[0::2] = d[:half]
            out[1::2] = d[half:]
            block = bytes(out)
        floats = struct.unpack(f"<{len(block) // 4}f", block)
        k = 0
        for row in range(rows):
            base = (y - ymin + row) * width
            for name in channels:
                values[name][base:base + width] = floats[k:k + width]
                k += width
    return width, height, values[channels[0]]


# --- Display geometry ----------------------------------------------------------------------------------


class Display:
    def __init__(self, width_px, height_px, width_mm, height_mm, distance_mm):
        self.width_px, self.height_px = width_px, height_px
        self.pitch_x, self.pitch_y = width_mm / width_px, height_mm / height_px
        self.distance = distance_mm

    def direction(self, x, y):
        v = ((x - self.width_px / 2) * self.pitch_x, (y - self.height_px / 2) * self.pitch_y, self.distance)
        n = math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
        return v[0] / n, v[1] / n, v[2] / n

    def eccentricity_deg(self, gaze, x, y):
        a, b = self.direction(*gaze), self.direction(x, y)
        dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
        cx = a[1] * b[2] - a[2] * b[1]
        cy = a[2] * b[0] - a[0] * b[2]
        cz = a[0] * b[1] - a[1] * b[0]
        return math.degrees(math.atan2(math.sqrt(cx * cx + cy * cy + cz * cz), dot))


def diagonal_display(width_px, height_px, diagonal_in, distance_mm):
    pitch = diagonal_in * 25.4 / math.hypot(width_px, height_px)
    return Display(width_px, height_px, pitch * width_px, pitch * height_px, distance_mm)


# --- The models, from the papers -----------------------------------------------------------------------


def rmfr_axis(c, phi):
    def g(t):
        return phi * t / (phi + t)

    def g_inverse(s):
        return phi * s / (phi - s)

    def to_buffer(x):  # eq. 4, with the gaze share c (the printed x / W is a typo)
        d = x - c
        return c + (1 - c) * g(d) / g(1 - c) if d >= 0 else c - c * g(-d) / g(c)

    def to_screen(u):  # eq. 6-7
        return c + g_inverse((u - c) / (1 - c) * g(1 - c)) if u >= c else c - g_inverse((c - u) / c * g(c))

    return to_buffer, to_screen


def rmfr_model(display, gaze, sigma, fx, fy):
    W, H = display.width_px, display.height_px
    w, h = max(1, round(W / sigma)), max(1, round(H / sigma))
    clamp = lambda s: min(max(s, 0.01), 0.99)  # the authors' code clamps the gaze share
    fwd_x, inv_x = rmfr_axis(clamp(gaze[0] / W), fx)
    fwd_y, inv_y = rmfr_axis(clamp(gaze[1] / H), fy)

    def slope(f, x, n):  # numerical derivative, in shares
        e = 1e-6
        return (f(min(x + e, 1.0)) - f(max(x - e, 0.0))) / (min(x + e, 1.0) - max(x - e, 0.0))

    column_slope = [slope(fwd_x, (x + 0.5) / W, W) * w / W for x in range(W)]
    row_slope = [slope(fwd_y, (y + 0.5) / H, H) * h / H for y in range(H)]
    density = lambda x, y: column_slope[x] * row_slope[y]
    xs = [inv_x((u + 0.5) / w) * W for u in range(w)]
    ys = [inv_y((v + 0.5) / h) * H for v in range(h)]
    positions = [(x, y) for y in ys for x in xs]
    return density, positions, w * h


def kfr_model(display, gaze, sigma, alpha):
    W, H = display.width_px, display.height_px
    w, h = max(1, round(W / sigma)), max(1, round(H / sigma))
    L = math.log(max(math.hypot(cx - gaze[0], cy - gaze[1]) for cx in (0, W) for cy in (0, H)))

    def forward(x, y):
        r = max(math.hypot(x - gaze[0], y - gaze[1]), 1.0)
        theta = math.atan2(y - gaze[1], x - gaze[0]) % (2 * math.pi)
        return w * (math.log(r) / L) ** alpha, h * theta / (2 * math.pi)

    def density(x, y):  # |Jacobian| of the forward map, by central differences of u and theta
        px, py = x + 0.5, y + 0.5
        r = math.hypot(px - gaze[0], py - gaze[1])
        if r <= 1.0 + 1e-3 or math.log(r) >= L:
            return None  # undefined within a pixel of the gaze (fovlab: 0) and beyond the disc
        e = 1e-4
        du_dr = (w * (math.log(r + e) / L) ** alpha - w * (math.log(r - e) / L) ** alpha) / (2 * e)
        return du_dr * (h / (2 * math.pi)) / r  # polar: dx dy = r dr dtheta

    def to_screen(u, v):
        r = math.exp(L * (u / w) ** (1 / alpha))
        a = 2 * math.pi * v / h
        return gaze[0] + r * math.cos(a), gaze[1] + r * math.sin(a), r

    positions, shaded = [], 0
    for v in range(h):
        for u in range(w):
            x, y, r = to_screen(u + 0.5, v + 0.5)
            s = (u + 0.5) / w
            radial = r * L * s ** (1 / alpha - 1) / (alpha * w)  # dr/du
            margin = radial + 2 * math.pi * r / h  # fovlab's rule: within a radial + tangential spacing
            if -margin <= x < W + margin and -margin <= y < H + margin:
                shaded += 1
                positions.append((x, y))
    return density, positions, shaded, forward


def hyperbolic_model(display, gaze, s2, s3, r1, r2, band):
    W, H = display.width_px, display.height_px
    ecc = lambda x, y: display.eccentricity_deg(gaze, x, y)

    def density(x, y):
        e = ecc(x + 0.5, y + 0.5)
        s = 1.0 if e < r1 else s2 if e < r2 else s3
        return 1.0 / (s * s)

    def box(radius, margin):  # screen points within `radius` degrees, grown by margin, on the screen
        xs, ys = [gaze[0]], [gaze[1]]
        far = 4.0 * (W + H)
        for k in range(128):
            a = 2 * math.pi * k / 128
            cx, cy = math.cos(a), math.sin(a)
            lo, hi = 0.0, far
            if ecc(gaze[0] + cx * far, gaze[1] + cy * far) <= radius:
                lo = far
            else:
                for _ in range(48):
                    mid = 0.5 * (lo + hi)
                    if ecc(gaze[0] + cx * mid, gaze[1] + cy * mid) <= radius:
                        lo = mid
                    else:
                        hi = mid
            xs.append(gaze[0] + cx * lo)
            ys.append(gaze[1] + cy * lo)
        m = margin + 1.0
        return max(0.0, min(xs) - m), max(0.0, min(ys) - m), min(W, max(xs) + m), min(H, max(ys) + m)

    def grid(b, s):
        if b[2] <= b[0] or b[3] <= b[1]:
            return 0, 0, 0, 0
        ox, oy = math.floor(b[0] / s) * s, math.floor(b[1] / s) * s
        return ox, oy, math.ceil((b[2] - ox) / s), math.ceil((b[3] - oy) / s)

    layers = [(1.0, grid(box(r1, 2.0), 1.0), 0.0, r1), (s2, grid(box(r2, 2 * s2), s2), r1 - band, r2),
              (s3, grid((0.0, 0.0, W, H), s3), r2 - band, 180.0)]

    def along(x, y, d):
        dx, dy = x - gaze[0], y - gaze[1]
        n = math.hypot(dx, dy)
        if n == 0:
            return x + max(d, 0.0), y
        k = max(0.0, n + d) / n
        return gaze[0] + dx * k, gaze[1] + dy * k

    positions = []
    for s, (ox, oy, columns, rows), lo, hi in layers:
        for row in range(rows):
            for column in range(columns):
                x, y = ox + (column + 0.5) * s, oy + (row + 0.5) * s
                if ecc(*along(x, y, -2 * s)) <= hi and ecc(*along(x, y, 2 * s)) >= lo:
                    positions.append((x, y))
    return density, positions, len(positions)


def lowbias32(x):
    x &= 0xFFFFFFFF
    x ^= x >> 16
    x = (x * 0x7FEB352D) & 0xFFFFFFFF
    x ^= x >> 15
    x = (x * 0x846CA68B) & 0xFFFFFFFF
    x ^= x >> 16
    return x


def linear_model(display, gaze, p_min, r1, r2, seed=0):
    def probability(x, y):
        e = display.eccentricity_deg(gaze, x + 0.5, y + 0.5)
        return 1.0 if e <= r1 else p_min if e >= r2 else 1.0 - (1.0 - p_min) * (e - r1) / (r2 - r1)

    positions = []
    base = lowbias32(0 + lowbias32(seed))  # frame 0
    for y in range(display.height_px):
        row = lowbias32(y + base)
        for x in range(display.width_px):
            if (lowbias32(x + row) >> 8) / 16777216.0 < probability(x, y):
                positions.append((x + 0.5, y + 0.5))
    return probability, positions, len(positions)


# --- Comparison ----------------------------------------------------------------------------------------


def grey(density):
    if density is None or not density > 0:
        return 0.0
    return min(max(1.0 + math.log2(density) / 8.0, 0.0), 1.0)


def compare(name, display, density, positions, shaded, out, render):
    W, H = display.width_px, display.height_px
    _, _, fov_grey = read_exr(render["density"])
    _, _, fov_mask = read_exr(render["mask"])
    stats = json.load(open(render["stats"]))
    worst, worst_at, clamped_disagree, compared = 0.0, None, 0, 0
    for y in range(H):
        for x in range(W):
            mine = density(x, y)
            g_fov = fov_grey[y * W + x]
            if mine is None:
                continue
            g_mine = grey(mine)
            inside = 2 ** -8 * 1.001 < mine < 0.999
            if not inside:
                if abs(g_mine - g_fov) > 1e-3:
                    clamped_disagree += 1
                continue
            compared += 1
            theirs = 2.0 ** (8.0 * (g_fov - 1.0))
            diff = abs(theirs / mine - 1.0)
            if diff > worst:
                worst, worst_at = diff, (x, y)
    # A position within 1e-3 px of a pixel edge (a centred gaze puts the middle sample exactly on
    # one) may land on either side in the GPU's float32: both pixels are accepted there.
    occupied = bytearray(W * H)
    either = set()
    for x, y in positions:
        ix, iy = math.floor(x), math.floor(y)
        if 0 <= ix < W and 0 <= iy < H:
            occupied[iy * W + ix] = 1
        near_x = {math.floor(x - 1e-3), math.floor(x + 1e-3)}
        near_y = {math.floor(y - 1e-3), math.floor(y + 1e-3)}
        if len(near_x) > 1 or len(near_y) > 1:
            either.update((a, b) for a in near_x for b in near_y)
    occupancy_differs = sum(1 for p in range(W * H)
                            if occupied[p] != (fov_mask[p] > 0.5) and (p % W, p // W) not in either)
    occupied_count = sum(occupied)
    gpu = stats["sampling"]["shaded_samples"]
    line = (f"{name}: density max relative difference {worst:.2e} over {compared} px (at {worst_at}), "
            f"{clamped_disagree} px differ where clamped; occupied pixels {occupied_count}, "
            f"{occupancy_differs} differ; shaded here {shaded}, fovlab's GPU {gpu}")
    print(line)
    out.write(line + "\n")
    return worst, occupancy_differs, occupied_count, shaded, gpu, clamped_disagree


def render(fovlab, out_dir, tag, method, width, height, display_flags, gaze, extra):
    paths = {k: os.path.join(out_dir, f"{tag}_{k}.{e}") for k, e in
             (("density", "exr"), ("mask", "exr"), ("stats", "json"), ("colour", "png"))}
    command = [fovlab, "render", "--scene", "primitives", "--method", method, "--width", str(width), "--height",
               str(height), "--spp", "1", "--gaze", f"{gaze[0]},{gaze[1]}", *display_flags, *extra, "--out",
               paths["colour"], "--density-out", paths["density"], "--mask-out", paths["mask"], "--stats-json",
               paths["stats"]]
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    return paths


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fovlab", default="build/release/fovlab")
    parser.add_argument("--out", default="/tmp/sampling-check")
    parser.add_argument("--scale", type=float, default=0.5, help="share of each display's pixels (speed)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    # Ye et al. 2022's headset (1440x1600 per eye; 238x264 mm at 100 mm) and a desktop
    # (24 inches at 600 mm); pixel counts scaled by --scale, the physical sizes kept.
    hw, hh = round(720 * args.scale), round(800 * args.scale)
    dw, dh = round(1280 * args.scale), round(720 * args.scale)
    cases = [
        ("headset", Display(hw, hh, 238.0, 264.0, 100.0), ["--size-mm", "238x264", "--distance-mm", "100"]),
        ("desktop", diagonal_display(dw, dh, 24.0, 600.0), ["--diagonal-in", "24", "--distance-mm", "600"]),
    ]
    failed = False
    with open(os.path.join(args.out, "report.txt"), "w") as report:
        for case, display, flags in cases:
            W, H = display.width_px, display.height_px
            for gaze in ((W / 2, H / 2), (round(0.2 * W) + 0.25, round(0.7 * H) + 0.75)):
                for method in ("rmfr", "kfr", "hyperbolic", "linear"):
                    tag = f"{case}_{W}x{H}_{gaze[0]}_{gaze[1]}_{method}"
                    paths = render(args.fovlab, args.out, tag, method, W, H, flags, gaze, [])
                    if method == "rmfr":
                        model = rmfr_model(display, gaze, 2.6, 0.3, 0.3)
                    elif method == "kfr":
                        model = kfr_model(display, gaze, 2.6, 4.0)[:3]
                    elif method == "hyperbolic":
                        model = hyperbolic_model(display, gaze, 2.0, 12.35, 10.0, 20.0, 1.0)
                    else:
                        model = linear_model(display, gaze, 0.047, 10.0, 20.0)
                    worst, differs, occupied, shaded, gpu, clamped = compare(tag, display, *model, report,
                                                                             paths)
                    # Tolerances: the grey is float32 (about 3e-7 relative in density) and the
                    # derivatives here are numerical (about 1e-6); a float32 position on the GPU can
                    # fall on the other side of a pixel edge (a few pixels in a frame).
                    if worst > 1e-4 or differs > max(3, occupied // 1000) or clamped > max(3, W * H // 10000):
                        failed = True
                    if method in ("rmfr", "kfr", "hyperbolic") and abs(shaded - gpu) > max(2, shaded // 1000):
                        failed = True
    print("FAILED" if failed else "all within tolerance")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
