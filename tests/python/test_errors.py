"""Bad input raises camdyn.InputError with the CLI's message and the dotted path;
a solver that gives up raises camdyn.SolverError."""
import json
import subprocess

import pytest

import camdyn


def cli_error(binary, config, *sets):
    args = [binary, "validate", str(config)]
    for s in sets:
        args += ["--set", s]
    done = subprocess.run(args, capture_output=True, text=True)
    assert done.returncode == 2, done.stderr
    return done.stderr.strip()


def test_bad_value_names_the_file_and_the_dotted_path(camdyn_binary, quickstart):
    with pytest.raises(camdyn.InputError) as caught:
        camdyn.load(quickstart, set={"contact.stiffness": -1.0})
    e = caught.value
    assert e.path == "mechanism.contact.stiffness"
    assert e.file == str(quickstart)
    assert e.reason and e.reason in str(e)
    assert isinstance(e, camdyn.Error) and isinstance(e, ValueError)
    # The CLI's message names the --set argument a value came from; the
    # reason and the dotted path are the same, word for word.
    assert cli_error(camdyn_binary, quickstart, "contact.stiffness=-1") == (
        f"camdyn: error: --set contact.stiffness=-1: {e.path}: {e.reason}")


def test_unknown_key_suggests_the_closest(quickstart):
    config = json.loads(quickstart.read_text(encoding="utf-8"))
    config["mechanism"]["follower"]["mas"] = 0.3
    with pytest.raises(camdyn.InputError) as caught:
        camdyn.Scene.from_dict(config, base_dir=quickstart.parent)
    assert caught.value.path == "mechanism.follower.mas"
    assert caught.value.file == ""
    assert "mass" in caught.value.reason


def test_a_cam_that_cannot_be_made_is_an_input_error(camdyn_binary, root):
    # An undercut is found when the cam is built, below the config layer; the error still names the file.
    config = root / "tests" / "data" / "bad_configs" / "undercut.json"
    with pytest.raises(camdyn.InputError) as caught:
        camdyn.load(config)
    assert caught.value.path == "mechanism.cam"
    assert caught.value.file == str(config)
    assert "undercut" in caught.value.reason
    assert cli_error(camdyn_binary, config) == f"camdyn: error: {caught.value}"


def test_missing_file(tmp_path):
    with pytest.raises(camdyn.InputError) as caught:
        camdyn.load(tmp_path / "missing.json")
    assert caught.value.file == str(tmp_path / "missing.json")


def test_a_solver_that_gives_up_raises_solver_error(quickstart):
    scene = camdyn.load(quickstart, set={"integrator.max_steps": 50})
    with pytest.raises(camdyn.SolverError) as caught:
        scene.simulate()
    assert caught.value.termination == "step_budget"
    assert isinstance(caught.value, camdyn.Error) and isinstance(caught.value, RuntimeError)
    assert caught.value.result.solver["termination"] == "step_budget"
    # As a status instead:
    result = scene.simulate(check=False)
    assert not result.converged and result.solver["message"]


def test_run_study_raises_input_error(quickstart, tmp_path):
    with pytest.raises(camdyn.InputError) as caught:
        camdyn.run_study(quickstart, out=tmp_path, set={"simulation.cycles": -1})
    assert caught.value.path == "simulation.cycles"
    assert caught.value.file == str(quickstart)
