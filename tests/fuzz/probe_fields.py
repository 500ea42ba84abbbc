#!/usr/bin/env python3
"""Hostile values in every numeric field of every committed study.

For each study under studies/, takes its resolved config from `camdyn
validate` (every field, defaults included), sets each numeric field in turn
to each of the given values with --set, and runs `camdyn run` (or `camdyn
validate` with --validate) under a time limit. Prints the cases that end
with an exit code other than 0, 2 or 3, use more memory than the limit, or
(with --report-timeouts) do not end in time. The libFuzzer targets mutate
bytes; this sweep is systematic over the fields a user can set, and found
the runaways in docs/fuzzing.md ("A sweep of every field").

    /usr/bin/python3 tests/fuzz/probe_fields.py --camdyn build/ci/camdyn
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


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


def studies(skip):
    for folder, _, files in sorted(os.walk(os.path.join(ROOT, "studies"))):
        for name in sorted(files):
            path = os.path.join(folder, name)
            if name.endswith(".json") and not any(s in path for s in skip):
                yield path


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--camdyn", default=os.path.join(ROOT, "build", "ci", "camdyn"))
    parser.add_argument("--values", default="2000000000,1e300,-1,5e-324")
    parser.add_argument("--timeout", type=float, default=8.0, help="seconds per run")
    parser.add_argument("--max-rss-mb", type=float, default=2500.0)
    parser.add_argument("--validate", action="store_true", help="validate only")
    parser.add_argument("--report-timeouts", action="store_true")
    parser.add_argument("--skip", default="identify,optimize", help="studies whose path has one of these")
    args = parser.parse_args()
    camdyn = os.path.abspath(args.camdyn)
    out = tempfile.mkdtemp(prefix="camdyn_probe_")
    seen, found = set(), 0
    for config in studies([s for s in args.skip.split(",") if s]):
        folder = os.path.dirname(config)
        resolved = subprocess.run([camdyn, "validate", config], cwd=folder, capture_output=True, text=True)
        try:
            doc = json.loads(resolved.stdout)
        except ValueError:
            continue  # not a config of its own (a base, a data file)
        for field, _ in numeric_leaves(doc):
            if field.split(".")[0] in ("grid", "zip", "overlays", "cases") or (doc.get("study"), field) in seen:
                continue
            seen.add((doc.get("study"), field))
            for value in args.values.split(","):
                command = [camdyn, "validate" if args.validate else "run", config, "--set", f"{field}={value}"]
                if not args.validate:
                    shutil.rmtree(os.path.join(out, "run"), ignore_errors=True)
                    command += ["--quiet", "--out", os.path.join(out, "run")]
                start = time.time()
                r = subprocess.run(["/usr/bin/time", "-f", "%M", "timeout", "-s", "KILL", str(args.timeout)] + command,
                                   cwd=folder, capture_output=True, text=True)
                seconds = time.time() - start
                lines = r.stderr.strip().splitlines()
                rss_mb = int(lines[-1]) / 1024 if lines and lines[-1].isdigit() else 0.0
                timed_out = r.returncode in (124, 137) or r.returncode == -9
                if (r.returncode not in (0, 2, 3) and not timed_out) or rss_mb > args.max_rss_mb or \
                        (timed_out and args.report_timeouts):
                    message = next((line for line in lines if line.startswith("camdyn")), "")
                    print(f"{os.path.relpath(config, ROOT)} {field}={value}: exit {r.returncode}, {seconds:.1f} s, "
                          f"{rss_mb:.0f} MB: {message[:240]}", flush=True)
                    found += 1
    shutil.rmtree(out, ignore_errors=True)
    print(f"probe_fields: {len(seen)} fields, {found} finding(s)")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
