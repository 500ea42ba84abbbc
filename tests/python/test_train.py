"""Scene.simulate on a follower train (docs/model.md §12) returns the train's
columns after the documented ones, each with a unit (camdyn.column_unit)."""
import numpy as np

import camdyn

# A bucket tappet on a 1.5:1 lever to a valve: the follower seated 0.2 mm above
# its base circle on a spring with mass, the valve on its own spring and seat.
TRAIN_SCENE = {
    "name": "python-train",
    "mechanism": {
        "cam": {"base_radius": 0.04, "rpm": 1200, "motion_law": {"segments": [
            {"type": "rise", "law": "cycloidal", "end_deg": 120, "lift": 0.008},
            {"type": "dwell", "end_deg": 180},
            {"type": "return", "law": "cycloidal", "end_deg": 300},
            {"type": "dwell", "end_deg": 360}]}},
        "follower": {"shape": {"type": "flat", "face_width": 0.03}, "mass": 0.05,
                     "spring": {"stiffness": 5000, "preload": 40, "mass": 0.02, "coils": 4},
                     "seat": {"position": 0.0002, "model": "hunt_crossley", "stiffness": 5e8,
                              "exponent": 1.0, "restitution": 0.3}},
        "contact": {"model": "hunt_crossley", "stiffness": 1e10, "exponent": 1.5, "restitution": 0.8},
        "train": [{"name": "valve", "mass": 0.06,
                   "link": {"ratio": 1.5, "stiffness": 2e7, "damping": 40},
                   "spring": {"stiffness": 30000, "preload": 300},
                   "seat": {"model": "hunt_crossley", "stiffness": 1e9, "exponent": 1.5,
                            "restitution": 0.3}}],
    },
    "simulation": {"cycles": 2, "discard_cycles": 1, "output_step_deg": 1.0},
}

TRAIN_COLUMNS = ["follower_seat_force", "follower_spring_force", "valve_position", "valve_velocity",
                 "valve_link_force", "valve_seat_force", "valve_spring_force"]


def test_train_columns_follow_the_documented_ones_with_their_units():
    result = camdyn.Scene.from_dict(TRAIN_SCENE).simulate(as_frame=False)
    assert result.converged, result.solver["message"]
    names = list(result.timeseries.dtype.names)
    assert names[:len(camdyn.TIMESERIES_UNITS)] == list(camdyn.TIMESERIES_UNITS)
    assert sorted(names[len(camdyn.TIMESERIES_UNITS):]) == sorted(TRAIN_COLUMNS)
    units = {name: camdyn.column_unit(name) for name in TRAIN_COLUMNS}
    assert units == {"follower_seat_force": "N", "follower_spring_force": "N", "valve_position": "m",
                     "valve_velocity": "m/s", "valve_link_force": "N", "valve_seat_force": "N",
                     "valve_spring_force": "N"}
    ts = result.timeseries
    assert np.all(np.isfinite(ts.valve_position)) and np.all(np.isfinite(ts.valve_link_force))
    # The link is one-sided and the valve follows the lever: up to the lift times the ratio.
    assert np.all(ts.valve_link_force >= 0.0)
    assert 0.9 * 1.5 * 0.008 < ts.valve_position.max() < 1.1 * 1.5 * 0.008


def test_samples_carry_the_train_columns_without_a_series():
    period = 60.0 / 1200.0  # [s]
    result = camdyn.Scene.from_dict(TRAIN_SCENE).simulate(series=False, sample_times=[1.2 * period, 1.5 * period],
                                                         as_frame=False)
    assert result.timeseries is None
    assert "valve_position" in result.samples.dtype.names
    assert "valve_link_force" in result.samples.dtype.names
    assert len(result.samples) == 2


def test_column_unit_knows_the_documented_columns_and_no_others():
    assert camdyn.column_unit("contact_force") == "N"
    assert camdyn.column_unit("follower_position") == "m"
    assert camdyn.column_unit("tip_stop_force") == "N"
    assert camdyn.column_unit("no_such_column") is None
    assert camdyn.column_unit("_position") is None


def test_units_come_from_the_compiled_module_and_know_an_arm():
    # One table in C++ (dynamics/series_columns.h) names the columns and their units.
    assert camdyn.TIMESERIES_UNITS == dict(camdyn._camdyn.series_column_units())
    assert camdyn.TRAIN_COLUMN_UNITS == dict(camdyn._camdyn.train_column_units())
    assert camdyn.TIMESERIES_UNITS["follower_acceleration"] == "m/s^2"
    assert camdyn.column_unit("follower_position", oscillating=True) == "rad"
    assert camdyn.column_unit("follower_velocity", oscillating=True) == "rad/s"
    assert camdyn.column_unit("follower_seat_force", oscillating=True) == "N m"
    assert camdyn.column_unit("valve_seat_force", oscillating=True) == "N"
    assert camdyn.column_unit("valve_link_force") == "N"
