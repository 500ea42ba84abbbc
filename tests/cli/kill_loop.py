#!/usr/bin/python3
"""kill -9 at random moments of simulate, compare, optimize and identify runs
(issue 19), each followed by a re-run into the same --out folder, checked
against an uninterrupted run of the same study (docs/outputs-and-resume.md):

* a killed run never looks finished: no complete.json after the kill;
* after the re-run: complete.json, no lock file, no temporary `<name>.tmp.<pid>`;
* finished work is kept: the journal lines of the killed run (compare,
  optimize, identify) are the start of the journal after the re-run, and a
  re-run after a kill that left journaled work says it resumed;
* the outputs are identical to the uninterrupted run's (JSON compared as
  values, without run times; CSV without run-time columns) for every study.

Usage: kill_loop.py CAMDYN SOURCE_DIR [--kills N] [--seed S] [--keep]
Exit 0 when every check passed; the failures are listed otherwise.
"""
import argparse
import csv
import io
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

# Small, fast versions of the shipped studies (a few seconds each).
STUDIES = {
    "simulate": ("studies/quickstart.json", [], ["summary.json", "events.csv", "timeseries.csv"]),
    "compare": ("studies/compare_laws.json",
                ['grid={"mechanism.cam.rpm": [800, 1420]}', "overlays=[]"],
                ["comparison.json", "comparison.csv"]),
    "optimize": ("studies/optimize_force.json",
                 ["optimizer.max_evaluations=10", "simulation.cycles=3", "operating_rpm=[1000]",
                  "rigid.enabled=false", "integrator.rtol=1e-6", "optimizer.evaluation_rtol=1e-5"],
                 ["result.json", "optimized.json", "history.csv"]),
    "identify": ("studies/identify_drop/identify_drop.json", [],
                 ["identified.json", "fit.csv", "identified_scene.json"]),
}

# Fields that measure the machine, not the study.
VOLATILE = re.compile(r"(run_time|time_s$|per_second$|wall|resumed)")
TEMPORARY = re.compile(r"\.tmp\.\d+$")


def command(camdyn, source, study, out):
    config, sets, _ = STUDIES[study]
    argv = [camdyn, "run", os.path.join(source, config), "--quiet", "--jobs", "2", "--out", out]
    for s in sets:
        argv += ["--set", s]
    return argv


def run(argv, timeout=300):
    return subprocess.run(argv, capture_output=True, text=True, timeout=timeout)


def strip_volatile(value):
    if isinstance(value, dict):
        return {k: strip_volatile(v) for k, v in value.items() if not VOLATILE.search(k)}
    if isinstance(value, list):
        return [strip_volatile(v) for v in value]
    return value


def content(path):
    """A file's deterministic content: JSON without the volatile fields, CSV without volatile columns."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    if path.endswith(".json"):
        return strip_volatile(json.loads(text))
    lines = [line for line in text.splitlines() if not line.startswith("#")]
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    if not rows:
        return rows
    keep = [i for i, name in enumerate(rows[0]) if not VOLATILE.search(name)]
    return [[row[i] for i in keep if i < len(row)] for row in rows]


def journal_lines(folder):
    """The complete lines of the folder's journal (a line cut by the kill is not one)."""
    path = os.path.join(folder, "journal.jsonl")
    if not os.path.exists(path):
        return []
    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    return text[: text.rfind("\n") + 1].splitlines() if "\n" in text else []


def leftovers(folder):
    found = []
    for root, _, files in os.walk(folder):
        found += [os.path.join(root, f) for f in files if TEMPORARY.search(f) or f == ".camdyn.lock"]
    return found


