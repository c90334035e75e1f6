#!/usr/bin/env python3
"""Structure rules the code base keeps (run by ctest as `structure`):

- no production function (core/, backends/, scene_file/, bench/, render/, python/; C++ and
  Python) longer than 80 lines (header line to closing brace);
- no C++ source file anywhere in the project longer than 500 lines;
- no header under core/ includes a JSON header (core depends on Eigen only);
- a file in core/ itself (the vocabulary every model shares) is included from more than one place:
  one that only the files of one model folder (core/<model>/) include belongs in that folder, and
  one that only backends/ includes belongs in backends/;
- no include cycle between files, a header and its source counting as one file (a.cpp including
  b.hpp and b.cpp including a.hpp is a cycle: neither can be read, built or moved without the
  other).

Functions are found by brace matching after comments, strings and preprocessor lines are removed:
a block opened at namespace or class scope whose header holds a parameter list is a function.
`--list N` prints every function longer than N lines instead of checking.
"""
import argparse
import ast
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
SOURCE_DIRS = ["core", "backends", "scene_file", "bench", "render", "python", "tests"]
FUNCTION_DIRS = ["core", "backends", "scene_file", "bench", "render", "python"]
MAX_FUNCTION_LINES = 80
MAX_FILE_LINES = 500
JSON_INCLUDE = re.compile(r'#\s*include\s*[<"]nlohmann/')
QUOTED_INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.MULTILINE)
# the folders whose files place a core/ file: its models' and the adapters' (bench/, tests/ and
# python/ use the models without being one)
PLACING_DIRS = ["core", "backends"]


def strip_code(text):
    """Comments, string and character literals and preprocessor lines blanked; newlines kept."""
    out = []
    i, n = 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if at_line_start and c in " \t":
            out.append(c)
            i += 1
            continue
        if at_line_start and c == "#":
            # preprocessor line, with continuations
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append("\n")
                    i += 2
                    continue
                i += 1
            continue
        at_line_start = False
        if text.startswith("//", i):
            while i < n and text[i] != "\n":
                i += 1
            continue
        if text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append("\n" * text.count("\n", i, end))
            i = end
            continue
        raw = re.match(r'R"([^(\s]*)\(', text[i:i + 20])
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            close = ")" + raw.group(1) + '"'
            end = text.find(close, i + raw.end())
            end = n if end < 0 else end + len(close)
            out.append('""' + "\n" * text.count("\n", i, end))
            i = end
            continue
        if c in "\"'":
            # a digit separator (1'000) is not a character literal
            if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum():
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
            continue
        if c == "\n":
            at_line_start = True
        out.append(c)
        i += 1
    return "".join(out)


def functions(text):
    """(name, first line, last line) of every function body in the file."""
    code = strip_code(text)
    found = []
    stack = []  # kinds of the open blocks: ns, class, func, inner
    header_start = 0  # index where the current declaration began
    for i, c in enumerate(code):
        if c in ";}":
            if c == "}" and stack:
                kind, name, start_line = stack.pop()
                if kind == "func":
                    found.append((name, start_line, code.count("\n", 0, i) + 1))
            header_start = i + 1
        elif c == "{":
            if stack and stack[-1][0] in ("func", "inner"):
                stack.append(("inner", "", 0))
                continue
            header = code[header_start:i]
            words = re.findall(r"[A-Za-z_]\w*", header.split("(")[0])
            if words and words[0] in ("namespace", "extern"):
                kind = "ns"
            elif any(w in ("class", "struct", "union", "enum") for w in words) and (
                    "(" not in header or header.index("(") > header.index(words[-1])):
                kind = "class" if ")" not in header else "func"
            elif ")" in header:
                kind = "func"
            else:
                kind = "inner"
            stripped = header.lstrip()
            first = header_start + (len(header) - len(stripped))
            name_match = re.findall(r"([~\w:]+)\s*\(", header)
            name = name_match[0] if name_match else "?"
            stack.append((kind, name, code.count("\n", 0, first) + 1))
            header_start = i + 1
    return found


