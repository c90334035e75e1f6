#!/usr/bin/env python3
"""The scene schema (docs/scene.schema.json) against the scene files and against the parser.

- the schema is a valid JSON Schema (draft 7), and every default and example in it is valid;
- every scene file under bench/scenes/ validates against it;
- its backend sections are the registry's knob tables (`chainmail backends --json`): names,
  types, defaults and ranges, as scripts/knob_docs.py writes them; `--update` rewrites them (and
  the `reference` list) from there;
- it and the parser (`chainmail check`) accept and refuse the same documents: a document with
  every key of the schema, the same document without each required key, with an unknown key in
  each object, with each value of the wrong type, at and past each bound, with each allowed and
  one unknown name; and the parser's resolved scene has no key the schema lacks and the
  schema's defaults;

so that neither can change without the other. Needs python3-jsonschema; exits 77 (skipped)
without it.
"""
import argparse
import copy
import json
import math
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent.parent
SCHEMA_PATH = ROOT / "docs" / "scene.schema.json"
SKIPPED = 77

sys.path.insert(0, str(ROOT / "scripts"))
import knob_docs  # noqa: E402  the schema's backend sections, written from the knob tables

try:
    import jsonschema
except ImportError:
    print("scene_schema: python3-jsonschema is not installed (scripts/install-deps.sh): skipped")
    sys.exit(SKIPPED)


def strip_comments(text):
    """JSON text without // and /* */ comments (outside strings), as the scene parser allows."""
    out, i, n, in_string = [], 0, len(text), False
    while i < n:
        c = text[i]
        if in_string:
            out.append(c)
            if c == "\\":
                out.append(text[i + 1])
                i += 1
            elif c == '"':
                in_string = False
        elif c == '"':
            in_string = True
            out.append(c)
        elif text.startswith("//", i):
            while i < n and text[i] != "\n":
                i += 1
            continue
        elif text.startswith("/*", i):
            i = text.index("*/", i) + 2
            continue
        else:
            out.append(c)
        i += 1
    return "".join(out)


# ---------------------------------------------------------------------------------------------
# the schema's backend sections from the registry

def backend_sections(registry):
    """{name: schema of its knob object} for the built backends, and every known name."""
    return knob_docs.schema_sections(registry)


def check_backends(schema, registry, errors, notes):
    sections, known = backend_sections(registry)
    committed = schema["properties"]["backends"]["properties"]
    if list(committed) != known:
        errors.append(f"backends: the schema lists {list(committed)}, the registry {known}")
    if schema["properties"]["reference"]["enum"] != known:
        errors.append(f"reference: the schema allows {schema['properties']['reference']['enum']}")
    for name in known:
        if name not in sections:
            notes.append(f"{name} is not built into this binary: its knobs are not compared")
        elif committed.get(name) != sections[name]:
            errors.append(f"backends.{name}: the schema's knobs differ from the registry's "
                          f"(scripts/knob_docs.py rewrites them)")


def update_backends(registry):
    SCHEMA_PATH.write_text(knob_docs.schema_text(SCHEMA_PATH.read_text(), registry))


# ---------------------------------------------------------------------------------------------
# documents from the schema

class Schema:
    def __init__(self, schema):
        self.root = schema

    def resolve(self, node):
        while "$ref" in node:
            node = self.root["definitions"][node["$ref"].split("/")[-1]]
        return node

    def branches(self, node):
        node = self.resolve(node)
        return [self.resolve(b) for b in node["oneOf"]] if "oneOf" in node else [node]

    def value(self, node, full, choice=0):
        """A valid value of `node`: every property when `full`, else the required ones only
        (arrays of objects get one item of each alternative either way)."""
        node = self.resolve(node)
        if node.get("type") not in ("object", "array"):
            for key in ("const", "examples", "default"):
                if key in node:
                    return node[key][0] if key == "examples" else node[key]
        node = self.branches(node)[choice]
        if node.get("type") == "object" and "properties" in node:
            return {key: self.value(sub, full) for key, sub in node["properties"].items()
                    if full or key in node.get("required", [])}
        if node.get("type") == "array" and "oneOf" in self.resolve(node["items"]):
            # one item of each alternative (colliders, pins)
            alternatives = self.branches(node["items"])
            return [self.value(node["items"], full, k) for k in range(len(alternatives))]
        if node.get("type") == "array" and node["items"].get("type") == "object":
            return [self.value(node["items"], full)]
        for key in ("const", "examples", "default", "enum"):
            if key in node:
                return node[key][0] if key in ("examples", "enum") else node[key]
        raise KeyError(f"no value for {node}")


