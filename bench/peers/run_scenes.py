#!/usr/bin/env python3
"""camdyn against an independent scipy reference on every scene of issue 38,
in one run (issue 38, item 4):

  long_flight    studies/peers/long_flight.json (a table cam, Hunt-Crossley,
                 200 revolutions of long flights; run_peers.py's scene)
  quickstart     studies/quickstart.json (cycloidal cam at 1300 rpm,
                 Lankarani-Nikravesh contact, follower damper: it jumps and
                 hammers back)
  stiff_contact  studies/peers/stiff_contact.json (the quickstart mechanism at
                 100 rpm on an undamped Hertz contact, no damper, rtol 1e-10:
                 bench/stiff_contact_bench.cc's scene); stiff_contact_adams
                 and stiff_contact_erk: the same with camdyn's
                 integrator.method cvode_adams, resp. arkode_erk of order 8;
                 stiff_contact_dop853: with camdyn's own DOP853

For each scene: camdyn's wall time as a user sees it (the release CLI with
every default output, process start included; the median of --repeat runs)
and its reported run_time_s; the CPU time of camdyn's simulation alone, the
work the reference's time covers (bench/peer_scenes_bench: no process start,
no time series, no outputs); the scipy reference's wall and CPU time (one
run); the ratios scipy/camdyn of both; and an agreement check of the two answers (first impacts,
steady impact angle and speed, largest gap, peak and least contact force)
within the tolerances in CHECKS. Writes --json (bench/results/peers_scenes.json).

The scipy references are run_peers.py's compliant model (the true roller/cam
gap, Radau or DOP853 in contact, DOP853 in flight scanned by conservative
advancement), extended here to the analytic cycloidal law, the Hertz and
Lankarani-Nikravesh laws and the follower damper, all from docs/model.md.

  /usr/bin/python3 bench/peers/run_scenes.py --json bench/results/peers_scenes.json
  /usr/bin/python3 bench/peers/run_scenes.py --scenes quickstart,stiff_contact --repeat 1
Exit status: 0 done and agreeing, 1 an agreement check failed, 2 bad input,
3 a peer failed, 77 scipy missing (CTest counts the test as skipped).
"""
import argparse
import csv
import json
import math
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_peers as rp  # noqa: E402  (exits 77 without numpy/scipy)

np = rp.np
solve_ivp = rp.solve_ivp
ROOT = rp.ROOT


def fail(code, message):
    print(f"run_scenes.py: {message}", file=sys.stderr)
    sys.exit(code)


# ---------------------------------------------------------------- analytic law


class CycloidalLaw:
    """A rise/dwell/return law of cycloidal segments (docs/config.md's
    segment form): over a segment of span b [rad] and lift h [m], at x from
    its start, the rise is s = h (x/b - sin(2 pi x/b)/(2 pi)) and the return
    h minus that. Same interface as run_peers.TableLaw."""

    def __init__(self, path):
        try:
            with open(path, encoding="utf-8") as f:
                spec = json.load(f)
        except (OSError, ValueError) as err:
            fail(2, f"{path}: cannot read the motion law: {err}")
        self.segments = []  # (start, end [rad], kind, lift at start, lift change [m])
        start, lift = 0.0, 0.0
        for i, seg in enumerate(spec.get("segments", [])):
            end = math.radians(float(seg["end_deg"]))
            kind = seg["type"]
            if kind != "dwell" and seg.get("law") != "cycloidal":
                fail(2, f"{path}: segments[{i}].law: only cycloidal is modelled here")
            change = {"rise": float(seg.get("lift", 0.0)), "return": -float(seg.get("lift", 0.0)), "dwell": 0.0}[kind]
            self.segments.append((start, end, lift, change))
            start, lift = end, lift + change
        if abs(start - 2.0 * math.pi) > 1e-12 or abs(lift) > 1e-15:
            fail(2, f"{path}: the segments must close the cycle at 360 deg and zero lift")
        self.max_s = max(s0 + max(0.0, c) for _, _, s0, c in self.segments)

    def eval(self, u):
        """s, s', s'' [m, m/rad, m/rad^2] at cam angle u [rad]."""
        u = u % (2.0 * math.pi)
        for a, b, s0, h in self.segments:
            if u < b:
                break
        if h == 0.0:
            return s0, 0.0, 0.0
        span = b - a
        z = 2.0 * math.pi * (u - a) / span
        return (s0 + h * ((u - a) / span - math.sin(z) / (2.0 * math.pi)), h / span * (1.0 - math.cos(z)),
                h * 2.0 * math.pi / (span * span) * math.sin(z))

    def eval_array(self, u, nu=0):
        return np.array([self.eval(x)[nu] for x in np.atleast_1d(u)])


