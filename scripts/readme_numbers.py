#!/usr/bin/env python3
"""Every number the README quotes, regenerated from the committed studies.

A quoted number carries a marker right after it in README.md:

    a rigid-model jump speed of 1174<!-- num:quickstart.jump_speed_rpm --> rpm

(an HTML comment: invisible on the rendered page). NUMBERS below says, for
each key, which run gives it, how to read it from that run's outputs, how the
README writes it and how far the quoted value may be from the fresh one (the
tolerance covers the rounding of the quoted text and, for timings, the noise
of the machine). The runs are the committed studies run with the given
camdyn binary (one `camdyn run` each, into a temporary folder), or a
committed benchmark result (bench/results/*.json) for the timings and the
counters that only a benchmark measures: those are read, not rerun, so
that whoever reruns a benchmark updates its README numbers with --update.

    python3 scripts/readme_numbers.py --check [--camdyn build/ci/camdyn]
        exit 1 and list every quoted number that drifted (quoted, fresh,
        tolerance); also fails on a marker without an entry here, an
        entry without a marker in the README, or a quoted
        studies/quickstart.json that is not the file
    python3 scripts/readme_numbers.py --update [--camdyn ...]
        rewrite the drifted numbers in README.md with the fresh values
    add --slow to either to include the slow studies (work_precision)
    python3 scripts/readme_numbers.py --list
        the keys, their sources and tolerances (no runs)

Left out, and why (the README says where each comes from):
  * studies/work_precision.json (about a minute in a release build, four
    on a loaded machine): its table is checked only with --slow.
  * studies/stability.json (360 runs, several minutes): its counts of ok
    and failed runs are quoted with the command and the slow test that
    make them, and not checked here.
  * the bouncing ball's jump map (603 and 635 rpm): minutes; 603 rpm is the
    closed form the tests check against.
  * bounds that tests assert (e.g. "within 0.2 % of the closed form"): those
    are the tests' tolerances, checked by the tests themselves.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import csv
import html
import json
import math
import os
import re
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
MARKER = re.compile(r"(?P<num>-?\d[\d,]*(?:\.\d+)?(?:e[-+]?\d+)?)<!-- num:(?P<key>[\w.\-]+) -->")


# --- the runs -------------------------------------------------------------

QS = "studies/quickstart.json"
RUNS: dict[str, list[str]] = {
    "quickstart": [QS],
    "quickstart_richardson": [QS, "--set", "integrator.error_estimate=richardson"],
    "quickstart_900": [QS, "--set", "mechanism.cam.rpm=900"],
    "quickstart_1600": [QS, "--set", "mechanism.cam.rpm=1600"],
    "speed_limit": [QS, "--set", "study=speed_limit", "--set", 'speed_limit={"low_rpm": 600, "high_rpm": 1600}'],
    "speed_limit_undamped": [QS, "--set", "study=speed_limit", "--set", 'speed_limit={"low_rpm": 600, "high_rpm": 1600}',
                             "--set", "mechanism.follower.damping=0"],
    # The damped rigid-model jump speed, which jump_map.json reports (two speeds suffice).
    "quickstart_jump_map": [QS, "--set", "study=jump_map", "--set",
                            'jump_map={"low_rpm": 1000, "high_rpm": 1010, "speeds": 2, "ranges": 1, '
                            '"transient_revolutions": 1, "samples": 2}',
                            "--set", 'periodic={"max_period": 1, "lyapunov_revolutions": 10}'],
    "contour_cam": ["studies/contour_cam/measured_roller_cam.json"],
    "compare_laws": ["studies/compare_laws.json"],
    "optimize_jump": ["studies/optimize_jump.json"],
    "identify_drop": ["studies/identify_drop/identify_drop.json"],
    "identify_single_drop": ["studies/identify_drop/identify_single_drop.json"],
    "identify_single_drop_forward": ["studies/identify_drop/identify_single_drop.json", "--set",
                                     "solver.differences=forward"],
    "identify_cam_rig": ["studies/identify_cam_rig/identify_cam_rig.json"],
    "work_precision": ["studies/work_precision.json"],  # slow: minutes
}
SLOW_RUNS = {"work_precision"}  # run only with --slow


class Run:
    """The outputs of one finished run (its --out folder) and its stdout."""

    def __init__(self, out: Path, stdout: str):
        self.out, self.stdout = out, stdout

    def json(self, name: str) -> dict:
        return json.loads((self.out / name).read_text())

    def metric(self, key: str) -> float:
        return float(self.json("summary.json")["metrics"][key])

    def verdict(self) -> str:
        """The report's verdict banner as text."""
        text = (self.out / "report.html").read_text()
        match = re.search(r'<div class="verdict[^"]*" id="verdict">(.*?)</div>', text, re.S)
        if not match:
            raise LookupError("no verdict banner in report.html")
        return html.unescape(re.sub(r"<[^>]+>", "", match.group(1)))

    def verdict_number(self, pattern: str) -> float:
        match = re.search(pattern, self.verdict())
        if not match:
            raise LookupError(f"verdict {self.verdict()!r} does not match {pattern!r}")
        return float(match.group(1))

    def rows(self, name: str) -> list[dict]:
        with open(self.out / name, newline="") as f:
            return list(csv.DictReader(f))


