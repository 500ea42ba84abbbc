"""scripts/check_structure.py's doc-reference check (its rule 3) on a small fake tree:
a citation of a missing doc, a section or heading the doc does not have, and any
mention of the outside spec files are reported, each at its line; citations that
resolve are not. Its unity-target check (rule 4) on another: a file-scope name two
.cc files of one target define is reported, members, locals, repeated aliases to one
type and functions of external linkage are not. CTest runs it (label scripts):

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


# Rule 4: a file-scope name defined in two .cc files of one unity target.
UNITY_A = r"""#include "dynamics/a.h"
namespace fs = std::filesystem;  // a namespace alias may be declared again
namespace camdyn {
namespace {
using Complex = std::complex<double>;  // the same alias again: allowed
using Index = int;
constexpr double kShared = 1.0;
constexpr const char* kText = R"({ "braces": { "in": "a raw string" } })";
struct Helper {
  int kInner = 1;  // a member, not file scope
  void method() { const double kLocal = 2.0; }
};
double helper(double x) { return x; }
void PrintTo(const Helper& h, std::ostream* os) {}  // gtest's, overloaded by type
}  // namespace
double public_function(double x) { return x; }  // external linkage: the linker's business
static int counter(int x) {
  const int kBodyLocal = x;
  return kBodyLocal;
}
}  // namespace camdyn
"""
UNITY_B = """namespace fs = std::filesystem;
namespace camdyn {
namespace {
using Complex = std::complex<double>;
using Index = long;
constexpr double kShared = 2.0;
double helper(int x) { return x; }  // an overload: a clash too
void PrintTo(const int& h, std::ostream* os) {}
int kInner = 0;
}  // namespace
double public_function(int x) { return x; }
static int counter(double x) { return 0; }  // an overload of a static function
struct Helper {};
}  // namespace camdyn
"""
UNITY_TEST = """namespace camdyn {
namespace {
constexpr double kTolerance = 1e-9;
TEST(Suite, Name) { EXPECT_TRUE(true); }
}  // namespace
}  // namespace camdyn
"""
UNITY_CMAKE = "set(study_runner_stems mpi_runner journal)\n"
UNITY_TEST_CMAKE = "set(test_areas io)\n"


@pytest.fixture
def unity_tree(tmp_path):
    files = {"CMakeLists.txt": UNITY_CMAKE, "tests/CMakeLists.txt": UNITY_TEST_CMAKE,
             "src/dynamics/a.cc": UNITY_A, "src/dynamics/b.cc": UNITY_B,
             # Two targets: the study library and its runner; the CLI's files each a target.
             "src/study/plain.cc": UNITY_TEST, "src/study/journal.cc": UNITY_TEST,
             "src/cli/main.cc": UNITY_TEST, "src/cli/run_study.cc": UNITY_TEST,
             "optim/one.cc": UNITY_TEST, "optim/identify/two.cc": UNITY_TEST,
             "tests/io/a_test.cc": UNITY_TEST, "tests/io/b_test.cc": UNITY_TEST.replace("Name", "Other")}
    for name, text in files.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text, encoding="utf-8")
    return tmp_path


def clashes(root):
    return [v.split(": ", 1)[1].split(" is defined")[0] for v in check_structure.unity_name_clashes(root)]


def test_unity_targets_follow_the_build(unity_tree):
    targets = {name: sorted(f.relative_to(unity_tree).as_posix() for f in files)
               for name, files in check_structure.unity_targets(unity_tree).items()}
    assert targets == {"camdyn_dynamics": ["src/dynamics/a.cc", "src/dynamics/b.cc"],
                       "camdyn_study_runner": ["src/study/journal.cc"], "camdyn_study": ["src/study/plain.cc"],
                       "camdyn_optim": ["optim/identify/two.cc", "optim/one.cc"],
                       "io_tests": ["tests/io/a_test.cc", "tests/io/b_test.cc"]}


def test_names_defined_twice_in_one_target_are_reported(unity_tree):
    assert sorted(clashes(unity_tree)) == sorted([
        "alias 'Index'", "variable 'kShared'", "function 'helper'", "function 'counter'", "type 'Helper'",
        "variable 'kTolerance'", "variable 'kTolerance'"])  # io_tests and camdyn_optim; not kInner (a member)


def test_a_clash_names_both_files_and_lines(unity_tree):
    found = check_structure.unity_name_clashes(unity_tree)
    assert ("src/dynamics/a.cc:7: variable 'kShared' is defined at file scope in 2 files of the unity target "
            "camdyn_dynamics (src/dynamics/a.cc:7 and src/dynamics/b.cc:6): one name per target") in found
