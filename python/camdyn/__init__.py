"""camdyn: cam-follower mechanisms that do not jump and do not hammer.

The Python face of the camdyn simulator (docs/python.md). It loads and checks
a scene as ``camdyn run`` does, simulates it, and hands back the numbers as
dicts and numpy arrays::

    import camdyn
    scene = camdyn.load("studies/quickstart.json", set={"cam.rpm": 1200})
    result = scene.simulate()
    print(result.metrics["peak_contact_force"], "N")

Errors: ``camdyn.InputError`` (a bad config or argument: ``file``, ``path``,
``reason``) and ``camdyn.SolverError`` (a solver gave up), both ``camdyn.Error``.
The GIL is released while camdyn computes, so threads simulate in parallel;
Ctrl-C stops a simulation on the main thread within about a second.
"""

import csv
import json
import numbers
import os
import tempfile

import numpy as np

from . import _camdyn
from ._camdyn import Error, InputError, SolverError, __version__

__all__ = [
    "Error", "InputError", "SolverError", "Result", "Scene", "__version__", "EVENT_UNITS", "TIMESERIES_UNITS",
    "TRAIN_COLUMN_UNITS", "column_unit", "jump_speed", "law", "load", "profile", "run_study",
]

#: The time series' columns, in order, and their units (summary.json's
#: timeseries.csv), read from the compiled module's one table. For an
#: oscillating follower the follower's coordinate is the arm angle:
#: follower_position [rad], follower_velocity [rad/s], follower_acceleration
#: [rad/s^2], kinematic_position [rad] (``column_unit(name, oscillating=True)``).
TIMESERIES_UNITS = dict(_camdyn.series_column_units())

#: The units of a follower train's columns (mechanism.train, seats, stops,
#: springs with mass; docs/model.md §12), by the suffix after the body's
#: name: ``valve_position`` [m], ``valve_link_force`` [N], ``follower_seat_force``
#: [N], ... They follow the columns of ``TIMESERIES_UNITS`` when the scene has
#: a train. A train body's coordinate is a length even after an oscillating
#: arm (its link's ratio is in m/rad); the follower's own ``follower_seat_force``,
#: ``follower_stop_force`` and ``follower_spring_force`` act along its
#: coordinate, so for an oscillating arm they are torques [N m].
TRAIN_COLUMN_UNITS = dict(_camdyn.train_column_units())


def column_unit(name, oscillating=False):
    """The unit of a time-series column: one of ``TIMESERIES_UNITS``, else a
    train column's from its suffix (``TRAIN_COLUMN_UNITS``; the longest suffix
    that fits, so ``valve_link_force`` is N). None for a name that is neither.
    ``oscillating``: the follower is an arm (its coordinate's columns in rad,
    its own seat, stop and spring forces in N m)."""
    unit = _camdyn.column_unit(str(name), bool(oscillating))
    return unit or None


#: The events' columns and their units: contact onsets and separations.
EVENT_UNITS = {
    "time": "s",
    "cam_angle_deg": "deg",
    "onset": "bool (True: the gap closes, False: it opens)",
    "speed": "m/s (approach speed at an onset, separation speed at a separation)",
    "impact": "bool (an onset after a separation, with a positive approach speed)",
    "grazing": "bool (an onset that is not an impact: no approach, or no separation before it)",
    "lash": "bool (a separation while a body rests on its seat, or the onset taking that lash up)",
    "cause": "str (a separation's cause: take_up, float or seat_bounce; an onset carries its separation's; '' otherwise)",
}


def _argument_error(name, reason):
    """InputError for a bad argument, as the C++ API raises it: no file, the argument's name as the path."""
    error = InputError(f"{name}: {reason}")
    error.file, error.path, error.reason = "", name, reason
    return error