# ---------------------------------------------------------------- the scene

# chi of F_n = K d^n (1 + chi d'/v0) (docs/model.md section 3)
CHI = {
    "hertz": lambda e: 0.0,
    "hunt_crossley": lambda e: 1.5 * (1.0 - e),
    "lankarani_nikravesh": lambda e: 0.75 * (1.0 - e * e),
}


class SceneSpec:
    """The parameters of a centred translating roller follower on a cam at
    constant speed (a table or a cycloidal law) with a Hertz-family contact,
    an optional follower damper, no gravity or friction."""

    def __init__(self, path):
        try:
            with open(path, encoding="utf-8") as f:
                cfg = json.load(f)
        except (OSError, ValueError) as err:
            fail(2, f"{path}: cannot read: {err}")
        mech = cfg.get("mechanism", {})
        cam, fol, con = mech.get("cam", {}), mech.get("follower", {}), mech.get("contact", {})

        def expect(cond, where, reason):
            if not cond:
                fail(2, f"{path}: {where}: {reason} (not a scene run_scenes.py models)")

        expect(fol.get("motion") == "translating", "mechanism.follower.motion", "must be translating")
        expect(fol.get("offset", 0.0) == 0.0, "mechanism.follower.offset", "must be 0")
        expect(fol.get("shape", {}).get("type") == "roller", "mechanism.follower.shape.type", "must be roller")
        expect(cfg.get("gravity", 0.0) == 0.0, "gravity", "must be 0")
        expect(con.get("model") in CHI, "mechanism.contact.model", f"one of {', '.join(CHI)}")
        expect(con.get("friction", {}).get("mu", 0.0) == 0.0, "mechanism.contact.friction.mu", "must be 0")
        expect(fol.get("initial", {}).get("position") is None, "mechanism.follower.initial.position", "must be null")
        expect(fol.get("initial", {}).get("velocity", 0.0) == 0.0, "mechanism.follower.initial.velocity", "must be 0")
        expect(cam.get("direction", "ccw") == "ccw", "mechanism.cam.direction", "must be ccw")
        law = cam.get("motion_law")
        if isinstance(law, dict) and "table" in law:
            table = law["table"]
            self.law = rp.TableLaw(os.path.join(os.path.dirname(path), table["file"]),
                                   table.get("angle_column", "angle_deg"), table.get("lift_column", "lift"), 5)
        elif isinstance(law, str):
            self.law = CycloidalLaw(os.path.join(ROOT, law))
        else:
            fail(2, f"{path}: mechanism.cam.motion_law: a table or a profiles/*.json of cycloidal segments")
        self.path = path
        self.name = cfg.get("name", os.path.basename(path))
        self.omega = float(cam["rpm"]) * 2.0 * math.pi / 60.0  # [rad/s]
        self.roller_radius = float(fol["shape"]["radius"])  # [m]
        self.y0 = float(cam["base_radius"]) + self.roller_radius  # lowest roller-centre height [m]
        self.mass = float(fol["mass"])  # [kg]
        self.stiffness = float(fol["spring"]["stiffness"])  # [N/m]
        self.preload = float(fol["spring"]["preload"])  # [N]
        self.damping = float(fol.get("damping", 0.0))  # follower damper c [N s/m]
        self.contact_model = con["model"]
        self.contact_k = float(con["stiffness"])  # [N/m^n]
        self.contact_n = float(con["exponent"])
        self.restitution = float(con.get("restitution", 0.8))
        self.chi = CHI[self.contact_model](self.restitution)
        self.v_ref = float(con.get("reference_velocity", 0.01))  # [m/s]
        sim, integ = cfg.get("simulation", {}), cfg.get("integrator", {})
        self.cycles = float(sim.get("cycles", 1))
        self.discard = float(sim.get("discard_cycles", 0))
        self.rtol = float(integ.get("rtol", 1e-8))
        self.atol = float(integ.get("atol", 1e-12))
        self.period = 2.0 * math.pi / self.omega  # one revolution [s]


