#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz targets (tests/fuzz/corpus/, docs/fuzzing.md)
from the studies, the profiles and the bad-config corpus. Re-run it after those
change: python3 tests/fuzz/make_corpus.py

* corpus/config: each config as config_fuzzer reads it: the file, then each
  file it names (extends, profiles, small data files) after a line
  "#--- NAME", names rewritten to those sections; larger data files are named
  by their path in the source tree (the loader falls back to it). A few
  seeds add "#--- --set" lines.
* corpus/scene: each config with `extends` merged in (as the loader merges)
  and file names rewritten to their path in the source tree: scene_fuzzer
  reads JSON text, which has no `extends`.
* corpus/csv: the lift table and identification records of the tests, and
  short files with all four columns csv_fuzzer reads (angle_deg, lift,
  time, force_N).
* corpus/journal: the records of the compare study journal_fuzzer resumes
  (JOURNAL_OVERRIDES, the same as its kOverrides), from a run of
  `camdyn` (--camdyn, default build/ci/camdyn; skipped when it is not
  built): all runs, some, a failed and a budget-cut record, the header.
* corpus/export: byte strings for export_fuzzer (FuzzedDataProvider input),
  one a committed follower study.
* corpus/run: the scene seeds run_fuzzer runs, less RUN_LEFT_OUT.
"""
import argparse
import json
import math
import os
import pathlib
import shutil
import subprocess
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = pathlib.Path(__file__).resolve().parent / "corpus"
EMBED_LIMIT = 4000  # bytes; larger data files are named by their source-tree path
REPLACED_WHOLE = {"mechanism.cam.motion_law"}


def sources():
    files = sorted(ROOT.glob("studies/*.json")) + sorted(ROOT.glob("studies/*/*.json"))
    files += sorted(ROOT.glob("tests/data/bad_configs/*.json")) + sorted(ROOT.glob("tests/data/identify/*.json"))
    return files


def referenced(value, folder):
    """The file a config string names, relative to the config's folder, or None."""
    if not isinstance(value, str) or not value or len(value) > 200:
        return None
    path = (folder / value)
    return path.resolve() if path.is_file() else None


def rewrite(node, folder, on_file):
    """Replaces every string naming a file by on_file(path)."""
    if isinstance(node, dict):
        return {k: rewrite(v, folder, on_file) for k, v in node.items()}
    if isinstance(node, list):
        return [rewrite(v, folder, on_file) for v in node]
    path = referenced(node, folder)
    return on_file(path) if path else node


def load(path):
    try:
        return json.loads(path.read_text(), object_pairs_hook=dict)
    except (json.JSONDecodeError, UnicodeDecodeError):
        return None


def config_seed(path):
    """The config_fuzzer input for `path`: main text plus its named files."""
    sections, names = [], {}

    def embed(file):
        if file in names:
            return names[file]
        if file.suffix != ".json" and file.stat().st_size > EMBED_LIMIT:
            return str(file.relative_to(ROOT))
        name = file.name
        names[file] = name
        doc = load(file)
        text = file.read_text() if doc is None else json.dumps(rewrite(doc, file.parent, embed), indent=1)
        sections.append((name, text))
        return name

    doc = load(path)
    main = path.read_text() if doc is None else json.dumps(rewrite(doc, path.parent, embed), indent=1)
    return main + "".join(f"\n#--- {name}\n{text}" for name, text in sections) + "\n"


def merge(base, patch, path=""):
    for key, value in patch.items():
        key_path = f"{path}.{key}" if path else key
        if key_path not in REPLACED_WHOLE and isinstance(base.get(key), dict) and isinstance(value, dict):
            merge(base[key], value, key_path)
        else:
            base[key] = value


def resolved(path, seen=()):
    """The config at `path` with `extends` merged in, file names from the source root."""
    doc = load(path) if path.is_file() else None
    if not isinstance(doc, dict) or path in seen:
        return None
    doc = rewrite(doc, path.parent, lambda f: str(f.relative_to(ROOT)))
    parent = doc.pop("extends", None)
    if isinstance(parent, str):
        base = resolved(ROOT / parent, seen + (path,))
        if base is None:
            return None
        merge(base, doc)
        doc = base
    return doc


def csv_seeds():
    seeds = {}
    for f in [ROOT / "tests/data/geometry/periodic_lift.csv"] + sorted(ROOT.glob("tests/data/identify/*.csv")):
        seeds[f.name] = f.read_text()
    drop = [line for line in (ROOT / "studies/identify_drop/drop_h005.csv").read_text().splitlines()
            if line and line[0].isdigit()]
    for n in (8, 24, 72):
        rows = ["angle_deg,lift,time,force_N"]
        for i in range(n):
            angle = 360.0 * i / n
            lift = 0.01 * (1 - math.cos(math.radians(angle)))
            rows.append(f"{angle:.6g},{lift:.6g},{drop[i * 4]}")
        rows.append(f"360,0,{drop[n * 4]}")
        seeds[f"table_and_record_{n}.csv"] = "\n".join(rows) + "\n"
    seeds["quoted_bom_crlf.csv"] = "\ufeff# comment\r\n\"angle_deg\", \"lift\",time,force_N\r\n0,0,0.00027,0\r\n" \
                                   "180,+0.02,0.000275,1.5e1\r\n360,0,0.00028,0\r\n"
    return seeds