def bench(file: str, name: str, field: str) -> float:
    """A field of one benchmark in a committed bench/results file."""
    data = json.loads((ROOT / "bench" / "results" / file).read_text())
    for b in data["benchmarks"]:
        if b["name"] == name:
            return float(b[field])
    raise LookupError(f"bench/results/{file}: no benchmark {name}")


def peer(name: str, field: str) -> float:
    """A field of one peer in bench/results/peers.json (bench/peers/run_peers.py)."""
    data = json.loads((ROOT / "bench" / "results" / "peers.json").read_text())
    return float(data["peers"][name][field])


def peer_scene(scene: str, path: tuple[str, ...]) -> float:
    """A field of one scene in bench/results/peers_scenes.json (bench/peers/run_scenes.py)."""
    data = json.loads((ROOT / "bench" / "results" / "peers_scenes.json").read_text())["scenes"][scene]
    for key in path:
        data = data[key]
    return float(data)


def law_row(run: Run, law: str) -> list[dict]:
    return [r for r in run.rows("comparison.csv") if r["case"] == law]


def first_separating_rpm(run: Run, law: str) -> float:
    return min(float(r["mechanism.cam.rpm"]) for r in law_row(run, law) if float(r["separation_fraction"]) > 0)


def work_precision_row(run: Run, scene: str, method: str, rtol: float | None, rk4_step_deg: float | None) -> dict:
    """The differential-tracking row of work_precision.csv for one method and tolerance (or rk4 step)."""
    for r in run.rows("work_precision.csv"):
        if r["scene"] != scene or r["method"] != method or r["tracking"] != "differential" or r["status"] != "ok":
            continue
        if rtol is not None and math.isclose(float(r["rtol"]), rtol):
            return r
        if rk4_step_deg is not None and r["step"]:
            rpm = 1300.0  # the quickstart scene's speed: the step in seconds is the angle step over ω
            if math.isclose(float(r["step"]), rk4_step_deg / 360 * 60 / rpm, rel_tol=1e-6):
                return r
    raise LookupError(f"work_precision.csv: no row {scene} {method} rtol {rtol} step {rk4_step_deg}°")


def identified(run: Run, name: str) -> dict:
    return run.json("identified.json")["parameters"][name]


def simulations(run: Run) -> float:
    return float(re.search(r"(\d+) simulations", run.stdout).group(1))


def reused(run: Run) -> float:
    return float(re.search(r"\((\d+) points reused\)", run.stdout).group(1))


def worst_drop_error(run: Run) -> float:
    """Largest relative error of the drop parameters against generate.py's true values [%]."""
    true = {"contact.stiffness": 2.5e9, "contact.exponent": 1.45, "contact.restitution": 0.7}
    return max(100 * abs(identified(run, k)["value"] / v - 1) for k, v in true.items())


def optimized_metric(run: Run, which: str, rpm: float, key: str) -> float:
    result = run.json("result.json")
    for entry in result[which]["metrics"]:
        if float(entry["rpm"]) == rpm:
            return float(entry[key])
    raise LookupError(f"result.json: no {which} metrics at {rpm} rpm")


# --- the numbers ----------------------------------------------------------


