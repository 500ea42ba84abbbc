"""docs/config.md against the config loader, both ways: every key the docs list
in a checked section is accepted where the docs put it, and every key the
loader accepts there (as `camdyn validate` prints the resolved config, every
field with its default) is documented. CTest runs it (label scripts) with the
camdyn binary in CAMDYN_BINARY:

    CAMDYN_BINARY=build/ci/camdyn /usr/bin/python3 -m pytest -q tests/scripts/config_doc_keys_test.py

A section heading says where its keys go: "## `mechanism.cam`" puts `rpm` at
`mechanism.cam.rpm` (and "### `drive`" under it at `mechanism.cam.drive.*`);
a study's heading ("## `optimize` (a study: ...)") puts its keys at the top
level, written as they stand (`optimizer.seed`, `speed_limit.low_rpm`).
`.ftol_rel` after `optimizer.xtol_rel` is `optimizer.ftol_rel`.
"""
import json
import os
import re
import subprocess
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "config.md"
STUDIES = ROOT / "studies"
CAMDYN = os.environ.get("CAMDYN_BINARY", str(ROOT / "build" / "ci" / "camdyn"))

# The scene sections every study shares, and where their keys go. `outputs`
# has one table per object (test_the_outputs_tables_match_the_loader); the
# motion law's segment types and the train's bodies have tables of their own
# shapes and are not checked here.
SCENE_SECTIONS = {
    "top level": "",
    "mechanism.cam": "mechanism.cam",
    "mechanism.cam/drive": "mechanism.cam.drive",
    "mechanism.cam/limits": "mechanism.cam.limits",
    "mechanism.follower": "mechanism.follower",
    "mechanism.contact": "mechanism.contact",
    "simulation": "simulation",
    "integrator": "integrator",
}
# Each study's own sections (its keys from the top level), with the start
# its keys must have there: a periodic study takes `periodic.*` of the shared
# section, a jump map `periodic.*` and `jump_map.*`.
STUDY_SECTIONS = {
    "optimize": [("optimize", "")],
    "identify": [("identify", "")],
    "compare": [("compare", "")],
    "convergence": [("convergence", "")],
    "speed_limit": [("speed_limit", "")],
    "periodic": [("periodic and jump_map", "periodic.")],
    "jump_map": [("periodic and jump_map", "")],
}
# Keys a loader reads and resolves away: they are not in the resolved config.
RESOLVED_AWAY = {"description", "extends"}

HEADING = re.compile(r"^(#+)\s+(.*?)\s*$")
TICKED = re.compile(r"`([^`]+)`")


def section_name(title):
    """"`mechanism.cam`" -> "mechanism.cam"; "`optimize` (a study...)" -> "optimize"; else lower-case text."""
    title = re.sub(r"\s*\(.*$", "", title)
    return " ".join(title.replace("`", "").lower().split())


def documented_keys():
    """{section: [key, ...]} from the first column of every table, "h2/h3" for a subsection."""
    sections, h2, current, fenced = {}, "", "", False
    for line in DOC.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            fenced = not fenced
            continue
        heading = None if fenced else HEADING.match(line)
        if heading:
            name = section_name(heading.group(2))
            if len(heading.group(1)) == 2:
                h2 = current = name
            elif len(heading.group(1)) == 3:
                current = h2 + "/" + name
            continue
        if fenced or not line.startswith("| `"):
            continue
        first = line.split("|")[1]
        keys = []
        for key in TICKED.findall(first):
            if key.startswith(".") and keys:  # `optimizer.xtol_rel`, `.ftol_rel`
                key = keys[-1].rsplit(".", 1)[0] + key
            keys.append(key)
        # `parameters."PATH"`: one entry per user path, documented as a whole.
        keys = [k.split('."')[0] for k in keys]
        sections.setdefault(current, []).extend(keys)
    return sections


def validate(config, *sets):
    args = [CAMDYN, "validate", str(config)]
    for s in sets:
        args += ["--set", s]
    return subprocess.run(args, capture_output=True, text=True, cwd=ROOT, timeout=60)


