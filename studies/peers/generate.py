#!/usr/bin/env python3
"""Writes cam_lift.csv: the lift table of the long-flight benchmark scene
(long_flight.json; issue 15, "the Siconos cam-follower benchmark").

The cam: base radius 0.4 m; a cycloidal rise of 0.2 m over 120 deg, a dwell
to 150 deg, a cycloidal return over 150 deg, a dwell to 360 deg; tabulated
every 0.1 deg (3,600 rows), as an encoder would give it. At 700 rpm the
spring-loaded follower (1.221 kg, 1430.8 N/m, 143.08 N preload) is thrown off
the rise at about 14 m/s, flies a large fraction of a metre off the cam and
lands once per revolution.

Run from this folder:  python3 generate.py
"""
import math

LIFT = 0.2  # [m]
RISE_END, DWELL_END, RETURN_END = math.radians(120), math.radians(150), math.radians(300)
ROWS = 3600


def cycloidal(x):
    return x - math.sin(2 * math.pi * x) / (2 * math.pi)


def lift(theta):
    """s [m] at cam angle theta [rad] in [0, 2 pi)."""
    if theta < RISE_END:
        return LIFT * cycloidal(theta / RISE_END)
    if theta < DWELL_END:
        return LIFT
    if theta < RETURN_END:
        return LIFT * (1.0 - cycloidal((theta - DWELL_END) / (RETURN_END - DWELL_END)))
    return 0.0


def main():
    with open("cam_lift.csv", "w", encoding="ascii") as out:
        out.write("angle_deg,lift\n")
        for i in range(ROWS):
            angle = 360.0 * i / ROWS
            out.write(f"{angle:.1f},{lift(math.radians(angle)):.12e}\n")


if __name__ == "__main__":
    main()
