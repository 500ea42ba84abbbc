"""scripts/check_structure.py's doc-reference check (its rule 3) on a small fake tree:
a citation of a missing doc, a section or heading the doc does not have, and any
mention of the outside spec files are reported, each at its line; citations that
resolve are not. CTest runs it (label scripts):

    /usr/bin/python3 -m pytest -q tests/scripts/check_structure_test.py
"""
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
import check_structure  # noqa: E402

MODEL = """# The model
## 1. Geometry
## 2. Contact
### 2.1 Tracking
```
## 9. In a code block, not a heading
```
"""
CONFIG = """# Config
## `mechanism.cam`
### `limits` (the cam must meet these)
## Outputs of `simulate`
"""
GOOD = """// docs/model.md §2 and model.md §1 and §2.1 (a bare name is looked for in docs/)
// docs/config.md `mechanism.cam`, docs/config.md, "Outputs of simulate",
// docs/config.md, section `limits`; a wrapped one: docs/model.md
// §1. The README.md at the top, and NOTES.md beside this file.
"""
BAD = """// ok: docs/model.md §1
// physics.md §3
// the layers (../shared/style.md)
// docs/missing.md
// docs/model.md §9 and §2.2
// docs/config.md, "No such heading"
// wrapped: docs/model.md
// §7
"""


@pytest.fixture
def tree(tmp_path):
    files = {"docs/model.md": MODEL, "docs/config.md": CONFIG, "README.md": "# camdyn\n",
             "src/io/NOTES.md": "# Notes\n", "src/io/good.h": GOOD, "tests/io/bad_test.cc": BAD}
    for name, text in files.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text, encoding="utf-8")
    return tmp_path


def violations(root):
    return check_structure.doc_reference_violations(root)


def test_citations_that_resolve_are_not_reported(tree):
    assert not [v for v in violations(tree) if v.startswith("src/io/good.h")]


def test_outside_files_are_reported_at_their_line(tree):
    found = violations(tree)
    assert any(v.startswith("tests/io/bad_test.cc:2: cites a file outside the repository ('physics.md')") for v in found)
    assert any(v.startswith("tests/io/bad_test.cc:3: cites a file outside the repository ('../shared')") for v in found)


def test_missing_docs_sections_and_headings_are_reported(tree):
    assert violations(tree) == [
        "tests/io/bad_test.cc:2: cites a file outside the repository ('physics.md'): cite docs/ instead",
        "tests/io/bad_test.cc:3: cites a file outside the repository ('../shared'): cite docs/ instead",
        "tests/io/bad_test.cc:4: cites 'docs/missing.md', which is not in the repository",
        "tests/io/bad_test.cc:5: cites 'docs/model.md §9', but docs/model.md has no heading '## 9.'",
        "tests/io/bad_test.cc:5: cites 'docs/model.md §2.2', but docs/model.md has no heading '## 2.2.'",
        "tests/io/bad_test.cc:6: cites 'docs/config.md, \"No such heading\"', but docs/config.md has no such heading",
        "tests/io/bad_test.cc:7: cites 'docs/model.md §7', but docs/model.md has no heading '## 7.'",
    ]


def test_the_check_runs_by_default(tree, monkeypatch, capsys):
    monkeypatch.setattr(check_structure, "ROOT", tree)
    monkeypatch.setattr(sys, "argv", ["check_structure.py"])
    assert check_structure.main() == 1
    assert "tests/io/bad_test.cc:4: cites 'docs/missing.md'" in capsys.readouterr().out