def weave_variants(schema):
    weaves = schema.branches(schema.root["properties"]["weave"])
    return [b["properties"]["type"]["const"] for b in weaves]


def document(schema, weave, full):
    """A scene with the given weave type: every key of the schema (`full`) or the required."""
    doc = schema.value(schema.root, full)
    types = weave_variants(schema)
    doc["weave"] = schema.value(schema.root["properties"]["weave"], full, types.index(weave))
    # arrays of objects too, with the required keys of their items only, when not full
    for key in ("pins", "colliders", "loads"):
        doc[key] = schema.value(schema.root["properties"][key], full)
    if full:
        doc["$schema"] = "../docs/scene.schema.json"
    return doc


def get(doc, path):
    for key in path:
        doc = doc[key]
    return doc


def put(doc, path, value):
    doc = copy.deepcopy(doc)
    get(doc, path[:-1])[path[-1]] = value
    return doc


def drop(doc, path):
    doc = copy.deepcopy(doc)
    del get(doc, path[:-1])[path[-1]]
    return doc


# ---------------------------------------------------------------------------------------------
# cases: (name, document, whether it is valid)

def number_cases(path, node, doc):
    def past(bound, direction):
        """the next integer or double beyond `bound` (direction -1: below, +1: above)"""
        if node["type"] == "integer":
            return bound + direction
        return math.nextafter(bound, direction * math.inf)

    if "minimum" in node:
        yield f"{path} at its minimum", put(doc, path, node["minimum"]), True
        yield f"{path} below its minimum", put(doc, path, past(node["minimum"], -1)), False
    if "exclusiveMinimum" in node:
        yield f"{path} at its open minimum", put(doc, path, node["exclusiveMinimum"]), False
    if "maximum" in node:
        yield f"{path} at its maximum", put(doc, path, node["maximum"]), True
        yield f"{path} above its maximum", put(doc, path, past(node["maximum"], 1)), False


def leaf_cases(schema, path, node, doc):
    """Type, bound and name cases of one value of `doc` at `path` described by `node`."""
    node = schema.resolve(node)
    kind = node.get("type")
    if kind in ("number", "integer"):
        yield f"{path} as a string", put(doc, path, "1"), False
        if kind == "integer":
            yield f"{path} as a fraction", put(doc, path, 1.5), False
        yield from number_cases(path, node, doc)
    elif kind == "boolean":
        yield f"{path} as a number", put(doc, path, 1), False
    elif kind == "string" or "enum" in node or "const" in node:
        yield f"{path} as a number", put(doc, path, 7), False
        for allowed in node.get("enum", []):
            yield f"{path} = {allowed}", put(doc, path, allowed), True
        if "enum" in node or "const" in node:
            yield f"{path} an unknown name", put(doc, path, "unknown_name"), False
        if "pattern" in node:
            for bad in ("a b", "a.b", "a/b", ""):
                yield f"{path} = {bad!r}", put(doc, path, bad), False
    elif kind == "array" and "minItems" in node:
        # a vector or a [row, col] cell: each component's type and bounds, its length
        yield f"{path} too short", put(doc, path, get(doc, path)[:-1]), False
        yield f"{path} as a number", put(doc, path, 1), False
        item = node["items"]
        yield from leaf_cases(schema, path + [0], item, doc)
    if "const" in node and kind is not None:
        other = node["const"] + 1 if isinstance(node["const"], int) else "unknown_name"
        yield f"{path} other than {node['const']}", put(doc, path, other), False
    if "not" in node:
        yield f"{path} = {node['not']['const']}", put(doc, path, node["not"]["const"]), False


