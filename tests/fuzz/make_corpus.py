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
"""
import json
import math
import os
import pathlib
import shutil

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


def write(folder, files):
    target = OUT / folder
    if target.exists():
        shutil.rmtree(target)
    target.mkdir(parents=True)
    for name, text in files.items():
        (target / name).write_text(text)


def main():
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


if __name__ == "__main__":
    main()
