#!/usr/bin/env python3
"""Synthetic drop-test force records for the contact identification study.

The truth is camdyn itself: rig.json (a roller dropped onto a cam held still)
is simulated with the TRUE contact parameters below at four drop heights, the
contact force is sampled on the force sensor's time base (2 MHz, a window
from shortly before contact; one more record of the lowest drop at 50 kHz),
and Gaussian noise of 1 % of each record's peak
force is added with a fixed seed. The records are committed, so tests and
users need neither Python nor this script; rerun it only to change the data:

    /usr/bin/python3 studies/identify_drop/generate.py --camdyn build/release/camdyn

(Debian's python3 with python3-numpy.)
"""

import argparse
import csv
import math
import os
import subprocess
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))

# What identify_drop.json has to find (contact model lankarani_nikravesh).
TRUTH = {
    "contact.stiffness": 2.5e9,   # K [N/m^n]
    "contact.exponent": 1.45,     # n [-]
    "contact.restitution": 0.7,   # e [-]
}
GRAVITY = 9.81                    # [m/s^2], as rig.json
GAP = 1e-4                        # rig.json follower.initial.position [m]
# record name, drop height [m], sampling interval [s], pre-trigger [s], record length [s]
RECORDS = [
    ("drop_h005", 0.005, 0.5e-6, 50e-6, 400e-6),   # 2 MHz: the impact (~0.2 ms) in ~450 samples
    ("drop_h020", 0.020, 0.5e-6, 50e-6, 400e-6),
    ("drop_h080", 0.080, 0.5e-6, 50e-6, 400e-6),
    ("drop_h320", 0.320, 0.5e-6, 50e-6, 400e-6),
    # The 5 mm drop on a 50 kHz data logger: about ten samples in the impact,
    # too few to show the pulse shape that separates stiffness from exponent.
    ("drop_h005_50khz", 0.005, 20e-6, 200e-6, 2e-3),
]
NOISE = 0.01                      # noise standard deviation / peak force of the record
SEED = 20240606


def simulate(camdyn, overrides, out_dir):
    """Runs rig.json with --set overrides; returns the columns of timeseries.csv."""
    cmd = [camdyn, "run", os.path.join(HERE, "rig.json"), "--out", out_dir, "--quiet"]
    for key, value in overrides.items():
        cmd += ["--set", f"{key}={value!r}"]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out_dir, "timeseries.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    return {key: np.array([float(r[key]) for r in rows]) for key in rows[0]}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--camdyn", default=os.path.join(ROOT, "build", "release", "camdyn"), help="camdyn binary")
    args = parser.parse_args()
    rng = np.random.default_rng(SEED)
    with tempfile.TemporaryDirectory() as tmp:
        for name, height, dt, pre_trigger, length in RECORDS:
            v0 = math.sqrt(2.0 * GRAVITY * height)  # impact speed [m/s]
            t_contact = GAP / v0                    # gravity adds < 0.1 % over the gap
            start = max(0.0, t_contact - pre_trigger)
            overrides = dict(TRUTH)
            overrides["follower.initial.velocity"] = -v0
            overrides["simulation.output_step"] = dt
            overrides["simulation.duration"] = start + length + 2 * dt
            ts = simulate(args.camdyn, overrides, os.path.join(tmp, name))
            keep = (ts["time"] >= start - 1e-12) & (ts["time"] <= start + length + 1e-12)
            t = ts["time"][keep]
            force = ts["contact_force"][keep]
            measured = force + rng.normal(0.0, NOISE * force.max(), force.size)
            path = os.path.join(HERE, name + ".csv")
            with open(path, "w", newline="") as f:
                f.write(f"# synthetic drop test: height {height * 1e3:g} mm, impact speed {v0:.6g} m/s, "
                        f"sampled at {1e-3 / dt:g} kHz; "
                        f"truth {TRUTH}; noise {NOISE:g} x peak force, seed {SEED}; made by generate.py\n")
                f.write("time,force_N\n")
                for ti, fi in zip(t, measured):
                    f.write(f"{ti:.9g},{fi:.6g}\n")
            print(f"{path}: {t.size} samples, peak force {force.max():.6g} N, v0 {v0:.6g} m/s")


if __name__ == "__main__":
    main()
