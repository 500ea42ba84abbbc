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
   Besides, the physics layer reads no config: src/dynamics/ includes
   nothing from io/ (nor, through it, nlohmann/json); the parameters set in
   place with the loader's checks are the study layer's
   (study/model_parameters.h).
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
4. No name is defined at file scope (namespace scope, anonymous namespaces
   included) in two .cc files of one unity-built target (CMakeLists.txt,
   CAMDYN_UNITY: the libraries camdyn_<layer> from src/<layer>/*.cc, the
   study runner's files apart; camdyn_optim from optim/, optim/optimize/ and
   optim/identify/; each test executable <area>_tests from tests/<area>/):
   the build compiles them as one translation unit, where the second is a
   redefinition. Counted: variables (constexpr, const or not), types,
   `using` aliases (again to another type), and functions of internal
   linkage (in an anonymous namespace, or static; an overload of another
   file's counts too, it may silently take that file's calls). The parser
   reads declarations at namespace scope only, skipping every other body,
   and compares names whichever namespace they are in.

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
# Layers that may not include a layer below them: (layer, included layer) -> why.
FORBIDDEN_BELOW = {("dynamics", "io"): "the physics layer reads no config (the config side is the study layer's)"}
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
            if (own, head) in FORBIDDEN_BELOW:
                found.append(f"{path.relative_to(ROOT)}:{number}: layer '{own}' includes '{target}': "
                             f"{FORBIDDEN_BELOW[(own, head)]}")
            elif LAYERS.index(head) > LAYERS.index(own):
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


# Rule 4: unity targets. Each target's .cc files compile as one translation unit
# (CMakeLists.txt, CAMDYN_UNITY), so a name two of them define at file scope
# is a redefinition there.
RUNNER_STEMS = re.compile(r"set\(study_runner_stems\s+([^)]*)\)")
SKIP_UNITY = re.compile(r"set_source_files_properties\(([^)]*?)\s+PROPERTIES\s+SKIP_UNITY_BUILD_INCLUSION\s+ON\)")
TEST_AREAS = re.compile(r"set\(test_areas\s+([^)]*)\)")
TEMPLATE_PREFIX = re.compile(r"^template\s*<")
ATTRIBUTES = re.compile(r"\[\[.*?\]\]|\balignas\s*\([^)]*\)")
IDENTIFIER_BEFORE = re.compile(r"(operator\s*\S+?|~?[A-Za-z_]\w*(?:\s*::\s*~?[A-Za-z_]\w*)*)\s*$")
TYPE_HEAD = re.compile(r"^(?:struct|class|union|enum(?:\s+class|\s+struct)?)\s+([A-Za-z_]\w*)(?!\s*::)")
ALIAS_HEAD = re.compile(r"^using\s+([A-Za-z_]\w*)\s*=")
NAMESPACE_HEAD = re.compile(r"^(?:inline\s+)?namespace\b\s*([\w:]*)\s*$")
MACRO_NAME = re.compile(r"^[A-Z][A-Z0-9_]*$")
# src/cli/: each file is a target of its own (camdyn is main.cc, camdyn_studies run_study.cc).
SINGLE_FILE_FOLDERS = {"cli"}
LIBRARY_NAMES = {"api": "camdyn_lib"}


def unity_targets(root=None):
    """The unity-built targets and their .cc files (relative paths), as CMakeLists.txt and tests/CMakeLists.txt glob them."""
    root = root or ROOT
    cmake = (root / "CMakeLists.txt").read_text(encoding="utf-8") if (root / "CMakeLists.txt").is_file() else ""
    test_cmake = (root / "tests/CMakeLists.txt")
    test_cmake = test_cmake.read_text(encoding="utf-8") if test_cmake.is_file() else ""
    stems = set(RUNNER_STEMS.search(cmake).group(1).split()) if RUNNER_STEMS.search(cmake) else set()
    skipped = {root / "tests" / s for m in SKIP_UNITY.finditer(test_cmake) for s in m.group(1).split()}
    skipped |= {root / s for m in SKIP_UNITY.finditer(cmake) for s in m.group(1).split()}
    targets = {}
    for folder in sorted(p for p in (root / "src").glob("*") if p.is_dir()):
        if folder.name in SINGLE_FILE_FOLDERS:
            continue
        files = sorted(folder.glob("*.cc"))
        if folder.name == "study":
            targets["camdyn_study_runner"] = [f for f in files if f.stem in stems]
            files = [f for f in files if f.stem not in stems]
        targets[LIBRARY_NAMES.get(folder.name, f"camdyn_{folder.name}")] = files
    targets["camdyn_optim"] = sorted(f for d in ("optim", "optim/optimize", "optim/identify")
                                     for f in (root / d).glob("*.cc"))
    areas = TEST_AREAS.search(test_cmake).group(1).split() if TEST_AREAS.search(test_cmake) else []
    for area in areas:
        for kind, target in (("test", f"{area}_tests"), ("slowtest", f"{area}_slow_tests")):
            targets[target] = sorted((root / "tests" / area).glob(f"*_{kind}.cc"))
    return {name: [f for f in files if f not in skipped] for name, files in targets.items() if files}


def code_only(text):
    """The text with comments, string and character literals and preprocessor lines blanked (newlines kept)."""
    out, i, n, line_start = [], 0, len(text), True
    while i < n:
        c = text[i]
        if line_start and c == "#":
            while i < n and not (text[i] == "\n" and text[i - 1] != "\\"):
                out.append("\n" if text[i] == "\n" else " ")
                i += 1
            continue
        if c == "\n":
            line_start = True
            out.append(c)
            i += 1
            continue
        if not c.isspace():
            line_start = False
        raw = re.match(r'(?:u8|[uUL])?R"([^(\s]*)\(', text[i:i + 20]) if c in "uULR" else None
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            end = text.find(")" + raw.group(1) + '"', i + raw.end())
            end = n if end < 0 else end + len(raw.group(1)) + 2
            out.append('""' + "".join("\n" for ch in text[i:end] if ch == "\n"))
            i = end
        elif text.startswith("//", i):
            while i < n and text[i] != "\n":
                i += 1
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append(" " + "\n" * text.count("\n", i, end))
            i = end
        elif c == '"' or (c == "'" and not (i > 0 and text[i - 1].isalnum())):
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def strip_template(head):
    """The declaration without its leading template <...> parameter lists."""
    while TEMPLATE_PREFIX.match(head):
        depth, i = 0, head.index("<")
        for i in range(head.index("<"), len(head)):
            depth += {"<": 1, ">": -1}.get(head[i], 0)
            if depth == 0:
                break
        head = head[i + 1:].lstrip()
    return head


def declared_name(head, terminator):
    """What a file-scope declaration (its text up to ';' or '{') defines: (kind, name, aliased) or None.
    kind is 'function' (a definition), 'variable', 'alias' or 'type'; aliased is an alias's type."""
    head = " ".join(ATTRIBUTES.sub(" ", strip_template(head)).split())
    if not head or head.startswith(("extern ", "friend ", "static_assert", "using namespace", "namespace ", "typedef ")):
        return None  # a namespace alias may be declared again (to the same namespace)
    alias = ALIAS_HEAD.match(head)
    if alias:
        return "alias", alias.group(1), head[alias.end():].replace(" ", "")
    type_head = TYPE_HEAD.match(head)
    if type_head:
        return ("type", type_head.group(1), None) if terminator == "{" and "=" not in head else None
    depth = 0
    for i, c in enumerate(head):
        if c in "<[" or (c == "(" and depth > 0):
            depth += 1
        elif c in ">]" or (c == ")" and depth > 0):
            depth -= 1
        elif depth == 0 and (c in "({" or (c == "=" and head[i - 1:i] not in ("=", "!", "<", ">", "r"))):
            break
    else:
        i, c = len(head), ";"
    name = IDENTIFIER_BEFORE.search(head[:i])
    if not name:
        return None
    constant = re.match(r"^(?:(?:static|inline|thread_local)\s+)*(?:constexpr|const|constinit)\b", head)
    if c == "(" and terminator == "{":
        return "function", name.group(1), None
    if c == "(" and not constant:
        return None  # a function's declaration (its definition counts)
    return "variable", name.group(1), None


def file_scope_names(path):
    """The names a .cc file defines at file scope: (kind, name, line, aliased). Functions count only with
    internal linkage (in an anonymous namespace, or static): two of one name are then a redefinition or an
    overload that may silently take the other file's calls; gtest's PrintTo and operators are overloaded
    by their argument's type on purpose."""
    text = code_only(path.read_text(encoding="utf-8"))
    stack = []          # per open brace: "namespace", "anonymous" or "body"
    head, head_line, line = [], None, 1
    skip_to_semicolon = False
    found = []
    for c in text:
        if c == "\n":
            line += 1
        at_file_scope = all(kind in ("namespace", "anonymous") for kind in stack)
        if not at_file_scope:
            if c == "{":
                stack.append("body")
            elif c == "}":
                stack.pop()
                if all(kind in ("namespace", "anonymous") for kind in stack):
                    head, head_line = [], None
            continue
        if c in ";{}":
            statement = "".join(head).strip()
            anonymous = "anonymous" in stack
            if c == "}":
                if stack:
                    stack.pop()
                skip_to_semicolon = False
            elif skip_to_semicolon:
                skip_to_semicolon = c != ";"
                if c == "{":
                    stack.append("body")
            elif c == "{" and NAMESPACE_HEAD.match(statement):
                stack.append("namespace" if NAMESPACE_HEAD.match(statement).group(1) else "anonymous")
            elif c == "{" and statement.startswith("extern"):
                stack.append("namespace")
            else:
                declared = None if statement.startswith((",", ":")) else declared_name(statement, c)
                if declared:
                    kind, name, aliased = declared
                    static = re.match(r"^(?:template\s*<.*?>\s*)?(?:inline\s+)?static\b", statement) is not None
                    overloaded = name.startswith("operator") or name == "PrintTo" or MACRO_NAME.match(name)
                    if "::" not in name and not overloaded and (kind != "function" or anonymous or static):
                        found.append((kind, name, head_line, aliased))
                if c == "{":
                    stack.append("body")
                    # After a type's or an initialiser's braces the declaration goes on to its ';'.
                    skip_to_semicolon = declared is not None and declared[0] != "function"
            head, head_line = [], None
            continue
        if head_line is None and not c.isspace():
            head_line = line
        head.append(c)
    return found


def unity_name_clashes(root=None):
    """A name two .cc files of one unity target define at file scope: a redefinition once the build
    compiles them as one translation unit (for functions of internal linkage, an overload that may
    silently take the other file's call)."""
    root = root or ROOT
    found = []
    for target, files in unity_targets(root).items():
        first = {}  # name -> [(file, line, kind, aliased)], the first definition in each file
        for path in files:
            seen = set()
            for kind, name, line, aliased in file_scope_names(path):
                if name not in seen:
                    seen.add(name)
                    first.setdefault(name, []).append((path.relative_to(root).as_posix(), line, kind, aliased))
        for name, places in sorted(first.items()):
            # An alias may be declared again to the same type ([dcl.typedef]).
            same_alias = all(p[2] == "alias" for p in places) and len({p[3] for p in places}) == 1
            if len(places) > 1 and not same_alias:
                where = " and ".join(f"{p[0]}:{p[1]}" for p in places)
                found.append(f"{places[0][0]}:{places[0][1]}: {places[0][2]} '{name}' is defined at file scope in "
                             f"{len(places)} files of the unity target {target} ({where}): one name per target")
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
                + long_functions(args.max_lines) + doc_reference_violations() + unity_name_clashes())
    for problem in problems:
        print(problem)
    print(f"check_structure: {len(problems)} problem(s) in {sum(1 for _ in sources())} files, "
          f"{len(public_headers())} public headers and the doc references of "
          f"{sum(1 for _ in citing_files(ROOT))} files, the file-scope names of {len(unity_targets())} unity targets "
          f"(layers {' < '.join(LAYERS)}; functions <= {args.max_lines} lines)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
