#!/usr/bin/env python3
"""Checks the two structural rules of camdyn's code (../shared/style.md, "Layers"):

1. No folder includes a folder above it. The layers, bottom first:
       common < scene < geometry < contact < integrate < dynamics < io < study < api < optim < cli < python
   A file in src/<layer>/ (optim/ with its study folders optim/optimize/
   and optim/identify/ is the optim layer, python/ the python layer) may
   include headers of its own layer and of the layers below it only, and
   never with "../". The Python module (python/) stands on the
   public API: of the private headers it includes only the study dispatch
   "cli/run_study.h".
   The public headers (include/camdyn/) belong to the api layer, except
   <camdyn/errors.h> and <camdyn/version.h>, which every layer may include.
   A public header includes only public headers and standard ones: a
   "dynamics/..." (or any private or third-party) header there would leak
   into every caller's build.
2. No function in src/, optim/ or python/ runs over MAX_LINES lines (from the line that
   opens its body to the line that closes it). Functions are found as the
   project's clang-format writes them: a definition whose body opens at the
   end of an unindented line and closes with an unindented "}".

Prints every violation as file:line and exits 1 if there is any.

    python3 scripts/check_structure.py [--max-lines 120]
"""
import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LAYERS = ["common", "scene", "geometry", "contact", "integrate", "dynamics", "io", "study", "api", "optim", "cli", "python"]
# The private headers the python layer may include (it is built on the public API).
PYTHON_PRIVATE = {"cli/run_study.h"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
ANY_INCLUDE = re.compile(r'^\s*#\s*include\s+([<"])([^>"]+)[>"]')
# Public headers any layer may include (they depend on nothing); the others are the api layer's.
PUBLIC_BASE = {"camdyn/errors.h", "camdyn/version.h"}
# A standard library header: <name>, no folder and no extension.
STANDARD = re.compile(r"^[a-z_0-9]+$")
NOT_FUNCTIONS = re.compile(r"^(namespace|struct|class|enum|union|extern)\b|=\s*\{$|^(static\s+)?(const|constexpr)\b.*=")


def layer_of(path):
    rel = path.relative_to(ROOT).parts
    if rel[0] in ("optim", "python"):
        return rel[0]  # optim/<study>/ included: one layer
    if rel[0] == "src" and len(rel) > 2:
        return rel[1]
    return None


def sources():
    for top in ("src", "optim", "python"):
        for path in sorted((ROOT / top).rglob("*")):
            if path.suffix in (".h", ".cc"):
                yield path


def include_violations():
    found = []
    for path in sources():
        own = layer_of(path)
        if own not in LAYERS:
            found.append(f"{path.relative_to(ROOT)}: folder '{own}' is not a known layer ({', '.join(LAYERS)})")
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
            public = ANY_INCLUDE.match(line)
            if (public and public.group(1) == "<" and public.group(2).startswith("camdyn/")
                    and public.group(2) not in PUBLIC_BASE and LAYERS.index(own) < LAYERS.index("api")):
                found.append(f"{path.relative_to(ROOT)}:{number}: layer '{own}' includes the public header "
                             f"'<{public.group(2)}>' of the layer above it, 'api'")
            match = INCLUDE.match(line)
            if not match:
                continue
            target = match.group(1)
            if ".." in Path(target).parts:
                found.append(f"{path.relative_to(ROOT)}:{number}: includes '{target}' through '..'")
                continue
            head = Path(target).parts[0] if len(Path(target).parts) > 1 else own
            if head not in LAYERS:
                continue  # a header beside this one, or a third-party header in quotes
            if own == "python" and target not in PYTHON_PRIVATE:
                found.append(f"{path.relative_to(ROOT)}:{number}: the python layer includes the private header "
                             f"'{target}': it stands on <camdyn/...> (and {', '.join(sorted(PYTHON_PRIVATE))})")
                continue
            if LAYERS.index(head) > LAYERS.index(own):
                found.append(f"{path.relative_to(ROOT)}:{number}: layer '{own}' includes '{target}' "
                             f"from the layer above it, '{head}'")
    return found


def public_headers():
    return sorted(p for p in (ROOT / "include").rglob("*") if p.name.endswith((".h", ".h.in")))


def public_include_violations():
    """A public header includes only <camdyn/...> and standard headers."""
    found = []
    for path in public_headers():
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
            match = ANY_INCLUDE.match(line)
            if not match:
                continue
            bracket, target = match.groups()
            if bracket == "<" and (target.startswith("camdyn/") or STANDARD.match(target)):
                continue
            found.append(f"{path.relative_to(ROOT)}:{number}: public header includes '{target}': only "
                         f"<camdyn/...> and standard headers may be included there (it would leak)")
    return found


def long_functions(max_lines):
    found = []
    for path in sources():
        lines = path.read_text(encoding="utf-8").splitlines()
        start = None   # line that opens the body being measured
        header = None  # first line of an unindented declaration still open (a signature over several lines)
        for number, line in enumerate(lines, start=1):
            stripped = line.rstrip()
            if start is not None:
                if stripped.startswith("}"):
                    length = number - start + 1
                    if length > max_lines:
                        head = lines[(header or start) - 1].strip()
                        found.append(f"{path.relative_to(ROOT)}:{header or start}: {length} lines: {head[:90]}")
                    start = header = None
                continue
            unindented = bool(stripped) and not stripped[0].isspace()
            comment = stripped.lstrip().startswith(("#", "//", "///", "*", "/*"))
            if not stripped or comment or stripped.endswith((";", "}")):
                header = None
                continue
            if unindented and header is None:
                header = number
            if header is not None and stripped.endswith("{"):
                if NOT_FUNCTIONS.search(lines[header - 1].strip()):
                    header = None
                else:
                    start = number
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--max-lines", type=int, default=120)
    args = parser.parse_args()
    problems = include_violations() + public_include_violations() + long_functions(args.max_lines)
    for problem in problems:
        print(problem)
    print(f"check_structure: {len(problems)} problem(s) in {sum(1 for _ in sources())} files "
          f"and {len(public_headers())} public headers "
          f"(layers {' < '.join(LAYERS)}; functions <= {args.max_lines} lines)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
