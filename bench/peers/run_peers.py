#!/usr/bin/env python3
"""Peers side by side (issue 15, item 5): the long-flight scene
(studies/peers/long_flight.json) through

  camdyn   the release binary (compliant Hunt-Crossley contact, CVODE BDF);
  scipy    an independent reference written here: the same compliant model,
           solve_ivp with events on the true roller/cam gap;
  siconos  an independent Moreau-Jean time-stepping model written here
           (rigid contact, Newton impact law), when python3-siconos imports.

Prints wall time, steps, impacts, impact angle and speed, max gap per peer and
the time ratios camdyn/peer; --json writes the numbers; --check K compares the
first K impacts of camdyn and scipy and exits 1 when they disagree.

Run with /usr/bin/python3 (Debian, numpy + scipy) from the repository root:
  python3 bench/peers/run_peers.py --camdyn build/release/camdyn
Exit status: 0 done, 1 --check failed, 2 bad input, 3 a peer failed,
77 scipy missing (CTest counts the test as skipped).
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import time

try:
    import numpy as np
    from scipy.integrate import solve_ivp
    from scipy.interpolate import PPoly, make_interp_spline
except ImportError as missing:  # the CTest skips on 77
    print(f"run_peers.py: skipped: {missing} (Debian: python3-scipy)", file=sys.stderr)
    sys.exit(77)

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCENE = os.path.join(ROOT, "studies", "peers", "long_flight.json")

# --check tolerances on the first K impacts, camdyn against scipy (README:
# "Why these tolerances").
ANGLE_TOL_DEG = 0.1
SPEED_TOL_REL = 5e-3


def fail(code, message):
    print(f"run_peers.py: {message}", file=sys.stderr)
    sys.exit(code)


# ---------------------------------------------------------------- the scene


def expect(cond, path, reason):
    if not cond:
        fail(2, f"{SCENE_FILE}: {path}: {reason} (run_peers.py models only the long-flight scene's mechanism)")


SCENE_FILE = SCENE


class Scene:
    """The parameters run_peers.py's own models use, read from the scene file
    and checked to be of the kind they model: a centred translating roller
    follower on a table cam at constant speed, Hunt-Crossley contact, no
    damper, gravity or friction."""

    def __init__(self, path, degree=5):
        global SCENE_FILE
        SCENE_FILE = path
        try:
            with open(path, encoding="utf-8") as f:
                cfg = json.load(f)
        except (OSError, ValueError) as err:
            fail(2, f"{path}: cannot read: {err}")
        try:
            self._read(cfg, path, degree)
        except (AttributeError, KeyError, TypeError, ValueError) as err:
            fail(2, f"{path}: not a scene run_peers.py models (a table cam and a translating roller): {err!r}")

    def _read(self, cfg, path, degree):
        mech = cfg.get("mechanism", {})
        cam, fol, con = mech.get("cam", {}), mech.get("follower", {}), mech.get("contact", {})
        table = cam.get("motion_law", {}).get("table")
        expect(isinstance(table, dict) and "file" in table, "mechanism.cam.motion_law.table", "a lift table is needed")
        expect(table.get("degree", 5) == 5, "mechanism.cam.motion_law.table.degree", "only 5 (quintic) is modelled")
        expect(fol.get("motion") == "translating", "mechanism.follower.motion", "must be translating")
        expect(fol.get("offset", 0.0) == 0.0, "mechanism.follower.offset", "must be 0")
        expect(fol.get("shape", {}).get("type") == "roller", "mechanism.follower.shape.type", "must be roller")
        expect(fol.get("damping", 0.0) == 0.0, "mechanism.follower.damping", "must be 0")
        expect(cfg.get("gravity", 0.0) == 0.0, "gravity", "must be 0")
        expect(con.get("model") == "hunt_crossley", "mechanism.contact.model", "must be hunt_crossley")
        expect(con.get("friction", {}).get("mu", 0.0) == 0.0, "mechanism.contact.friction.mu", "must be 0")
        expect(fol.get("initial", {}).get("position") is None, "mechanism.follower.initial.position",
               "must be null (in contact at rest)")
        expect(fol.get("initial", {}).get("velocity", 0.0) == 0.0, "mechanism.follower.initial.velocity", "must be 0")
        expect(cam.get("initial_angle_deg", 0.0) == 0.0, "mechanism.cam.initial_angle_deg", "must be 0")
        self.path = path
        self.base_radius = float(cam["base_radius"])  # [m]
        self.omega = float(cam["rpm"]) * 2.0 * math.pi / 60.0  # [rad/s]
        expect(cam.get("direction", "ccw") == "ccw", "mechanism.cam.direction", "must be ccw")
        self.roller_radius = float(fol["shape"]["radius"])  # [m]
        self.mass = float(fol["mass"])  # [kg]
        self.stiffness = float(fol["spring"]["stiffness"])  # [N/m]
        self.preload = float(fol["spring"]["preload"])  # [N]
        self.contact_k = float(con["stiffness"])  # [N/m^n]
        self.contact_n = float(con["exponent"])
        self.restitution = float(con["restitution"])
        self.v_ref = float(con.get("reference_velocity", 0.01))  # [m/s]
        integ = cfg.get("integrator", {})
        self.rtol = float(integ.get("rtol", 1e-8))
        self.atol = float(integ.get("atol", 1e-12))
        self.law = TableLaw(os.path.join(os.path.dirname(path), table["file"]),
                            table.get("angle_column", "angle_deg"), table.get("lift_column", "lift"), degree)
        self.interpolation = {5: "quintic", 3: "cubic"}[degree]
        self.y0 = self.base_radius + self.roller_radius  # lowest roller-centre height [m]
        self.period = 2.0 * math.pi / self.omega  # one revolution [s]


class TableLaw:
    """The lift table as camdyn reads it: the periodic quintic interpolating
    spline with knots at the rows (scipy make_interp_spline, bc periodic; for
    odd degree its knots are the data sites, as camdyn's PeriodicBSpline),
    turned into piecewise polynomials on the uniform grid for scalar
    evaluation without scipy's per-call overhead. degree 3 gives the periodic
    cubic spline instead (--interpolation cubic), to see what it changes."""

    def __init__(self, path, angle_column, lift_column, degree=5):
        angles, lifts = [], []
        try:
            with open(path, encoding="ascii") as f:
                for row in csv.DictReader(f):
                    angles.append(float(row[angle_column]))
                    lifts.append(float(row[lift_column]))
        except (OSError, KeyError, ValueError) as err:
            fail(2, f"{path}: cannot read the lift table: {err}")
        if angles and angles[-1] == 360.0:
            angles.pop()
            lifts.pop()
        x = np.radians(np.array(angles + [360.0]))
        y = np.array(lifts + [lifts[0]])
        self.spline = make_interp_spline(x, y, k=degree, bc_type="periodic")
        self.ppoly = PPoly.from_spline(self.spline)
        breaks = self.ppoly.x
        # Pieces of the periodic spline over [0, 2 pi): the breaks are the rows.
        first = np.searchsorted(breaks, 0.0, side="right") - 1
        self.n = len(angles)
        self.h = 2.0 * math.pi / self.n
        if not np.allclose(x[:-1], np.arange(self.n) * self.h, atol=1e-12):
            fail(2, f"{path}: run_peers.py needs a uniform angle grid")
        coeffs = np.zeros((6, self.n))  # highest power first, padded to degree 5
        coeffs[5 - degree:, :] = self.ppoly.c[:, first:first + self.n]
        self.pieces = [tuple(coeffs[:, i]) for i in range(self.n)]
        self.max_s = float(np.max(self.spline(np.linspace(0.0, 2.0 * math.pi, 20 * self.n))))

    def eval(self, u):
        """s, s', s'' [m, m/rad, m/rad^2] at cam angle u [rad]."""
        u = u % (2.0 * math.pi)
        i = int(u / self.h)
        if i >= self.n:
            i = self.n - 1
        x = u - i * self.h
        c5, c4, c3, c2, c1, c0 = self.pieces[i]
        s = ((((c5 * x + c4) * x + c3) * x + c2) * x + c1) * x + c0
        ds = (((5.0 * c5 * x + 4.0 * c4) * x + 3.0 * c3) * x + 2.0 * c2) * x + c1
        d2s = ((20.0 * c5 * x + 12.0 * c4) * x + 6.0 * c3) * x + 2.0 * c2
        return s, ds, d2s

    def eval_array(self, u, nu=0):
        return self.spline(np.mod(u, 2.0 * math.pi), nu)


# ---------------------------------------------------------------- geometry


class Gap:
    """The roller's true gap to the cam: the signed distance of the roller
    centre C = (0, y0 + q) from the pitch curve (the path of the roller centre
    in contact; the contour is its inner offset by the roller radius, so the
    roller surface's gap to the contour equals that distance). The pitch point
    at cam-frame angle u is, in the world, W(u) = rho(u) (sin a, cos a) with
    rho = y0 + s(u), a = u - theta. Its nearest point is found by Newton on
    f(u) = (W - C).W'(u) = 0, warm-started from the last solution; the contact
    point is off the follower axis wherever s' != 0."""

    def __init__(self, scene):
        self.law = scene.law
        self.y0 = scene.y0
        self.alpha = 0.0  # last u - theta [rad]

    def at(self, q, theta):
        """(g [m], g_q = dg/dq, g_theta = dg/dtheta [m/rad]) at follower
        displacement q [m] and cam angle theta [rad]."""
        theta = theta % (2.0 * math.pi)  # so that theta + a resolves steps of 1e-15 rad
        a = self._nearest(q, theta, self.alpha)
        if a is None:  # lost: restart from the nearest of a fine sampling
            grid = np.linspace(-math.pi, math.pi, 1441)
            rho = self.y0 + self.law.eval_array(theta + grid)
            a = self._nearest(q, theta, float(grid[np.argmin(rho * rho - 2.0 * (self.y0 + q) * rho * np.cos(grid))]))
            if a is None:
                raise RuntimeError(f"gap: no nearest pitch point at q = {q} m, theta = {theta} rad")
        a = (a + math.pi) % (2.0 * math.pi) - math.pi
        self.alpha = a
        s, ds, _ = self.law.eval(theta + a)
        rho = self.y0 + s
        sa, ca = math.sin(a), math.cos(a)
        w1x, w1y = ds * sa + rho * ca, ds * ca - rho * sa
        norm = math.hypot(w1x, w1y)
        nx, ny = -w1y / norm, w1x / norm  # outward normal (the curve runs clockwise)
        g = nx * (-rho * sa) + ny * (self.y0 + q - rho * ca)
        # dg/dtheta at fixed q: the curve turns with the cam, dW/dtheta = J W.
        g_theta = -(nx * (-rho * ca) + ny * (rho * sa))
        return g, ny, g_theta

    def _nearest(self, q, theta, a):
        """u - theta of the nearest pitch point by Newton from a; None if lost."""
        Y = self.y0 + q
        step = 1.0
        for _ in range(60):
            s, ds, d2s = self.law.eval(theta + a)
            rho = self.y0 + s
            sa, ca = math.sin(a), math.cos(a)
            w1x, w1y = ds * sa + rho * ca, ds * ca - rho * sa
            w2x = d2s * sa + 2.0 * ds * ca - rho * sa
            w2y = d2s * ca - 2.0 * ds * sa - rho * ca
            dx, dy = rho * sa, rho * ca - Y  # W - C
            f = dx * w1x + dy * w1y
            fp = w1x * w1x + w1y * w1y + dx * w2x + dy * w2y
            step = -f / fp if fp > 0.0 else -math.copysign(0.05, f)
            step = max(-0.1, min(0.1, step))
            a += step
            if abs(step) < 1e-14:
                return a
        return a if abs(step) < 1e-11 else None  # converged to the rounding floor

    def far_bound(self, q):
        """A lower bound of the gap [m] (0 when contact may be near)."""
        return max(0.0, self.y0 + q - (self.y0 + self.law.max_s) - 0.05)


def pressure_cos(law, y0, theta):
    """cos of the pressure angle of a centred roller at cam angle theta."""
    s, ds, _ = law.eval(theta)
    rho = y0 + s
    return rho / math.hypot(rho, ds)


# ---------------------------------------------------------------- camdyn


def run_camdyn(binary, scene, revolutions, discard):
    with tempfile.TemporaryDirectory(prefix="camdyn_peers_") as out:
        cmd = [binary, "run", scene.path, "--out", out, "--quiet",
               "--set", f"simulation.cycles={revolutions}", "--set", f"simulation.discard_cycles={discard}"]
        start = time.perf_counter()
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
        wall = time.perf_counter() - start
        if proc.returncode != 0:
            fail(3, f"camdyn exited {proc.returncode}: {' '.join(cmd)}\n{proc.stderr}")
        with open(os.path.join(out, "summary.json"), encoding="utf-8") as f:
            summary = json.load(f)
        impacts = []
        with open(os.path.join(out, "events.csv"), encoding="ascii") as f:
            for row in csv.DictReader(f):
                if row["kind"] == "onset" and row["impact"] == "1":
                    impacts.append((float(row["time"]), float(row["cam_angle_deg"]), float(row["speed"])))
    solver, metrics = summary["solver"], summary["metrics"]
    return {
        "model": "compliant Hunt-Crossley, CVODE BDF, differential tracking" if solver.get("tracking") ==
                 "differential" else f"compliant Hunt-Crossley, CVODE BDF, {solver.get('tracking')} tracking",
        "wall_s": wall,
        "run_time_s": solver.get("run_time_s"),
        "steps": solver.get("steps"),
        "rhs_evaluations": solver.get("rhs_evaluations"),
        "restarts": solver.get("restarts"),
        "projections": solver.get("tracking_projections"),
        "impacts": impacts,
        "impact_count_reported": metrics.get("impact_count"),
        "max_gap_reported": metrics.get("max_separation_gap"),
        "max_impact_velocity_reported": metrics.get("max_impact_velocity"),
    }


# ---------------------------------------------------------------- scipy


class Compliant:
    """The compliant model: m q'' = F_n g_q - (F0 + k q), F_n = K d^n (1 +
    3 (1 - e)/2 d'/v0) for d = -g > 0 (clamped at 0), v0 the approach speed
    at the onset (never below the reference velocity)."""

    def __init__(self, scene):
        self.sc = scene
        self.gap = Gap(scene)
        self.v0 = scene.v_ref
        self.hc = 1.5 * (1.0 - scene.restitution)

    def contact_rhs(self, t, x):
        sc = self.sc
        q, v = x
        g, g_q, g_th = self.gap.at(q, sc.omega * t)
        force = 0.0
        if g < 0.0:
            delta_rate = -(g_q * v + g_th * sc.omega)
            force = max(0.0, sc.contact_k * (-g) ** sc.contact_n * (1.0 + self.hc * delta_rate / self.v0))
        return [v, (force * g_q - sc.preload - sc.stiffness * q) / sc.mass]

    def flight_rhs(self, t, x):
        sc = self.sc
        return [x[1], -(sc.preload + sc.stiffness * x[0]) / sc.mass]

    def flight_jac(self, t, x):
        return [[0.0, 1.0], [-self.sc.stiffness / self.sc.mass, 0.0]]

    def accel_bound(self, x_a, x_b):
        """A bound of |q''| [m/s^2] in flight between the states x_a and x_b."""
        sc = self.sc
        return (sc.preload + sc.stiffness * max(abs(x_a[0]), abs(x_b[0]))) / sc.mass

    def gap_event(self, t, x):
        bound = self.gap.far_bound(x[0])
        return bound if bound > 0.0 else self.gap.at(x[0], self.sc.omega * t)[0]

    def approach_speed(self, t, x):
        _, g_q, g_th = self.gap.at(x[0], self.sc.omega * t)
        return -(g_q * x[1] + g_th * self.sc.omega)


def max_gap_of(sol, model, t_from):
    """Largest true gap [m] of a flight segment's dense output after t_from."""
    a, b = max(sol.t[0], t_from), sol.t[-1]
    if b <= a:
        return None
    omega = model.sc.omega
    ts = np.linspace(a, b, 65)
    gaps = [model.gap.at(sol.sol(t)[0], omega * t)[0] for t in ts]
    i = int(np.argmax(gaps))
    lo, hi = ts[max(i - 1, 0)], ts[min(i + 1, len(ts) - 1)]
    for _ in range(60):  # golden section on the unimodal neighbourhood
        m1, m2 = hi - 0.618 * (hi - lo), lo + 0.618 * (hi - lo)
        if model.gap.at(sol.sol(m1)[0], omega * m1)[0] < model.gap.at(sol.sol(m2)[0], omega * m2)[0]:
            lo = m1
        else:
            hi = m2
    tm = 0.5 * (lo + hi)
    return max(max(gaps), model.gap.at(sol.sol(tm)[0], omega * tm)[0])


# A touch shorter than this [s] may be missed in flight (README: its depth
# and speed are far below anything the metrics resolve).
MIN_SCAN_STEP = 1e-6


class Segment:
    """What one solve_ivp-like segment did: steps, evaluations, its dense
    output (sol(t)), and the event (t, x) that ended it, if any."""

    def __init__(self):
        self.steps = self.nfev = self.njev = 0
        self.t = []
        self.sol = None
        self.event = None


def fly(model, t0, x0, t_end, method):
    """Free flight from (t0, x0) until the gap closes or t_end. The solver's
    steps are scanned for contact by conservative advancement: from a sample
    with gap g the next is g / V later, V a bound of the closing speed (the
    follower's speed plus the cam surface's, at most omega times the pitch
    curve's largest radius), so no contact longer than MIN_SCAN_STEP is
    stepped over (solve_ivp's events look only at step ends and miss the
    short grazes of the return stroke); the onset is then found by brentq."""
    from scipy.integrate import DOP853, LSODA, RK45, BDF, Radau, OdeSolution
    from scipy.optimize import brentq
    sc = model.sc
    solvers = {"DOP853": DOP853, "RK45": RK45, "Radau": Radau, "BDF": BDF, "LSODA": LSODA}
    if method not in solvers:
        fail(2, f"--flight-method {method}: one of {', '.join(solvers)}")
    kw = {"jac": model.flight_jac} if method in ("Radau", "BDF", "LSODA") else {}
    solver = solvers[method](model.flight_rhs, t0, x0, t_end, rtol=sc.rtol, atol=sc.atol, **kw)
    seg = Segment()
    ts, interpolants = [t0], []
    surface_speed = sc.omega * (sc.y0 + sc.law.max_s)  # [m/s]

    def gap(t, x):
        bound = model.gap.far_bound(x[0])
        return bound if bound > 0.0 else model.gap.at(x[0], sc.omega * t)[0]

    while seg.event is None and solver.status == "running":
        t_old, x_old = solver.t, solver.y.copy()
        message = solver.step()
        if solver.status == "failed":
            fail(3, f"scipy {method} failed in flight at t = {t_old} s: {message}")
        seg.steps += 1
        dense = solver.dense_output()
        ts.append(solver.t)
        interpolants.append(dense)
        accel = model.accel_bound(x_old, solver.y)
        closing = max(abs(x_old[1]), abs(solver.y[1])) + accel * (solver.t - t_old) + surface_speed
        tau, g = t_old, gap(t_old, x_old)
        while tau < solver.t:
            nxt = min(solver.t, tau + max(g / closing, MIN_SCAN_STEP))
            g_nxt = gap(nxt, dense(nxt))
            if g_nxt <= 0.0:
                t_hit = brentq(lambda t: gap(t, dense(t)), tau, nxt, xtol=1e-15, rtol=4 * np.finfo(float).eps) if g > 0.0 else tau
                seg.event = (t_hit, list(dense(t_hit)))
                ts[-1] = t_hit
                break
            tau, g = nxt, g_nxt
    seg.nfev, seg.njev = solver.nfev, getattr(solver, "njev", 0)
    seg.t = ts
    seg.sol = OdeSolution(ts, interpolants)
    return seg


def touch(model, t0, x0, t_end, method):
    """A contact episode from (t0, x0) until the gap opens or t_end."""
    sc = model.sc

    def opening(t, x):  # separation: the gap opens
        return model.gap.at(x[0], sc.omega * t)[0]

    opening.terminal, opening.direction = True, 1.0
    sol = solve_ivp(model.contact_rhs, (t0, t_end), x0, method=method, rtol=sc.rtol, atol=sc.atol, events=opening)
    if sol.status < 0:
        fail(3, f"scipy {method} failed in contact at t = {t0} s: {sol.message}")
    seg = Segment()
    seg.steps, seg.nfev, seg.njev = len(sol.t) - 1, sol.nfev, sol.njev
    if sol.status == 1:
        seg.event = (float(sol.t_events[0][0]), list(sol.y_events[0][0]))
    return seg


def run_scipy(scene, revolutions, discard, flight_method, contact_method):
    model = Compliant(scene)
    t_end = revolutions * scene.period
    t_from = discard * scene.period
    # In contact at rest at cam angle 0, at static equilibrium: K d^n = F0 + k q.
    s0 = scene.law.eval(0.0)[0]
    q = s0
    for _ in range(5):
        q = s0 - ((scene.preload + scene.stiffness * q) / scene.contact_k) ** (1.0 / scene.contact_n)
    x, t = [q, 0.0], 0.0
    contact = True
    impacts, max_gap = [], 0.0
    steps = nfev = njev = segments = 0
    start = time.perf_counter()
    while t < t_end:
        seg = touch(model, t, x, t_end, contact_method) if contact else fly(model, t, x, t_end, flight_method)
        steps += seg.steps
        nfev += seg.nfev
        njev += seg.njev
        segments += 1
        if not contact:
            gap = max_gap_of(seg, model, t_from)
            if gap is not None:
                max_gap = max(max_gap, gap)
        if seg.event is None:
            break
        t, x = seg.event
        if not contact:
            speed = model.approach_speed(t, x)
            impacts.append((t, math.degrees(scene.omega * t), speed))
            model.v0 = max(speed, scene.v_ref)
        contact = not contact
    wall = time.perf_counter() - start
    return {
        "model": f"compliant Hunt-Crossley, {flight_method} in flight, solve_ivp {contact_method} in contact, "
                 f"{scene.interpolation} table spline",
        "wall_s": wall,
        "steps": steps,
        "rhs_evaluations": nfev,
        "jacobian_evaluations": njev,
        "restarts": segments - 1,
        "impacts": impacts,
        "max_gap": max_gap,
    }


def hunt_crossley_restitution(scene):
    """The rebound/approach speed ratio of the scene's Hunt-Crossley law in a
    straight impact of a free mass (m d'' = -K d^n (1 + c d'/v0)): it does not
    depend on m, K or v0 (scaling), and for e = 0.8 it is above e, since the
    3 (1 - e)/2 factor is exact only as e -> 1 (Flores et al. 2011)."""
    c = 1.5 * (1.0 - scene.restitution)
    n = scene.contact_n

    def rhs(t, x):
        d = max(x[0], 0.0)
        return [x[1], -(d ** n) * (1.0 + c * x[1])]

    def out(t, x):
        return x[0]

    out.terminal, out.direction = True, -1.0
    # Units m = K = v0 = 1: not stiff; the contact lasts ~3.
    sol = solve_ivp(rhs, (0.0, 100.0), [0.0, 1.0], method="DOP853", rtol=1e-12, atol=1e-14, events=out,
                    first_step=1e-6)
    return -float(sol.y_events[0][0][1])


# ---------------------------------------------------------------- siconos


def step_loop(n_steps, forcing, heights, state, compute, advance):
    """The Moreau-Jean step loop: sets each step's forcing, steps (compute,
    advance), records the height z in heights and returns the impacts as
    (step, z before, z' before). state = (fExt, q, velocity, impulse) views."""
    f_ext, z, zdot, lam = state
    impact_steps = []
    flying = False
    for i in range(n_steps):
        f_ext[0] = forcing[i]
        z_before, v_before = z[0], zdot[0]
        compute()
        if lam[0] > 0.0:
            if flying:
                impact_steps.append((i, z_before, v_before))
            flying = False
        elif z[0] > FLIGHT_HEIGHT:
            flying = True
        heights[i + 1] = z[0]
        advance()
    return impact_steps


def python_loop_overhead(n_steps, forcing):
    """Wall time [s] of step_loop without the Siconos calls: the part of the
    Siconos peer's wall time that a C++ driver would not spend."""
    def nothing():
        pass

    state = (np.zeros(1), np.zeros(1), np.zeros(1), np.zeros(1))
    start = time.perf_counter()
    step_loop(n_steps, forcing, np.empty(n_steps + 1), state, nothing, nothing)
    return time.perf_counter() - start


# Above this height [m] with no impulse in the step the Moreau-Jean follower
# is in flight, and its next impulse is an impact (not persistent contact).
FLIGHT_HEIGHT = 1e-9


def run_siconos(scene, revolutions, discard, dt, restitution):
    """Moreau-Jean on the relative coordinate z = q - s(theta(t)): the
    follower's height above the cam along its axis. In it the follower is a
    LagrangianLinearTIDS, m z'' + k z = -(F0 + k s + m w^2 s'') + r, and the
    cam is the fixed boundary z >= 0 (LagrangianLinearTIR y = z) with a
    Newton impact law z'+ = -e z'-; the cam's motion enters as the inertial
    and spring forcing, set at each step's midpoint. z = 0 exactly where the
    true gap is 0, and there the normal relative speed is cos(phi) z', so the
    Newton law on z is the one on the normal gap."""
    try:
        import siconos.kernel as sk
    except ImportError as err:
        return {"skipped": f"siconos not importable ({err}; Debian: python3-siconos)"}
    law = scene.law
    w = scene.omega
    t_end = revolutions * scene.period
    n_steps = int(round(t_end / dt))
    t_mid = (np.arange(n_steps) + 0.5) * dt
    forcing = -(scene.preload + scene.stiffness * law.eval_array(w * t_mid) +
                scene.mass * w * w * law.eval_array(w * t_mid, 2))
    ds = sk.LagrangianLinearTIDS([0.0], [0.0], [[scene.mass]])
    ds.setKPtr(np.array([[scene.stiffness]]))
    ds.setFExtPtr(np.array([forcing[0]]))
    inter = sk.Interaction(sk.NewtonImpactNSL(restitution), sk.LagrangianLinearTIR(np.array([[1.0]])))
    nsds = sk.NonSmoothDynamicalSystem(0.0, n_steps * dt)
    nsds.insertDynamicalSystem(ds)
    nsds.link(inter, ds)
    sim = sk.TimeStepping(nsds, sk.TimeDiscretisation(0.0, dt), sk.MoreauJeanOSI(0.5), sk.LCP())
    state = (ds.fExt(), ds.q(), ds.velocity(), inter.lambda_(1))
    heights = np.empty(n_steps + 1)
    heights[0] = 0.0
    start = time.perf_counter()
    impact_steps = step_loop(n_steps, forcing, heights, state, sim.computeOneStep, sim.nextStep)
    wall = time.perf_counter() - start
    overhead = python_loop_overhead(n_steps, forcing)
    impacts = []
    for i, z_before, v_before in impact_steps:
        # The impact inside step i, at z_before + z' tau = 0 (first order).
        tau = min(dt, max(0.0, z_before / -v_before)) if v_before < 0.0 else 0.0
        t = i * dt + tau
        impacts.append((t, math.degrees(w * t), -v_before * pressure_cos(law, scene.y0, w * t)))
    # Max true gap over the window: near each revolution's highest z.
    gap = Gap(scene)
    max_gap = 0.0
    first = int(math.ceil(discard * scene.period / dt))
    per_rev = int(scene.period / dt)
    for lo in range(first, n_steps + 1, per_rev):
        hi = min(lo + per_rev, n_steps + 1)
        j = lo + int(np.argmax(heights[lo:hi]))
        for k in range(max(lo, j - 400), min(hi, j + 401), 4):
            th = w * k * dt
            q = heights[k] + law.eval(th)[0]
            gap.alpha = 0.0
            max_gap = max(max_gap, gap.at(q, th)[0])
    return {
        "model": f"rigid, Newton impact law e = {restitution:.4f}, Siconos MoreauJeanOSI(0.5) + LCP, dt {dt:g} s, "
                 f"{scene.interpolation} table spline",
        "restitution": restitution,
        "wall_s": wall,
        "python_loop_s": overhead,
        "steps": n_steps,
        "impacts": impacts,
        "max_gap": max_gap,
    }


# ---------------------------------------------------------------- report


def window_stats(result, t_from):
    window = [imp for imp in result["impacts"] if imp[0] >= t_from]
    stats = {"impacts_in_window": len(window)}
    if window:
        stats["mean_impact_angle_deg"] = float(np.mean([a % 360.0 for _, a, _ in window]))
        stats["last_impact_angle_deg"] = window[-1][1] % 360.0
        stats["mean_impact_speed"] = float(np.mean([v for _, _, v in window]))
        stats["last_impact_speed"] = window[-1][2]
    return stats


def fmt(value, spec):
    return format(value, spec) if isinstance(value, (int, float)) else "-"


def print_table(results, t_from):
    print(f"{'peer':8} {'wall s':>8} {'steps':>9} {'impacts':>7} {'mean ang':>9} {'last ang':>9} "
          f"{'mean v':>8} {'last v':>8} {'max gap':>8} {'camdyn/peer':>11}")
    camdyn_wall = results.get("camdyn", {}).get("wall_s")
    for name, r in results.items():
        if "skipped" in r:
            print(f"{name:8} skipped: {r['skipped']}")
            continue
        st = r["window"]
        ratio = camdyn_wall / r["wall_s"] if camdyn_wall else None
        gap = r.get("max_gap", r.get("max_gap_reported"))
        print(f"{name:8} {r['wall_s']:8.2f} {r['steps']:9d} {st['impacts_in_window']:7d} "
              f"{fmt(st.get('mean_impact_angle_deg'), '9.3f')} {fmt(st.get('last_impact_angle_deg'), '9.3f')} "
              f"{fmt(st.get('mean_impact_speed'), '8.3f')} {fmt(st.get('last_impact_speed'), '8.3f')} "
              f"{fmt(gap, '8.4f')} {fmt(ratio, '11.3f')}")
    c = results.get("camdyn")
    if c and "skipped" not in c:
        print(f"camdyn: run_time_s {c['run_time_s']:.2f} (integration), restarts {c['restarts']}, "
              f"tracking projections {c['projections']}, impact_count {c['impact_count_reported']}")
    k = results.get("siconos")
    if k and "skipped" not in k:
        bare = k["wall_s"] - k["python_loop_s"]
        print(f"siconos: {k['python_loop_s']:.2f} s of its wall time is the Python step loop itself (timed "
              f"without the Siconos calls); without it {bare:.2f} s"
              + (f", camdyn/siconos {c['wall_s'] / bare:.3f}" if c and "skipped" not in c else ""))
    print("(angles in deg mod 360, speeds = normal approach speed in m/s, max gap in m, over the window; "
          "camdyn/peer > 1: camdyn slower)")


def check_impacts(a, b, count):
    """Compares the first `count` impacts of a and b; returns the failures."""
    failures, rows = [], []
    if len(a) < count or len(b) < count:
        failures.append(f"fewer than {count} impacts: camdyn {len(a)}, scipy {len(b)}")
    for k, (ia, ib) in enumerate(zip(a[:count], b[:count])):
        d_angle = abs(ia[1] - ib[1])
        d_speed = abs(ia[2] - ib[2]) / max(abs(ib[2]), 1e-300)
        rows.append((k + 1, ia[1], ib[1], d_angle, ia[2], ib[2], d_speed))
        if not d_angle <= ANGLE_TOL_DEG:
            failures.append(f"impact {k + 1}: angle {ia[1]:.6f} deg against {ib[1]:.6f} deg")
        if not d_speed <= SPEED_TOL_REL:
            failures.append(f"impact {k + 1}: speed {ia[2]:.6f} m/s against {ib[2]:.6f} m/s")
    print(f"{'impact':>6} {'camdyn deg':>12} {'scipy deg':>12} {'|d| deg':>9} {'camdyn m/s':>11} "
          f"{'scipy m/s':>11} {'rel d':>9}")
    for row in rows:
        print(f"{row[0]:6d} {row[1]:12.5f} {row[2]:12.5f} {row[3]:9.2e} {row[4]:11.5f} {row[5]:11.5f} {row[6]:9.2e}")
    return failures, rows



def write_json_atomically(path, value):
    """Writes `value` as indented JSON to `path` through a temporary file, so a
    killed run never leaves a partial file."""
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump(value, f, indent=2)
        f.write("\n")
    os.replace(tmp, path)

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--camdyn", default=os.path.join(ROOT, "build", "release", "camdyn"), help="camdyn binary")
    ap.add_argument("--scene", default=SCENE, help="the scene (default studies/peers/long_flight.json)")
    ap.add_argument("--revolutions", type=int, default=200, help="revolutions (metrics over the last half)")
    ap.add_argument("--peers", default="camdyn,scipy,siconos", help="comma-separated subset")
    ap.add_argument("--flight-method", default="DOP853", help="solve_ivp method in flight (default DOP853)")
    ap.add_argument("--contact-method", default="Radau", help="solve_ivp method in contact (default Radau)")
    ap.add_argument("--interpolation", choices=("quintic", "cubic"), default="quintic",
                    help="the table spline of the scipy and siconos peers (camdyn's is quintic)")
    ap.add_argument("--siconos-dt", type=float, default=1e-5, help="Moreau-Jean time step [s]")
    ap.add_argument("--siconos-restitution", default="scene",
                    help="the Newton law's e: 'scene' (the contact's restitution, default), 'matched' (the "
                         "Hunt-Crossley law's actual rebound ratio) or a number")
    ap.add_argument("--check", type=int, default=0, metavar="K",
                    help=f"compare camdyn's first K impacts with scipy's (angle within {ANGLE_TOL_DEG} deg, "
                         f"speed within {100 * SPEED_TOL_REL:.1f} %%); exit 1 if not")
    ap.add_argument("--json", help="write the numbers here")
    args = ap.parse_args()
    if args.revolutions < 2:
        fail(2, f"--revolutions {args.revolutions}: must be at least 2")
    if not args.siconos_dt > 0.0:
        fail(2, f"--siconos-dt {args.siconos_dt}: must be > 0")
    peers = [p.strip() for p in args.peers.split(",") if p.strip()]
    for p in peers:
        if p not in ("camdyn", "scipy", "siconos"):
            fail(2, f"--peers: unknown peer '{p}' (camdyn, scipy, siconos)")
    if args.check and not {"camdyn", "scipy"} <= set(peers):
        fail(2, "--check needs the peers camdyn and scipy")
    scene = Scene(os.path.abspath(args.scene), 5 if args.interpolation == "quintic" else 3)
    discard = args.revolutions // 2
    t_from = discard * scene.period
    if "camdyn" in peers and not os.access(args.camdyn, os.X_OK):
        fail(2, f"--camdyn {args.camdyn}: not an executable (build it: cmake --build build/release --target camdyn)")

    e_hc = hunt_crossley_restitution(scene)
    if args.siconos_restitution == "scene":
        siconos_e = scene.restitution
    elif args.siconos_restitution == "matched":
        siconos_e = e_hc
    else:
        try:
            siconos_e = float(args.siconos_restitution)
        except ValueError:
            siconos_e = -1.0
        if not 0.0 <= siconos_e <= 1.0:
            fail(2, f"--siconos-restitution {args.siconos_restitution}: 'scene', 'matched' or a number in [0, 1]")
    results = {}
    for name in peers:
        print(f"running {name} ...", file=sys.stderr, flush=True)
        if name == "camdyn":
            results[name] = run_camdyn(args.camdyn, scene, args.revolutions, discard)
        elif name == "scipy":
            results[name] = run_scipy(scene, args.revolutions, discard, args.flight_method, args.contact_method)
        else:
            results[name] = run_siconos(scene, args.revolutions, discard, args.siconos_dt, siconos_e)
        if "skipped" not in results[name]:
            results[name]["window"] = window_stats(results[name], t_from)
    print(f"scene {os.path.relpath(scene.path)}: {args.revolutions} revolutions at "
          f"{scene.omega * 30.0 / math.pi:g} rpm, metrics over the last {args.revolutions - discard}; "
          f"the Hunt-Crossley law (e = {scene.restitution:g}) rebounds at {e_hc:.4f} of the approach speed")
    print_table(results, t_from)
    out = {"scene": os.path.relpath(scene.path, ROOT), "revolutions": args.revolutions, "discard": discard,
           "interpolation": scene.interpolation,
           "machine": {"cpus": os.cpu_count(), "load_avg": list(os.getloadavg())},
           "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
           "hunt_crossley_rebound_ratio": e_hc, "peers": {}}
    for name, r in results.items():
        entry = {k: v for k, v in r.items() if k != "impacts"}
        if "impacts" in r:
            entry["first_impacts"] = [{"time_s": t, "angle_deg": a, "speed": v} for t, a, v in r["impacts"][:10]]
            if "wall_s" in results.get("camdyn", {}) and name != "camdyn":
                entry["camdyn_over_peer_wall"] = results["camdyn"]["wall_s"] / r["wall_s"]
        out["peers"][name] = entry
    status = 0
    if args.check:
        failures, rows = check_impacts(results["camdyn"]["impacts"], results["scipy"]["impacts"], args.check)
        out["check"] = {"impacts": args.check, "angle_tol_deg": ANGLE_TOL_DEG, "speed_tol_rel": SPEED_TOL_REL,
                        "max_angle_diff_deg": max((r[3] for r in rows), default=None),
                        "max_speed_diff_rel": max((r[6] for r in rows), default=None), "failures": failures}
        for msg in failures:
            print(f"CHECK FAILED: {msg}", file=sys.stderr)
        status = 1 if failures else 0
        if not failures:
            print(f"check: the first {args.check} impacts agree (angle within {ANGLE_TOL_DEG} deg, "
                  f"speed within {SPEED_TOL_REL:.1%})")
    if args.json:
        write_json_atomically(args.json, out)
    return status


if __name__ == "__main__":
    sys.exit(main())
