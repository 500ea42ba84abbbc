#!/usr/bin/env python3
"""Hostile values in every numeric field of every committed study.

For each study under studies/, takes its resolved config from `camdyn
validate` (every field, defaults included) and runs `camdyn validate` or
`camdyn run` (on a study budget, --max-study-time) with --set overrides:

* each numeric field in turn set to each of the hostile values (--values);
* derived sizes: each field that sizes work (a count, samples, speeds,
  harmonics, starts, steps, cycles, grid points: SIZE_WORDS) set to huge
  counts (SIZE_VALUES), each step or tolerance (STEP_WORDS) to tiny ones
  (which multiply the samples a run takes), and each list of numbers (a
  grid axis, a spline's knots) replaced by a long one (LONG_LIST values);
* pairs: each field's hostile value together with a hostile value of one
  other field of the same study, the partner chosen by a fixed-seed RNG.

A case passes when camdyn ends with exit 0, 2 or 3 within the time limit,
within the memory limit, and (runs) writes no NaN or Inf as a value into any
JSON or CSV file under --out. Everything else is a finding: another exit
code, a signal, a timeout (every run has a study budget below the limit, so
a timeout means a part that is not held to it), too much memory, a
non-finite number. Known findings are listed in EXPECTED_FINDINGS: they
are reported but do not fail the sweep (--ci does not run them), and the
full sweep names the entries it no longer finds.

    /usr/bin/python3 tests/fuzz/probe_fields.py --camdyn build/ci/camdyn --ci   # CTest probe.fields, < 90 s
    /usr/bin/python3 tests/fuzz/probe_fields.py --camdyn build/ci/camdyn        # the full sweep, label slow

docs/fuzzing.md ("A sweep of every field") says what the sweeps found.
"""
import argparse
import concurrent.futures
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

HOSTILE_VALUES = "2000000000,1e300,-1,5e-324"
# A field sizes work when its last key has one of these words.
SIZE_WORDS = re.compile(r"count|sample|speeds|harmonic|starts|steps|cycles|grid|points|evaluations|iterations|"
                        r"measured_values|order|period")
SIZE_VALUES = ["1000000000", "4294967296", "1e15"]
# A step or tolerance: tiny values make the work it divides huge.
STEP_WORDS = re.compile(r"step|tolerance|rtol|atol|resolution|spacing")
STEP_VALUES = ["1e-9", "1e-14"]
LONG_LIST = 5000  # elements of a long list (an argument of --set may hold 128 kB)
PAIR_SEED = 36  # the pairs' RNG seed: the same pairs every time

# Known findings, each (study, --set) as regular expressions matched against
# the study's path (relative to the source tree) and any one --set of a case,
# the reason, and optionally "run" (only runs, not validations):
# reported as expected, not failing the sweep; in --ci not run at all (they
# are known, and a timeout costs its whole limit).
# None open (docs/fuzzing.md, "Findings open"); an entry reads
# (r"studies/layout_.*\.json", r".*", "why, and where it is tracked", "run").
EXPECTED_FINDINGS = []
# Top-level keys whose numbers are not fields of one scene (runs of other scenes, plot overlays).
SKIPPED_ROOTS = ("zip", "overlays", "cases", "scenes")


def numeric_leaves(node, path=""):
    """(dotted path, value) of every number in a resolved config; short arrays only."""
    if isinstance(node, dict):
        for key, value in node.items():
            yield from numeric_leaves(value, f"{path}.{key}" if path else key)
    elif isinstance(node, list) and len(node) <= 8:
        for i, value in enumerate(node):
            yield from numeric_leaves(value, f"{path}[{i}]")
    elif isinstance(node, (int, float)) and not isinstance(node, bool):
        yield path, node


def number_lists(node, path=""):
    """(dotted path, list) of every non-empty list of numbers (grid axes, knots, points' coordinates)."""
    if isinstance(node, dict):
        for key, value in node.items():
            yield from number_lists(value, f"{path}.{key}" if path else key)
    elif isinstance(node, list) and node:
        if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in node):
            yield path, node
        elif len(node) <= 8:
            for i, value in enumerate(node):
                yield from number_lists(value, f"{path}[{i}]")


def long_list(values):
    """LONG_LIST numbers spanning the range of `values` (a grid axis of 5,000 speeds, ...)."""
    low, high = min(values), max(values)
    if low == high:
        high = low + 1
    return "[" + ",".join(f"{low + (high - low) * i / (LONG_LIST - 1):.7g}" for i in range(LONG_LIST)) + "]"


def studies(skip):
    for folder, _, files in sorted(os.walk(os.path.join(ROOT, "studies"))):
        for name in sorted(files):
            path = os.path.join(folder, name)
            if name.endswith(".json") and not any(s in path for s in skip):
                yield path