@dataclass
class Num:
    key: str
    source: str  # a RUNS name, or "bench" (bench/results, nothing is run)
    get: Callable[[Run | None], float]
    fmt: str  # how the README writes it: a format spec, or "e1" (1.2e-7), "e0" (5e-8), "comma" (7,126)
    tol: str  # "0.5" absolute, or "1%" relative to the fresh value

    def text(self, value: float) -> str:
        if self.fmt.startswith("e"):
            mantissa, exponent = f"{value:.{int(self.fmt[1:])}e}".split("e")
            return f"{mantissa}e{int(exponent)}"
        if self.fmt == "comma":
            return f"{value:,.0f}"
        return format(value, self.fmt)

    def allowed(self, fresh: float) -> float:
        return abs(fresh) * float(self.tol[:-1]) / 100 if self.tol.endswith("%") else float(self.tol)


def m(key: str) -> Callable[[Run], float]:
    return lambda r: r.metric(key)


NUMBERS = [
    # The quickstart report (studies/quickstart.json at 1300 rpm).
    Num("quickstart.jump_speed_rpm", "quickstart", m("jump_speed_rpm"), ".0f", "0.5"),
    Num("quickstart.impacts", "quickstart", m("impact_count"), ".0f", "0"),
    Num("quickstart.separation_percent", "quickstart", lambda r: 100 * r.metric("separation_fraction"), ".0f", "0.5"),
    Num("quickstart.peak_force_kN", "quickstart", lambda r: r.metric("peak_contact_force") / 1e3, ".1f", "0.05"),
    Num("quickstart.energy_residual", "quickstart", m("energy_residual"), "e1", "4%"),
    Num("quickstart.richardson_position_m", "quickstart_richardson",
        lambda r: r.json("summary.json")["solver"]["error_estimate"]["position"], "e1", "4%"),
    Num("quickstart.richardson_peak_force", "quickstart_richardson",
        lambda r: r.json("summary.json")["solver"]["error_estimate"]["peak_contact_force"], "e1", "5%"),
    # The verdict banners quoted in the outputs table.
    Num("verdict.900.min_force_N", "quickstart_900",
        lambda r: r.verdict_number(r"minimum contact force ([\d.]+) N"), ".1f", "0.05"),
    Num("verdict.900.angle_deg", "quickstart_900", lambda r: r.verdict_number(r"N at ([\d.]+)°"), ".1f", "0.05"),
    Num("verdict.1600.separates_deg", "quickstart_1600", lambda r: r.verdict_number(r"separates at ([\d.]+)°"),
        ".1f", "0.05"),
    Num("verdict.1600.lands_deg", "quickstart_1600", lambda r: r.verdict_number(r"lands at ([\d.]+)°"), ".1f",
        "0.05"),
    Num("verdict.1600.landing_speed", "quickstart_1600", lambda r: r.verdict_number(r"at ([\d.]+) m/s"), ".2f",
        "0.005"),
    Num("verdict.1600.jump_speed_rpm", "quickstart_1600",
        lambda r: r.verdict_number(r"jump speed ([\d.]+) rpm"), ".1f", "0.05"),
    # speed_limit on the quickstart.
    Num("speed_limit.rpm", "speed_limit", lambda r: r.json("speed_limit.json")["speed_limit_rpm"], ".0f", "0.5"),
    Num("speed_limit.undamped_rpm", "speed_limit_undamped", lambda r: r.json("speed_limit.json")["speed_limit_rpm"],
        ".0f", "0.5"),
    Num("speed_limit.undamped_below_percent", "speed_limit_undamped",
        lambda r: 100 * (1 - r.json("speed_limit.json")["speed_limit_rpm"] /
                         r.json("speed_limit.json")["rigid_jump_speed_rpm"]), ".1f", "0.05"),
    Num("jump_map.damped_jump_speed_rpm", "quickstart_jump_map",
        lambda r: r.json("jump_map.json")["damped_rigid_jump_speed_rpm"], ".0f", "0.5"),
    # The measured contour cam.
    Num("contour.rms_um", "contour_cam", lambda r: 1e6 * r.json("summary.json")["contour_fit"]["rms_residual"], ".1f",
        "0.05"),
    Num("contour.base_radius_mm", "contour_cam", lambda r: 1e3 * r.json("summary.json")["contour_fit"]["base_radius"],
        ".4f", "0.00005"),
    # The compare_laws table.
    *[Num(f"laws.{law}.jump_speed_rpm", "compare_laws",
          (lambda law: lambda r: float(law_row(r, law)[0]["jump_speed_rpm"]))(law), ".0f", "0.5")
      for law in ("polynomial_4567", "spline", "cycloidal", "polynomial_345", "modified_trapezoid", "modified_sine")],
    *[Num(f"laws.{law}.first_separating_rpm", "compare_laws",
          (lambda law: lambda r: first_separating_rpm(r, law))(law), ".0f", "0")
      for law in ("polynomial_4567", "spline", "cycloidal", "polynomial_345", "modified_trapezoid", "modified_sine")],
    # optimize_jump: the certificate and the result.
    Num("optimize.any_law_rpm", "optimize_jump", lambda r: r.json("result.json")["rigid_stage"]["certificate"]
        ["any_law_jump_free_rpm"], ".0f", "0.5"),
    Num("optimize.family_rpm", "optimize_jump", lambda r: r.json("result.json")["rigid_stage"]["certificate"]
        ["family_jump_free_rpm"], ".0f", "0.5"),
    Num("optimize.baseline_law_rpm", "optimize_jump", lambda r: r.json("result.json")["rigid_stage"]["certificate"]
        ["baseline_jump_free_rpm"], ".0f", "0.5"),
    Num("optimize.jump_speed_after_rpm", "optimize_jump",
        lambda r: optimized_metric(r, "optimized", 1300, "jump_speed_rpm"), ".0f", "0.5"),
    Num("optimize.separation_before", "optimize_jump",
        lambda r: optimized_metric(r, "baseline", 1300, "separation_fraction"), ".2f", "0.005"),
    Num("optimize.peak_force_before_N", "optimize_jump",
        lambda r: optimized_metric(r, "baseline", 1300, "peak_contact_force"), ".0f", "0.5"),
    Num("optimize.peak_force_after_N", "optimize_jump",
        lambda r: optimized_metric(r, "optimized", 1300, "peak_contact_force"), ".0f", "0.5"),
    # Identification.
    Num("identify.drop_worst_error_percent", "identify_drop", worst_drop_error, ".1f", "0.05"),
    Num("identify.single_drop_central_simulations", "identify_single_drop", simulations, ".0f", "0"),
    Num("identify.single_drop_forward_simulations", "identify_single_drop_forward", simulations, ".0f", "0"),
    Num("identify.cam_rig_stiffness", "identify_cam_rig", lambda r: identified(r, "contact.stiffness")["value"],
        "e3", "0.01%"),
    Num("identify.cam_rig_stiffness_error_percent", "identify_cam_rig",
        lambda r: 100 * abs(identified(r, "contact.stiffness")["value"] / 6e9 - 1), ".1f", "0.05"),
    Num("identify.cam_rig_damping", "identify_cam_rig", lambda r: identified(r, "follower.damping")["value"], ".6g",
        "0.00005"),
    Num("identify.cam_rig_damping_error_percent", "identify_cam_rig",
        lambda r: 100 * abs(identified(r, "follower.damping")["value"] / 20 - 1), ".3f", "0.0005"),
    Num("identify.cam_rig_simulations", "identify_cam_rig", simulations, ".0f", "0"),
    Num("identify.cam_rig_reused", "identify_cam_rig", reused, ".0f", "0"),
    # The work-precision table (studies/work_precision.json; slow: only with --slow).
    *[Num(f"wp.{scene}.{method}.{what}", "work_precision",
          (lambda scene, method, rtol, step, column: lambda r: float(
              work_precision_row(r, scene, method, rtol, step)[column]))(scene, method, rtol, step, column),
          fmt, tol)
      for scene, method, rtol, step in [("quickstart", "cvode_bdf", 1e-8, None), ("quickstart", "cvode_adams", 1e-8, None),
                                        ("quickstart", "arkode_erk", 1e-8, None),
                                        ("quickstart", "arkode_dirk", 1e-8, None), ("quickstart", "rk4", None, 0.0625),
                                        ("stiff", "cvode_bdf", 1e-8, None), ("stiff", "cvode_adams", 1e-8, None),
                                        ("stiff", "arkode_erk", 1e-6, None), ("stiff", "arkode_dirk", 1e-6, None)]
      for what, column, fmt, tol in [("error_m", "error_position", "e1", "5%"), ("rhs", "rhs_evaluations", "comma",
                                                                                 "1%")]],
    # Benchmarks (bench/results/*.json, release build, 2 cores): read, not rerun.
    Num("bench.long_flight.closed_form_s", "bench",
        lambda _: 1e-3 * bench("simulation.json", "BM_LongFlight/0/min_time:2.000", "real_time"), ".2f", "0.005"),
    Num("bench.long_flight.integrated_s", "bench",
        lambda _: 1e-3 * bench("simulation.json", "BM_LongFlight/1/iterations:1", "real_time"), ".1f", "0.05"),
    Num("bench.long_flight.restarts_per_impact", "bench",
        lambda _: bench("simulation.json", "BM_LongFlight/0/min_time:2.000", "restarts_and_projections_per_impact"),
        ".1f", "0.05"),
    Num("bench.long_flight.integrated_restarts_per_impact", "bench",
        lambda _: bench("simulation.json", "BM_LongFlight/1/iterations:1", "restarts_and_projections_per_impact"),
        ",.0f", "0.5"),
    Num("bench.table.build_36k_ms", "bench",
        lambda _: bench("table.json", "BM_TableLawBuild/36000", "real_time"), ".0f", "0.5"),
    Num("bench.table.build_360k_ms", "bench",
        lambda _: bench("table.json", "BM_TableLawBuild/360000", "real_time"), ".0f", "0.5"),
    Num("peers.camdyn_wall_s", "bench", lambda _: peer("camdyn", "wall_s"), ".2f", "0.005"),
    Num("peers.camdyn_run_time_s", "bench", lambda _: peer("camdyn", "run_time_s"), ".2f", "0.005"),
    Num("peers.scipy_wall_s", "bench", lambda _: peer("scipy", "wall_s"), ".1f", "0.05"),
    Num("peers.siconos_wall_s", "bench", lambda _: peer("siconos", "wall_s"), ".1f", "0.05"),
    # The README's table of every scene of issue 38 (bench/peers/run_scenes.py).
    *[Num(f"peers_scenes.{scene}.{what}", "bench",
          (lambda scene, path: lambda _: peer_scene(scene, path))(scene, path), fmt, tol)
      for scene in ("long_flight", "quickstart", "stiff_contact", "stiff_contact_adams", "stiff_contact_erk",
                    "stiff_contact_dop853")
      for what, path, fmt, tol in [("camdyn_wall_s", ("camdyn", "wall_s"), ".2f", "0.005"),
                                   ("camdyn_cpu_s", ("camdyn", "cpu_s"), ".2f", "0.005"),
                                   ("camdyn_simulation_cpu_s", ("camdyn_simulation", "cpu_s"), ".3f", "0.0005"),
                                   ("scipy_cpu_s", ("scipy", "cpu_s"), ".1f", "0.05"),
                                   ("wall_ratio", ("scipy_over_camdyn_wall",), ".0f", "0.5"),
                                   ("cpu_ratio", ("scipy_over_camdyn_cpu",), ".0f", "0.5"),
                                   ("simulation_ratio", ("scipy_over_camdyn_simulation_cpu",), ".0f", "0.5")]],
    Num("bench.quickstart_run_s", "bench", lambda _: 1e-3 * bench("simulation.json", "BM_QuickstartCycle/0",
                                                                  "real_time"), ".2f", "0.005"),
    Num("bench.tracking.differential_ms", "bench",
        lambda _: 1e3 * bench("simulation.json", "BM_QuickstartCycle/0", "s_per_cycle"), ".1f", "0.05"),
    Num("bench.tracking.differential_error_m", "bench",
        lambda _: bench("simulation.json", "BM_QuickstartCycle/0", "error_position_m"), "e1", "3%"),
    Num("bench.tracking.newton_ms", "bench",
        lambda _: 1e3 * bench("simulation.json", "BM_QuickstartCycle/1", "s_per_cycle"), ".1f", "0.05"),
    Num("bench.tracking.newton_error_m", "bench",
        lambda _: bench("simulation.json", "BM_QuickstartCycle/1", "error_position_m"), "e1", "3%"),
    Num("bench.rhs.differential_ns", "bench", lambda _: bench("simulation.json", "BM_RightHandSide/0", "cpu_time"),
        ".0f", "0.5"),
    Num("bench.rhs.newton_ns", "bench", lambda _: bench("simulation.json", "BM_RightHandSide/1", "cpu_time"), ".0f",
        "0.5"),
    Num("bench.periodic.ball_shooting_revolutions", "bench",
        lambda _: bench("periodic.json", "BM_ShootingBouncingBall/real_time", "revolutions"), ".0f", "0"),
    Num("bench.periodic.ball_plain_revolutions", "bench",
        lambda _: bench("periodic.json", "BM_PlainRunUntilSettledBouncingBall/iterations:1/real_time", "revolutions"),
        ".0f", "0"),
    Num("bench.periodic.ball_ratio", "bench",
        lambda _: bench("periodic.json", "BM_PlainRunUntilSettledBouncingBall/iterations:1/real_time",
                        "revolutions_ratio"), ".0f", "0.5"),
    Num("bench.periodic.quickstart_plain_revolutions", "bench",
        lambda _: bench("periodic.json", "BM_PlainRunUntilSettled/20/iterations:1/real_time", "revolutions"),
        ".0f", "0"),
    Num("bench.periodic.quickstart_shooting_revolutions", "bench",
        lambda _: bench("periodic.json", "BM_ShootingToThePeriodicOrbit/20/real_time", "revolutions"), ".0f", "0"),
    Num("bench.steady.step_us", "bench",
        lambda _: 1e6 * bench("simulation.json", "BM_SteadyContactStep/0", "s_per_step"), ".1f", "0.05"),
    Num("bench.steady.integration_step_us", "bench",
        lambda _: 1e6 * bench("simulation.json", "BM_SteadyContactStep/1", "s_per_step"), ".1f", "0.05"),
    Num("bench.steady.steps", "bench",
        lambda _: bench("simulation.json", "BM_SteadyContactStep/0", "steps"), ",.0f", "0.5"),
    Num("bench.compare.jobs1_s", "bench",
        lambda _: bench("compare.json", "BM_CompareStudy/jobs:1/iterations:3/real_time", "real_time"), ".2f", "0.005"),
    Num("bench.compare.jobs2_s", "bench",
        lambda _: bench("compare.json", "BM_CompareStudy/jobs:2/iterations:3/real_time", "real_time"), ".2f", "0.005"),
    Num("bench.compare.speedup", "bench",
        lambda _: bench("compare.json", "BM_CompareStudy/jobs:1/iterations:3/real_time", "real_time") /
        bench("compare.json", "BM_CompareStudy/jobs:2/iterations:3/real_time", "real_time"), ".2f", "0.005"),
    Num("bench.optimize.study_s", "bench",
        lambda _: bench("optimize.json", "BM_OptimizeJumpStudy/iterations:1/real_time", "real_time"), ".1f", "0.05"),
    Num("bench.optimize.rigid_stage_ms", "bench",
        lambda _: bench("optimize.json", "BM_RigidStage/real_time", "real_time"), ".0f", "0.5"),
    Num("bench.identify.cam_rig_s", "bench",
        lambda _: bench("identify.json", "BM_IdentifyCamRigStudy/iterations:1", "real_time"), ".2f", "0.005"),
]


