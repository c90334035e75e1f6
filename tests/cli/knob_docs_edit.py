#!/usr/bin/env python3
"""A knob's range edited in its table reaches both generated files (scripts/knob_docs.py).

The registry of the binary (`chainmail backends --json`, what the KnobTables declare) is changed as
an edit of the tables would change it: a number knob's range and unit, and a choice knob's names
(one more). Run on copies of docs/backends.md and docs/scene.schema.json:

- the unchanged registry leaves both copies as they are (--check passes);
- the changed one makes --check fail, and a rewrite changes exactly those knobs' rows of the docs
  (the new range and unit, the new names; every other line the same) and exactly their nodes in
  the schema (bounds, enum);
- a rewrite from the unchanged registry gives back the committed files byte for byte.
"""
import argparse
import copy
import json
import pathlib
import shutil
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent.parent
SCRIPT = ROOT / "scripts" / "knob_docs.py"


def generate(registry, folder, *flags):
    path = folder / "registry.json"
    path.write_text(json.dumps(registry))
    return subprocess.run([sys.executable, str(SCRIPT), "--registry", str(path),
                           "--docs", str(folder / "backends.md"),
                           "--schema", str(folder / "scene.schema.json"), *flags],
                          capture_output=True, text=True)


def edited(registry):
    """The registry with the first number knob's range and unit changed and the first choice
    knob given one more name: (registry, [(backend, knob), ...])."""
    registry = copy.deepcopy(registry)
    changed = {}
    for backend in registry["backends"]:
        for knob in backend.get("knobs", []) if backend["built"] else []:
            if knob["type"] == "number" and knob["name"] != "dt" and "number" not in changed:
                knob["min"] = knob["min"] / 4 if knob["min"] > 0 else 0.125
                knob["max"] = knob["max"] * 8 + 0.5
                knob["default"] = max(knob["default"], knob["min"])
                knob["unit"] = "m²/s"
                changed["number"] = (backend["name"], knob)
            elif knob["type"] == "choice" and "choice" not in changed:
                knob["choices"] = knob["choices"] + ["edited_name"]
                changed["choice"] = (backend["name"], knob)
    if "number" not in changed:
        raise SystemExit("knob_docs_edit: no built backend has a number knob")
    return registry, list(changed.values())


def expected_cells(knob_docs, knob):
    """The range cell the docs row must show for an edited knob."""
    if knob["type"] == "choice":
        return ", ".join(f"`{name}`" for name in knob["choices"])
    return f"[{knob_docs.number_text(knob['min'])}, {knob_docs.number_text(knob['max'])}] m²/s"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--chainmail", required=True)
    args = parser.parse_args()
    registry = json.loads(subprocess.run([args.chainmail, "backends", "--json"], check=True,
                                         capture_output=True, text=True).stdout)
    failures = []

    def expect(condition, what):
        if not condition:
            failures.append(what)

    with tempfile.TemporaryDirectory(prefix="chainmail-knob-docs-") as name:
        folder = pathlib.Path(name)
        docs, schema = folder / "backends.md", folder / "scene.schema.json"
        shutil.copy(ROOT / "docs" / "backends.md", docs)
        shutil.copy(ROOT / "docs" / "scene.schema.json", schema)
        docs_before, schema_before = docs.read_text(), schema.read_text()

        result = generate(registry, folder, "--check")
        expect(result.returncode == 0, f"--check on the committed files: {result.stdout}")

        changed, knobs = edited(registry)
        result = generate(changed, folder, "--check")
        expect(result.returncode == 1, f"--check after the edit exited {result.returncode}")
        expect(docs.read_text() == docs_before and schema.read_text() == schema_before,
               "--check changed a file")

        result = generate(changed, folder)
        expect(result.returncode == 0, f"rewrite: {result.stdout}{result.stderr}")
        old_lines, new_lines = docs_before.split("\n"), docs.read_text().split("\n")
        differing = [b for a, b in zip(old_lines, new_lines) if a != b]
        expect(len(old_lines) == len(new_lines) and len(differing) == len(knobs),
               f"docs: {len(differing)} lines changed, expected the rows of "
               f"{[knob['name'] for _, knob in knobs]}")
        sys.path.insert(0, str(SCRIPT.parent))
        import knob_docs
        for (backend, knob), row in zip(knobs, differing):
            expect(row.startswith(f"| `{knob['name']}` |"), f"docs: changed line {row!r}")
            cell = expected_cells(knob_docs, knob)
            expect(f"| {cell} |" in row, f"docs: {row!r} lacks {cell}")

        old_schema, new_schema = json.loads(schema_before), json.loads(schema.read_text())
        for backend, knob in knobs:
            nodes = new_schema["properties"]["backends"]["properties"][backend]["properties"]
            node = nodes[knob["name"]]
            if knob["type"] == "choice":
                expect(node["enum"] == knob["choices"],
                       f"schema: {backend}.{knob['name']} enum {node.get('enum')}")
            else:
                expect(node["minimum"] == knob["min"] and node["maximum"] == knob["max"],
                       f"schema: {backend}.{knob['name']} bounds {node.get('minimum')}, "
                       f"{node.get('maximum')}; expected {knob['min']}, {knob['max']}")
            old_nodes = old_schema["properties"]["backends"]["properties"][backend]["properties"]
            expect(old_nodes[knob["name"]] != node, f"schema: {knob['name']} unchanged")
            old_nodes[knob["name"]] = node
        expect(old_schema == new_schema, "schema: the rewrite changed more than the edited nodes")

        result = generate(registry, folder)
        expect(docs.read_text() == docs_before and schema.read_text() == schema_before,
               "a rewrite from the unchanged registry did not give the committed files back")

    for failure in failures:
        print(f"FAIL {failure}")
    edits = ", ".join(f"{backend}.{knob['name']}" for backend, knob in knobs)
    print(f"knob_docs_edit: {edits} edited, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