class Model:
    """m q'' = F_n g_q - (F0 + k q) - c q', F_n = max(0, K d^n (1 + chi d'/v0))
    for d = -g > 0, v0 the approach speed at the onset (never below the
    reference velocity); g the true gap of run_peers.Gap."""

    def __init__(self, scene):
        self.sc = scene
        self.gap = rp.Gap(scene)
        self.v0 = scene.v_ref

    def force(self, t, x):
        sc = self.sc
        g, g_q, g_th = self.gap.at(x[0], sc.omega * t)
        if g >= 0.0:
            return 0.0, g_q
        delta_rate = -(g_q * x[1] + g_th * sc.omega)
        return max(0.0, sc.contact_k * (-g) ** sc.contact_n * (1.0 + sc.chi * delta_rate / self.v0)), g_q

    def contact_rhs(self, t, x):
        sc = self.sc
        f, g_q = self.force(t, x)
        return [x[1], (f * g_q - sc.preload - sc.stiffness * x[0] - sc.damping * x[1]) / sc.mass]

    def flight_rhs(self, t, x):
        sc = self.sc
        return [x[1], -(sc.preload + sc.stiffness * x[0] + sc.damping * x[1]) / sc.mass]

    def flight_jac(self, t, x):
        sc = self.sc
        return [[0.0, 1.0], [-sc.stiffness / sc.mass, -sc.damping / sc.mass]]

    def accel_bound(self, x_a, x_b):
        sc = self.sc
        q, v = max(abs(x_a[0]), abs(x_b[0])), max(abs(x_a[1]), abs(x_b[1]))
        return (sc.preload + sc.stiffness * q + sc.damping * v) / sc.mass

    def approach_speed(self, t, x):
        _, g_q, g_th = self.gap.at(x[0], self.sc.omega * t)
        return -(g_q * x[1] + g_th * self.sc.omega)


# ---------------------------------------------------------------- scipy


def touch(model, t0, x0, t_end, method, t_from, extremes):
    """A contact episode from (t0, x0) until the gap opens or t_end; updates
    extremes = [peak force, its bracket, least force, its bracket] over
    t >= t_from from the accepted steps, a bracket being the neighbouring
    steps' times, the dense output and the episode's v0."""
    sc = model.sc

    def opening(t, x):
        return model.gap.at(x[0], sc.omega * t)[0]

    opening.terminal, opening.direction = True, 1.0
    sol = solve_ivp(model.contact_rhs, (t0, t_end), x0, method=method, rtol=sc.rtol, atol=sc.atol, events=opening,
                    dense_output=True)
    if sol.status < 0:
        fail(3, f"scipy {method} failed in contact at t = {t0} s: {sol.message}")
    ts = sol.t
    for i in range(len(ts)):
        if ts[i] >= t_from:
            f = model.force(ts[i], sol.y[:, i])[0]
            bracket = (ts[max(i - 1, 0)], ts[min(i + 1, len(ts) - 1)], sol.sol, model.v0)
            if f > extremes[0]:
                extremes[0:2] = [f, bracket]
            if f < extremes[2]:
                extremes[2:4] = [f, bracket]
    seg = rp.Segment()
    seg.steps, seg.nfev, seg.njev = len(sol.t) - 1, sol.nfev, sol.njev
    if sol.status == 1:
        seg.event = (float(sol.t_events[0][0]), list(sol.y_events[0][0]))
    return seg