# --- running, checking, updating -------------------------------------------


def run_study(camdyn: str, name: str, scratch: Path) -> Run:
    out = scratch / name
    cmd = [camdyn, "run", *RUNS[name], "--out", str(out), "--quiet"]
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: exit {done.returncode}\n{done.stderr}")
    return Run(out, done.stdout)


def fresh_values(camdyn: str, needed: list[Num], jobs: int) -> dict[str, float]:
    names = sorted({n.source for n in needed if n.source != "bench"})
    with tempfile.TemporaryDirectory(prefix="camdyn_readme_") as tmp:
        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
            futures = {name: pool.submit(run_study, camdyn, name, Path(tmp)) for name in names}
            runs = {name: f.result() for name, f in futures.items()}
        values = {}
        for n in needed:
            value = n.get(runs.get(n.source))
            if not math.isfinite(value):
                raise ValueError(f"{n.key}: the fresh value is {value}")
            values[n.key] = value
    return values


def quoted_config_problems(text: str) -> list[str]:
    """The README's "config in one look" must be studies/quickstart.json (without its description)."""
    match = re.search(r"`studies/quickstart\.json` \(its `description` left out[^\n]*\n[^\n]*\n\n```json\n(.*?)```",
                      text, re.S)
    if not match:
        return ["README.md: the quoted studies/quickstart.json block is missing"]
    file = json.loads((ROOT / QS).read_text())
    file.pop("description", None)
    if json.loads(match.group(1)) != file:
        return ["README.md: the quoted studies/quickstart.json differs from the file"]
    return []