class Case:
    """One camdyn invocation: a study, its overrides, validate or run."""

    def __init__(self, config, sets, run):
        self.config, self.sets, self.run = config, sets, run

    def key(self):
        return tuple((os.path.relpath(self.config, ROOT),) + tuple(self.sets))

    def label(self):
        shown = [s if len(s) <= 60 else s[:57] + "..." for s in self.sets]
        return f"{'run' if self.run else 'validate'} {os.path.relpath(self.config, ROOT)} {' '.join(shown)}"


def cases_of(config, doc, args, rng, seen):
    """The cases of one study: every field with every value, derived sizes, pairs."""
    values = args.values.split(",")
    fields = []
    for field, _ in numeric_leaves(doc):
        if field.split(".")[0].split("[")[0] in SKIPPED_ROOTS or (doc.get("study"), field) in seen:
            continue
        seen.add((doc.get("study"), field))
        fields.append(field)
    out = []
    for n, field in enumerate(fields):
        # The CI walk gives each field one of the values in turn; the full sweep all of them.
        chosen = [values[n % len(values)]] if args.ci else values
        out += [[f"{field}={v}"] for v in chosen]
        last = field.split(".")[-1].split("[")[0]
        if SIZE_WORDS.search(last):
            out += [[f"{field}={v}"] for v in (SIZE_VALUES[:1] if args.ci else SIZE_VALUES)]
        if STEP_WORDS.search(last):
            out += [[f"{field}={v}"] for v in (STEP_VALUES[:1] if args.ci else STEP_VALUES)]
    for path, items in number_lists(doc):
        if len(items) > 1 and path.split(".")[0].split("[")[0] not in ("overlays", "cases"):
            out.append([f"{path}={long_list(items)}"])
    grid = doc.get("grid")
    if isinstance(grid, dict) and len(grid) >= 1:
        # The derived size of a grid is the product of its axes: two long axes.
        axes = [k for k, v in grid.items() if isinstance(v, list) and v]
        sets = [f"grid.{k}={long_list(grid[k])}" for k in axes[:2]]
        if len(axes) < 2 and fields:
            sets.append(f"grid.{fields[0]}={long_list([1, 2])}")
        out.append(sets)
    if len(fields) > 1:
        pairs = fields if not args.ci else rng.sample(fields, min(len(fields), args.ci_pairs))
        for field in pairs:
            partner = rng.choice([f for f in fields if f != field])
            out.append([f"{field}={rng.choice(values)}", f"{partner}={rng.choice(values)}"])
    return out


NON_FINITE = {"nan", "-nan", "+nan", "inf", "-inf", "+inf", "infinity", "-infinity", "+infinity"}


def non_finite_values(out_dir):
    """'file: where' of each NaN or Inf written as a value into a JSON or CSV file under `out_dir`."""
    found = []
    for folder, _, files in os.walk(out_dir):
        for name in files:
            path = os.path.join(folder, name)
            rel = os.path.relpath(path, out_dir)
            try:
                with open(path, encoding="utf-8", errors="replace") as f:
                    text = f.read()
            except OSError:
                continue
            if name.endswith(".json") or name.endswith(".jsonl"):
                constants = []
                for line in (text.splitlines() if name.endswith(".jsonl") else [text]):
                    try:
                        json.loads(line, parse_constant=constants.append)
                    except ValueError:
                        pass  # a file that is not JSON is another test's business
                if constants:
                    found.append(f"{rel}: {constants[0]}")
            elif name.endswith(".csv"):
                for number, line in enumerate(text.splitlines(), 1):
                    if line.startswith("#"):
                        continue
                    bad = [cell for cell in line.split(",") if cell.strip().strip('"').lower() in NON_FINITE]
                    if bad:
                        found.append(f"{rel} line {number}: {bad[0]}")
                        break
    return found


def expected_finding(case):
    """The entry of EXPECTED_FINDINGS a case hits (its study, one of its --set), or None."""
    study = os.path.relpath(case.config, ROOT)
    return next((entry for entry in EXPECTED_FINDINGS
                 if re.fullmatch(entry[0], study) and any(re.fullmatch(entry[1], s) for s in case.sets) and
                 (case.run or entry[3:] != ("run",))), None)


