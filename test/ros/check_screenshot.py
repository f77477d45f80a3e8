#!/usr/bin/env python3
"""Screenshot of the X display and a check of its pixels: the rviz view must show the liners (the mantle's
orange-brown, the translucent blue-grey concave) and the particles (saturated fragment colours), not just the
empty grid on a dark background. Usage: check_screenshot.py DISPLAY OUT.png"""
import colorsys
import sys

from PIL import ImageGrab


def main(display, out):
    img = ImageGrab.grab(xdisplay=display).convert("RGB")
    img.save(out)
    w, h = img.size
    px = img.load()
    mantle = particles = background = 0
    hues = set()
    for y in range(0, h, 2):
        for x in range(0, w, 2):
            r, g, b = px[x, y]
            hh, ss, vv = colorsys.rgb_to_hsv(r / 255, g / 255, b / 255)
            if abs(r - 48) < 6 and abs(g - 48) < 6 and abs(b - 48) < 6:
                background += 1
            elif r > g > b and 0.02 < hh < 0.13 and 0.3 < ss < 0.75 and vv > 0.25:
                mantle += 1  # lit orange-brown of the mantle (0.75, 0.55, 0.3)
            if ss > 0.55 and vv > 0.35:
                particles += 1
                hues.add(int(hh * 12))
    total = (w // 2) * (h // 2)
    print(f"screenshot {w}x{h}: background {background / total:.1%}, mantle-coloured {mantle / total:.2%}, "
          f"saturated {particles / total:.2%} in {len(hues)} hue bands")
    ok = True
    if mantle < 0.005 * total:
        print("FAIL: no liner visible")
        ok = False
    if particles < 0.001 * total or len(hues) < 3:
        print("FAIL: no particles visible (too few saturated pixels in distinct fragment colours)")
        ok = False
    if background > 0.97 * total:
        print("FAIL: the view is empty")
        ok = False
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