def quoted_numbers(text: str) -> list[re.Match]:
    return list(MARKER.finditer(text))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--check", action="store_true", help="fail listing every drifted number")
    mode.add_argument("--update", action="store_true", help="rewrite the drifted numbers in README.md")
    mode.add_argument("--list", action="store_true", help="list the keys, sources and tolerances")
    parser.add_argument("--camdyn", default=str(ROOT / "build/ci/camdyn"), help="the camdyn binary to run")
    parser.add_argument("--jobs", type=int, default=2, help="studies run side by side (default 2)")
    parser.add_argument("--slow", action="store_true",
                        help="also the numbers of the slow studies (" + ", ".join(sorted(SLOW_RUNS)) + ")")
    args = parser.parse_args()

    by_key = {n.key: n for n in NUMBERS}
    if args.list:
        for n in NUMBERS:
            print(f"{n.key:48} {n.source:30} tol {n.tol}")
        return 0

    text = README.read_text()
    quotes = quoted_numbers(text)
    problems = [f"README.md: marker num:{q['key']} has no entry in scripts/readme_numbers.py"
                for q in quotes if q["key"] not in by_key]
    problems += quoted_config_problems(text)
    quoted_keys = {q["key"] for q in quotes}
    problems += [f"scripts/readme_numbers.py: {n.key} is quoted nowhere in README.md"
                 for n in NUMBERS if n.key not in quoted_keys]
    camdyn = os.path.abspath(args.camdyn)
    if not os.access(camdyn, os.X_OK):
        print(f"readme_numbers: {camdyn} is not an executable camdyn", file=sys.stderr)
        return 2
    checked = {n.key for n in NUMBERS if n.key in quoted_keys and (args.slow or n.source not in SLOW_RUNS)}
    try:
        fresh = fresh_values(camdyn, [n for n in NUMBERS if n.key in checked], args.jobs)
    except (RuntimeError, LookupError, ValueError, KeyError, OSError) as e:
        print(f"readme_numbers: cannot remake the numbers: {e}", file=sys.stderr)
        return 1

    drifted = []
    pieces, last = [], 0
    for q in quotes:
        n = by_key.get(q["key"])
        if n is None or n.key not in checked:
            continue
        quoted = float(q["num"].replace(",", ""))
        value = fresh[n.key]
        line = text.count("\n", 0, q.start()) + 1
        if abs(quoted - value) > n.allowed(value):
            drifted.append(f"README.md:{line}: {n.key}: quoted {q['num']}, fresh {n.text(value)} ({value:.6g}), "
                           f"tolerance {n.tol}")
            pieces += [text[last:q.start("num")], n.text(value)]
            last = q.end("num")
    pieces.append(text[last:])

    if args.update and drifted:
        tmp = README.with_suffix(".md.tmp")
        tmp.write_text("".join(pieces))
        os.replace(tmp, README)
    for p in problems + drifted:
        print(p)
    verb = "updated" if args.update else "drifted"
    skipped = len({q["key"] for q in quotes} - checked - (quoted_keys - set(by_key)))
    print(f"readme_numbers: {len(quotes)} quoted numbers, {len(checked)} keys checked"
          f"{f' ({skipped} of the slow studies left out: --slow)' if skipped else ''}, {len(drifted)} {verb}, "
          f"{len(problems)} other problems")
    return 1 if problems or (drifted and args.check) else 0


if __name__ == "__main__":
    sys.exit(main())