def _integer(name, value, low, high, why=""):
    """value as an int in [low, high]; InputError naming the argument otherwise."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Integral, np.integer)):
        raise _argument_error(name, f"must be a whole number, got {value!r}")
    if not low <= value <= high:
        raise _argument_error(name, f"must be {low} … {high}{why}, got {value}")
    return int(value)


def _numbers(name, values, unit):
    """values as a 1-d float array, at most the points one call takes (finiteness is checked in C++)."""
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as e:
        raise _argument_error(name, f"must be numbers {unit}: {e}") from None
    if array.ndim > 1:
        raise _argument_error(name, f"must be a flat sequence of numbers {unit}, got an array of shape {array.shape}")
    if array.size > _camdyn._MAX_POINTS_PER_CALL:
        raise _argument_error(name, f"{array.size} values asked for: at most {_camdyn._MAX_POINTS_PER_CALL} in one "
                                    "call (the cap of camdyn export --points)")
    return np.ascontiguousarray(array.ravel())


def _plain(value):
    """numpy scalars and arrays as the Python numbers and lists JSON takes."""
    if isinstance(value, (np.generic, np.ndarray)):
        return value.tolist()
    raise TypeError(f"{type(value).__name__} is not a JSON value")


def _json(value):
    return json.dumps(value, allow_nan=False, default=_plain)


def _json_value(path, value):
    """A value as JSON, or InputError naming its dotted path (NaN and inf have no JSON form)."""
    if isinstance(value, (float, np.floating)) and not np.isfinite(value):
        raise _argument_error(path, f"expected a finite number, got {value}")
    try:
        return _json(value)
    except (TypeError, ValueError) as e:
        raise _argument_error(path, f"{value!r} cannot be written as JSON ({e}): give a finite number, a string, "
                                    "a list or a dict") from None


def _path(name, value):
    """A file or folder name (str or os.PathLike) as a str; InputError naming the argument otherwise."""
    try:
        path = os.fspath(value)
    except TypeError:
        raise _argument_error(name, f"must be a file name (str or os.PathLike), got {type(value).__name__}") from None
    if isinstance(path, bytes):
        raise _argument_error(name, "must be a file name as str, got bytes")
    return path


def _overrides(values):
    """--set assignments from a dict {"cam.rpm": 1200} (values as JSON) or strings "cam.rpm=1200"."""
    if values is None:
        return []
    if isinstance(values, dict):
        return [f"{key}={_json_value(str(key), value)}" for key, value in values.items()]
    if isinstance(values, str):
        return [values]
    if not isinstance(values, (list, tuple)) or not all(isinstance(v, str) for v in values):
        raise _argument_error("set", "must be a dict {dotted path: value} or strings 'dotted.path=value', got "
                                     f"{values!r:.80}")
    return list(values)


def _table(columns, names, as_frame):
    """Columns (name -> 1-d array) as a pandas DataFrame, or a numpy record array."""
    if as_frame is None:
        try:
            import pandas  # noqa: F401  (optional)
            as_frame = True
        except ImportError:
            as_frame = False
    if as_frame:
        import pandas
        return pandas.DataFrame({name: columns[name] for name in names})
    return np.rec.fromarrays([columns[name] for name in names], names=list(names))


def _series_table(columns, names, as_frame):
    """The time series (or samples) as a table; None when there are no rows.

    The energy balance is closed when a run ends, so a run that stopped early
    has no energy_residual column: it is NaN there.
    """
    rows = len(columns["time"])
    if rows == 0:
        return None
    full = {name: columns[name] if len(columns[name]) == rows else np.full(rows, np.nan) for name in names}
    return _table(full, names, as_frame)


class Result:
    """What ``Scene.simulate`` returns.

    Attributes:
        metrics: summary.json's metrics by name (SI units; ``impact_count`` as
            a float; ``jump_speed_rpm`` is ``inf`` when the law never decelerates;
            ``peak_contact_stress`` only with materials and ``max_face_excursion``
            only for a flat face, absent otherwise). None when the run failed
            (``failed``): a run cut short has no metrics to trust.
        failed: True when the run did not reach its end (``simulate(check=False)``);
            ``status`` and ``solver["message"]`` say why.
        status: how the run ended: ``"converged"``, ``"step_budget"``, ...
        solver: how the run ended (``termination``, ``converged``, ``message``)
            and what it cost (``steps``, ``rhs_evaluations``, ...), under
            summary.json's ``solver`` names.
        timeseries: the columns of ``TIMESERIES_UNITS`` at the config's output
            step, then a follower train's (``TRAIN_COLUMN_UNITS``; ``column_unit``
            gives any column's unit): a numpy record array
            (``r.timeseries["contact_force"]``, or ``r.timeseries.contact_force``),
            or a pandas DataFrame.
        events: contact onsets and separations (``EVENT_UNITS``), likewise.
            None with ``series=False``.
        samples: the state at ``sample_times`` (the columns of ``timeseries``), or None.
        model: the model's ``states``, force ``elements``, ``cam``,
            ``follower`` and ``contact_pair`` (summary.json ``model``).
        metrics_over: ``"window"`` or ``"periodic_orbit"`` (simulation.steady_state).
        steady_state: with simulation.steady_state, the orbit found or why not.
    """

    def __init__(self, raw, model, as_frame):
        names = raw["timeseries_columns"]
        self.solver = raw["solver"]
        # The metrics of a run cut short are over part of the window, or none
        # of it (all zero): they would read like a good design.
        self.metrics = dict(raw["metrics"]) if self.solver["converged"] else None
        self.timeseries = _series_table(raw["timeseries"], names, as_frame)
        # Its own columns: a train's are named when its first row is, so a run
        # without a series (series=False) names them only in its samples.
        self.samples = _series_table(raw["samples"], list(raw["samples"]), as_frame)
        self.events = _table(raw["events"], list(EVENT_UNITS), as_frame)
        self.model = model
        self.metrics_over = raw["metrics_over"]
        self.steady_state = raw["steady_state"]

    @property
    def converged(self):
        return self.solver["converged"]

    @property
    def failed(self):
        return not self.solver["converged"]

    @property
    def status(self):
        return self.solver["termination"]

    def __repr__(self):
        if self.failed:
            return f"<camdyn.Result {self.status} (failed, no metrics): {self.solver['message']}>"
        return (f"<camdyn.Result {self.solver['termination']}: separation_fraction "
                f"{self.metrics['separation_fraction']:.4g}, peak_contact_force "
                f"{self.metrics['peak_contact_force']:.6g} N>")


class Scene:
    """A checked scene: a cam-follower mechanism and how to run it.

    Make one with ``camdyn.load(path, set=...)``, ``Scene.from_dict(d)`` or
    ``Scene.from_json(text)``. Loading checks everything ``camdyn validate``
    checks and raises ``InputError`` naming the dotted path. Threads may
    simulate one scene at once; ``set`` changes one field in place.
    """

    def __init__(self, impl):
        self._impl = impl

    @classmethod
    def load(cls, path, set=None):
        """Reads a config file as ``camdyn run PATH --set ...`` does (``extends`` resolved)."""
        return cls(_camdyn._Scene.load(_path("path", path), _overrides(set)))

    @classmethod
    def from_json(cls, text, base_dir=None, set=None):
        """A scene from a config's JSON text; relative file names resolve against base_dir (default: cwd)."""
        if not isinstance(text, str):
            raise _argument_error("text", f"must be the config's JSON text as str, got {type(text).__name__}")
        return cls(_camdyn._Scene.from_json(text, _path("base_dir", base_dir) if base_dir else "", _overrides(set)))

    @classmethod
    def from_dict(cls, config, base_dir=None, set=None):
        """A scene from a config as a dict (as json.load gives it)."""
        return cls.from_json(_json_value("config", config), base_dir, set)

    def set(self, path, value):
        """Sets one field by its dotted path ("cam.rpm", "contact.stiffness"),
        checked as the config loader checks it (InputError naming the path),
        without loading the config file again. A change that leaves the cam's
        geometry as it is (speed, masses, springs, contact) keeps the geometry
        and runs to the bit as a scene loaded with that override. Returns the
        scene, so calls chain."""
        if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
            self._impl.set_text(str(path), value if isinstance(value, str) else _json_value(str(path), value))
        else:
            try:
                number = float(value)
            except OverflowError:
                raise _argument_error(str(path), f"expected a finite number, got {value}") from None
            self._impl.set(str(path), number)  # NaN and inf are refused there, by name
        return self

    @property
    def name(self):
        return self._impl.name

    @property
    def rpm(self):
        """The cam speed the scene runs at [rpm]."""
        return self._impl.rpm

    @property
    def resolved(self):
        """The fully resolved config (every default filled in), as a dict."""
        return json.loads(self._impl.resolved_json())

    @property
    def model(self):
        """The model's states, force elements, drive, follower and contact pair (summary.json ``model``)."""
        return self._impl.model()

    def jump_speed(self):
        """The rigid-model jump speed [rpm]; inf when the law never decelerates."""
        return self._impl.jump_speed_rpm()

    def profile(self, points=360):
        """The cam's outline in the cam frame: ``u`` [rad], ``contour_x/y`` [m], ``pitch_x/y`` [m].

        points: 3 … 1,000,000 (the cap of ``camdyn export --points``); InputError otherwise.
        """
        return self._impl.profile(_integer("points", points, 3, _camdyn._MAX_POINTS_PER_CALL,
                                           " (the cap of camdyn export --points)"))

    def law(self, angles_deg):
        """The motion law at cam angles [deg]: ``s`` [m], ``ds`` [m/rad], ``d2s`` [m/rad^2], ``d3s`` [m/rad^3].

        angles_deg: finite numbers, at most 1,000,000; InputError otherwise.
        """
        return self._impl.law(_numbers("angles_deg", angles_deg, "[deg]"))

    def simulate(self, *, series=True, sample_times=None, jobs=1, check=True, as_frame=None):
        """Simulates the scene as ``camdyn run`` does and returns a ``Result``.

        series: record the time series at the config's output step.
        sample_times: extra times [s] at which the state is sampled
            (``Result.samples``): finite, ascending, within the run (0 to
            ``solver["simulated_time_s"]``), at most 1,000,000.
        jobs: threads for simulation.steady_state's orbit search (0: one per core; at most 1024).
        check: raise ``SolverError`` (with ``termination`` and the partial
            ``result``) when the run did not converge; with False, read
            ``result.failed`` and ``result.status`` instead (its metrics are None).
        as_frame: tables as pandas DataFrames (True), numpy record arrays
            (False), or DataFrames when pandas can be imported (None).

        A bad argument raises ``InputError`` naming it (``path``) before
        anything runs. Ctrl-C (a Python signal handler that raises) stops a
        run on the main thread within about a second.
        """
        times = [] if sample_times is None else _numbers("sample_times", sample_times, "[s]").tolist()
        raw = self._impl.simulate(bool(series), times, _integer("jobs", jobs, 0, _camdyn._MAX_JOBS))
        result = Result(raw, self.model, as_frame)
        if check and not result.converged:
            error = SolverError(result.solver["message"] or result.solver["termination"])
            error.termination = result.solver["termination"]
            error.result = result
            raise error
        return result

    def __repr__(self):
        return f"<camdyn.Scene {self.name!r} at {self.rpm:g} rpm>"