def object_cases(schema, path, node, doc, skip_sections, skip_keys=()):
    """Cases of the object at `path` and, recursively, of everything in it but `skip_keys`."""
    node = schema.resolve(node)
    here = get(doc, path)
    if path:
        yield f"{path} as a number", put(doc, path, 1), False
    if not (path and path[0] == "backends" and len(path) == 2 and path[1] in skip_sections):
        yield f"{path} with an unknown key", put(doc, path + ["no_such_key"], 1), False
    for key in node.get("required", []):
        if key != "type":  # the weave's and a collider's type choose the alternative
            yield f"{path + [key]} missing", drop(doc, path + [key]), False
    for key, sub in node.get("properties", {}).items():
        if key not in here or key in skip_keys or (path == ["backends"] and key in skip_sections):
            continue
        sub = schema.resolve(sub)
        if sub.get("type") == "object" and "properties" in sub:
            yield from object_cases(schema, path + [key], sub, doc, skip_sections)
        elif "oneOf" in sub and sub.get("type") != "array":
            branch = schema.branches(sub)[0] if "properties" not in sub else sub
            if "properties" in branch:
                yield from object_cases(schema, path + [key], branch, doc, skip_sections)
            else:
                yield from leaf_cases(schema, path + [key], branch, doc)
        elif sub.get("type") == "array" and "minItems" not in sub:
            yield f"{path + [key]} as an object", put(doc, path + [key], {}), False
            for index, item in enumerate(get(doc, path + [key])):
                branches = schema.branches(sub["items"])
                branch = branches[index] if len(branches) > 1 else branches[0]
                yield from object_cases(schema, path + [key, index], branch, doc, skip_sections)
        else:
            yield from leaf_cases(schema, path + [key], sub, doc)


def parser_cases(schema, unbuilt):
    """Every case, on the weave variant where its key means something on its own."""
    cases = []
    for weave in weave_variants(schema):
        doc = document(schema, weave, full=True)
        cases.append((f"every key ({weave} weave)", doc, True))
        weave_node = schema.branches(schema.root["properties"]["weave"])[
            weave_variants(schema).index(weave)]
        cases += list(object_cases(schema, ["weave"], weave_node, doc, unbuilt))
        if weave == "grid":  # ring sizes on their own: a grid does not interlock
            cases += list(object_cases(schema, ["ring"], schema.root["properties"]["ring"], doc,
                                       unbuilt))
        if weave == "4in1":
            cases += list(object_cases(schema, [], schema.root, doc, unbuilt, ("weave", "ring")))
            # a pin by [row, col] as well as by index
            for cell, valid in (([1, 2], True), ([-1, 0], False)):
                cases.append((f"pins[0].ring = {cell}", put(doc, ["pins", 0, "ring"], cell), valid))
    return cases


def run_check(chainmail, files, resolved=False):
    """{file: (valid, resolved document or message)} from one `chainmail check` of them all."""
    command = [chainmail, "check", *files] + (["--resolved"] if resolved else [])
    done = subprocess.run(command, capture_output=True, text=True, timeout=300)
    results = {}
    if resolved:
        for file, line in zip([f for f in files], done.stdout.splitlines()):
            results[file] = (True, json.loads(line))
        return results, done
    for line in done.stdout.splitlines():
        file = line.split(": ok: ")[0]
        results[file] = (True, line)
    for line in done.stderr.splitlines():
        for file in files:
            if line.startswith(f"chainmail: {file}: "):
                results.setdefault(file, (False, line))
    return results, done


# ---------------------------------------------------------------------------------------------

def check_scene_files(validator, errors):
    files = sorted((ROOT / "bench" / "scenes").rglob("*.json"))
    for path in files:
        document = json.loads(strip_comments(path.read_text()))
        for error in validator.iter_errors(document):
            errors.append(f"{path.relative_to(ROOT)}: {list(error.path)}: {error.message}")
    return files


def check_examples(schema, validator_class, errors):
    """Every default and example is a valid value of its own node."""
    def walk(node, where):
        if isinstance(node, dict):
            values = [("default", node["default"])] if "default" in node else []
            values += [("examples", value) for value in node.get("examples", [])]
            probe = dict(node, definitions=schema.root["definitions"])
            for key, value in values:
                if not validator_class(probe).is_valid(value):
                    errors.append(f"{where}: {key} {value!r} is not valid there")
            for key, sub in node.items():
                if key not in ("default", "examples", "const", "enum", "not"):
                    walk(sub, f"{where}/{key}")
        elif isinstance(node, list):
            for k, sub in enumerate(node):
                walk(sub, f"{where}/{k}")
    walk(schema.root, "#")


