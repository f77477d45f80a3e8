#!/usr/bin/env python3
"""What a user sees in rviz: the liners (the mantle's lit orange-brown, the translucent blue-grey concave) and,
within the chamber they outline, the particles (fragment colours, saturation 0.75), and right of it the force map's
legend (a colour bar on its fixed kN scale, saturation 1). A view with liners but
no particles, particles away from the liners, or nothing at all fails.
Usage: check_screenshot.py DISPLAY OUT.png    (grabs the X display, saves it, checks it)
       check_screenshot.py --image IN.png     (checks a saved picture)"""
import sys

import numpy as np
from matplotlib.colors import rgb_to_hsv
from PIL import Image


def render_view(a):
    """The 3D view inside the rviz window: the rows and columns mostly of its background grey (48, 48, 48)."""
    bg = np.abs(a - 48 / 255).max(axis=2) < 6 / 255
    cols = np.nonzero(bg.mean(axis=0) > 0.25)[0]
    rows = np.nonzero(bg.mean(axis=1) > 0.25)[0]
    if len(cols) == 0 or len(rows) == 0:
        return None
    return a[rows[0]:rows[-1] + 1, cols[0]:cols[-1] + 1], bg[rows[0]:rows[-1] + 1, cols[0]:cols[-1] + 1]


def check(img):
    a = np.asarray(img.convert("RGB"), dtype=float) / 255.0
    view = render_view(a)
    if view is None:
        return ["no rviz 3D view (no area of its background grey)"]
    v, bg = view
    hsv = rgb_to_hsv(v)
    h, s, val = hsv[..., 0], hsv[..., 1], hsv[..., 2]
    r, g, b = v[..., 0], v[..., 1], v[..., 2]
    # Fragment colours are 0.25 + 0.75 x a pure hue: saturation 0.75 however lit (the force-map spheres,
    # blue to red with green 0.2, are more saturated; the mantle less).
    particles = (s > 0.72) & (s < 0.78) & (val > 0.3)
    mantle = (r > g) & (g > b) & (h > 0.02) & (h < 0.13) & (s > 0.3) & (s < 0.68) & (val > 0.25)
    concave = (b > r + 0.02) & (h > 0.5) & (h < 0.72) & (s > 0.05) & (s < 0.4) & (val > 0.2)
    liner = mantle | concave
    total = v.shape[0] * v.shape[1]
    n_p, n_m, n_c = int(particles.sum()), int(mantle.sum()), int(concave.sum())
    print(f"3D view {v.shape[1]}x{v.shape[0]} px: background {bg.mean():.1%}, mantle {n_m / total:.2%}, "
          f"concave {n_c / total:.2%}, particles {n_p / total:.2%}")
    errors = []
    if n_m < 0.005 * total:
        errors.append("no mantle visible")
    if n_p < 0.002 * total:
        errors.append("no particles visible")
    if errors:
        return errors
    # The chamber in the picture: the box around the liner pixels (1st to 99th percentile, so that a few
    # stray pixels do not stretch it), enlarged by 5 %.
    ys, xs = np.nonzero(liner)
    x0, x1 = np.percentile(xs, [1, 99])
    y0, y1 = np.percentile(ys, [1, 99])
    mx, my = 0.05 * (x1 - x0), 0.05 * (y1 - y0)
    py, px = np.nonzero(particles)
    inside = (px >= x0 - mx) & (px <= x1 + mx) & (py >= y0 - my) & (py <= y1 + my)
    cx, cy = px.mean(), py.mean()
    counts = np.bincount((h[particles] * 12).astype(int) % 12, minlength=12)
    bands = int((counts >= 20).sum())
    print(f"liners span x {x0:.0f}-{x1:.0f}, y {y0:.0f}-{y1:.0f} px; {inside.mean():.1%} of particle pixels within, "
          f"their centre at ({cx:.0f}, {cy:.0f}); {bands} hue bands")
    if inside.mean() < 0.9:
        errors.append(f"only {inside.mean():.0%} of the particle pixels lie within the liners (need 90 %)")
    # Rock fills the annulus around the mantle: the particles' centre is near the chamber's axis in the picture.
    if not (x0 + 0.25 * (x1 - x0) <= cx <= x1 - 0.25 * (x1 - x0) and y0 <= cy <= y1):
        errors.append("the particles are not centred on the chamber")
    if bands < 3:
        errors.append(f"particles in {bands} hue bands (fragments show >= 3)")
    errors += check_legend(hsv, x1 + 0.3 * (x1 - x0))  # clear of the force-map spheres on the concave's edge
    return errors


def check_legend(hsv, right_of):
    """The force map's legend right of the chamber: a colour bar of saturation 1, red (the scale) above magenta above
    blue (0 kN), one over the other."""
    h, s, val = hsv[..., 0], hsv[..., 1], hsv[..., 2]
    bar = (s > 0.9) & (val > 0.25)
    bar[:, :int(right_of)] = False
    red = bar & ((h < 0.04) | (h > 0.96))
    mid = bar & (h > 0.78) & (h < 0.89)
    blue = bar & (h > 0.62) & (h < 0.72)
    n = [int(m.sum()) for m in (red, mid, blue)]
    print(f"legend right of x {right_of:.0f} px: red {n[0]}, magenta {n[1]}, blue {n[2]} px")
    if min(n) < 30:
        return ["no force-map legend (a red-to-blue colour bar) right of the chamber"]
    rows = [np.nonzero(m)[0].mean() for m in (red, mid, blue)]
    cols = [np.nonzero(m)[1].mean() for m in (red, mid, blue)]
    if not (rows[0] < rows[1] < rows[2]) or max(cols) - min(cols) > 40:
        return [f"the legend's colours are not one bar, red over blue (rows {rows}, columns {cols})"]
    return []


def main(argv):
    if len(argv) == 3 and argv[1] == "--image":
        img = Image.open(argv[2])
    elif len(argv) == 3:
        from PIL import ImageGrab
        img = ImageGrab.grab(xdisplay=argv[1])
        img.save(argv[2])
    else:
        sys.exit(__doc__)
    errors = check(img)
    for e in errors:
        print("FAIL:", e)
    if not errors:
        print("screenshot: particles within the chamber outlined by the liners")
    sys.exit(1 if errors else 0)


if __name__ == "__main__":
    main(sys.argv)