def file_graph(graph):
    """{file: files it includes} from {path: paths it includes}, a file being its path from the
    root without its extension (a.hpp and a.cpp are one file)."""
    def name(path):
        return str(path.relative_to(ROOT).with_suffix(""))
    files = {}
    for path, targets in graph.items():
        here = name(path)
        files.setdefault(here, set()).update(name(t) for t in targets if name(t) != here)
    for targets in list(files.values()):
        for target in targets:
            files.setdefault(target, set())
    return files


def include_cycles(graph):
    """The strongly connected components of more than one file (Tarjan, iterative), each sorted."""
    index, low, on_stack, stack, cycles = {}, {}, set(), [], []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, edges = work[-1]
            child = next(edges, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    cycles.append(sorted(component))
    return sorted(cycles)


def cycle_problems(graph):
    return [f"include cycle: {' <-> '.join(c)}" for c in include_cycles(file_graph(graph))]


def python_functions(text):
    """(name, first line, last line) of every function and method in a Python file."""
    return [(node.name, node.lineno, node.end_lineno) for node in ast.walk(ast.parse(text))
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))]
def includes(path, text):
    """The project files `path` includes with quotes: from its own folder, the source root or
    tests/ (the tests' include directory), as the compiler looks."""
    found = []
    for name in QUOTED_INCLUDE.findall(text):
        for base in (path.parent, ROOT, ROOT / "tests"):
            target = (base / name).resolve()
            if target.is_file():
                found.append(target)
                break
    return found


def placement_problems(graph):
    """core/ files that serve one model folder, or only backends/, from outside it."""
    users = {}
    for path, targets in graph.items():
        rel = path.relative_to(ROOT)
        if rel.parts[0] not in PLACING_DIRS:
            continue
        place = "/".join(rel.parts[:-1])
        for target in targets:
            if target.parent == ROOT / "core" and target.stem != path.stem:
                users.setdefault(target, set()).add(place)
    problems = []
    for target, places in sorted(users.items()):
        if len(places) == 1:
            (place,) = places
            if place != "core":
                problems.append(f"{target.relative_to(ROOT)}: only {place}/ includes it: "
                                f"move it into {place}/")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--list", type=int, metavar="N",
                        help="print functions longer than N lines (every checked folder)")
    args = parser.parse_args()

    problems = []
    graph = {}
    sources = sorted(p for d in SOURCE_DIRS for p in (ROOT / d).rglob("*")
                     if p.suffix in (".cpp", ".hpp", ".h") and p.is_file())
    scripts = sorted(p for d in FUNCTION_DIRS for p in (ROOT / d).rglob("*.py") if p.is_file())
    for path in sources + scripts:
        rel = path.relative_to(ROOT)
        text = path.read_text(encoding="utf-8", errors="replace")
        found = python_functions(text) if path.suffix == ".py" else None
        if found is not None:
            for name, first, last in found:
                length = last - first + 1
                if args.list is not None and length > args.list:
                    print(f"{length:5d}  {rel}:{first}  {name}")
                elif args.list is None and length > MAX_FUNCTION_LINES:
                    problems.append(f"{rel}:{first}: function {name} is {length} lines "
                                    f"(limit {MAX_FUNCTION_LINES})")
            continue
        lines = text.count("\n") + (0 if text.endswith("\n") else 1)
        graph[path.resolve()] = includes(path, text)
        if args.list is not None:
            for name, first, last in functions(text):
                if last - first + 1 > args.list:
                    print(f"{last - first + 1:5d}  {rel}:{first}  {name}")
            continue
        if lines > MAX_FILE_LINES:
            problems.append(f"{rel}: {lines} lines (limit {MAX_FILE_LINES})")
        if rel.parts[0] == "core" and path.suffix in (".hpp", ".h") and JSON_INCLUDE.search(text):
            problems.append(f"{rel}: a core header includes a JSON header")
        if rel.parts[0] in FUNCTION_DIRS:
            for name, first, last in functions(text):
                length = last - first + 1
                if length > MAX_FUNCTION_LINES:
                    problems.append(f"{rel}:{first}: function {name} is {length} lines "
                                    f"(limit {MAX_FUNCTION_LINES})")
    if args.list is not None:
        return 0
    problems += cycle_problems(graph)
    problems += placement_problems(graph)
    for p in problems:
        print(p)
    print(f"structure: {len(sources) + len(scripts)} files, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
