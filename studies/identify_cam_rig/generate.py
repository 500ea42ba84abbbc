#!/usr/bin/env python3
"""Synthetic cam-rig acceleration records for the contact identification study.

The truth is camdyn itself: rig.json (a cam driving a roller follower above
its jump speed, so that the follower separates and hammers back) is simulated
with the TRUE contact stiffness and follower damping below at two cam speeds;
the follower acceleration is sampled on the accelerometer's time base
(100 kHz) over the half revolution where it happens: from the start of
the return (180 deg, the follower resting on the dwell) to 1.5 ms after the
follower lands again, and Gaussian noise of 1 % of each record's peak
acceleration is added with a fixed seed. The
records are committed, so tests and users need neither Python nor this
script; rerun it only to change the data:

    /usr/bin/python3 studies/identify_cam_rig/generate.py --camdyn build/release/camdyn

(Debian's python3 with python3-numpy.)
"""

import argparse
import csv
import os
import subprocess
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))

# What identify_cam_rig.json has to find.
TRUTH = {
    "contact.stiffness": 6e9,     # K [N/m^1.5]
    "follower.damping": 20.0,     # c [N s/m]
}
SPEEDS = [("rig_1200rpm", 1200.0), ("rig_1300rpm", 1300.0)]  # record name, cam speed [rpm]
START_DEG = 180.0                 # record starts at the start of the return [deg]
AFTER_LANDING = 1.5e-3            # and ends this long after the first landing impact [s]
DT = 1e-5                         # accelerometer sampling interval [s] (100 kHz)
NOISE = 0.01                      # noise standard deviation / peak |acceleration| of the record
SEED = 20240607


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {key: np.array([float(r[key]) if key != "kind" else 0.0 for r in rows]) for key in rows[0]}, rows


def simulate(camdyn, overrides, out_dir):
    """Runs rig.json with --set overrides; returns the columns of timeseries.csv and the events."""
    cmd = [camdyn, "run", os.path.join(HERE, "rig.json"), "--out", out_dir, "--quiet"]
    for key, value in overrides.items():
        cmd += ["--set", f"{key}={value}"]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    series, _ = read_csv(os.path.join(out_dir, "timeseries.csv"))
    _, events = read_csv(os.path.join(out_dir, "events.csv"))
    return series, events


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--camdyn", default=os.path.join(ROOT, "build", "release", "camdyn"), help="camdyn binary")
    args = parser.parse_args()
    rng = np.random.default_rng(SEED)
    with tempfile.TemporaryDirectory() as tmp:
        for name, rpm in SPEEDS:
            overrides = {key: repr(value) for key, value in TRUTH.items()}
            overrides["cam.rpm"] = repr(rpm)
            overrides["simulation.output_step_deg"] = "null"
            overrides["simulation.output_step"] = repr(DT)
            ts, events = simulate(args.camdyn, overrides, os.path.join(tmp, name))
            start = START_DEG / 360.0 * 60.0 / rpm
            landing = min(float(e["time"]) for e in events if e["kind"] == "onset" and float(e["time"]) > start)
            keep = (ts["time"] >= start - 1e-12) & (ts["time"] <= landing + AFTER_LANDING)
            t = ts["time"][keep]
            acc = ts["follower_acceleration"][keep]
            measured = acc + rng.normal(0.0, NOISE * np.abs(acc).max(), acc.size)
            path = os.path.join(HERE, name + ".csv")
            with open(path, "w", newline="") as f:
                f.write(f"# synthetic cam rig: {rpm:g} rpm, first revolution from {START_DEG:g} deg to "
                        f"{AFTER_LANDING * 1e3:g} ms after the landing at {landing:.6g} s, accelerometer at {1e-3 / DT:g} kHz; "
                        f"truth {TRUTH}; noise {NOISE:g} x peak |acceleration|, seed {SEED}; made by generate.py\n")
                f.write("t_s,accel_m_s2\n")
                for ti, ai in zip(t, measured):
                    f.write(f"{ti:.9g},{ai:.6g}\n")
            print(f"{path}: {t.size} samples, peak |acceleration| {np.abs(acc).max():.6g} m/s^2")


if __name__ == "__main__":
    main()