def refine_extreme(model, bracket, sign):
    """The force's extreme (sign +1: max, -1: min) between the two steps
    around the largest (least) step value, by golden section on the dense
    output (the steps are a small fraction of a contact vibration apart)."""
    lo, hi, dense, v0 = bracket
    v0_now, model.v0 = model.v0, v0  # the episode's onset speed

    def f(t):
        return sign * model.force(t, dense(t))[0]

    for _ in range(60):
        m1, m2 = hi - 0.618 * (hi - lo), lo + 0.618 * (hi - lo)
        if f(m1) > f(m2):
            hi = m2
        else:
            lo = m1
    extreme = sign * f(0.5 * (lo + hi))
    model.v0 = v0_now
    return extreme


def run_scipy(scene, flight_method, contact_method):
    model = Model(scene)
    t_end = scene.cycles * scene.period
    t_from = scene.discard * scene.period
    # In contact at rest at cam angle 0, in static equilibrium: K d^n = F0 + k q.
    s0 = scene.law.eval(0.0)[0]
    q = s0
    for _ in range(8):
        q = s0 - ((scene.preload + scene.stiffness * q) / scene.contact_k) ** (1.0 / scene.contact_n)
    x, t = [q, 0.0], 0.0
    contact = True
    impacts, max_gap = [], 0.0
    extremes = [-math.inf, None, math.inf, None]
    steps = nfev = njev = segments = 0
    start, cpu_start = time.perf_counter(), time.process_time()
    while t < t_end:
        if contact:
            seg = touch(model, t, x, t_end, contact_method, t_from, extremes)
        else:
            seg = rp.fly(model, t, x, t_end, flight_method)
            gap = rp.max_gap_of(seg, model, t_from)
            if gap is not None:
                max_gap = max(max_gap, gap)
            extremes[2] = min(extremes[2], 0.0) if seg.t[-1] > t_from else extremes[2]
        steps += seg.steps
        nfev += seg.nfev
        njev += seg.njev
        segments += 1
        if seg.event is None:
            break
        t, x = seg.event
        if not contact:
            speed = model.approach_speed(t, x)
            impacts.append((t, math.degrees(scene.omega * t), speed))
            model.v0 = max(speed, scene.v_ref)
        contact = not contact
    # The force's extremes between the accepted steps.
    peak, least = extremes[0], extremes[2]
    if extremes[1] is not None:
        peak = max(peak, refine_extreme(model, extremes[1], 1.0))
    if extremes[3] is not None and least > 0.0:
        least = min(least, refine_extreme(model, extremes[3], -1.0))
    wall, cpu = time.perf_counter() - start, time.process_time() - cpu_start
    return {"model": f"compliant {scene.contact_model}, solve_ivp {contact_method} in contact, {flight_method} in "
                     "flight (conservative advancement + brentq for onsets)",
            "wall_s": wall, "cpu_s": cpu, "steps": steps, "rhs_evaluations": nfev, "jacobian_evaluations": njev,
            "restarts": segments - 1, "impacts": impacts, "max_gap": max_gap,
            "peak_contact_force": peak, "min_contact_force": least}


# ---------------------------------------------------------------- camdyn


def run_camdyn_once(binary, scene, out, overrides):
    """(wall, CPU) seconds of one CLI run, process start and outputs included."""
    cmd = [binary, "run", scene.path, "--out", out, "--quiet"]
    for o in overrides:
        cmd += ["--set", o]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        fail(3, f"camdyn exited {proc.returncode}: {' '.join(cmd)}\n{proc.stderr}")
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def run_camdyn(binary, scene, repeat, overrides):
    walls, cpus = [], []
    with tempfile.TemporaryDirectory(prefix="camdyn_scenes_") as base:
        for i in range(repeat):
            out = os.path.join(base, str(i))
            wall, cpu = run_camdyn_once(binary, scene, out, overrides)
            walls.append(wall)
            cpus.append(cpu)
        with open(os.path.join(out, "summary.json"), encoding="utf-8") as f:
            summary = json.load(f)
        impacts = []
        with open(os.path.join(out, "events.csv"), encoding="ascii") as f:
            for row in csv.DictReader(f):
                if row["kind"] == "onset" and row["impact"] == "1":
                    impacts.append((float(row["time"]), float(row["cam_angle_deg"]), float(row["speed"])))
    solver, metrics = summary["solver"], summary["metrics"]
    method = {"cvode_bdf": "CVODE BDF", "cvode_adams": "CVODE Adams", "arkode_erk": "ARKODE ERK",
              "arkode_dirk": "ARKODE DIRK", "dop853": "camdyn's DOP853"}.get(solver.get("method"), solver.get("method"))
    order = [o.split("=", 1)[1] for o in overrides if o.startswith("integrator.order=")]
    method += f" order {order[-1]}" if order else ""
    return {"model": f"compliant {scene.contact_model}, {method}, {solver.get('tracking')} tracking",
            "overrides": overrides,
            "wall_s": statistics.median(walls), "wall_s_runs": walls,
            "cpu_s": statistics.median(cpus), "cpu_s_runs": cpus, "run_time_s": solver.get("run_time_s"),
            "steps": solver.get("steps"), "rhs_evaluations": solver.get("rhs_evaluations"),
            "error_test_failures": solver.get("error_test_failures"), "restarts": solver.get("restarts"),
            "impacts": impacts, "impact_count_reported": metrics.get("impact_count"),
            "max_gap": metrics.get("max_separation_gap"),
            "peak_contact_force": metrics.get("peak_contact_force"),
            "min_contact_force": metrics.get("min_contact_force")}


