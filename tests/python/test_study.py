"""camdyn.run_study runs a study as `camdyn run` does and returns its main result."""
import json
import subprocess

import camdyn


def test_periodic_study_is_the_clis(camdyn_binary, root, tmp_path):
    config = root / "studies" / "periodic" / "bouncing_ball.json"
    result = camdyn.run_study(config, out=tmp_path / "py", jobs=1)
    subprocess.run([camdyn_binary, "run", str(config), "--out", str(tmp_path / "cli"), "--quiet", "--jobs", "1"],
                   check=True, capture_output=True)
    cli = json.loads((tmp_path / "cli" / "periodic.json").read_text(encoding="utf-8"))
    assert (tmp_path / "py" / "periodic.json").exists()
    # Every number the same to the last bit (json.load reads them exactly); only the run time differs.
    for d in (result, cli):
        del d["run_time_s"]
    assert result == cli
    assert result["study"] == "periodic" and result["motion"] == "periodic"

def test_compare_study_from_a_dict_in_a_temporary_folder(root):
    config = json.loads((root / "studies" / "quickstart.json").read_text(encoding="utf-8"))
    config.update({"name": "py_compare", "study": "compare", "cases": [{"name": "quickstart"}],
                   "grid": {"mechanism.cam.rpm": [900, 1300]},
                   "metrics": ["separation_fraction", "peak_contact_force"]})
    config["simulation"]["cycles"] = 2
    result = camdyn.run_study(config, base_dir=root / "studies", jobs=2)
    assert result["name"] == "py_compare"
    text = json.dumps(result)
    assert "separation_fraction" in text and "peak_contact_force" in text


def test_simulate_study_returns_the_summary(quickstart, tmp_path):
    summary = camdyn.run_study(quickstart, out=tmp_path, set={"cam.rpm": 900})
    assert summary["study"] == "simulate"
    assert summary["metrics"]["separation_fraction"] == 0.0
    assert (tmp_path / "summary.json").exists() and (tmp_path / "report.html").exists()


def test_a_temporary_folder_is_never_named(quickstart, tmp_path, capfd):
    """Without `out` the folder is deleted on return: nothing printed names it; with `out` the summary says where."""
    result = camdyn.run_study(quickstart, set={"simulation.cycles": 2})
    printed = capfd.readouterr().out
    assert "metrics" in result
    assert "report" not in printed and "camdyn-" not in printed, printed
    camdyn.run_study(quickstart, out=tmp_path / "kept", set={"simulation.cycles": 2})
    printed = capfd.readouterr().out
    assert str(tmp_path / "kept") in printed and "report" in printed, printed