def load(path, set=None):
    """Loads and checks a config file: ``camdyn.load("studies/quickstart.json", set={"cam.rpm": 1200})``.

    ``set`` overrides fields as ``--set`` does: a dict of dotted paths to
    values, or strings ``"cam.rpm=1200"``. Raises ``InputError``.
    """
    return Scene.load(path, set)


def jump_speed(scene):
    """The scene's rigid-model jump speed [rpm] (inf when the law never decelerates)."""
    return scene.jump_speed()


def profile(scene, n=360):
    """The cam's contour and pitch curve at n points (dict of arrays; see Scene.profile)."""
    return scene.profile(n)


def law(scene, angles):
    """s, s', s'', s''' of the motion law at cam angles [deg] (dict of arrays; see Scene.law)."""
    return scene.law(angles)


def _read_main_output(path):
    if path.endswith(".csv"):
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
        header, body = rows[0], rows[1:]
        return {name: [row[i] for row in body] for i, name in enumerate(header)}
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def run_study(config, out=None, jobs=0, set=None, base_dir=None):
    """Runs a study config as ``camdyn run`` does and returns its main result as a dict.

    config: a config file's path, or a config as a dict (its relative file
        names resolve against base_dir, default the current directory).
    out: the output folder; None runs in a temporary folder that is removed
        afterwards (only the returned dict remains, and nothing is printed
        that names the folder).
    jobs: parallel jobs for the studies that run many simulations (0: one per core).
    set: overrides, as for ``load``.

    The dict is the study's main JSON output: result.json (optimize),
    identified.json (identify), comparison.json (compare), periodic.json,
    jump_map.json, speed_limit.json or summary.json (simulate); for a
    convergence study, work_precision.csv's columns (as strings).
    Raises InputError and SolverError as the CLI exits 2 and 3.
    """
    jobs = _integer("jobs", jobs, 0, _camdyn._MAX_JOBS)
    if isinstance(config, dict):
        file, text = "", _json_value("config", config)
        base = _path("base_dir", base_dir) if base_dir else ""
    else:
        file, text, base = _path("config", config), "", ""
    overrides = _overrides(set)
    folder = _path("out", out) if out is not None else None
    with tempfile.TemporaryDirectory(prefix="camdyn-") as scratch:
        # The study's stdout summary names its report: not printed for a folder deleted on return.
        outcome = _camdyn.run_study(file, text, base, overrides, folder if folder is not None else scratch, jobs, out is not None)
        if outcome["exit_code"] != 0:
            raise Error(f"the {outcome['study']} study stopped with exit code {outcome['exit_code']}")
        return _read_main_output(outcome["main_output"])
