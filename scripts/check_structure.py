#!/usr/bin/env python3
"""Checks the three structural rules of camdyn's code (docs/architecture.md, "Layers"):

1. No folder includes a folder above it. The layers, bottom first:
       common < scene < io < geometry < contact < integrate < dynamics < output < study < api < optim < cli < python
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
3. Every doc a source or script file cites (in src/, optim/, python/,
   include/, tests/, bench/, scripts/) is in the repository: a path such as
   docs/NAME.md (a bare NAME.md: at the top, in docs/ or beside the file)
   exists; a section "docs/model.md §N" (or §N.M) matches a numbered heading
   "## N." of that file; a heading cited by its title, in quotes or
   backticks right after the path (docs/architecture.md, "Adding a contact
   law"; docs/config.md `motion_law`), matches a heading of that file. Any
   mention of physics.md, interface.md or ../shared cites a file outside the
   repository and is a violation.

Prints every violation as file:line: reason and exits 1 if there is any.

    python3 scripts/check_structure.py [--max-lines 120]
"""
import argparse
import functools
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LAYERS = ["common", "scene", "io", "geometry", "contact", "integrate", "dynamics", "output", "study", "api", "optim", "cli", "python"]
# The private headers the python layer may include (it is built on the public API).
PYTHON_PRIVATE = {"cli/run_study.h"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
ANY_INCLUDE = re.compile(r'^\s*#\s*include\s+([<"])([^>"]+)[>"]')
# Public headers any layer may include (they depend on nothing); the others are the api layer's.
PUBLIC_BASE = {"camdyn/errors.h", "camdyn/version.h"}
# A standard library header: <name>, no folder and no extension.
STANDARD = re.compile(r"^[a-z_0-9]+$")
NOT_FUNCTIONS = re.compile(r"^(namespace|struct|class|enum|union|extern)\b|=\s*\{$|^(static\s+)?(const|constexpr)\b.*=")

# Doc references (check 3): the folders whose text files are searched, and the files read as text there.
DOC_CITING = ("src", "optim", "python", "include", "tests", "bench", "scripts")
# This check and its test name the outside files on purpose.
DOC_CHECK_EXEMPT = {"scripts/check_structure.py", "tests/scripts/check_structure_test.py"}
TEXT_SUFFIXES = {".h", ".cc", ".in", ".py", ".sh", ".cmake", ".txt", ".json", ".dict", ".md"}
# Docs that live outside the repository: a reader of the code has none of them.
OUTSIDE = re.compile(r"physics\.md|interface\.md|\.\./shared\b")
# A doc path: NAME.md, with folders or not, not part of a longer path or word.
DOC_PATH = re.compile(r"(?<![\w./-])((?:[\w.-]+/)*[\w-][\w.-]*\.md)\b")
# What may follow a doc path: its sections (§7; §1 and §4; §2, §3) or a heading's title.
SECTIONS = re.compile(r"\s*§\s*\d+(?:\.\d+)*(?:(?:\s*,\s*|\s+and\s+)§\s*\d+(?:\.\d+)*)*")
SECTION_NUMBER = re.compile(r"§\s*(\d+(?:\.\d+)*)")
# docs/a.md, "Title" or docs/a.md ("Title"); docs/config.md `motion_law` or docs/config.md, section `compare`.
QUOTED_TITLE = re.compile(r'(?:,\s*(?:section\s+)?|\s*\(|\s+section\s+)"([^"]+)"')
BACKTICK_TITLE = re.compile(r"(?:,\s*section)?\s+`([^`]+)`")
HEADING = re.compile(r"^#+\s+(.*?)\s*$")
HEADING_NUMBER = re.compile(r"^(\d+(?:\.\d+)*)\.?\s")
COMMENT_LEADER = re.compile(r"^\s*(?:///?|#|\*|/\*)?\s*")


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


TYPE_DEFINITION = re.compile(r"^(?:struct|class|enum class|enum)\s+([A-Za-z_]\w*)\s*(?:final\s*)?[:{]")


def defined_types(path):
    return {m.group(1) for line in path.read_text(encoding="utf-8").splitlines() if (m := TYPE_DEFINITION.match(line))}


def type_name_clashes():
    """A type of the public API (namespace camdyn) defined again in the library:
    two classes of one name in one program break the one-definition rule."""
    public = {}
    for path in public_headers():
        for name in defined_types(path):
            public[name] = path.relative_to(ROOT)
    found = []
    for path in sources():
        if layer_of(path) in ("api", "python"):
            continue
        for name in sorted(defined_types(path) & public.keys()):
            found.append(f"{path.relative_to(ROOT)}: defines '{name}', a type of the public header {public[name]}: "
                         f"two classes of one name in one program break the one-definition rule")
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


def citing_files(root):
    for top in DOC_CITING:
        for path in sorted((root / top).rglob("*")):
            exempt = path.relative_to(root).as_posix() in DOC_CHECK_EXEMPT
            if path.is_file() and path.suffix in TEXT_SUFFIXES and not exempt:
                yield path


@functools.lru_cache(maxsize=None)
def headings(doc):
    """The headings of a markdown file, outside code blocks: (normalised titles, section numbers)."""
    titles, numbers, fenced = set(), set(), False
    for line in doc.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            fenced = not fenced
        match = None if fenced else HEADING.match(line)
        if match:
            titles.add(normalised(match.group(1)))
            number = HEADING_NUMBER.match(match.group(1))
            if number:
                numbers.add(number.group(1))
    return titles, numbers


def normalised(title):
    return " ".join(title.replace("`", "").lower().split())


def resolve_doc(root, path, cited):
    """The file a doc path names: from the top of the repository, beside the citing file, or (a bare name) in docs/."""
    candidates = [root / cited, path.parent / cited] + ([root / "docs" / cited] if "/" not in cited else [])
    return next((c for c in candidates if c.is_file()), None)


def title_matches(titles, title):
    wanted = normalised(title)
    return any(t == wanted or t.startswith(wanted + " (") for t in titles)


def reference_problems(doc, cited, rest):
    """What is wrong with a citation of an existing doc, given the text that follows its path."""
    titles, numbers = headings(doc)
    sections = SECTIONS.match(rest)
    if sections:
        return [f"cites '{cited} §{n}', but {cited} has no heading '## {n}.'"
                for n in SECTION_NUMBER.findall(sections.group()) if n not in numbers]
    title = QUOTED_TITLE.match(rest) or BACKTICK_TITLE.match(rest)
    if title and not title_matches(titles, title.group(1)):
        return [f"cites '{cited}, \"{title.group(1)}\"', but {cited} has no such heading"]
    return []


def line_problems(root, path, line, following):
    """The doc-reference violations of one line; `following` is the next line, where a citation may go on."""
    if OUTSIDE.search(line):
        return [f"cites a file outside the repository ('{OUTSIDE.search(line).group()}'): cite docs/ instead"]
    text = line + " " + COMMENT_LEADER.sub("", following, count=1)
    found = []
    for match in DOC_PATH.finditer(text):
        if match.start() >= len(line):
            break
        cited = match.group(1)
        doc = resolve_doc(root, path, cited)
        if doc is None:
            found.append(f"cites '{cited}', which is not in the repository")
        else:
            found.extend(reference_problems(doc, cited, text[match.end():]))
    return found


def doc_reference_violations(root=None):
    """Every doc a source or script file cites exists in the repository, with the section or heading cited."""
    root = root or ROOT
    found = []
    for path in citing_files(root):
        lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
        for number, line in enumerate(lines, start=1):
            following = lines[number] if number < len(lines) else ""
            found.extend(f"{path.relative_to(root)}:{number}: {problem}"
                         for problem in line_problems(root, path, line, following))
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--max-lines", type=int, default=120)
    args = parser.parse_args()
    problems = (include_violations() + public_include_violations() + type_name_clashes()
                + long_functions(args.max_lines) + doc_reference_violations())
    for problem in problems:
        print(problem)
    print(f"check_structure: {len(problems)} problem(s) in {sum(1 for _ in sources())} files, "
          f"{len(public_headers())} public headers and the doc references of "
          f"{sum(1 for _ in citing_files(ROOT))} files "
          f"(layers {' < '.join(LAYERS)}; functions <= {args.max_lines} lines)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
