"""Jump onset of the quickstart cam: a notebook-style sweep over cam speed.

Runs the quickstart scene (studies/quickstart.json) at speeds around its
rigid-model jump speed, in parallel threads, and plots the fraction of time
the follower is off the cam against the speed, with the rigid-model jump
speed marked. That estimate leaves the damper (20 N s/m) out; the sweep
shows where this scene actually starts to leave the cam, and how hard it
hammers back (the impacts).

    PYTHONPATH=build/ci/python /usr/bin/python3 examples/python/jump_onset.py out/jump_onset

Writes jump_onset.png into the folder given (default out/jump_onset). CTest
runs it (tests/python/test_examples.py).
"""
# %% Set-up
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # no display needed; writes a file
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import camdyn  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
out_dir = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out/jump_onset")
out_dir.mkdir(parents=True, exist_ok=True)

# %% The scene and its rigid-model jump speed
config = ROOT / "studies" / "quickstart.json"
scene = camdyn.load(config)
jump = camdyn.jump_speed(scene)
print(f"{scene.name}: rigid-model jump speed {jump:.1f} rpm")

# %% Sweep the speed from 80 % to 130 % of it (the GIL is released: threads run in parallel)
speeds = np.linspace(0.8 * jump, 1.3 * jump, 26)


def run(rpm):
    return camdyn.load(config, set={"cam.rpm": float(rpm)}).simulate(series=False).metrics


with ThreadPoolExecutor() as pool:
    metrics = list(pool.map(run, speeds))
separation = np.array([m["separation_fraction"] for m in metrics])
impacts = np.array([m["impact_count"] for m in metrics])
onset = speeds[np.argmax(separation > 0)] if (separation > 0).any() else float("nan")
print(f"first speed of the sweep that separates: {onset:.1f} rpm")

# %% Plot
fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(speeds, 100 * separation, "o-", label="separated (% of the evaluated time)")
ax.axvline(jump, color="k", linestyle="--", label=f"rigid-model jump speed {jump:.0f} rpm")
ax.set_xlabel("cam speed [rpm]")
ax.set_ylabel("separation [%]")
ax.set_title(f"Jump onset: {scene.name}")
twin = ax.twinx()
twin.plot(speeds, impacts, "s:", color="tab:red", label="impacts")
twin.set_ylabel("impacts in the evaluated cycles", color="tab:red")
ax.legend(loc="upper left")
fig.tight_layout()
png = out_dir / "jump_onset.png"
fig.savefig(png, dpi=120)
print(f"wrote {png}")
