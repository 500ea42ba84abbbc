#!/usr/bin/env python3
"""Writes dohc_bucket_lift.json: a valve lift with constant-velocity lash ramps.

The event is centred at 90 deg of cam and lasts 180 deg. Lift is the sum of
 * the ramps: a constant cam velocity RAMP_VELOCITY [m/deg] from 0 deg (reached
   smoothly over BLEND_DEG) that blends smoothly back to zero velocity over
   BLEND_DEG after RAMP_END_DEG, so the ramp rises to about 0.38 mm; mirrored
   on the closing side (ramp ends at 180 - RAMP_END_DEG), and
 * the main lobe, MAIN_LIFT over +-MAIN_HALF_WIDTH_DEG about the centre, the
   polynomial bell of generate_valve_lift.py (C3 at its ends),
so that a lash of up to about 0.35 mm is taken up on the ramp at the ramp's
constant velocity (0.0113 mm/deg: 0.34 m/s at 5000 cam rpm).
The ramps end where the main lobe is well under way (RAMP_END_DEG), so the
cam's velocity rises without a dip. Written as a periodic quintic spline
through the lift every 1 deg. Run from the repository root:
    python3 profiles/generate_dohc_lift.py
"""
import json
import os

from generate_valve_lift import bell  # the main lobe's polydyne bell, C3 at |x| = 1

CENTRE_DEG = 90.0
MAIN_LIFT = 9.0e-3            # [m]
MAIN_HALF_WIDTH_DEG = 62.0    # main lobe from 28 to 152 deg
RAMP_VELOCITY = 0.0113e-3     # [m/deg]
RAMP_END_DEG = 32.0           # the opening ramp's constant velocity ends here
BLEND_DEG = 4.0
STEP_DEG = 1.0


def smoother(x):
    """0 below 0, 1 above 1, C2 in between."""
    x = min(max(x, 0.0), 1.0)
    return x * x * x * (10.0 - 15.0 * x + 6.0 * x * x)


def ramp_velocity(theta_deg):
    """The opening ramp's velocity [m/deg] at theta (0 outside it)."""
    return RAMP_VELOCITY * smoother(theta_deg / BLEND_DEG) * (1.0 - smoother((theta_deg - RAMP_END_DEG) / BLEND_DEG))


def ramp_height(theta_deg, steps_per_deg=200):
    """The integral of the ramp's velocity from 0 to theta [m] (midpoint rule)."""
    n = max(0, int(round(theta_deg * steps_per_deg)))
    h = 1.0 / steps_per_deg
    return sum(ramp_velocity((i + 0.5) * h) for i in range(n)) * h


RAMP_TOP_DEG = RAMP_END_DEG + BLEND_DEG
RAMP_HEIGHT = ramp_height(RAMP_TOP_DEG)


def lift(theta_deg):
    opening = ramp_height(min(theta_deg, RAMP_TOP_DEG)) if 0.0 <= theta_deg <= CENTRE_DEG else 0.0
    mirrored = 2 * CENTRE_DEG - theta_deg
    closing = ramp_height(min(mirrored, RAMP_TOP_DEG)) if 0.0 <= mirrored < CENTRE_DEG else 0.0
    return opening + closing + MAIN_LIFT * bell((theta_deg - CENTRE_DEG) / MAIN_HALF_WIDTH_DEG)


def main():
    knots = [i * STEP_DEG for i in range(int(round(360.0 / STEP_DEG)))]
    lifts = [round(lift(t), 12) for t in knots]
    here = os.path.dirname(os.path.abspath(__file__))
    doc = {
        "description": (
            "DOHC bucket valve lift with constant-velocity lash ramps: %.2f mm main lobe over +-%g deg about %g deg "
            "of cam plus opening and closing ramps at a constant %.4f mm/deg up to %.3f mm, the opening ramp's "
            "constant velocity ending at %g deg (the closing ramp's starting at %g deg); event 0-180 deg. "
            "Written as a periodic quintic spline through the lift every %g deg by profiles/generate_dohc_lift.py."
            % (MAIN_LIFT * 1e3, MAIN_HALF_WIDTH_DEG, CENTRE_DEG, RAMP_VELOCITY * 1e3, RAMP_HEIGHT * 1e3,
               RAMP_END_DEG, 2 * CENTRE_DEG - RAMP_END_DEG, STEP_DEG)),
        "spline": {"degree": 5, "knots_deg": knots, "lift": lifts},
    }
    with open(os.path.join(here, "dohc_bucket_lift.json"), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
