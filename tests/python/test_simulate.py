"""Scene.simulate gives what `camdyn run` gives, with the documented columns and units."""
import json
import math
import os
import struct
import subprocess

import numpy as np
import pytest

import camdyn


def same_bits(a, b):
    return struct.pack("<d", a) == struct.pack("<d", b)


def cli_summary(binary, config, out, sets=()):
    args = [binary, "run", str(config), "--out", str(out), "--quiet"]
    for assignment in sets:
        args += ["--set", assignment]
    subprocess.run(args, check=True, capture_output=True)
    with open(out / "summary.json", encoding="utf-8") as f:
        return json.load(f)


# The plain run, and the metrics over one period of the orbit the run settles on.
@pytest.mark.parametrize("sets", [[], ["simulation.steady_state=true"]], ids=["window", "steady_state"])
def test_quickstart_metrics_are_the_clis_to_the_last_bit(camdyn_binary, quickstart, tmp_path, sets):
    summary = cli_summary(camdyn_binary, quickstart, tmp_path, sets)
    result = camdyn.load(quickstart, set=sets).simulate(as_frame=False)
    assert set(result.metrics) == set(summary["metrics"])
    for name, value in summary["metrics"].items():
        expected = math.inf if value is None else float(value)  # summary.json writes an infinite jump speed as null
        assert same_bits(result.metrics[name], expected), (name, result.metrics[name], expected)
    for counter in ("steps", "rhs_evaluations", "events", "tracking_resets", "error_test_failures",
                    "nonlinear_iterations", "jacobian_evaluations", "restarts", "tracking_projections"):
        assert result.solver[counter] == summary["solver"][counter], counter
    for name in ("method", "rtol", "atol", "termination", "message", "simulated_time_s", "evaluated_from_s"):
        assert result.solver[name] == summary["solver"][name], name
    assert result.metrics_over == summary["metrics_over"]
    assert result.steady_state == summary.get("steady_state", "")
    for name in ("states", "elements", "cam", "follower", "contact_pair"):
        assert result.model[name] == summary["model"][name], name


def test_overrides_are_the_clis(camdyn_binary, quickstart, tmp_path):
    subprocess.run([camdyn_binary, "run", str(quickstart), "--out", str(tmp_path), "--quiet", "--set", "cam.rpm=900"],
                   check=True, capture_output=True)
    summary = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    for overrides in ({"cam.rpm": 900}, ["cam.rpm=900"], {"mechanism.cam.rpm": 900.0}, {"cam.rpm": np.int64(900)}):
        result = camdyn.load(quickstart, set=overrides).simulate(series=False)
        assert result.timeseries is None
        for name, value in summary["metrics"].items():
            if value is not None:
                assert same_bits(result.metrics[name], float(value)), (overrides, name)


def test_from_dict_is_the_file(quickstart):
    config = json.loads(quickstart.read_text(encoding="utf-8"))
    from_file = camdyn.load(quickstart).simulate(series=False)
    from_dict = camdyn.Scene.from_dict(config, base_dir=quickstart.parent).simulate(series=False)
    assert from_dict.metrics == from_file.metrics
    assert camdyn.load(quickstart).resolved == camdyn.Scene.from_dict(config, base_dir=quickstart.parent).resolved


def test_timeseries_has_the_documented_columns_and_units(quickstart):
    scene = camdyn.load(quickstart)
    result = scene.simulate(as_frame=False)
    ts = result.timeseries
    assert list(ts.dtype.names) == list(camdyn.TIMESERIES_UNITS)
    # time [s] and cam_angle_deg [deg]: the cam turns rpm * 6 degrees a second.
    assert np.allclose(ts.cam_angle_deg - ts.cam_angle_deg[0], 6.0 * scene.rpm * (ts.time - ts.time[0]), rtol=1e-12)
    assert np.all(ts.cam_speed_rpm == scene.rpm)
    # output_step_deg 0.25 over 4 cycles.
    assert len(ts) == 4 * 360 * 4 + 1
    # follower_velocity [m/s] is the rate of follower_position [m].
    dt = np.diff(ts.time)
    rate = np.diff(ts.follower_position) / dt
    mid = 0.5 * (ts.follower_velocity[1:] + ts.follower_velocity[:-1])
    in_contact = (ts.gap[1:] < 0) & (ts.gap[:-1] < 0)
    assert np.max(np.abs(rate - mid)) < 0.05 * np.max(np.abs(ts.follower_velocity))
    # contact_force [N], gap [m]: the metrics of the evaluated window come from these.
    window = ts.time >= result.solver["evaluated_from_s"]
    assert np.max(ts.contact_force[window]) <= result.metrics["peak_contact_force"]
    assert np.max(ts.contact_force[window]) > 0.5 * result.metrics["peak_contact_force"]
    assert np.all(ts.contact_force[ts.gap > 0] == 0.0)
    assert in_contact.any()
    # kinematic_position [m] is the law's lift s(θ) plus the follower's lowest position.
    lift = scene.law(ts.cam_angle_deg)["s"]
    offset = ts.kinematic_position - lift
    assert np.ptp(offset) < 1e-12
    assert lift.min() == pytest.approx(0.0, abs=1e-15) and lift.max() == pytest.approx(0.02, rel=1e-9)


