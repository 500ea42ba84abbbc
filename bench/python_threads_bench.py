#!/usr/bin/env python3
"""Two Python threads against one on a batch of quickstart simulations: the
speed-up the released GIL gives (docs/python.md, "Threads"; goal: at least
1.7 on two cores).

A batch of 80 quickstart runs at 1200-1595 rpm (0.02-0.05 s each) runs on a
pool of one thread, then of two, up to --tries times; the best try counts.
Each try also measures how many cores other processes used meanwhile (from
/proc/stat): a try with other work on the machine understates the speed-up.
Both pools ask for record arrays: pandas DataFrames are built by Python code,
which holds the GIL. The runs must give the same metrics whichever thread ran
them (checked). Writes --json (bench/results/python_threads.json).

  PYTHONPATH=build/ci/python /usr/bin/python3 bench/python_threads_bench.py \\
      --json bench/results/python_threads.json

Exit status: 0 done (whatever the speed-up; the JSON says whether it met the
goal), 2 bad input, 3 a run did not converge.
"""
import argparse
import json
import os
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

import camdyn

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
QUICKSTART = os.path.join(ROOT, "studies", "quickstart.json")
SPEEDS = [1200 + 5 * k for k in range(80)]  # [rpm]
GOAL = 1.7


def wall_time(pool_size, scenes):
    """Wall time of the batch on `pool_size` threads [s], and the runs' metrics."""
    start = time.perf_counter()
    with ThreadPoolExecutor(max_workers=pool_size) as pool:
        results = list(pool.map(lambda s: s.simulate(series=False, as_frame=False), scenes))
    elapsed = time.perf_counter() - start
    if not all(r.converged for r in results):
        print("python_threads_bench: a quickstart run did not converge", file=sys.stderr)
        sys.exit(3)
    return elapsed, [r.metrics for r in results]


def busy_seconds():
    """CPU time every process on the machine has used (Linux /proc/stat) [s]."""
    with open("/proc/stat", encoding="ascii") as f:
        ticks = [int(x) for x in f.readline().split()[1:9]]
    idle = ticks[3] + ticks[4]  # idle, iowait
    return (sum(ticks) - idle) / os.sysconf("SC_CLK_TCK")


def own_seconds():
    t = os.times()
    return t.user + t.system


def timed_try(scenes):
    """One thread, then two: their wall times [s] and the cores other processes used meanwhile."""
    busy, own, start = busy_seconds(), own_seconds(), time.perf_counter()
    one, metrics_one = wall_time(1, scenes)
    two, metrics_two = wall_time(2, scenes)
    elapsed = time.perf_counter() - start
    others = max(0.0, (busy_seconds() - busy) - (own_seconds() - own)) / elapsed
    if metrics_two != metrics_one:
        print("python_threads_bench: two threads gave other metrics than one", file=sys.stderr)
        sys.exit(3)
    return {"one_thread_s": one, "two_threads_s": two, "speed_up": one / two, "other_processes_cores": others}


def write_atomic(path, document):
    directory = os.path.dirname(os.path.abspath(path))
    with tempfile.NamedTemporaryFile("w", dir=directory, delete=False, suffix=".tmp", encoding="utf-8") as f:
        json.dump(document, f, indent=2)
        f.write("\n")
    os.replace(f.name, path)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tries", type=int, default=4, help="timed tries (the best counts)")
    parser.add_argument("--json", help="where to write the results")
    args = parser.parse_args()
    if args.tries < 1:
        print(f"python_threads_bench: --tries: must be >= 1, got {args.tries}", file=sys.stderr)
        return 2
    scenes = [camdyn.load(QUICKSTART, set={"cam.rpm": rpm}) for rpm in SPEEDS]
    wall_time(2, scenes[:2])  # warm-up: page in the code
    tries = []
    for _ in range(args.tries):
        tries.append(timed_try(scenes))
        t = tries[-1]
        print(f"{len(scenes)} simulations: one thread {t['one_thread_s']:.2f} s, two threads "
              f"{t['two_threads_s']:.2f} s, speed-up {t['speed_up']:.2f} "
              f"(other processes: {t['other_processes_cores']:.2f} cores)")
    best = max(tries, key=lambda t: t["speed_up"])
    document = {
        "benchmark": "python_threads",
        "simulations": len(scenes),
        "cores": os.cpu_count(),
        "load_average": list(os.getloadavg()),
        "goal_speed_up": GOAL,
        "best_speed_up": best["speed_up"],
        "meets_goal": best["speed_up"] >= GOAL,
        "tries": tries,
    }
    print(f"best speed-up {best['speed_up']:.2f} (goal {GOAL})")
    if args.json:
        write_atomic(args.json, document)
    return 0


if __name__ == "__main__":
    sys.exit(main())
