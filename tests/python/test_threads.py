"""The GIL is released while camdyn simulates: a Python loop on the main thread
keeps at least 30 % of its own pace beside a simulation on another thread
(with the GIL held through the call it falls to about 0.4 %: tried), and a
thread pool of two runs a batch of simulations at least 1.7 times as fast as
one thread on two cores. Both ask for record arrays: with pandas installed
the default DataFrames are built by Python code, which holds the GIL.

CTest runs this file on its own with RUN_SERIAL, so no other test takes the
cores; the batch (1.5–4 s on one thread) is long enough to time by wall
clock. Other programs on the machine can still take a core, so the timing is
tried up to four times and the best try counts. When every try found the
machine busy (other processes using more than a third of a core, from
/proc/stat) the test is skipped rather than failed: no timing can show the
speed-up then.
"""
import os
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import pytest

import camdyn

BATCH = 80  # quickstart runs of 0.02–0.05 s each
SPEEDS = [1200 + 5 * k for k in range(BATCH)]
REQUIRED = 1.7
TRIES = 4
BUSY = 1.0 / 3.0  # cores used by other processes that make a try unfit for timing


def wall_time(pool_size, scenes):
    start = time.perf_counter()
    with ThreadPoolExecutor(max_workers=pool_size) as pool:
        # Record arrays, not DataFrames: building those is Python work that holds the GIL.
        results = list(pool.map(lambda s: s.simulate(series=False, as_frame=False), scenes))
    elapsed = time.perf_counter() - start
    assert all(r.converged for r in results)
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
    """One thread, then two: (speed-up, cores other processes used meanwhile)."""
    busy, own, start = busy_seconds(), own_seconds(), time.perf_counter()
    one, metrics_one = wall_time(1, scenes)
    two, metrics_two = wall_time(2, scenes)
    elapsed = time.perf_counter() - start
    others = max(0.0, (busy_seconds() - busy) - (own_seconds() - own)) / elapsed
    assert metrics_two == metrics_one  # the same runs, whichever thread ran them
    assert one > 1.0, "the batch is too short to time"
    print(f"{BATCH} simulations: one thread {one:.2f} s, two threads {two:.2f} s, speed-up {one / two:.2f}"
          f" (other processes: {others:.2f} cores)")
    return one / two, others


def count_for(seconds):
    """Iterations of a pure-Python loop in `seconds` of wall time (it needs the GIL)."""
    n, end = 0, time.perf_counter() + seconds
    while time.perf_counter() < end:
        n += 1
    return n


def test_python_keeps_running_while_another_thread_simulates(quickstart):
    # The check that does not depend on the machine's speed: a GIL held
    # through the call would stop this thread's loop for the whole run, and
    # it runs at least half its own pace even with one core to share.
    scene = camdyn.load(quickstart, set={"simulation.cycles": 60})
    scene.simulate(series=False, as_frame=False)  # warm-up: what the call imports, imported now
    alone = count_for(0.2) / 0.2  # [iterations/s]
    # Record arrays: building DataFrames afterwards is Python work (it holds the GIL, rightly).
    worker = threading.Thread(target=lambda: scene.simulate(series=False, as_frame=False))
    n, start = 0, time.perf_counter()
    worker.start()
    while worker.is_alive():
        n += 1
    elapsed = time.perf_counter() - start
    worker.join()
    assert elapsed > 0.2, "the run is too short to show anything"
    assert n / elapsed > 0.3 * alone, f"{n / elapsed:.3g} iterations/s beside the run, {alone:.3g} alone"


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="needs two cores")
def test_two_threads_are_at_least_1_7_times_one(quickstart):
    scenes = [camdyn.load(quickstart, set={"cam.rpm": rpm}) for rpm in SPEEDS]
    wall_time(2, scenes[:2])  # warm-up: page in the code
    tries = []
    for _ in range(TRIES):
        tries.append(timed_try(scenes))
        if tries[-1][0] >= REQUIRED:
            return
    best, others = max(tries)
    if min(o for _, o in tries) > BUSY:
        pytest.skip(f"the machine is busy (other processes used {min(o for _, o in tries):.2f} cores or more "
                    f"in every try); best speed-up {best:.2f}")
    assert best >= REQUIRED, f"best speed-up {best:.2f} (other processes then: {others:.2f} cores)"
