"""Every argument of the Python entry points is checked as a config field is:
a bad one raises camdyn.InputError naming the argument (its `path`, no
`file`) and the reason, before anything runs; a run that fails has no
metrics that could read like a good design."""
import numpy as np
import pytest

import camdyn

# The cap on the points of one call: camdyn export --points's (docs/config.md).
MAX_POINTS = 1_000_000


@pytest.fixture
def scene(quickstart):
    return camdyn.load(quickstart)


def end_time(scene):
    """The run's end [s]: simulation.cycles revolutions at mechanism.cam.rpm, from the config alone."""
    return scene.resolved["simulation"]["cycles"] * 60.0 / scene.rpm


def argument_error(call, argument):
    with pytest.raises(camdyn.InputError) as caught:
        call()
    e = caught.value
    assert e.path == argument and e.file == ""
    assert str(e) == f"{argument}: {e.reason}"
    return e.reason


# sample_times: finite, ascending, within [0, end of the run].

@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf")])
def test_a_time_that_is_not_finite_is_named_not_dropped(scene, bad):
    # The valid times around it were dropped with it before.
    reason = argument_error(lambda: scene.simulate(series=False, sample_times=[0.01, bad, 0.02]), "sample_times")
    assert reason.startswith(f"sample_times[1] is {bad}")


def test_descending_times_are_an_input_error_not_a_solver_error(scene):
    reason = argument_error(lambda: scene.simulate(series=False, sample_times=[0.02, 0.01]), "sample_times")
    assert "sample_times[1] = 0.01 s comes before sample_times[0] = 0.02 s" in reason
    assert "ascending" in reason


def test_a_negative_time_is_before_the_run(scene):
    reason = argument_error(lambda: scene.simulate(series=False, sample_times=[-0.01, 0.0]), "sample_times")
    assert "sample_times[0] = -0.01 s is before the run's start" in reason


def test_a_time_past_the_run_is_named_with_the_runs_end(scene):
    t_end = end_time(scene)
    late = t_end * (1 + 1e-9)
    reason = argument_error(lambda: scene.simulate(series=False, sample_times=[0.0, late]), "sample_times")
    assert f"sample_times[1] = {late!r} s is after the run's end at {t_end!r} s" in reason


def test_times_from_the_start_to_the_end_of_the_run_are_all_sampled(scene):
    t_end = end_time(scene)
    times = [0.0, 0.01, 0.01, t_end]  # equal times are ascending too
    result = scene.simulate(series=False, sample_times=times, as_frame=False)
    assert result.solver["simulated_time_s"] == pytest.approx(t_end, rel=1e-15)
    assert list(result.samples.time) == times


def test_too_many_sample_times_name_the_cap(scene):
    reason = argument_error(lambda: scene.simulate(series=False, sample_times=np.zeros(MAX_POINTS + 1)),
                            "sample_times")
    assert f"at most {MAX_POINTS}" in reason


def test_sample_times_must_be_a_flat_list_of_numbers(scene):
    argument_error(lambda: scene.simulate(series=False, sample_times=["soon"]), "sample_times")
    argument_error(lambda: scene.simulate(series=False, sample_times=np.zeros((2, 2))), "sample_times")


@pytest.mark.parametrize("jobs", [-1, 10**9, 2.5, True])
def test_jobs_is_a_whole_number_within_the_cap(scene, jobs):
    argument_error(lambda: scene.simulate(series=False, jobs=jobs), "jobs")


# The cam and the law.

@pytest.mark.parametrize("bad", [float("nan"), float("inf")])
def test_the_law_at_an_angle_that_is_not_finite_is_an_input_error(scene, bad):
    # It returned zeros for NaN before: a law that reads as a dwell.
    reason = argument_error(lambda: scene.law([0.0, bad]), "angles_deg")
    assert reason.startswith(f"angles_deg[1] is {bad}")
    argument_error(lambda: camdyn.law(scene, [bad]), "angles_deg")


def test_a_profile_of_a_billion_points_is_refused_naming_the_cap(scene):
    # About 40 GB before; now refused before anything is allocated.
    reason = argument_error(lambda: camdyn.profile(scene, 10**9), "points")
    assert "1000000" in reason and "1000000000" in reason
    assert len(scene.profile(MAX_POINTS // 1000)["u"]) == MAX_POINTS // 1000


@pytest.mark.parametrize("points", [2, 0, -5, 3.5, "360", True])
def test_profile_points_are_a_whole_number_of_at_least_three(scene, points):
    argument_error(lambda: scene.profile(points), "points")


# Overrides and set: NaN and inf have no JSON form.

@pytest.mark.parametrize("bad", [float("nan"), float("inf")])
def test_a_value_that_is_not_finite_is_named_by_its_path(quickstart, scene, bad):
    reason = argument_error(lambda: camdyn.load(quickstart, set={"cam.rpm": bad}), "cam.rpm")
    assert "finite" in reason
    reason = argument_error(lambda: scene.set("mechanism.cam.rpm", bad), "mechanism.cam.rpm")
    assert "finite" in reason
    assert scene.rpm == 1300  # unchanged


def test_a_huge_whole_number_is_named_not_overflowed(scene):
    reason = argument_error(lambda: scene.set("cam.rpm", 10**400), "cam.rpm")
    assert "finite" in reason


def test_file_names_and_overrides_of_the_wrong_type_are_named(quickstart):
    argument_error(lambda: camdyn.load(1300), "path")
    argument_error(lambda: camdyn.load(quickstart, set=1300), "set")
    argument_error(lambda: camdyn.load(quickstart, set=["cam.rpm=1300", 5]), "set")
    argument_error(lambda: camdyn.Scene.from_json(b"{}"), "text")
    argument_error(lambda: camdyn.run_study(3.5), "config")


@pytest.mark.parametrize("jobs", [-1, 1.5])
def test_run_study_jobs_are_checked_before_it_runs(quickstart, tmp_path, jobs):
    argument_error(lambda: camdyn.run_study(quickstart, out=tmp_path / "out", jobs=jobs), "jobs")
    assert not (tmp_path / "out").exists()


# A failed run.

def test_a_failed_run_has_no_metrics_and_says_it_failed(quickstart):
    # 50 steps end the run before the evaluated window starts: its metrics
    # were all zero, which reads as no separation and no impact.
    scene = camdyn.load(quickstart, set={"integrator.max_steps": 50})
    result = scene.simulate(check=False)
    assert result.failed and not result.converged
    assert result.status == "step_budget" == result.solver["termination"]
    assert result.metrics is None
    assert "failed" in repr(result) and "step budget" in repr(result)
    with pytest.raises(camdyn.SolverError) as caught:
        scene.simulate()
    assert caught.value.result.metrics is None and caught.value.result.failed


def test_a_converged_run_has_its_metrics(scene):
    result = scene.simulate(series=False)
    assert not result.failed and result.status == "converged"
    assert result.metrics["peak_contact_force"] > 0
