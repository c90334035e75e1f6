#!/usr/bin/env python3
"""Structure rules the code base keeps (run by ctest as `structure`):

- no function in bench/, backends/, scene_file/ or render/ longer than 80 lines (header line to
  closing brace);
- no C++ source file anywhere in the project longer than 500 lines;
- no header under core/ includes a JSON header (core depends on Eigen only).

Functions are found by brace matching after comments, strings and preprocessor lines are removed:
a block opened at namespace or class scope whose header holds a parameter list is a function.
`--list N` prints every function longer than N lines instead of checking.
"""
import argparse
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
SOURCE_DIRS = ["core", "backends", "scene_file", "bench", "render", "tests"]
FUNCTION_DIRS = ["bench", "backends", "scene_file", "render"]
MAX_FUNCTION_LINES = 80
MAX_FILE_LINES = 500
JSON_INCLUDE = re.compile(r'#\s*include\s*[<"]nlohmann/')


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


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--list", type=int, metavar="N",
                        help="print functions longer than N lines (every checked folder)")
    args = parser.parse_args()

    problems = []
    sources = sorted(p for d in SOURCE_DIRS for p in (ROOT / d).rglob("*")
                     if p.suffix in (".cpp", ".hpp", ".h") and p.is_file())
    for path in sources:
        rel = path.relative_to(ROOT)
        text = path.read_text(encoding="utf-8", errors="replace")
        lines = text.count("\n") + (0 if text.endswith("\n") else 1)
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
    for p in problems:
        print(p)
    print(f"structure: {len(sources)} files, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