def resolved_paths(config, *sets):
    """Every dotted path of the resolved config: objects walked, a list or a map of user names a leaf."""
    run = validate(config, *sets)
    assert run.returncode == 0, f"{config} {sets}: {run.stderr}"
    paths = set()

    def walk(value, path):
        if path:
            paths.add(path)
        if isinstance(value, dict):
            for key, child in value.items():
                walk(child, f"{path}.{key}" if path else key)

    walk(json.loads(run.stdout), "")
    return paths


@pytest.fixture(scope="module")
def docs():
    return documented_keys()


def study_configs(tmp_path_factory):
    """A valid config of every study type, as (study, config file, --set arguments)."""
    tmp = tmp_path_factory.mktemp("configs")
    quickstart = STUDIES / "quickstart.json"
    (tmp / "compare.json").write_text(json.dumps(
        {"extends": str(quickstart), "study": "compare", "grid": {"mechanism.cam.rpm": [1000, 1100]}}))
    (tmp / "convergence.json").write_text(json.dumps(
        {"extends": str(quickstart), "study": "convergence", "methods": ["cvode_bdf"], "tolerances": [1e-5],
         "tracking": ["differential"], "rk4_steps_deg": [0.5]}))
    return [
        ("simulate", quickstart, ()),
        ("simulate", STUDIES / "followers" / "oscillating_flat.json", ()),
        ("simulate", STUDIES / "followers" / "shaft_drive.json", ()),
        ("simulate", STUDIES / "followers" / "translating_mushroom.json", ()),
        ("optimize", STUDIES / "optimize_jump.json", ()),
        ("identify", STUDIES / "identify_drop" / "identify_drop.json", ()),
        ("compare", tmp / "compare.json", ()),
        ("convergence", tmp / "convergence.json", ()),
        ("speed_limit", quickstart, ("study=speed_limit",)),
        ("periodic", STUDIES / "periodic" / "bouncing_ball.json", ()),
        ("jump_map", quickstart, ("study=jump_map", 'jump_map={"low_rpm": 1000, "high_rpm": 1300}')),
    ]


@pytest.fixture(scope="module")
def resolved(tmp_path_factory):
    """{study: the union of the resolved paths of its configs}."""
    if not Path(CAMDYN).is_file():
        pytest.skip(f"no camdyn binary at {CAMDYN} (set CAMDYN_BINARY)")
    out = {}
    configs = study_configs(tmp_path_factory)
    with ThreadPoolExecutor() as pool:  # one validate each, side by side
        found = pool.map(lambda c: resolved_paths(c[1], *c[2]), configs)
        for (study, _, _), paths in zip(configs, found):
            out.setdefault(study, set()).update(paths)
    return out


def expected_keys(docs, study, scene=True):
    """The full paths the docs say `study` accepts: the scene's sections (with `scene`) and its own."""
    keys = set()
    for section, prefix in SCENE_SECTIONS.items() if scene else []:
        assert section in docs, f"docs/config.md has no section '{section}' (headings: {sorted(docs)})"
        keys.update(f"{prefix}.{k}" if prefix else k for k in docs[section])
    for section, start in STUDY_SECTIONS.get(study, []):
        assert section in docs, f"docs/config.md has no section '{section}'"
        keys.update(k for k in docs[section] if k.startswith(start))
    return keys


def is_documented(path, keys):
    """`path` is a documented key, an object whose fields are documented, or lies under a documented key
    that documents no narrower key (an object described as a whole)."""
    for key in keys:
        if path == key or key.startswith(path + "."):
            return True
        if path.startswith(key + ".") and not any(k.startswith(key + ".") for k in keys):
            return True
    return False


def accepted(path, paths):
    return path in paths or any(p.startswith(path + ".") for p in paths)


def test_the_optimize_fields_are_documented_at_the_top_level(docs):
    # The attack: an `optimize` heading read as an `optimize` object.
    assert "optimize" in docs and "optimizer.seed" in docs["optimize"]
    text = DOC.read_text(encoding="utf-8")
    assert "not in an\n`optimize` object" in text


