"""Ctrl-C stops a simulation within about a second: the run polls Python's
signal handlers between integrator steps (at most every 0.25 s of wall
time) on the main thread, instead of raising only when it returns."""
import os
import signal
import threading
import time

import pytest

import camdyn

# Long enough that a run which ignores the signal takes far longer than the
# bound: the quickstart's 40 revolutions take about 0.4 s on one core, these
# 3000 about 30 s.
LONG_RUN = {"simulation.cycles": 3000}
# The run checks every 0.25 s; the rest of the bound is the step in
# progress and a machine shared with other work [s].
BOUND_S = 2.0


def send_sigint_after(delay_s, sent):
    def send():
        sent.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)
    timer = threading.Timer(delay_s, send)
    timer.start()
    return timer


@pytest.fixture
def default_sigint():
    """Python's own Ctrl-C handler (KeyboardInterrupt), whatever the runner installed."""
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, before)


def test_ctrl_c_raises_keyboard_interrupt_within_the_bound(quickstart, default_sigint):
    scene = camdyn.load(quickstart, set=LONG_RUN)
    sent = []
    timer = send_sigint_after(0.5, sent)
    try:
        with pytest.raises(KeyboardInterrupt):
            scene.simulate(series=False)
        raised = time.monotonic()
    finally:
        timer.cancel()
    assert sent, "the run ended before the signal was sent"
    assert raised - sent[0] < BOUND_S
    # The scene is intact: a run after the interrupted one gives what a fresh scene gives.
    short = {"simulation.cycles": 4}
    again = scene.set("simulation.cycles", 4).simulate(series=False)
    assert again.metrics == camdyn.load(quickstart, set=short).simulate(series=False).metrics


def test_a_handler_that_returns_lets_the_run_finish(quickstart):
    # The handler runs while the run is in progress (not when it returns), and
    # a handler that raises nothing does not stop it.
    scene = camdyn.load(quickstart, set={"simulation.cycles": 150})
    handled = []
    before = signal.signal(signal.SIGINT, lambda signum, frame: handled.append(time.monotonic()))
    sent = []
    timer = send_sigint_after(0.3, sent)
    try:
        result = scene.simulate(series=False)
        returned = time.monotonic()
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, before)
    if not sent:
        pytest.skip("the run ended before the signal was sent (a fast machine)")
    assert result.converged
    assert len(handled) == 1 and handled[0] - sent[0] < BOUND_S
    assert handled[0] < returned - 0.1, "the handler ran only when the run returned"


def test_a_run_on_another_thread_is_not_affected(quickstart):
    # Python runs signal handlers on the main thread only; a worker's run
    # neither polls them nor stops.
    scene = camdyn.load(quickstart)
    results = []
    worker = threading.Thread(target=lambda: results.append(scene.simulate(series=False)))
    worker.start()
    worker.join()
    assert results[0].metrics == scene.simulate(series=False).metrics


def test_ctrl_c_stops_a_study_and_keeps_its_journal(quickstart, default_sigint, tmp_path):
    # A speed_limit study whose speeds each take seconds: Ctrl-C stops it
    # within the bound (every run stops as on a used-up study budget), the
    # journal keeps the speeds that finished, and a re-run resumes from it.
    out = tmp_path / "limit"
    study = {"study": "speed_limit", "simulation.cycles": 400,
             "speed_limit": {"low_rpm": 500, "high_rpm": 1600, "scan": 4, "tolerance_rpm": 20}}
    sent = []
    timer = send_sigint_after(1.0, sent)
    started = time.monotonic()
    try:
        with pytest.raises(KeyboardInterrupt):
            camdyn.run_study(quickstart, out=str(out), jobs=1, set=study)
        raised = time.monotonic()
    finally:
        timer.cancel()
    assert sent, "the study ended before the signal was sent"
    assert raised - sent[0] < BOUND_S, f"stopped {raised - sent[0]:.2f} s after the signal"
    assert raised - started < 30.0
    assert not (out / "complete.json").exists()
    assert (out / "journal.jsonl").exists()