def kill_at(argv, delay):
    """Starts argv, SIGKILLs it after `delay` s; returns whether it had already finished (exit 0)."""
    process = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        code = process.wait(timeout=delay)
        return code == 0
    except subprocess.TimeoutExpired:
        process.send_signal(signal.SIGKILL)
        process.wait()
        return False


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("camdyn")
    parser.add_argument("source")
    parser.add_argument("--kills", type=int, default=20, help="kills in all (spread over the four studies)")
    parser.add_argument("--seed", type=int, default=int(time.time()))
    parser.add_argument("--keep", action="store_true", help="keep the work folder")
    args = parser.parse_args()
    rng = random.Random(args.seed)
    work = tempfile.mkdtemp(prefix="camdyn_kill_loop_")
    failures = []
    print(f"kill_loop: seed {args.seed}, work folder {work}", flush=True)

    reference, duration = {}, {}
    for study in STUDIES:
        out = os.path.join(work, "reference", study)
        t0 = time.monotonic()
        done = run(command(args.camdyn, args.source, study, out))
        duration[study] = time.monotonic() - t0
        if done.returncode != 0:
            failures.append(f"{study}: the uninterrupted run exited {done.returncode}: {done.stderr.strip()}")
            continue
        files = STUDIES[study][2]
        reference[study] = {f: content(os.path.join(out, f)) for f in files}
        print(f"  {study}: uninterrupted run {duration[study]:.2f} s", flush=True)

    kills = 0
    studies = [s for s in STUDIES if s in reference]
    trial = -1
    while studies and kills < args.kills and trial < 2 * args.kills:
        trial += 1
        study = studies[trial % len(studies)]
        out = os.path.join(work, "killed", f"{trial:02d}_{study}")
        argv = command(args.camdyn, args.source, study, out)
        # One kill, or a second one during the re-run that resumes the first.
        for _ in range(1 + (rng.random() < 0.3)):
            delay = rng.uniform(0.02, 0.95 * duration[study])
            finished = kill_at(argv, delay)
            kills += not finished
            where = f"{study} trial {trial} (killed after {delay:.2f} s)"
            if not finished and os.path.exists(os.path.join(out, "complete.json")):
                # The kill came after the run's last write (complete.json) but before the
                # process ended (a sanitizer build spends a moment in its exit-time checks):
                # the run had finished, so it is no kill, and its outputs must be complete.
                kills -= 1
                differ = [name for name, expected in reference[study].items()
                          if not os.path.exists(os.path.join(out, name)) or content(os.path.join(out, name)) != expected]
                if differ:
                    failures.append(f"{where}: complete.json survives the kill, but {', '.join(differ)} "
                                    "differ from the uninterrupted run's")
        before = journal_lines(out)
        # The header line and at least one record: journaled work the re-run must take.
        had_work = len(before) > 1
        rerun = run(argv)
        if rerun.returncode != 0:
            failures.append(f"{where}: the re-run exited {rerun.returncode}: {rerun.stderr.strip()}")
            continue
        if not os.path.exists(os.path.join(out, "complete.json")):
            failures.append(f"{where}: no complete.json after the re-run")
        for path in leftovers(out):
            failures.append(f"{where}: {os.path.relpath(path, out)} left after the re-run")
        after = journal_lines(out)
        if after[: len(before)] != before:
            failures.append(f"{where}: the re-run dropped or rewrote journal lines of the killed run")
        if had_work and study in ("optimize", "identify") and "resumed" not in rerun.stdout:
            failures.append(f"{where}: the journal had work but the re-run did not say it resumed")
        for name, expected in reference[study].items():
            path = os.path.join(out, name)
            if not os.path.exists(path):
                failures.append(f"{where}: {name} missing after the re-run")
            elif content(path) != expected:
                failures.append(f"{where}: {name} differs from the uninterrupted run's")
        print(f"  {where}: re-run {'resumed' if had_work else 'afresh'}, checked", flush=True)

    print(f"kill_loop: {kills} kills at random moments, {len(failures)} failures", flush=True)
    for failure in failures:
        print("  FAIL " + failure)
    if kills < args.kills:
        failures.append(f"only {kills} kills landed before the runs finished ({args.kills} wanted)")
        print("  FAIL " + failures[-1])
    if not args.keep and not failures:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