def test_events_have_the_documented_columns(quickstart):
    result = camdyn.load(quickstart).simulate(series=False, as_frame=False)
    ev = result.events
    assert list(ev.dtype.names) == list(camdyn.EVENT_UNITS)
    assert ev.onset.dtype == np.bool_ and ev.impact.dtype == np.bool_ and ev.grazing.dtype == np.bool_
    assert not np.any(ev.impact & ev.grazing) and not np.any(ev.grazing & ~ev.onset)
    assert np.all(ev.speed[ev.impact] > 0)
    assert np.all(np.diff(ev.time) >= 0)
    assert np.all(ev.speed >= 0)
    evaluated = ev.time >= result.solver["evaluated_from_s"]
    assert np.count_nonzero(ev.impact & evaluated) == result.metrics["impact_count"]
    assert np.max(ev.speed[ev.impact & evaluated]) == pytest.approx(result.metrics["max_impact_velocity"], rel=1e-12)


def test_samples_at_given_times(quickstart):
    result = camdyn.load(quickstart).simulate(series=False, sample_times=[0.01, 0.02], as_frame=False)
    assert list(result.samples.time) == [0.01, 0.02]


def test_tables_are_pandas_frames_when_pandas_is_importable(quickstart, pandas):
    result = camdyn.load(quickstart).simulate(series=True)
    assert isinstance(result.timeseries, pandas.DataFrame)
    assert list(result.timeseries.columns) == list(camdyn.TIMESERIES_UNITS)


def test_jump_speed_profile_and_law(quickstart):
    scene = camdyn.load(quickstart)
    result = scene.simulate(series=False)
    assert camdyn.jump_speed(scene) == result.metrics["jump_speed_rpm"]
    assert 1100 < camdyn.jump_speed(scene) < 1250
    # The roller's centre runs ρ = 10 mm outside the contour; on the base
    # circle (the dwell, s = 0) it is at r_b + ρ = 50 mm from the cam centre.
    p = camdyn.profile(scene, 720)
    assert {k: len(v) for k, v in p.items()} == dict.fromkeys(("u", "contour_x", "contour_y", "pitch_x", "pitch_y"), 720)
    distance = np.hypot(p["pitch_x"] - p["contour_x"], p["pitch_y"] - p["contour_y"])
    assert np.allclose(distance, 0.01, rtol=0, atol=1e-12)
    radius = np.hypot(p["pitch_x"], p["pitch_y"])
    assert radius.min() == pytest.approx(0.05, rel=1e-12)
    assert radius.max() == pytest.approx(0.07, rel=1e-9)
    # The law: derivatives against central differences in the cam angle, half
    # a degree away from the segment ends (0, 120, 180, 300 deg), where d3s jumps.
    angles = np.linspace(0.5, 359.5, 360)
    h = 1e-3  # deg
    law, up, down = camdyn.law(scene, angles), camdyn.law(scene, angles + h), camdyn.law(scene, angles - h)
    step = np.radians(h)
    for value, rate in (("s", "ds"), ("ds", "d2s"), ("d2s", "d3s")):
        difference = (up[value] - down[value]) / (2 * step)
        assert np.allclose(difference, law[rate], rtol=1e-5, atol=1e-6 * np.max(np.abs(law[rate]))), rate


def test_version_is_the_cmake_projects(camdyn_binary):
    cli = subprocess.run([camdyn_binary, "--version"], check=True, capture_output=True, text=True).stdout.split()[-1]
    assert camdyn.__version__ == cli
    assert len(camdyn.__version__.split(".")) == 3
    if "CAMDYN_PROJECT_VERSION" in os.environ:  # set by CTest: project(camdyn VERSION ...)
        assert camdyn.__version__ == os.environ["CAMDYN_PROJECT_VERSION"]


def test_threads_get_the_single_thread_run(quickstart):
    from concurrent.futures import ThreadPoolExecutor
    scene = camdyn.load(quickstart)
    alone = scene.simulate(series=False)
    with ThreadPoolExecutor(max_workers=2) as pool:
        runs = list(pool.map(lambda _: scene.simulate(series=False), range(2)))
    for run in runs:
        assert run.metrics == alone.metrics


# Scene.set: an rpm sweep on one scene, without loading the config again, runs
# to the bit as scenes loaded with the override (the file is gone by then).
def test_set_sweeps_the_speed_in_place_to_the_bit(quickstart, tmp_path):
    config = tmp_path / "quickstart.json"
    with open(quickstart, encoding="utf-8") as f:
        document = json.load(f)
    document["mechanism"]["cam"]["motion_law"] = str(quickstart.parent.parent / document["mechanism"]["cam"]["motion_law"])
    config.write_text(json.dumps(document), encoding="utf-8")
    scene = camdyn.load(config, set=["simulation.cycles=2"])
    config.unlink()
    for rpm in (900.0, 1300.0):
        swept = scene.set("cam.rpm", rpm).simulate(series=False, as_frame=False)
        loaded = camdyn.load(quickstart, set=["simulation.cycles=2", f"cam.rpm={rpm}"]).simulate(
            series=False, as_frame=False)
        assert scene.rpm == rpm
        for name, value in loaded.metrics.items():
            assert same_bits(swept.metrics[name], value), (rpm, name)
        assert swept.solver["steps"] == loaded.solver["steps"]


def test_set_refuses_what_the_loader_refuses_and_keeps_the_scene(quickstart):
    scene = camdyn.load(quickstart)
    with pytest.raises(camdyn.InputError, match=r"mechanism\.follower\.mass.*must be > 0"):
        scene.set("follower.mass", -1.0)
    with pytest.raises(camdyn.InputError, match="did you mean 'rpm'"):
        scene.set("cam.rpmm", 1000)
    assert scene.rpm == 1300
    assert scene.set("contact.model", "hertz").resolved["mechanism"]["contact"]["model"] == "hertz"