# Seeds run_fuzzer cannot run within libFuzzer's -timeout: an optimise
# study's rigid stage and the layout optimisation do not stop on
# --max-study-time (docs/fuzzing.md, "Findings open"): 4.6 s, 2.0 s and 7.5 s
# on a budget of 0.05 s in the ci build, over a minute under ASan.
RUN_LEFT_OUT = {"studies_layout_packaging_arm.json", "valvetrain_optimize_train.json",
                "studies_optimize_valve_lobe.json"}

JOURNAL_OVERRIDES = [
    'grid={"mechanism.cam.rpm":[600,1200]}',
    'cases=[{"name":"cycloidal"},{"name":"polynomial_345","set":["mechanism.cam.motion_law.segments[0].law=polynomial_345"]}]',
    'overlays=[{"mechanism.cam.rpm":1200}]',
    "simulation.cycles=2",
    "simulation.discard_cycles=1",
    "simulation.output_step_deg=5",
]


def journal_seeds(camdyn):
    """Seeds for journal_fuzzer from a real run of its study; None without a camdyn binary."""
    if not os.path.isfile(camdyn):
        return None
    with tempfile.TemporaryDirectory() as out:
        command = [camdyn, "run", str(ROOT / "studies/compare_laws.json"), "--quiet", "--out", out]
        for s in JOURNAL_OVERRIDES:
            command += ["--set", s]
        subprocess.run(command, check=True, capture_output=True)
        lines = pathlib.Path(out, "journal.jsonl").read_text().splitlines()
    header, records = lines[0], lines[1:]
    failed = json.loads(records[0])
    failed.update({"status": "failed", "error": "integrator.max_steps (1000) reached at t = 0.01 s",
                   "budget": "integrator.max_steps", "metrics": {m: None for m in failed["metrics"]}})
    return {
        "complete.jsonl": "\n".join(records) + "\n",
        "half.jsonl": "\n".join(records[:2]) + "\n",
        "failed_and_cut.jsonl": "\n".join([json.dumps(failed, separators=(",", ":"))] + records[1:]) + "\n",
        "header_and_records.jsonl": "\n".join([header] + records) + "\n",
        "last_line_cut.jsonl": "\n".join(records)[:-40],
    }


def export_seeds():
    """FuzzedDataProvider bytes: the study index and the first choices are read from the end."""
    seeds = {}
    for study in range(5):
        seeds[f"study{study}_nominal.bin"] = bytes([0x40] * 24 + [0x03, 0x05, 0x01, study])
        seeds[f"study{study}_fuzzed.bin"] = bytes(range(48)) + bytes([0x00, study])
    return seeds


def write(folder, files):
    target = OUT / folder
    if target.exists():
        shutil.rmtree(target)
    target.mkdir(parents=True)
    for name, content in files.items():
        if isinstance(content, bytes):
            (target / name).write_bytes(content)
        else:
            (target / name).write_text(content)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--camdyn", default=str(ROOT / "build/ci/camdyn"))
    args = parser.parse_args()
    config, scene = {}, {}
    for path in sources():
        stem = f"{path.parent.name}_{path.stem}"
        config[stem + ".txt"] = config_seed(path)
        doc = resolved(path)
        if doc is not None and "bad_configs" not in path.parts:
            scene[stem + ".json"] = json.dumps(doc, indent=1) + "\n"
    quick = config_seed(ROOT / "studies/quickstart.json")
    config["set_overrides.txt"] = quick + "#--- --set\nmechanism.cam.rpm=1500\nsimulation.cycles=2\n" \
                                          "contact.model=\"hertz\"\nintegrator={\"method\":\"rk4\",\"step\":1e-5}\n"
    compare = config_seed(ROOT / "studies/compare_laws.json")
    config["set_compare_grid.txt"] = compare + "#--- --set\ngrid={\"mechanism.cam.rpm\":[600,1200]}\n"
    write("config", config)
    write("scene", scene)
    write("csv", csv_seeds())
    write("run", {name: text for name, text in scene.items() if name not in RUN_LEFT_OUT})
    write("export", export_seeds())
    journal = journal_seeds(args.camdyn)
    if journal is not None:
        write("journal", journal)


if __name__ == "__main__":
    main()