# ---------------------------------------------------------------- agreement

# What must agree, per scene, camdyn against scipy. Impact angles [deg] and
# speeds [relative] as run_peers.py's --check (bench/peers/README.md: "Why the
# test tolerances"); window means, largest gap and contact-force extremes
# relative. Both integrate the same ODE at the scene's rtol, so their states
# differ by ~rtol per contact vibration; the tolerances sit well above what
# was measured (README there, "Every scene in one run") and far below what a
# wrong model gives (a wrong law or a missed touch moves these by percent).
CHECKS = {
    "long_flight": {"first_impacts": 5, "angle_deg": 0.1, "speed_rel": 5e-3, "window_rel": 1e-4},
    "quickstart": {"first_impacts": 5, "angle_deg": 0.1, "speed_rel": 5e-3, "window_rel": 1e-3},
    "stiff_contact": {"first_impacts": 0, "angle_deg": 0.1, "speed_rel": 5e-3, "window_rel": 2e-4},
}


def rel(a, b):
    if a is None or b is None:
        return math.inf
    return abs(a - b) / max(abs(b), 1e-300)


def agreement(name, scene, cam, ref):
    """Compares camdyn's answer with scipy's; returns (rows, failures)."""
    tol = CHECKS[name]
    rows, failures = [], []
    k = tol["first_impacts"]
    ia, ib = cam["impacts"], ref["impacts"]
    if len(ia) < k or len(ib) < k:
        failures.append(f"fewer than {k} impacts: camdyn {len(ia)}, scipy {len(ib)}")
    for i, (a, b) in enumerate(zip(ia[:k], ib[:k])):
        rows.append((f"impact {i + 1} angle deg", a[1], b[1], abs(a[1] - b[1]), tol["angle_deg"]))
        rows.append((f"impact {i + 1} speed m/s", a[2], b[2], rel(a[2], b[2]), tol["speed_rel"]))
    t_from = scene.discard * scene.period
    wa = [x for x in ia if x[0] >= t_from]
    wb = [x for x in ib if x[0] >= t_from]
    if len(wa) != len(wb):
        failures.append(f"impacts in the window: camdyn {len(wa)}, scipy {len(wb)}")
    elif wa:
        rows.append(("mean impact speed m/s", float(np.mean([x[2] for x in wa])), float(np.mean([x[2] for x in wb])),
                     None, tol["window_rel"]))
        rows.append(("largest gap m", cam["max_gap"], ref["max_gap"], None, tol["window_rel"]))
    rows.append(("peak contact force N", cam["peak_contact_force"], ref["peak_contact_force"], None, tol["window_rel"]))
    if ref["min_contact_force"] > 0.0 or cam["min_contact_force"] > 0.0:
        rows.append(("least contact force N", cam["min_contact_force"], ref["min_contact_force"], None,
                     tol["window_rel"]))
    out = []
    for what, a, b, diff, limit in rows:
        diff = rel(a, b) if diff is None else diff
        ok = bool(diff <= limit)
        if not ok:
            failures.append(f"{what}: camdyn {a}, scipy {b} (difference {diff:.3g} > {limit:g})")
        out.append({"quantity": what, "camdyn": float(a), "scipy": float(b), "difference": float(diff),
                    "tolerance": limit, "ok": ok})
    return out, failures