def test_the_loader_rejects_an_optimize_object():
    if not Path(CAMDYN).is_file():
        pytest.skip(f"no camdyn binary at {CAMDYN}")
    run = validate(STUDIES / "optimize_jump.json", 'optimize={"operating_rpm": [1000]}')
    assert run.returncode == 2 and "unknown key 'optimize'" in run.stderr, run.stderr


@pytest.mark.parametrize("study", list(STUDY_SECTIONS) + ["simulate"])
def test_every_documented_key_is_accepted_where_the_docs_put_it(docs, resolved, study):
    """In the resolved config of the study, or (a key with no default: a variant, or read and resolved away)
    accepted by `validate --set` on that study's config, i.e. not an unknown key. The scene's keys are
    checked on the simulate study (every study reads the scene with the same loader)."""
    missing = []
    for key in sorted(expected_keys(docs, study, scene=study == "simulate")):
        if key in RESOLVED_AWAY or accepted(key, resolved[study]):
            continue
        missing.append(key)
    base, sets = STUDY_BASE[study]
    with ThreadPoolExecutor() as pool:
        runs = pool.map(lambda key: validate(base, *sets, f"{key}=null"), missing)
        unknown = [f"{key}: {run.stderr.strip()}" for key, run in zip(missing, runs)
                   if "unknown key" in run.stderr or "unknown field" in run.stderr]
    assert not unknown, f"{study}: documented in docs/config.md but not accepted there:\n" + "\n".join(unknown)


@pytest.mark.parametrize("study", list(STUDY_SECTIONS) + ["simulate"])
def test_every_accepted_key_is_documented(docs, resolved, study):
    keys = expected_keys(docs, study)
    undocumented = sorted(p for p in resolved[study] if not is_documented(p, keys))
    assert not undocumented, f"{study}: accepted by the loader but not in docs/config.md: {undocumented}"


STUDY_BASE = {
    "simulate": (STUDIES / "quickstart.json", ()),
    "optimize": (STUDIES / "optimize_jump.json", ()),
    "identify": (STUDIES / "identify_drop" / "identify_drop.json", ()),
    "compare": (STUDIES / "quickstart.json", ("study=compare",)),
    "convergence": (STUDIES / "work_precision.json", ()),
    "speed_limit": (STUDIES / "quickstart.json", ("study=speed_limit",)),
    "periodic": (STUDIES / "periodic" / "bouncing_ball.json", ()),
    "jump_map": (STUDIES / "quickstart.json", ("study=jump_map", 'jump_map={"low_rpm": 1000, "high_rpm": 1300}')),
}


def output_table_keys():
    """{"profile": [...], "valvetrain": [...]}: the "## `outputs`" section has one table per object,
    each after the line that introduces it ("`profile`: null (default) or an object; ...")."""
    tables, current, inside = {}, None, False
    for line in DOC.read_text(encoding="utf-8").splitlines():
        heading = HEADING.match(line)
        if heading:
            inside = section_name(heading.group(2)) == "outputs"
            continue
        if not inside:
            continue
        intro = re.match(r"^`(\w+)`: ", line)
        if intro:
            current = intro.group(1)
        elif current and line.startswith("| `"):
            tables.setdefault(current, []).extend(TICKED.findall(line.split("|")[1]))
    return tables


def test_the_outputs_tables_match_the_loader():
    """Each object of `outputs` given as {} resolves to its fields with their defaults: those must be the
    documented ones, and each documented one must be among them."""
    if not Path(CAMDYN).is_file():
        pytest.skip(f"no camdyn binary at {CAMDYN}")
    tables = output_table_keys()
    assert set(tables) == {"profile", "valvetrain"}, tables
    run = validate(STUDIES / "quickstart.json", "outputs.profile={}", "outputs.valvetrain={}")
    assert run.returncode == 0, run.stderr
    outputs = json.loads(run.stdout)["outputs"]
    assert set(outputs) == set(tables), f"outputs objects: loader {sorted(outputs)}, docs {sorted(tables)}"
    for name, keys in tables.items():
        assert set(outputs[name]) == set(keys), f"outputs.{name}: loader {sorted(outputs[name])}, docs {sorted(keys)}"
