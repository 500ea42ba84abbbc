#!/usr/bin/env python3
"""Runs every committed study with two camdyn binaries and compares the numbers
they write, to the last bit.

A refactoring that must not change behaviour (issue 13) is checked with it:

    python3 scripts/compare_studies.py --old OLD/camdyn --new build/release/camdyn

Compared: every number of summary.json, result.json, identified.json,
comparison.json, speed_limit.json, periodic.json (and its orbit/ run),
jump_map.json and the CSV outputs (timeseries, history, fit, comparison,
work_precision, jump_map). Left out, because they differ between any two runs: run and
wall times, the version string, and file paths. Numbers are compared as parsed
doubles (the writers print round-trip text), so equal means bit-identical.
Keys that only the new binary writes are additions (the interface allows
them) and are listed once, not counted as differences; a key the new binary
no longer writes is a difference. Exit status 0 when every study agrees, 1
otherwise; each difference is printed with the study, file and key.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUTPUT_FILES = ["summary.json", "result.json", "identified.json", "comparison.json", "speed_limit.json",
                "periodic.json", "jump_map.json", "orbit/summary.json",
                "timeseries.csv", "history.csv", "fit.csv", "comparison.csv", "work_precision.csv", "jump_map.csv",
                "orbit/timeseries.csv"]


def volatile(key):
    """Keys whose values legitimately differ between two runs of the same build."""
    k = key.lower()
    return ("run_time" in k or k.endswith("time_s") or "per_second" in k
            or k in ("camdyn_version", "version", "elapsed_s")
            or "wall" in k or k in ("file", "config", "source", "out", "path", "output"))


def committed_studies():
    """Every JSON under studies/ with a top-level "study" key (profiles of other files are skipped)."""
    found = []
    for path in sorted((ROOT / "studies").rglob("*.json")):
        try:
            doc = json.loads(path.read_text())
        except (OSError, ValueError):
            continue
        if isinstance(doc, dict) and "study" in doc:
            found.append(path)
    return found


def run_study(binary, study, out_dir, jobs):
    out_dir.mkdir(parents=True, exist_ok=True)
    start = time.monotonic()
    cmd = [str(binary), "run", str(study), "--out", str(out_dir), "--quiet", "--jobs", str(jobs)]
    proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    return proc.returncode, proc.stderr.strip().splitlines()[-3:], time.monotonic() - start


def same_text(a, b):
    """Equal, or both a wall-time budget running out (where is the machine's speed, not the code's)."""
    budget = "wall-time budget"
    return a == b or (budget in a and budget in b and a.split(" exceeded")[0] == b.split(" exceeded")[0])


def number(text):
    try:
        return float(text)
    except ValueError:
        return None


def same_number(a, b):
    return a == b or (math.isnan(a) and math.isnan(b))


def compare_json(a, b, where, diffs, added):
    if isinstance(a, dict) and isinstance(b, dict):
        for key in sorted(set(a) | set(b)):
            if volatile(key):
                continue
            if key not in a:
                added.append(f"{where}.{key}")  # an addition to the outputs, allowed by the interface
                continue
            if key not in b:
                diffs.append(f"{where}.{key}: only in old (removed)")
                continue
            compare_json(a[key], b[key], f"{where}.{key}", diffs, added)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            diffs.append(f"{where}: {len(a)} elements (old) vs {len(b)} (new)")
            return
        for i, (x, y) in enumerate(zip(a, b)):
            compare_json(x, y, f"{where}[{i}]", diffs, added)
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        if not same_number(float(a), float(b)):
            diffs.append(f"{where}: {a!r} (old) vs {b!r} (new), rel {rel(a, b):.3g}")
    elif isinstance(a, str) and isinstance(b, str):
        if not same_text(a, b) and not ("/" in a or "\\" in a):
            diffs.append(f"{where}: {a!r} (old) vs {b!r} (new)")
    elif a != b:
        diffs.append(f"{where}: {a!r} (old) vs {b!r} (new)")


def rel(a, b):
    scale = max(abs(float(a)), abs(float(b)))
    return abs(float(a) - float(b)) / scale if scale > 0 else 0.0


def compare_csv(path_a, path_b, where, diffs):
    with open(path_a, newline="") as fa, open(path_b, newline="") as fb:
        rows_a, rows_b = list(csv.reader(fa)), list(csv.reader(fb))
    if not rows_a or not rows_b or rows_a[0] != rows_b[0]:
        diffs.append(f"{where}: header differs")
        return
    header = rows_a[0]
    if len(rows_a) != len(rows_b):
        diffs.append(f"{where}: {len(rows_a) - 1} rows (old) vs {len(rows_b) - 1} (new)")
        return
    reported = 0
    for r, (ra, rb) in enumerate(zip(rows_a[1:], rows_b[1:]), start=1):
        for c, name in enumerate(header):
            if volatile(name) or c >= len(ra) or c >= len(rb):
                continue
            x, y = number(ra[c]), number(rb[c])
            equal = same_number(x, y) if x is not None and y is not None else same_text(ra[c], rb[c])
            if not equal and reported < 5:
                diffs.append(f"{where} row {r} {name}: {ra[c]} (old) vs {rb[c]} (new)")
                reported += 1


def compare_outputs(dir_a, dir_b, study_name, added):
    diffs = []
    for name in OUTPUT_FILES:
        a, b = dir_a / name, dir_b / name
        if not a.exists() and not b.exists():
            continue
        if a.exists() != b.exists():
            diffs.append(f"{study_name}/{name}: only in {'new' if b.exists() else 'old'}")
            continue
        if name.endswith(".json"):
            compare_json(json.loads(a.read_text()), json.loads(b.read_text()), f"{study_name}/{name}", diffs,
                         added)
        else:
            compare_csv(a, b, f"{study_name}/{name}", diffs)
    return diffs


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--old", required=True, help="camdyn binary before the change")
    parser.add_argument("--new", required=True, help="camdyn binary after the change")
    parser.add_argument("--out", default="out/compare_studies", help="where both runs write (default %(default)s)")
    parser.add_argument("--only", action="append", default=[], help="run only studies whose path contains this")
    parser.add_argument("--skip", action="append", default=[], help="skip studies whose path contains this")
    parser.add_argument("--jobs", type=int, default=1, help="--jobs passed to each run (default 1: deterministic)")
    parser.add_argument("--parallel", type=int, default=2, help="runs at once (default 2)")
    args = parser.parse_args()

    studies = [s for s in committed_studies()
               if (not args.only or any(o in str(s) for o in args.only))
               and not any(k in str(s) for k in args.skip)]
    out = Path(args.out).resolve()
    tasks = []
    for study in studies:
        name = str(study.relative_to(ROOT / "studies").with_suffix("")).replace(os.sep, "__")
        tasks.append((study, name, "old", Path(args.old).resolve()))
        tasks.append((study, name, "new", Path(args.new).resolve()))

    def work(task):
        study, name, side, binary = task
        return task, run_study(binary, study, out / side / name, args.jobs)

    exit_codes = {}
    with ThreadPoolExecutor(max_workers=max(1, args.parallel)) as pool:
        for (study, name, side, _), (code, tail, seconds) in pool.map(work, tasks):
            exit_codes[(name, side)] = code
            print(f"  ran {name:45s} {side}: exit {code} in {seconds:6.1f} s", flush=True)
            if code not in (0,):
                for line in tail:
                    print(f"      {line}")

    failed = 0
    added = []
    for study in studies:
        name = str(study.relative_to(ROOT / "studies").with_suffix("")).replace(os.sep, "__")
        diffs = []
        if exit_codes[(name, "old")] != exit_codes[(name, "new")]:
            diffs.append(f"exit {exit_codes[(name, 'old')]} (old) vs {exit_codes[(name, 'new')]} (new)")
        diffs += compare_outputs(out / "old" / name, out / "new" / name, name, added)
        status = "identical" if not diffs else f"{len(diffs)} differences"
        print(f"{name:45s} {status}")
        for d in diffs[:20]:
            print(f"    {d}")
        failed += bool(diffs)
    keys = sorted({a.split("/", 1)[1] for a in added})
    if keys:
        print(f"added output keys (not differences): {', '.join(keys)}")
    print(f"{len(studies) - failed} identical, {failed} differ")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