def run_case(case, camdyn, args, scratch):
    """None if the case passes, else what went wrong."""
    command = [camdyn, "run" if case.run else "validate", case.config]
    for s in case.sets:
        command += ["--set", s]
    out = tempfile.mkdtemp(prefix="case_", dir=scratch)
    if case.run:
        command += ["--quiet", "--out", out, "--max-study-time", str(args.study_budget)]
    start = time.time()
    r = subprocess.run(["/usr/bin/time", "-f", "%M", "timeout", "-s", "KILL", str(args.timeout)] + command,
                       cwd=os.path.dirname(case.config), capture_output=True, text=True, errors="replace")
    seconds = time.time() - start
    lines = r.stderr.strip().splitlines()
    rss_mb = int(lines[-1]) / 1024 if lines and lines[-1].isdigit() else 0.0
    # timeout -s KILL: the child dies of SIGKILL, /usr/bin/time reports "Command terminated by signal 9", exit 137.
    timed_out = r.returncode in (124, 137) and seconds >= args.timeout * 0.95
    problems = []
    if timed_out:
        problems.append(f"no end within {args.timeout:g} s")
    elif r.returncode not in (0, 2, 3):
        problems.append(f"exit {r.returncode}")
    if rss_mb > args.max_rss_mb:
        problems.append(f"{rss_mb:.0f} MB")
    if case.run and not timed_out:
        problems += [f"non-finite value in {w}" for w in non_finite_values(out)[:3]]
    shutil.rmtree(out, ignore_errors=True)
    if not problems:
        return None
    message = next((line for line in lines if line.startswith("camdyn")), "")
    return f"{'; '.join(problems)} ({seconds:.1f} s): {message[:200]}"


def resolved_configs(camdyn, skip):
    for config in studies([s for s in skip.split(",") if s]):
        r = subprocess.run([camdyn, "validate", config], cwd=os.path.dirname(config), capture_output=True, text=True)
        try:
            doc = json.loads(r.stdout)
        except ValueError:
            continue  # not a config of its own (a base, a data file)
        if isinstance(doc, dict):
            yield config, doc


def plan(camdyn, args):
    """Every case of the sweep, in a fixed order."""
    rng = random.Random(PAIR_SEED)
    seen, cases = set(), []
    for config, doc in resolved_configs(camdyn, args.skip):
        for sets in cases_of(config, doc, args, rng, seen):
            cases.append(Case(config, sets, run=not args.validate and not args.ci))
    if args.ci:
        # A sample of the validate cases also run, each on a short study budget.
        sample = random.Random(PAIR_SEED).sample(cases, min(len(cases), args.ci_runs))
        cases += [Case(c.config, c.sets, run=True) for c in sample]
    return cases


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--camdyn", default=os.path.join(ROOT, "build", "ci", "camdyn"))
    parser.add_argument("--values", default=HOSTILE_VALUES)
    parser.add_argument("--timeout", type=float, default=20.0, help="seconds per case before it is a finding")
    parser.add_argument("--study-budget", type=float, default=4.0, help="--max-study-time of each run [s]")
    parser.add_argument("--max-rss-mb", type=float, default=2500.0)
    parser.add_argument("--validate", action="store_true", help="validate only")
    parser.add_argument("--ci", action="store_true",
                        help="CI-sized: one value a field, a sample of pairs, a sample of short runs")
    parser.add_argument("--ci-pairs", type=int, default=3, help="pairs a study in --ci")
    parser.add_argument("--ci-runs", type=int, default=24, help="cases also run in --ci")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--skip", default="", help="studies whose path has one of these (comma-separated)")
    args = parser.parse_args()
    camdyn = os.path.abspath(args.camdyn)
    if args.ci:
        args.timeout = min(args.timeout, 15.0)
        args.study_budget = min(args.study_budget, 1.0)
    start = time.time()
    cases = plan(camdyn, args)
    if args.ci:
        known = [c for c in cases if expected_finding(c)]
        cases = [c for c in cases if not expected_finding(c)]
        print(f"probe_fields: {len(known)} cases of known findings (EXPECTED_FINDINGS) not run", flush=True)
    scratch = tempfile.mkdtemp(prefix="camdyn_probe_")
    found, expected_seen = 0, set()
    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
            results = pool.map(lambda c: (c, run_case(c, camdyn, args, scratch)), cases)
            for case, problem in results:
                if problem is None:
                    continue
                expected = expected_finding(case)
                if expected:
                    expected_seen.add(expected)
                    print(f"expected ({expected[2]}): {case.label()}: {problem}", flush=True)
                    continue
                print(f"FINDING {case.label()}: {problem}", flush=True)
                found += 1
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    if not args.ci:
        for entry in EXPECTED_FINDINGS:
            if entry not in expected_seen:
                print(f"expected but not found (fixed? remove it from EXPECTED_FINDINGS): {entry[0]} {entry[1]}")
    runs = sum(c.run for c in cases)
    print(f"probe_fields: {len(cases)} cases ({runs} runs, {len(cases) - runs} validations), "
          f"{found} finding(s), {len(expected_seen)} expected, {time.time() - start:.0f} s")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
