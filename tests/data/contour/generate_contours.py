#!/usr/bin/env python3
"""Writes the contour-cam point files used by tests/geometry/contour_cam_test.cc.

Each file is a `motion_law` object of docs/config.md, `{ "contour": { "points": [[x, y], ...] } }`,
in metres, cam frame at cam angle 0:

* roller_cam_cycloidal.json: the contour of a translating roller cam (base radius 40 mm,
  roller 10 mm, offset 5 mm, counterclockwise cam) for the 20 mm cycloidal
  rise (0-120 deg) / dwell / cycloidal return (180-300 deg) / dwell law, 360 points,
  synthesised here independently of the C++ code (the pitch curve P(u) = R(-u) (e, y0 + s(u)),
  the contour its inner offset by the roller radius).
* roller_cam_cycloidal_noisy.json: the same points with Gaussian noise, sigma = 2 um per
  coordinate (seeded), as from a coordinate measuring machine.
* lobed_concave.json: r(phi) = 40 mm (1 + 0.15 cos 3 phi), 180 points: three concave
  flanks of radius 57.8 mm around 60, 180 and 300 deg.

Run from anywhere: python3 tests/data/contour/generate_contours.py
"""
import json
import math
import os
import random

HERE = os.path.dirname(os.path.abspath(__file__))
RB, RR, E, H = 0.04, 0.01, 0.005, 0.02


def cycloidal(x, beta):
    """s and ds/dtheta of a cycloidal rise of H over beta rad, x in [0, 1]."""
    s = H * (x - math.sin(2 * math.pi * x) / (2 * math.pi))
    ds = H / beta * (1 - math.cos(2 * math.pi * x))
    return s, ds


def law(theta):
    deg = math.degrees(theta) % 360.0
    if deg < 120:
        return cycloidal(deg / 120, math.radians(120))
    if deg < 180:
        return H, 0.0
    if deg < 300:
        s, ds = cycloidal((deg - 180) / 120, math.radians(120))
        return H - s, -ds
    return 0.0, 0.0


def roller_contour(u):
    y0 = math.sqrt((RB + RR) ** 2 - E ** 2)
    s, ds = law(u)
    c, sn = math.cos(-u), math.sin(-u)
    qx, qy = E, y0 + s
    # P = R(-u) q, P' = R(-u) (q' - J q) with J q = (-qy, qx).
    px, py = c * qx - sn * qy, sn * qx + c * qy
    vx, vy = 0.0 + qy, ds - qx
    dpx, dpy = c * vx - sn * vy, sn * vx + c * vy
    norm = math.hypot(dpx, dpy)
    nx, ny = -dpy / norm, dpx / norm  # J P' / |P'|: outward for the clockwise pitch curve
    return px - RR * nx, py - RR * ny


def write(name, points):
    doc = {"contour": {"points": [[round(x, 12), round(y, 12)] for x, y in points]}}
    text = "{\n  \"contour\": {\n    \"points\": [\n"
    text += ",\n".join("      [%s, %s]" % (repr(p[0]), repr(p[1])) for p in doc["contour"]["points"])
    text += "\n    ]\n  }\n}\n"
    path = os.path.join(HERE, name)
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


def main():
    n = 360
    exact = [roller_contour(2 * math.pi * i / n) for i in range(n)]
    write("roller_cam_cycloidal.json", exact)
    rng = random.Random(20240611)
    write("roller_cam_cycloidal_noisy.json", [(x + rng.gauss(0, 2e-6), y + rng.gauss(0, 2e-6)) for x, y in exact])
    lobed = []
    for i in range(180):
        phi = 2 * math.pi * i / 180
        r = 0.04 * (1 + 0.15 * math.cos(3 * phi))
        lobed.append((r * math.cos(phi), r * math.sin(phi)))
    write("lobed_concave.json", lobed)


if __name__ == "__main__":
    main()
