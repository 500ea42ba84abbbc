"""The examples run, and the README quotes the Python example CI runs."""
import os
import subprocess
import sys

EXAMPLES = "examples/python"


def run(root, script, *args):
    env = dict(os.environ, MPLBACKEND="Agg")
    done = subprocess.run([sys.executable, str(root / EXAMPLES / script), *map(str, args)], cwd=root, env=env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_readme_quotes_the_example_verbatim(root):
    example = (root / EXAMPLES / "readme_example.py").read_text(encoding="utf-8")
    readme = (root / "README.md").read_text(encoding="utf-8")
    assert f"```python\n{example}```\n" in readme


def test_readme_example_runs(root):
    out = run(root, "readme_example.py")
    assert "jump speed" in out and "peak contact force" in out


def test_jump_onset_example_plots(root, tmp_path):
    out = run(root, "jump_onset.py", tmp_path)
    png = tmp_path / "jump_onset.png"
    assert png.exists() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "rigid-model jump speed" in out