# ---------------------------------------------------------------- main

# name: (scene file, solve_ivp method in contact, camdyn --set overrides,
# the scene whose scipy reference it shares). DOP853 in the undamped contact:
# it resolves the contact vibration in a fifth of Radau's steps and CPU.
SCENES = {
    "long_flight": ("studies/peers/long_flight.json", "Radau", [], None),
    "quickstart": ("studies/quickstart.json", "Radau", [], None),
    "stiff_contact": ("studies/peers/stiff_contact.json", "DOP853", [], None),
    "stiff_contact_adams": ("studies/peers/stiff_contact.json", "DOP853", ["integrator.method=cvode_adams"],
                            "stiff_contact"),
    "stiff_contact_erk": ("studies/peers/stiff_contact.json", "DOP853",
                          ["integrator.method=arkode_erk", "integrator.order=8"], "stiff_contact"),
    "stiff_contact_dop853": ("studies/peers/stiff_contact.json", "DOP853", ["integrator.method=dop853"],
                             "stiff_contact"),
}
CHECKS["stiff_contact_adams"] = CHECKS["stiff_contact"]
CHECKS["stiff_contact_erk"] = CHECKS["stiff_contact"]
CHECKS["stiff_contact_dop853"] = CHECKS["stiff_contact"]


def run_simulation_bench(binary, name):
    """camdyn's simulation alone for scene `name` (bench/peer_scenes_bench.cc:
    the scene file loaded as the CLI loads it, no time series, no outputs):
    CPU seconds per run, Google Benchmark's mean over at least 0.5 s."""
    cmd = [binary, f"--benchmark_filter=^simulate_scene_file/{name}$", "--benchmark_format=json",
           "--benchmark_min_time=0.5"]
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        fail(3, f"{' '.join(cmd)} exited {proc.returncode}\n{proc.stderr}")
    runs = [b for b in json.loads(proc.stdout)["benchmarks"] if b.get("run_type", "iteration") == "iteration"]
    if len(runs) != 1:
        fail(3, f"{binary}: expected one benchmark for {name}, got {len(runs)}")
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[runs[0]["time_unit"]]
    return {"cpu_s": runs[0]["cpu_time"] * scale, "iterations": runs[0]["iterations"],
            "steps": runs[0].get("steps"), "peak_contact_force": runs[0].get("peak_contact_force_N")}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--camdyn", default=os.path.join(ROOT, "build", "release", "camdyn"), help="camdyn binary")
    ap.add_argument("--scenes", default=",".join(SCENES), help="comma-separated subset of " + ", ".join(SCENES))
    ap.add_argument("--repeat", type=int, default=3, help="camdyn runs per scene, the median wall reported")
    ap.add_argument("--contact-method", help="solve_ivp method in contact for every scene (default per scene)")
    ap.add_argument("--flight-method", default="DOP853", help="solve_ivp method in flight (default DOP853)")
    ap.add_argument("--simulation-bench", default=os.path.join(ROOT, "build", "release", "bench", "peer_scenes_bench"),
                    help="bench/peer_scenes_bench binary for camdyn's simulation alone ('none': skip that timing)")
    ap.add_argument("--json", help="write the numbers here")
    args = ap.parse_args()
    names = [s.strip() for s in args.scenes.split(",") if s.strip()]
    for n in names:
        if n not in SCENES:
            fail(2, f"--scenes: unknown scene '{n}' ({', '.join(SCENES)})")
    if args.repeat < 1:
        fail(2, f"--repeat {args.repeat}: must be at least 1")
    if not os.access(args.camdyn, os.X_OK):
        fail(2, f"--camdyn {args.camdyn}: not an executable (cmake --build build/release --target camdyn)")
    bench = None if args.simulation_bench == "none" else args.simulation_bench
    if bench and not os.access(bench, os.X_OK):
        fail(2, f"--simulation-bench {bench}: not an executable (cmake --build build/release --target "
                "peer_scenes_bench, or --simulation-bench none)")
    out = {"command": "/usr/bin/python3 bench/peers/run_scenes.py " + " ".join(sys.argv[1:]),
           "machine": {"cpus": os.cpu_count(), "load_avg_start": list(os.getloadavg())},
           "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "scenes": {}}
    status = 0
    print(f"{'scene':20} {'camdyn wall s':>13} {'cpu s':>7} {'sim cpu s':>9} {'scipy wall s':>12} {'cpu s':>7} "
          f"{'wall ratio':>10} {'cpu ratio':>9} {'sim ratio':>9} {'agree':>6} {'load':>5}")
    references = {}
    for name in names:
        rel_path, method, overrides, shares = SCENES[name]
        scene = SceneSpec(os.path.join(ROOT, rel_path))
        method = args.contact_method or method
        print(f"running {name}: camdyn ...", file=sys.stderr, flush=True)
        cam = run_camdyn(args.camdyn, scene, args.repeat, overrides)
        sim = run_simulation_bench(bench, name) if bench else None
        load_cam = os.getloadavg()[0]
        if shares in references:
            ref, load_ref = references[shares]
        else:
            print(f"running {name}: scipy ({method} in contact) ...", file=sys.stderr, flush=True)
            ref = run_scipy(scene, args.flight_method, method)
            load_ref = os.getloadavg()[0]
            references[name] = (ref, load_ref)
        rows, failures = agreement(name, scene, cam, ref)
        for msg in failures:
            print(f"AGREEMENT FAILED ({name}): {msg}", file=sys.stderr)
        status = 1 if failures else status
        ratio = ref["wall_s"] / cam["wall_s"]
        cpu_ratio = ref["cpu_s"] / cam["cpu_s"]
        sim_ratio = ref["cpu_s"] / sim["cpu_s"] if sim else None
        print(f"{name:20} {cam['wall_s']:13.3f} {cam['cpu_s']:7.3f} {sim['cpu_s'] if sim else math.nan:9.4f} "
              f"{ref['wall_s']:12.2f} {ref['cpu_s']:7.2f} {ratio:10.1f} {cpu_ratio:9.1f} "
              f"{sim_ratio if sim else math.nan:9.1f} {'yes' if not failures else 'NO':>6} {max(load_cam, load_ref):5.2f}")
        for r in rows:
            print(f"    {r['quantity']:24} camdyn {r['camdyn']:.9g}  scipy {r['scipy']:.9g}  "
                  f"diff {r['difference']:.2e} (tol {r['tolerance']:g})")
        print(f"    camdyn: {cam['steps']} steps, {cam['error_test_failures']} error-test failures, wall runs "
              + ", ".join(f"{w:.3f}" for w in cam["wall_s_runs"]) + f" s; scipy: {ref['steps']} steps, "
              f"{ref['rhs_evaluations']} right-hand sides")
        out["scenes"][name] = {
            "scene": rel_path, "camdyn_set": overrides, "scipy_shared_with": shares, "cycles": scene.cycles,
            "discard_cycles": scene.discard, "rtol": scene.rtol,
            "load_avg_1min": {"camdyn": load_cam, "scipy": load_ref},
            "camdyn": {k: v for k, v in cam.items() if k != "impacts"} | {"first_impacts": cam["impacts"][:5]},
            "scipy": {k: v for k, v in ref.items() if k != "impacts"} | {"first_impacts": ref["impacts"][:5]},
            "scipy_over_camdyn_wall": ratio, "scipy_over_camdyn_cpu": cpu_ratio,
            "scipy_over_camdyn_run_time": ref["wall_s"] / cam["run_time_s"],
            "camdyn_simulation": sim, "scipy_over_camdyn_simulation_cpu": sim_ratio,
            "agreement": {"ok": not failures, "rows": rows, "failures": failures}}
    out["machine"]["load_avg_end"] = list(os.getloadavg())
    if args.json:
        rp.write_json_atomically(args.json, out)
    return status


if __name__ == "__main__":
    sys.exit(main())