def check_resolved(schema, validator, chainmail, folder, errors):
    """The parser's resolved scenes: no key the schema lacks; the schema's defaults filled in."""
    given = {}
    for weave in weave_variants(schema):
        for kind in ("full", "minimal"):
            path = folder / f"{kind}_{weave}.json"
            given[str(path)] = document(schema, weave, kind == "full")
            path.write_text(json.dumps(given[str(path)]))
    results, done = run_check(chainmail, list(given), resolved=True)
    if done.returncode != 0:
        errors.append(f"chainmail check --resolved refused a schema document: {done.stderr}")
        return
    for file, (_, resolved) in results.items():
        for error in validator.iter_errors(resolved):
            errors.append(f"{file}: the resolved scene: {list(error.path)}: {error.message}")
        compare_defaults(schema, schema.root, given[file], resolved, [], errors)


def compare_defaults(schema, node, given, resolved, path, errors):
    """Each key the document leaves out resolves to the schema's default."""
    node = schema.resolve(node)
    if "oneOf" in node and "properties" not in node:
        for branch in schema.branches(node):
            if branch.get("properties", {}).get("type", {}).get("const") == resolved.get("type"):
                compare_defaults(schema, branch, given, resolved, path, errors)
        return
    for key, sub in node.get("properties", {}).items():
        sub = schema.resolve(sub)
        if key not in resolved or key == "backends":
            continue  # a camera left automatic; knob sections are kept as written
        if key not in given and "default" in sub and resolved[key] != sub["default"]:
            errors.append(f"{path + [key]}: the parser's default is {resolved[key]!r}, the "
                          f"schema's {sub['default']!r}")
        inner = given.get(key, {} if isinstance(resolved[key], dict) else [])
        if isinstance(resolved[key], dict):
            compare_defaults(schema, sub, inner, resolved[key], path + [key], errors)
        elif isinstance(resolved[key], list) and sub.get("type") == "array" and inner:
            for k, item in enumerate(resolved[key]):
                if isinstance(item, dict):
                    compare_defaults(schema, sub["items"], inner[k], item, path + [key, k], errors)


def check_parser(schema, validator, chainmail, folder, unbuilt, errors):
    cases = parser_cases(schema, unbuilt)
    files = []
    for k, (_, doc, _) in enumerate(cases):
        path = folder / f"case_{k:04d}.json"
        path.write_text(json.dumps(doc))
        files.append(str(path))
    results, _ = run_check(chainmail, files)
    for file, (name, doc, valid) in zip(files, cases):
        by_schema = validator.is_valid(doc)
        by_parser, said = results.get(file, (None, "no answer"))
        if by_schema != valid or by_parser != valid:
            errors.append(f"{name}: expected {'valid' if valid else 'refused'}; the schema says "
                          f"{'valid' if by_schema else 'refused'}, the parser: {said}")
    return len(cases)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--chainmail", required=True)
    parser.add_argument("--update", action="store_true",
                        help="rewrite the schema's backend sections from the registry")
    args = parser.parse_args()
    schema_json = json.loads(SCHEMA_PATH.read_text())
    registry = json.loads(subprocess.run([args.chainmail, "backends", "--json"], check=True,
                                         capture_output=True, text=True).stdout)
    if args.update:
        update_backends(registry)
        print(f"scene_schema: rewrote the backend sections of {SCHEMA_PATH.relative_to(ROOT)}")
        return 0

    errors, notes = [], []
    validator_class = jsonschema.Draft7Validator
    validator_class.check_schema(schema_json)
    validator = validator_class(schema_json)
    schema = Schema(schema_json)
    check_examples(schema, validator_class, errors)
    scenes = check_scene_files(validator, errors)
    check_backends(schema_json, registry, errors, notes)
    unbuilt = [b["name"] for b in registry["backends"] if not b["built"]]
    with tempfile.TemporaryDirectory(prefix="chainmail-schema-") as folder:
        check_resolved(schema, validator, args.chainmail, pathlib.Path(folder), errors)
        cases = check_parser(schema, validator, args.chainmail, pathlib.Path(folder), unbuilt,
                             errors)
    for note in notes:
        print(f"note: {note}")
    for error in errors:
        print(f"FAIL {error}")
    print(f"scene_schema: {len(scenes)} scene files, {cases} parser cases, {len(errors)} failures")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
