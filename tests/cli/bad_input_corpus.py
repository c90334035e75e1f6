#!/usr/bin/env python3
"""Bad-input corpus for the `chainmail` command line (Python 3 standard library only).

Every case writes its inputs (scene files, victims at --out paths, FIFOs, links) into a fresh
temporary folder, runs the binary once with cwd = a fresh empty folder and HOME, XDG_CACHE_HOME
and TMPDIR pointed into a second fresh folder, and checks:

  * exit status 2 (not a signal, not 3, no hang: a per-case timeout is a failure);
  * stderr is exactly one non-empty line that starts with "chainmail: " and contains the case's
    expected token (the offending key in dotted form, the offending path, or the flag);
  * nothing was written: the recursive listing (kind, mode, size, mtime, ctime, inode, link
    target, content hash) of the cwd, the home folder and the inputs folder (which holds every
    victim) is the same after the case as before, and an outside victim (/dev/null) is still the
    same character device.

Cases of class `control` are positive: they must exit 0 and write their output folder, so that a
binary that refuses everything cannot pass. They are not part of the bad-input count.

When run as root, every case runs as uid/gid 65534 (nobody), so that a faulty binary cannot
replace /dev/null or write under /proc; the binary and its source tree must then be readable by
others. Unless the binary is built with a sanitizer, cases run under RLIMIT_AS = --max-memory-gib
(default 4).

Usage: bad_input_corpus.py --chainmail PATH [--jobs N] [--filter SUBSTR] [--list]
                           [--report-classes] [--timeout S] [--keep]
The last line printed is "N passed, M failed" (controls included); exit 0 only when M == 0.
"""

import argparse
import concurrent.futures
import copy
import hashlib
import json
import os
import resource
import shlex
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time

SCENE = "corpus-scene.json"  # the scene file's name in every case's inputs folder
NOBODY = 65534

BACKENDS = ["plausible", "massspring", "bullet", "ode", "torus_xpbd"]
OPTIONAL_BACKENDS = ["bullet", "ode"]  # a build may lack them

# knob specs of backends/*_backend.cpp: name, type, min, max (a choice: its names, None)
KNOBS = {
    "plausible": [
        ("dt", "number", 1e-6, 0.1),
        ("iterations", "integer", 1, 100000),
        ("max_link_fraction", "number", 0.2, 1.0),
        ("damping", "number", 0.0, 1000.0),
        ("repulsion_fraction", "number", 0.0, 2.0),
        ("repulsion_stiffness", "number", 0.0, 1e9),
        ("contact_skin", "number", 0.0, 10.0),
        ("contact_margin", "number", 0.0, 1.0),
        ("swivel", "boolean", 0, 1),
        ("shock_propagation", "boolean", 0, 1),
        ("swivel_extended", "number", 0.0, 1.5707963267948966),
        ("swivel_fit", "boolean", 0, 1),
    ],
    "massspring": [
        ("dt", "number", 1e-7, 0.1),
        ("substeps", "integer", 0, 1000),
        ("ks", "number", 0.0, 1e9),
        ("shear_ks", "number", 0.0, 1e9),
        ("bend_ks", "number", 0.0, 1e9),
        ("stretch", "number", 1e-6, 10.0),
        ("damping_percent", "number", 0.0, 100.0),
        ("correction_passes", "integer", 0, 10000),
        ("max_extension", "number", 0.0, 10.0),
        ("thickness", "number", 0.0, 10.0),
        ("areal_density", "number", 0.0, 1e6),
    ],
    "bullet": [
        ("dt", "number", 1e-5, 0.1),
        ("substeps", "integer", 1, 64),
        ("solver_iterations", "integer", 1, 1000),
        ("restitution", "number", 0.0, 1.0),
        ("linear_damping", "number", 0.0, 1.0),
        ("angular_damping", "number", 0.0, 1.0),
        ("pieces", "integer", 6, 256),
        ("length_scale", "number", 1e-3, 1e6),
        ("split_impulse", "boolean", 0, 1),
        ("contact_processing_threshold", "number", 0.0, 1e3),
        ("friction_directions", "integer", 1, 2),
    ],
    "ode": [
        ("dt", "number", 1e-7, 1.0),
        ("substeps", "integer", 1, 10000),
        ("iterations", "integer", 1, 100000),
        ("sor", "number", 0.05, 1.95),
        ("erp", "number", 0.0, 1.0),
        ("cfm", "number", 0.0, 1.0),
        ("restitution", "number", 0.0, 1.0),
        ("linear_damping", "number", 0.0, 1e4),
        ("angular_damping", "number", 0.0, 1e4),
        ("pieces", "integer", 6, 256),
        ("length_scale", "number", 1e-3, 1e6),
        ("max_contacts", "integer", 1, 32),
        ("max_correcting_velocity", "number", 0.0, 1e3),
        ("contact_layer", "number", 0.0, 1.0),
    ],
    "torus_xpbd": [
        ("dt", "number", 1e-6, 0.1),
        ("substeps", "integer", 1, 10000),
        ("friction", "number", 0.0, 10.0),
        ("restitution", "number", 0.0, 1.0),
        ("compliance", "number", 0.0, 1e3),
        ("damping", "number", 0.0, 1e4),
        ("sleeping", "boolean", 0, 1),
        ("friction_law", "choice", ["cone", "pyramid"], None),
    ],
}

# ---------------------------------------------------------------------------------------------
# JSON text with full control: duplicate members, literal (non-JSON) tokens, deep nesting


class Raw:
    """Literal text in the JSON document (NaN, 1e400, 300 digits, deep nesting...)."""

    def __init__(self, text):
        self.text = text


class Pairs:
    """An object written member by member (duplicates allowed)."""

    def __init__(self, pairs):
        self.pairs = pairs


def dump(value):
    if isinstance(value, Raw):
        return value.text
    if isinstance(value, Pairs):
        return "{" + ",".join(json.dumps(k) + ":" + dump(v) for k, v in value.pairs) + "}"
    if isinstance(value, dict):
        return "{" + ",".join(json.dumps(k) + ":" + dump(v) for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ",".join(dump(v) for v in value) + "]"
    if isinstance(value, float):
        assert value == value and abs(value) != float("inf")
        return repr(value)
    return json.dumps(value)  # str, int, bool, None


def parse_key(key):
    """'colliders[0].radius' -> ['colliders', 0, 'radius']"""
    path = []
    for part in key.split("."):
        name, _, rest = part.partition("[")
        if name:
            path.append(name)
        while rest:
            index, _, rest = rest.partition("]")
            path.append(int(index))
            rest = rest[1:] if rest.startswith("[") else rest
    return path


def key_tokens(key):
    """the key as the scene loader names it, and the same with '.k' for '[k]'"""
    alt = key.replace("[", ".").replace("]", "")
    return (key,) if alt == key else (key, alt)


def node_at(doc, path):
    for p in path:
        doc = doc[p]
    return doc


def with_value(doc, key, value):
    doc = copy.deepcopy(doc)
    path = parse_key(key)
    parent = doc
    for p in path[:-1]:
        if isinstance(p, str) and p not in parent:
            parent[p] = {}
        parent = parent[p]
    parent[path[-1]] = value
    return doc


def without(doc, key):
    doc = copy.deepcopy(doc)
    path = parse_key(key)
    del node_at(doc, path[:-1])[path[-1]]
    return doc


def with_duplicate(doc, key, second=None):
    """the member `key` written twice (the second time with `second`, default the same value)"""
    doc = copy.deepcopy(doc)
    path = parse_key(key)
    parent_path, name = path[:-1], path[-1]
    obj = node_at(doc, parent_path)
    pairs = []
    for k, v in obj.items():
        pairs.append((k, v))
        if k == name:
            pairs.append((k, v if second is None else second))
    if not parent_path:
        return Pairs(pairs)
    node_at(doc, parent_path[:-1])[parent_path[-1]] = Pairs(pairs)
    return doc


# ---------------------------------------------------------------------------------------------
# scenes: the minimal valid scene and the contexts that the cases mutate


def base_scene():
    return {
        "name": "corpus",
        "weave": {"type": "4in1", "rows": 4, "cols": 4, "plane": "xy"},
        "pins": [{"edge": "top"}],
        "duration": 0.02,
        "sample_interval": 0.01,
        "reference": "plausible",
        "backends": {"plausible": {}},
    }


def context(name):
    s = base_scene()
    if name == "base":
        pass
    elif name == "sections":  # every optional section present, each with valid values
        s["description"] = "bad-input corpus"
        s["ring"] = {"wire_diameter": 0.0016, "inner_diameter": 0.008, "density": 7850.0,
                     "friction": 0.3}
        s["weave"]["center"] = [0.0, 0.0, 0.0]
        s["initial_velocity"] = [0.0, 0.0, 0.0]
        s["gravity"] = [0.0, -9.81, 0.0]
        s["features"] = {"self_contact": True}
        s["output"] = {"frames": False}
        s["camera"] = {"position": [0.0, 0.05, 0.1], "target": [0.0, 0.0, 0.0], "fov_deg": 40.0}
        s["stability"] = {"max_speed": 20.0, "links_must_hold": True, "max_stretch": 1.25,
                          "energy_growth": 1.5}
        s["reference_dt"] = 0.0
    elif name == "chain":
        s["weave"] = {"type": "chain", "cols": 4, "plane": "xy"}
    elif name == "grid":
        s["weave"] = {"type": "grid", "rows": 4, "cols": 4, "plane": "xy", "spacing": 0.008}
    elif name == "pin_ring":
        s["pins"] = [{"ring": 0}]
    elif name == "pin_pair":
        s["pins"] = [{"ring": [0, 0]}]
    elif name == "pin_corner":
        s["pins"] = [{"corner": "top_left"}]
    elif name == "plane":
        s["colliders"] = [{"type": "plane", "point": [0.0, -1.0, 0.0], "normal": [0.0, 1.0, 0.0],
                           "friction": 0.3}]
    elif name == "sphere":
        s["colliders"] = [{"type": "sphere", "center": [0.0, -1.0, 0.0], "radius": 0.01,
                           "friction": 0.3}]
    elif name == "box":
        s["colliders"] = [{"type": "box", "center": [0.0, -1.0, 0.0],
                           "half_extents": [0.01, 0.01, 0.01]}]
    elif name == "cylinder":
        s["colliders"] = [{"type": "cylinder", "center": [0.0, -1.0, 0.0], "radius": 0.01,
                           "half_height": 0.01}]
    elif name == "support":
        s["support"] = {"center": [0.0, -1.0, 0.0], "radius": 0.01}
    elif name == "loads":
        s["loads"] = [{"ring": [1, 1], "mass_factor": 2.0}]
    elif name == "knobs":
        s["backends"] = {"plausible": {"dt": 0.004}}
    else:
        raise KeyError(name)
    return s


def full_scene():
    """every context at once: the control that shows each context is valid"""
    s = context("sections")
    s["pins"] = [{"edge": "top"}, {"ring": 5}, {"ring": [1, 2]}, {"corner": "top_left"}]
    s["colliders"] = (context("plane")["colliders"] + context("sphere")["colliders"] +
                      context("box")["colliders"] + context("cylinder")["colliders"])
    s["support"] = context("support")["support"]
    s["loads"] = context("loads")["loads"]
    s["backends"] = {"plausible": {"dt": 0.004}}
    return s


# ---------------------------------------------------------------------------------------------
# cases


class Case:
    def __init__(self, cid, cls, argv, tokens=(), scene=None, ops=(), pre=(), after_pre=(),
                 external=(), expect=2, check=None):
        self.id = cid
        self.cls = cls
        self.argv = list(argv)          # after the binary; @IN@, @CWD@, @SCENE@ are replaced
        self.tokens = tuple(tokens)     # stderr must contain one of them
        self.scene = scene              # bytes of @SCENE@, or None (no scene file)
        self.ops = list(ops)            # inputs-folder set-up: see make_inputs
        self.pre = list(pre)            # commands that must exit 0 before the case (no checks)
        self.after_pre = list(after_pre)
        self.external = list(external)  # outside paths that must keep their kind (/dev/null)
        self.expect = expect            # 2, or 0 for a control
        self.check = check              # control: (dirs) -> error string or None


def scene_bytes(doc):
    return dump(doc).encode()


RUN = ["run", "@SCENE@"]
FILE_TOKEN = (SCENE,)

N31, N32, N63, N64 = 2 ** 31, 2 ** 32, 2 ** 63, 2 ** 64
DIGITS300 = "9" * 300


def ctx_id(ctx, key):
    return key if ctx in ("base", "sections", "knobs") else ctx + "." + key


def scene_case(cases, cls, cid, doc, tokens, argv_extra=()):
    cases.append(Case(cid, cls, RUN + list(argv_extra), tokens,
                      doc if isinstance(doc, bytes) else scene_bytes(doc)))


def just_below(lo):
    return lo - abs(lo) * 1e-9 if lo else -1e-12


def number_cases(cases, ctx, key, lo, hi, lo_exclusive, full=True):
    doc = context(ctx)
    kid = ctx_id(ctx, key)
    tok = key_tokens(key)
    for variant, value in [("string", "0.5"), ("bool", True), ("null", None), ("array", [0.5]),
                           ("object", {"value": 0.5})]:
        scene_case(cases, "scene.type", f"scene.type.{kid}.{variant}", with_value(doc, key, value),
                   tok)
    ranges = []
    if lo_exclusive:
        ranges.append(("at-min", float(lo)))
    ranges += [("below", just_below(float(lo))), ("far-below", float(lo) - 1000.0 * (abs(lo) + 1)),
               ("above", float(hi) * (1 + 1e-9)), ("far-above", float(hi) * 1000.0)]
    if not full:
        ranges = [r for r in ranges if r[0] in ("at-min", "below", "above")]
    for variant, value in ranges:
        scene_case(cases, "scene.range", f"scene.range.{kid}.{variant}", with_value(doc, key, value),
                   tok)
    bigs = [("digits300", Raw(DIGITS300)), ("2^64", N64)]
    if full:
        bigs += [("-digits300", Raw("-" + DIGITS300)), ("2^31", N31), ("2^63", N63),
                 ("-2^63-1", -N63 - 1)]
    for variant, value in bigs:
        scene_case(cases, "scene.range", f"scene.range.{kid}.{variant}", with_value(doc, key, value),
                   tok)
    syntax = [("NaN", "NaN")]
    if full:
        syntax += [("Infinity", "Infinity"), ("-Infinity", "-Infinity"), ("1e400", "1e400"),
                   ("-1e400", "-1e400")]
    for variant, text in syntax:
        scene_case(cases, "scene.syntax", f"scene.syntax.{kid}.{variant}",
                   with_value(doc, key, Raw(text)), FILE_TOKEN)


def integer_cases(cases, ctx, key, lo, hi, full=True):
    doc = context(ctx)
    kid = ctx_id(ctx, key)
    tok = key_tokens(key)
    types = [("string", "4"), ("bool", True), ("null", None), ("fraction", 1.5)]
    if full:
        types += [("array", [4]), ("object", {"value": 4})]
    for variant, value in types:
        scene_case(cases, "scene.type", f"scene.type.{kid}.{variant}", with_value(doc, key, value),
                   tok)
    ranges = [("below", lo - 1), ("above", hi + 1)]
    if full:
        ranges += [("far-below", lo - 1000000), ("far-above", hi * 1000 + 1000)]
    bigs = [("2^32", N32), ("2^63", N63), ("2^64", N64), ("-2^63-1", -N63 - 1)]
    if full:
        bigs += [("2^31", N31), ("2^31-1", N31 - 1), ("-2^31-1", -N31 - 1), ("2^32+1", N32 + 1),
                 ("digits300", Raw(DIGITS300)), ("-digits300", Raw("-" + DIGITS300))]
    for variant, value in ranges + bigs:
        if isinstance(value, int) and lo <= value <= hi:
            continue
        scene_case(cases, "scene.range", f"scene.range.{kid}.{variant}", with_value(doc, key, value),
                   tok)
    if full:
        for variant, text in [("NaN", "NaN"), ("Infinity", "Infinity"), ("1e400", "1e400")]:
            scene_case(cases, "scene.syntax", f"scene.syntax.{kid}.{variant}",
                       with_value(doc, key, Raw(text)), FILE_TOKEN)


def boolean_cases(cases, ctx, key, full=True):
    doc = context(ctx)
    kid = ctx_id(ctx, key)
    variants = [("string", "true"), ("one", 1), ("zero", 0), ("null", None)]
    if full:
        variants += [("array", [True]), ("object", {"value": True}), ("string-false", "false")]
    for variant, value in variants:
        scene_case(cases, "scene.type", f"scene.type.{kid}.{variant}", with_value(doc, key, value),
                   key_tokens(key))


def enum_cases(cases, ctx, key, allowed):
    doc = context(ctx)
    kid = ctx_id(ctx, key)
    tok = key_tokens(key)
    for variant, value in [("number", 1), ("bool", True), ("null", None), ("array", [allowed[0]]),
                           ("object", {"value": allowed[0]})]:
        scene_case(cases, "scene.type", f"scene.type.{kid}.{variant}", with_value(doc, key, value),
                   tok)
    for variant, value in [("unknown", "nosuch"), ("empty", ""), ("upper", allowed[0].upper()),
                           ("trailing-space", allowed[0] + " "), ("nul", allowed[0] + "\u0000")]:
        if value in allowed:
            continue
        scene_case(cases, "scene.range", f"scene.range.{kid}.{variant}", with_value(doc, key, value),
                   tok)


def vec3_cases(cases, ctx, key, lo, hi, full=True):
    doc = context(ctx)
    kid = ctx_id(ctx, key)
    tok = key_tokens(key)
    types = [("string", "0,0,0"), ("number", 0.0), ("null", None), ("bool", True),
             ("object", {"x": 0.0, "y": 0.0, "z": 0.0}), ("empty", []), ("two", [0.0, 0.0]),
             ("four", [0.0, 0.0, 0.0, 0.0]), ("element-string", ["0", 0.0, 0.0]),
             ("element-null", [0.0, None, 0.0]), ("element-bool", [0.0, 0.0, True]),
             ("element-array", [[0.0], 0.0, 0.0]), ("nested", [[0.0, 0.0, 0.0]])]
    if not full:
        types = types[:3] + types[6:8] + types[8:10]
    for variant, value in types:
        scene_case(cases, "scene.type", f"scene.type.{kid}.{variant}", with_value(doc, key, value),
                   tok)
    ranges = [("x-above", [hi * (1 + 1e-9), 0.0, 0.0]), ("z-below", [0.0, 0.0, just_below(lo)]),
              ("y-2^64", [0.0, N64, 0.0]), ("x-digits300", [Raw(DIGITS300), 0.0, 0.0])]
    if full:
        ranges += [("y-far-below", [0.0, lo * 1000.0 - 1.0, 0.0]), ("z-2^63", [0.0, 0.0, N63])]
    for variant, value in ranges:
        scene_case(cases, "scene.range", f"scene.range.{kid}.{variant}", with_value(doc, key, value),
                   tok)
    syntax = [("x-NaN", "[NaN,0,0]"), ("y-Infinity", "[0,Infinity,0]")]
    if full:
        syntax += [("z-1e400", "[0,0,1e400]"), ("trailing-comma", "[0,0,0,]")]
    for variant, text in syntax:
        scene_case(cases, "scene.syntax", f"scene.syntax.{kid}.{variant}",
                   with_value(doc, key, Raw(text)), FILE_TOKEN)


def object_cases(cases, ctx, key):
    doc = context(ctx)
    kid = ctx_id(ctx, key)
    for variant, value in [("string", "x"), ("number", 1), ("array", []), ("null", None),
                           ("bool", True)]:
        scene_case(cases, "scene.type", f"scene.type.{kid}.{variant}", with_value(doc, key, value),
                   key_tokens(key))


def array_cases(cases, ctx, key):
    doc = context(ctx)
    kid = ctx_id(ctx, key)
    for variant, value in [("object", {}), ("string", "x"), ("number", 1), ("null", None),
                           ("bool", True)]:
        scene_case(cases, "scene.type", f"scene.type.{kid}.{variant}", with_value(doc, key, value),
                   key_tokens(key))
    element = key + "[0]"
    for variant, value in [("number", [1]), ("null", [None]), ("string", ["x"]), ("array", [[]]),
                           ("bool", [True])]:
        scene_case(cases, "scene.type", f"scene.type.{kid}[0].{variant}",
                   with_value(doc, key, value), key_tokens(element))


def scene_key_cases(cases):
    # numbers: key, context, min, max, min exclusive (core/scene.cpp)
    numbers = [
        ("sections", "ring.wire_diameter", 0.0, 1.0, True),
        ("sections", "ring.inner_diameter", 0.0, 10.0, True),
        ("sections", "ring.density", 0.0, 1e5, True),
        ("sections", "ring.friction", 0.0, 10.0, False),
        ("chain", "weave.spacing", 0.7, 1.0, False),  # chain: [0.5 + WD/ID, 1]
        ("grid", "weave.spacing", 0.0, 100.0, True),
        ("sphere", "colliders[0].friction", 0.0, 10.0, False),
        ("sphere", "colliders[0].radius", 0.0, 1e3, True),
        ("cylinder", "colliders[0].radius", 0.0, 1e3, True),
        ("cylinder", "colliders[0].half_height", 0.0, 1e3, True),
        ("support", "support.radius", 0.0, 1e3, True),
        ("loads", "loads[0].mass_factor", 1e-3, 1e6, False),
        ("base", "duration", 0.0, 1e5, True),
        ("base", "sample_interval", 0.0, 1e5, True),
        ("sections", "camera.fov_deg", 1.0, 170.0, False),
        ("sections", "stability.max_speed", 0.0, 1e6, True),
        ("sections", "stability.max_stretch", 1.0, 1e3, False),
        ("sections", "stability.energy_growth", 1.0, 1e6, False),
        ("sections", "reference_dt", 0.0, 1.0, False),
    ]
    for ctx, key, lo, hi, excl in numbers:
        number_cases(cases, ctx, key, lo, hi, excl)
    integers = [
        ("base", "weave.rows", 1, 4096),
        ("base", "weave.cols", 1, 4096),
        ("chain", "weave.rows", 1, 1),
        ("chain", "weave.cols", 2, 1 << 20),
        ("pin_ring", "pins[0].ring", 0, 15),
    ]
    for ctx, key, lo, hi in integers:
        integer_cases(cases, ctx, key, lo, hi)
    vectors = [
        ("sections", "weave.center", -1e6, 1e6, True),
        ("plane", "colliders[0].point", -1e6, 1e6, False),
        ("plane", "colliders[0].normal", -1e6, 1e6, False),
        ("sphere", "colliders[0].center", -1e6, 1e6, True),
        ("box", "colliders[0].center", -1e6, 1e6, False),
        ("box", "colliders[0].half_extents", 1e-9, 1e3, True),
        ("cylinder", "colliders[0].center", -1e6, 1e6, False),
        ("support", "support.center", -1e6, 1e6, True),
        ("sections", "initial_velocity", -1e3, 1e3, True),
        ("sections", "gravity", -1e4, 1e4, True),
        ("sections", "camera.position", -1e6, 1e6, True),
        ("sections", "camera.target", -1e6, 1e6, False),
    ]
    for ctx, key, lo, hi, full in vectors:
        vec3_cases(cases, ctx, key, lo, hi, full)
    # vectors with a meaning beyond their range
    for variant, value in [("zero", [0.0, 0.0, 0.0]), ("tiny", [0.0, 1e-300, 0.0])]:
        scene_case(cases, "scene.range", f"scene.range.plane.colliders[0].normal.{variant}",
                   with_value(context("plane"), "colliders[0].normal", value),
                   key_tokens("colliders[0].normal"))
    for variant, value in [("zero-x", [0.0, 0.01, 0.01]), ("negative-y", [0.01, -0.01, 0.01])]:
        scene_case(cases, "scene.range", f"scene.range.box.colliders[0].half_extents.{variant}",
                   with_value(context("box"), "colliders[0].half_extents", value),
                   key_tokens("colliders[0].half_extents"))
    for ctx, key in [("sections", "features.self_contact"), ("sections", "output.frames"),
                     ("sections", "stability.links_must_hold")]:
        boolean_cases(cases, ctx, key)
    enums = [
        ("base", "weave.type", ["chain", "4in1", "grid"]),
        ("base", "weave.plane", ["xz", "xy", "yz", "yx"]),
        ("base", "pins[0].edge", ["top", "bottom", "left", "right"]),
        ("pin_corner", "pins[0].corner", ["top_left", "top_right", "bottom_left", "bottom_right"]),
        ("sphere", "colliders[0].type", ["plane", "sphere", "box", "cylinder"]),
        ("base", "reference", BACKENDS),
    ]
    for ctx, key, allowed in enums:
        enum_cases(cases, ctx, key, allowed)
    # name: a string that names the output folder
    doc = context("base")
    for variant, value in [("number", 1), ("bool", True), ("null", None), ("array", ["corpus"]),
                           ("object", {"name": "corpus"})]:
        scene_case(cases, "scene.type", f"scene.type.name.{variant}", with_value(doc, "name", value),
                   ("name",))
    for variant, value in [("empty", ""), ("space", "a b"), ("dot", "a.b"), ("slash", "a/b"),
                           ("backslash", "a\\b"), ("dot-only", "."), ("dot-dot", ".."),
                           ("absolute", "/corpus")]:
        scene_case(cases, "scene.range", f"scene.range.name.{variant}", with_value(doc, "name", value),
                   ("name",))
    doc = context("sections")
    for variant, value in [("number", 1), ("bool", True), ("array", ["x"]), ("object", {})]:
        scene_case(cases, "scene.type", f"scene.type.description.{variant}",
                   with_value(doc, "description", value), ("description",))
    for ctx, key in [("sections", "ring"), ("base", "weave"), ("sections", "features"),
                     ("sections", "output"), ("sections", "camera"), ("sections", "stability"),
                     ("support", "support"), ("base", "backends"), ("base", "backends.plausible")]:
        object_cases(cases, ctx, key)
    for ctx, key in [("base", "pins"), ("sphere", "colliders"), ("loads", "loads")]:
        array_cases(cases, ctx, key)


def missing_cases(cases):
    items = [
        ("base", "name"), ("base", "weave"), ("base", "weave.type"), ("base", "weave.rows"),
        ("base", "weave.cols"), ("chain", "weave.cols"), ("grid", "weave.spacing"),
        ("grid", "weave.rows"), ("base", "duration"), ("sphere", "colliders[0].type"),
        ("sphere", "colliders[0].center"), ("sphere", "colliders[0].radius"),
        ("box", "colliders[0].center"), ("box", "colliders[0].half_extents"),
        ("cylinder", "colliders[0].center"), ("cylinder", "colliders[0].radius"),
        ("cylinder", "colliders[0].half_height"), ("support", "support.center"),
        ("support", "support.radius"), ("loads", "loads[0].ring"),
        ("loads", "loads[0].mass_factor"),
    ]
    for ctx, key in items:
        scene_case(cases, "scene.missing", f"scene.missing.{ctx_id(ctx, key)}",
                   without(context(ctx), key), key_tokens(key))
    # a pin names exactly one of ring, edge, corner
    pin_tokens = key_tokens("pins[0]")
    for variant, pin in [("none", {}), ("edge+corner", {"edge": "top", "corner": "top_left"}),
                         ("ring+edge", {"ring": 0, "edge": "top"}),
                         ("ring+corner", {"ring": [0, 0], "corner": "top_left"})]:
        scene_case(cases, "scene.missing", f"scene.missing.pins[0].{variant}",
                   with_value(context("base"), "pins", [pin]), pin_tokens)
    # an empty document: the first required key
    scene_case(cases, "scene.missing", "scene.missing.everything", {}, ("name",))


def unknown_cases(cases):
    items = [
        ("base", "extra"), ("sections", "ring.extra"), ("base", "weave.extra"),
        ("sections", "features.extra"), ("sections", "output.extra"), ("sections", "camera.extra"),
        ("sections", "stability.extra"), ("base", "pins[0].extra"), ("plane", "colliders[0].extra"),
        ("sphere", "colliders[0].extra"), ("box", "colliders[0].extra"),
        ("cylinder", "colliders[0].extra"), ("support", "support.extra"),
        ("loads", "loads[0].extra"), ("base", "backends.nosuch"),
        ("base", "duraton"), ("base", "weave.row"), ("sections", "ring.densty"),
        # a key of another collider type
        ("plane", "colliders[0].radius"), ("sphere", "colliders[0].half_extents"),
        ("box", "colliders[0].radius"), ("cylinder", "colliders[0].normal"),
        ("sphere", "colliders[0].normal"),
        # a key of another pin kind is in scene.missing (two kinds); a key of another weave
        ("base", "weave.spacing"),
    ]
    for ctx, key in items:
        value = {} if key == "backends.nosuch" else 0.01
        if key == "colliders[0].half_extents" or key == "colliders[0].normal":
            value = [0.0, 1.0, 0.0]
        scene_case(cases, "scene.unknown", f"scene.unknown.{ctx_id(ctx, key)}",
                   with_value(context(ctx), key, value), key_tokens(key))
    # an unknown key beside a valid one, deep in an array
    doc = context("base")
    doc["pins"] = [{"edge": "top"}, {"edge": "bottom", "extra": 1}]
    scene_case(cases, "scene.unknown", "scene.unknown.pins[1].extra", doc,
               key_tokens("pins[1].extra"))


def duplicate_cases(cases):
    items = [
        ("base", "name"), ("base", "weave"), ("base", "duration"), ("base", "reference"),
        ("base", "backends"), ("base", "pins"), ("sections", "gravity"),
        ("sections", "description"), ("base", "weave.type"), ("base", "weave.rows"),
        ("base", "weave.cols"), ("base", "weave.plane"), ("sections", "ring.density"),
        ("sections", "camera.fov_deg"), ("sections", "stability.max_speed"),
        ("sections", "features.self_contact"), ("sections", "output.frames"),
        ("base", "pins[0].edge"), ("sphere", "colliders[0].radius"),
        ("sphere", "colliders[0].type"), ("support", "support.radius"),
        ("loads", "loads[0].mass_factor"), ("base", "backends.plausible"),
        ("knobs", "backends.plausible.dt"),
    ]
    for ctx, key in items:
        scene_case(cases, "scene.duplicate", f"scene.duplicate.{ctx_id(ctx, key)}",
                   with_duplicate(context(ctx), key), key_tokens(key))
    scene_case(cases, "scene.duplicate", "scene.duplicate.weave.rows.conflicting",
               with_duplicate(context("base"), "weave.rows", 5), key_tokens("weave.rows"))
    scene_case(cases, "scene.duplicate", "scene.duplicate.duration.conflicting",
               with_duplicate(context("base"), "duration", 0.03), key_tokens("duration"))


def deep(kind, depth, closed=True):
    if kind == "array":
        return "[" * depth + ("]" * depth if closed else "")
    return '{"a":' * depth + ("1" + "}" * depth if closed else "")


def nesting_cases(cases):
    for depth in (10000, 100000):
        for kind in ("array", "object"):
            name = f"{kind}.{depth}"
            scene_case(cases, "scene.nesting", f"scene.nesting.document.{name}",
                       deep(kind, depth).encode(), FILE_TOKEN)
            for key in ("description", "backends.plausible.dt", "extra", "weave.rows"):
                scene_case(cases, "scene.nesting", f"scene.nesting.{key}.{name}",
                           with_value(context("base"), key, Raw(deep(kind, depth))), FILE_TOKEN)
            scene_case(cases, "scene.nesting", f"scene.nesting.unclosed.{name}",
                       (dump(base_scene())[:-1] + ',"extra":' + deep(kind, depth, False)).encode(),
                       FILE_TOKEN)
    # the same through --set: the value is JSON when it parses
    scene = scene_bytes(base_scene())
    for key in ("weave.rows", "description"):
        for kind in ("array", "object"):
            cases.append(Case(f"scene.nesting.set.{key}.{kind}.10000", "scene.nesting",
                              RUN + ["--set", f"{key}={deep(kind, 10000)}"],
                              (SCENE,) + key_tokens(key), scene))
    # not JSON: a plain string, which weave.rows refuses (description would take it)
    # (10,000 levels: flag.set.rows-unclosed-10000)
    cases.append(Case("scene.nesting.set.weave.rows.unclosed-array.100000", "scene.nesting",
                      RUN + ["--set", "weave.rows=" + deep("array", 100000, False)],
                      (SCENE, "--set") + key_tokens("weave.rows"), scene))


def ring_reference_cases(cases):
    pin_tokens = key_tokens("pins[0].ring")
    for variant, ring in [("index-16", 16), ("index-minus-1", -1), ("index-2^31", N31),
                          ("index-2^32", N32), ("row-4", [4, 0]), ("col-4", [0, 4]),
                          ("row-minus-1", [-1, 0]), ("col-minus-1", [0, -1]),
                          ("row-2^32", [N32, 0]), ("col-2^32", [0, N32]),
                          ("row-2^32+1", [N32 + 1, 1]), ("row-2^31", [N31, 0]),
                          ("col-2^63", [0, N63]), ("row-2^64", [N64, 0]), ("one", [1]),
                          ("three", [1, 2, 3]), ("empty", []), ("string", ["0", 0]),
                          ("fraction", [0.5, 0]), ("nested", [[0, 0]])]:
        scene_case(cases, "scene.rings", f"scene.rings.pins[0].ring.{variant}",
                   with_value(context("base"), "pins", [{"ring": ring}]), pin_tokens)
    # chain: one row, `cols` rings
    for variant, ring in [("index-4", 4), ("row-1", [1, 0]), ("col-2^32", [0, N32])]:
        scene_case(cases, "scene.rings", f"scene.rings.chain.pins[0].ring.{variant}",
                   with_value(context("chain"), "pins", [{"ring": ring}]), pin_tokens)
    doc = context("base")
    doc["pins"] = [{"edge": "top"}, {"ring": [9, 9]}]
    scene_case(cases, "scene.rings", "scene.rings.pins[1].ring.row-9", doc,
               key_tokens("pins[1].ring"))
    load_tokens = key_tokens("loads[0].ring")
    for variant, ring in [("row-4", [4, 0]), ("col-4", [0, 4]), ("row-minus-1", [-1, 0]),
                          ("row-2^32", [N32, 0]), ("col-2^32", [0, N32]),
                          ("row-2^32+1", [N32 + 1, 1]), ("row-2^63", [N63, 0]),
                          ("row-2^64", [N64, 0]), ("index", 5), ("one", [1]),
                          ("string", ["1", 1]), ("fraction", [1, 1.5])]:
        scene_case(cases, "scene.rings", f"scene.rings.loads[0].ring.{variant}",
                   with_value(context("loads"), "loads[0].ring", ring), load_tokens)


def geometry_cases(cases):
    def ring(ctx, inner):
        return with_value(context(ctx), "ring", {"wire_diameter": 0.0016, "inner_diameter": inner})

    # chain needs ID/WD >= 2, 4in1 >= 3.5 (core/weave.hpp)
    tok = key_tokens("ring.inner_diameter")
    scene_case(cases, "scene.geometry", "scene.geometry.chain.aspect-just-below",
               ring("chain", 0.0031999), tok)
    scene_case(cases, "scene.geometry", "scene.geometry.chain.aspect-1",
               ring("chain", 0.0016), tok)
    scene_case(cases, "scene.geometry", "scene.geometry.4in1.aspect-just-below",
               ring("base", 0.0055999), tok)
    scene_case(cases, "scene.geometry", "scene.geometry.4in1.aspect-tiny",
               ring("base", 1e-300), tok)
    tok = key_tokens("weave.spacing")
    for variant, value in [("1e-300", 1e-300), ("5e-324", 5e-324)]:
        scene_case(cases, "scene.geometry", f"scene.geometry.grid.spacing-{variant}",
                   with_value(context("grid"), "weave.spacing", value), tok)
    scene_case(cases, "scene.geometry", "scene.geometry.chain.spacing-1e-300",
               with_value(context("chain"), "weave.spacing", 1e-300), tok)


def budget_cases(cases, absent=()):
    def weave(ctx, rows, cols, duration=None):
        doc = context(ctx)
        if rows is not None:
            doc["weave"]["rows"] = rows
        doc["weave"]["cols"] = cols
        if duration is not None:
            doc["duration"] = duration
        return doc

    scene_case(cases, "scene.budget", "scene.budget.4in1-4096x4096",
               weave("base", 4096, 4096), ("weave",))
    scene_case(cases, "scene.budget", "scene.budget.grid-4096x4096",
               weave("grid", 4096, 4096), ("weave",))
    scene_case(cases, "scene.budget", "scene.budget.4in1-1000x1000-duration-1e5",
               weave("base", 1000, 1000, 1e5), ("duration", "weave"))
    scene_case(cases, "scene.budget", "scene.budget.chain-1048576-duration-1e5",
               weave("chain", None, 1 << 20, 1e5), ("duration", "weave"))
    if "bullet" not in absent:
        scene_case(cases, "scene.budget", "scene.budget.4in1-1000x1000-bullet-duration-1e5",
                   with_value(weave("base", 1000, 1000, 1e5), "backends", {"bullet": {}}),
                   ("duration", "weave"))
    cases.append(Case("scene.budget.set-4096x4096", "scene.budget",
                      RUN + ["--set", "weave.rows=4096", "--set", "weave.cols=4096"], ("weave",),
                      scene_bytes(base_scene())))


def knob_cases(cases, absent):
    for backend in BACKENDS:
        if backend in absent:
            continue  # a build without a backend skips its knobs with a note: not bad input there
        for name, kind, lo, hi in KNOBS[backend]:
            key = f"backends.{backend}.{name}"
            tok = (key,)
            if kind == "number":
                variants = [("string", "0.01"), ("below", just_below(float(lo))),
                            ("above", float(hi) * (1 + 1e-9)), ("2^64", N64)]
                if name == "dt":
                    variants += [("null", None), ("bool", True), ("digits300", Raw(DIGITS300))]
            elif kind == "integer":
                variants = [("string", "4"), ("fraction", lo + 0.5), ("below", lo - 1),
                            ("above", hi + 1), ("2^32", N32), ("2^63", N63), ("2^64", N64)]
            elif kind == "choice":
                variants = [("unknown", "nosuch"), ("empty", ""), ("upper", lo[0].upper()),
                            ("index", 0), ("bool", True), ("null", None), ("array", [lo[0]]),
                            ("nul", lo[0] + "\u0000")]
            else:
                variants = [("string", "true"), ("one", 1), ("null", None)]
            for variant, value in variants:
                doc = context("base")
                doc["backends"] = {"plausible": {}, backend: {name: value}}
                scene_case(cases, "scene.knob", f"scene.knob.{key}.{variant}", doc, tok)
            if name == "dt":
                doc = context("base")
                doc["backends"] = {"plausible": {}, backend: {name: Raw("NaN")}}
                scene_case(cases, "scene.knob", f"scene.knob.{key}.NaN", doc, FILE_TOKEN)
        tok = (f"backends.{backend}.extra",)
        doc = context("base")
        doc["backends"] = {"plausible": {}, backend: {"extra": 1}}
        scene_case(cases, "scene.knob", f"scene.knob.backends.{backend}.extra", doc, tok)


def syntax_cases(cases):
    valid = dump(base_scene())
    garbage = bytes((i * 73 + 41) % 256 for i in range(4096))
    items = [
        ("empty", b""), ("whitespace", b"  \n\t \n"), ("garbage", garbage),
        ("array", b"[]"), ("null", b"null"), ("string", b'"x"'), ("number", b"1"),
        ("true", b"true"), ("array-of-scene", ("[" + valid + "]").encode()),
        ("trailing-comma", (valid[:-1] + ",}").encode()),
        ("unclosed", valid[:-1].encode()), ("truncated", valid[: len(valid) // 2].encode()),
        ("single-quotes", valid.replace('"', "'").encode()),
        ("unquoted-key", valid.replace('"name"', "name").encode()),
        ("trailing-garbage", (valid + " x").encode()), ("two-documents", (valid + valid).encode()),
        ("invalid-utf8", valid.replace('"corpus"', '"corp\xffus"').encode("latin-1")),
        ("nul-byte", valid.replace('"corpus"', '"corp\x00us"').encode()),
        ("raw-nul", (valid + "\x00").encode()),
        ("lone-surrogate", valid.replace('"corpus"', '"corp\\ud800us"').encode()),
        ("bad-escape", valid.replace('"corpus"', '"corp\\qus"').encode()),
        ("utf16", valid.encode("utf-16")),
        ("leading-zero", valid.replace('"duration":0.02', '"duration":00.02').encode()),
        ("plus-sign", valid.replace('"duration":0.02', '"duration":+0.02').encode()),
        ("bare-fraction", valid.replace('"duration":0.02', '"duration":.02').encode()),
        ("hex", valid.replace('"rows":4', '"rows":0x4').encode()),
        ("unclosed-comment", (valid + "/* x").encode()),
        ("control-char-in-string", valid.replace('"corpus"', '"corp\nus"').encode()),
    ]
    for variant, data in items:
        cases.append(Case(f"scene.syntax.file.{variant}", "scene.syntax", RUN, FILE_TOKEN, data))


def scene_path_cases(cases):
    valid = scene_bytes(base_scene())
    long_name = "s" * 300
    items = [
        ("directory", "@IN@/adir", [("dir", "adir")]),
        ("dot", ".", []),
        ("fifo", "@IN@/fifo.json", [("fifo", "fifo.json")]),
        ("proc-self-mem", "/proc/self/mem", []),
        ("dev-zero", "/dev/zero", []),
        ("dev-null", "/dev/null", []),
        ("missing", "@IN@/missing.json", []),
        ("missing-folder", "@IN@/nowhere/scene.json", []),
        ("dangling-symlink", "@IN@/dangling.json", [("symlink", "dangling.json", "@IN@/nowhere")]),
        ("symlink-loop", "@IN@/loop.json", [("symlink", "loop.json", "@IN@/loop.json")]),
        ("trailing-slash", "@SCENE@/", []),
        ("parent-is-file", "@SCENE@/scene.json", []),
        ("long-component", f"@IN@/{long_name}.json", []),
        ("empty", "", []),
    ]
    for variant, path, ops in items:
        token = (path,) if path else ("scene",)
        cases.append(Case(f"path.scene.{variant}", "path.scene", ["run", path], token, valid, ops))


def flag_cases(cases):
    valid = scene_bytes(base_scene())
    sweep = ["sweep", "@SCENE@", "--vary", "backends.{backend}.dt=0.002"]
    commands = {
        "run": RUN,
        "sweep": sweep,
        "stability": ["stability", "--quick"],
        "bench": ["bench", "--quick", "--no-render"],
    }

    def add(cid, argv, tokens):  # class: flag.<group>
        cases.append(Case(cid, ".".join(cid.split(".")[:2]), argv, tokens, valid))

    for command, argv in commands.items():
        for variant, value in [("empty-middle", "plausible,,ode"), ("trailing-comma", "plausible,"),
                               ("comma", ","), ("empty", ""), ("unknown", "nosuch"),
                               ("one-unknown", "plausible,nosuch"), ("upper", "PLAUSIBLE")]:
            add(f"flag.backends.{command}.{variant}", argv + ["--backends", value], ("--backends",))
    for variant, value, tok in [
        ("trailing-dot", "a.b.=1", ("--set",)), ("no-key", "=1", ("--set",)),
        ("double-dot", "a..b=1", ("--set",)), ("leading-dot", ".a=1", ("--set",)),
        ("no-equals", "noequals", ("--set",)), ("empty", "", ("--set",)),
        ("only-dot", ".=1", ("--set",)),
        ("rows-1e400", "weave.rows=1e400", key_tokens("weave.rows")),
        ("rows-string", "weave.rows=abc", key_tokens("weave.rows")),
        ("rows-zero", "weave.rows=0", key_tokens("weave.rows")),
        ("rows-fraction", "weave.rows=4.5", key_tokens("weave.rows")),
        ("rows-2^32", "weave.rows=4294967296", key_tokens("weave.rows")),
        ("rows-empty", "weave.rows=", key_tokens("weave.rows")),
        ("duration-negative", "duration=-1", key_tokens("duration")),
        ("duration-NaN", "duration=NaN", key_tokens("duration")),
        ("unknown-key", "nosuch=1", ("nosuch",)),
        ("unknown-nested", "weave.nosuch=1", ("weave.nosuch",)),
        ("index-out-of-range", "pins.5.edge=top", ("pins",)),
        ("index-not-a-number", "pins.x=1", ("pins",)),
        ("parent-not-object", "name.x=1", ("name",)),
        ("knob-out-of-range", "backends.plausible.dt=0", ("backends.plausible.dt",)),
        ("unknown-backend", "backends.nosuch.dt=0.01", ("backends.nosuch",)),
        ("section-not-object", "ring=1", ("ring",)),
        ("weave-array", "weave=[]", ("weave",)),
    ]:
        add(f"flag.set.{variant}", RUN + ["--set", value], tok)
    add("flag.set.rows-unclosed-10000", RUN + ["--set", "weave.rows=" + "[" * 10000],
        ("weave.rows", "--set", SCENE))
    # renderer options without --render, and unknown names with it
    add("flag.render.shader-without-render", RUN + ["--shader", "texture"], ("--shader",))
    add("flag.render.material-without-render", RUN + ["--material", "gold"], ("--material",))
    add("flag.render.unknown-shader", RUN + ["--render", "--shader", "nosuch"],
        ("--shader", "--render"))
    add("flag.render.unknown-material", RUN + ["--render", "--material", "nosuch"],
        ("--material", "--render"))
    # the command line itself
    add("flag.command.none", [], ("subcommand",))
    add("flag.command.unknown", ["nosuch"], ("nosuch", "subcommand"))
    add("flag.command.upper", ["RUN", "@SCENE@"], ("RUN", "subcommand"))
    add("flag.command.run-no-scene", ["run"], ("scene",))
    add("flag.command.run-extra-argument", RUN + ["extra"], ("extra",))
    add("flag.command.run-unknown-flag", RUN + ["--nosuch"], ("--nosuch",))
    add("flag.command.run-out-no-value", RUN + ["--out"], ("--out",))
    add("flag.command.run-set-no-value", RUN + ["--set"], ("--set",))
    add("flag.command.sweep-no-vary", ["sweep", "@SCENE@"], ("--vary",))
    add("flag.command.stability-unknown-flag", ["stability", "--quick", "--nosuch"], ("--nosuch",))
    add("flag.command.bench-unknown-flag", ["bench", "--quick", "--nosuch"], ("--nosuch",))
    for variant, value in [("nan", "nan"), ("inf", "inf"), ("minus-1", "-1"), ("zero", "0"),
                           ("minus-inf", "-inf"), ("text", "abc"), ("1e400", "1e400")]:
        add(f"flag.stability.max-wall-{variant}",
            ["stability", "--quick", "--backends", "plausible", "--max-wall", value],
            ("--max-wall",))
    for variant, value, tok in [
        ("nonsense", "nonsense", ("--vary",)),
        ("empty-values", "backends.{backend}.dt=", ("--vary",)),
        ("no-key", "=0.1", ("--vary",)),
        ("empty", "", ("--vary",)),
        ("text-value", "backends.{backend}.dt=abc", ("backends.plausible.dt",)),
        ("zero-dt", "backends.{backend}.dt=0.002,0", ("backends.plausible.dt",)),
        ("rows-zero", "weave.rows=0,4", key_tokens("weave.rows")),
        ("unknown-key", "nosuch=1", ("nosuch",)),
    ]:
        add(f"flag.sweep.vary-{variant}",
            ["sweep", "@SCENE@", "--vary", value, "--backends", "plausible"], tok)
    # the reference backend's own knob: every point would be measured against itself
    add("flag.sweep.vary-reference-knob",
        ["sweep", "@SCENE@", "--vary", "backends.plausible.iterations=2,8", "--backends",
         "plausible", "--set", "reference=plausible"],
        ("--vary backends.plausible.iterations", "reference"))
    for variant, value in [("zero", "0"), ("minus-1", "-1"), ("text", "abc")]:
        add(f"flag.sweep.jobs-{variant}", sweep + ["--backends", "plausible", "--jobs", value],
            ("--jobs",))
    add("flag.bench.jobs-zero", ["bench", "--quick", "--no-render", "--backends", "plausible",
                                 "--jobs", "0"], ("--jobs",))
    for variant, value in [("zero", "0"), ("minus-1", "-1"), ("text", "abc"), ("empty", ""),
                           ("fraction", "1.5"), ("huge", "99999999999")]:
        add(f"flag.run.threads-{variant}", RUN + ["--threads", value], ("--threads",))
        add(f"flag.sweep.threads-{variant}",
            sweep + ["--backends", "plausible", "--threads", value], ("--threads",))
    for variant, value in [("zero", "0"), ("above", "257"), ("text", "abc")]:
        add(f"flag.bench.scaling-max-{variant}", ["bench", "--quick", "--no-render", "--backends",
                                                   "plausible", "--scaling-max", value],
            ("--scaling-max",))
    add("flag.stability.threads-zero",
        ["stability", "--quick", "--backends", "plausible", "--threads", "0"], ("--threads",))
    add("flag.bench.threads-zero", ["bench", "--quick", "--no-render", "--backends", "plausible",
                                    "--threads", "0"], ("--threads",))
    for variant, value in [("unknown", "nosuch"), ("all", "all"), ("list", "plausible,massspring")]:
        add(f"flag.reference.{variant}", RUN + ["--reference", value], ("--reference",))
    for flag in ("--max-memory", "--max-hours"):
        for variant, value in [("nan", "nan"), ("minus-1", "-1"), ("text", "abc"), ("empty", ""),
                               ("minus-inf", "-inf")]:
            add(f"flag.budget.{flag[2:]}-{variant}", RUN + [flag, value], (flag,))


OUT_COMMANDS = {
    "run": RUN,
    "sweep": ["sweep", "@SCENE@", "--vary", "backends.{backend}.dt=0.002", "--backends",
              "plausible"],
    "stability": ["stability", "--quick", "--backends", "plausible"],
    "bench": ["bench", "--quick", "--backends", "plausible", "--no-render"],
}

# inputs-folder set-up shared by the output-path cases
OUT_VICTIMS = [
    ("file", "victim.txt", b"a user's file: must stay byte-identical\n"),
    ("dir", "foreign"), ("file", "foreign/unrelated.txt", b"unrelated\n"),
    ("dir", "empty"),
    ("dir", "target"), ("file", "target/kept.txt", b"kept\n"),
    ("symlink", "link", "@IN@/target"),
    ("symlink", "filelink", "@IN@/victim.txt"),
    ("symlink", "dangling", "@IN@/nowhere"),
    ("fifo", "fifo"),
    ("dir", "fake"), ("file", "fake/.chainmail-manifest.json", b"not a manifest\n"),
    ("file", "fake/unrelated.txt", b"unrelated\n"),
]


def out_cases(cases):
    valid = scene_bytes(base_scene())
    long_name = "o" * 300
    kinds = [
        ("file", "@IN@/victim.txt", False, []),
        ("file.force", "@IN@/victim.txt", True, []),
        ("dev-null", "/dev/null", False, ["/dev/null"]),
        ("dev-null.force", "/dev/null", True, ["/dev/null"]),
        ("folder-foreign", "@IN@/foreign", False, []),
        ("folder-foreign.force", "@IN@/foreign", True, []),
        ("folder-empty", "@IN@/empty", False, []),
        ("folder-fake-manifest", "@IN@/fake", False, []),
        ("folder-fake-manifest.force", "@IN@/fake", True, []),
        ("symlink-folder", "@IN@/link", False, []),
        ("symlink-folder.force", "@IN@/link", True, []),
        ("symlink-file", "@IN@/filelink", False, []),
        ("symlink-dangling", "@IN@/dangling", False, []),
        ("symlink-dangling.force", "@IN@/dangling", True, []),
        ("fifo", "@IN@/fifo", False, []),
        ("proc", "/proc/chainmail-corpus/out", False, []),
        ("parent-is-file", "@IN@/victim.txt/out", False, []),
        ("long-component", f"@IN@/{long_name}", False, []),
        ("dot", ".", False, []),
        ("trailing-slash-folder", "@IN@/foreign/", False, []),
        ("trailing-slash-file", "@IN@/victim.txt/", False, []),
        ("empty", "", False, []),
        ("blank", "   ", False, []),
    ]
    for command, argv in OUT_COMMANDS.items():
        for variant, path, force, external in kinds:
            if path.strip() == "":
                tokens = ("--out",)
            elif path.endswith("/") and len(path) > 1:
                tokens = (path, path.rstrip("/"))
            else:
                tokens = (path,)
            cases.append(Case(f"out.{command}.{variant}", f"out.{command}",
                              argv + ["--out", path] + (["--force"] if force else []), tokens,
                              valid, OUT_VICTIMS, external=external))
    # a folder made by chainmail, then changed by the user or claimed by another command
    made = ["run", "@SCENE@", "--out", "@IN@/made"]
    cases.append(Case("out.run.folder-made-then-user-file", "out.run",
                      RUN + ["--out", "@IN@/made"], ("@IN@/made",), valid, OUT_VICTIMS,
                      pre=[made], after_pre=[("file", "made/notes.txt", b"the user's notes\n")]))
    cases.append(Case("out.run.folder-made-then-user-file.force", "out.run",
                      RUN + ["--out", "@IN@/made", "--force"], ("@IN@/made",), valid, OUT_VICTIMS,
                      pre=[made], after_pre=[("file", "made/notes.txt", b"the user's notes\n")]))
    cases.append(Case("out.sweep.folder-made-by-run", "out.sweep",
                      OUT_COMMANDS["sweep"] + ["--out", "@IN@/made"], ("@IN@/made",), valid,
                      OUT_VICTIMS, pre=[made]))
    cases.append(Case("out.stability.folder-made-by-run", "out.stability",
                      OUT_COMMANDS["stability"] + ["--out", "@IN@/made"], ("@IN@/made",), valid,
                      OUT_VICTIMS, pre=[made]))


def nonempty_dir(rel):
    def check(dirs):
        path = expand(rel, dirs)
        if os.path.islink(path) or not os.path.isdir(path):
            return f"{path} is not a folder"
        if not os.listdir(path):
            return f"{path} is empty"
        return None
    return check


def control_cases(cases):
    valid = scene_bytes(base_scene())

    def add(cid, argv, out, scene=valid, ops=(), pre=()):
        cases.append(Case(cid, "control", argv, (), scene, ops, pre=pre, expect=0,
                          check=nonempty_dir(out)))

    add("control.run.out", RUN + ["--out", "@IN@/fresh"], "@IN@/fresh")
    add("control.run.default-out", RUN, "@CWD@/results/corpus/run")
    add("control.run.nested-out", RUN + ["--out", "@IN@/a/b/c"], "@IN@/a/b/c")
    add("control.run.force-empty-folder", RUN + ["--out", "@IN@/empty", "--force"], "@IN@/empty",
        ops=[("dir", "empty")])
    add("control.run.replace-own-folder", RUN + ["--out", "@IN@/again"], "@IN@/again",
        pre=[RUN + ["--out", "@IN@/again"]])
    add("control.run.set", RUN + ["--set", "weave.rows=5", "--out", "@IN@/set"], "@IN@/set")
    add("control.run.full-scene", RUN + ["--out", "@IN@/full"], "@IN@/full",
        scene=scene_bytes(full_scene()))
    add("control.run.chain", RUN + ["--out", "@IN@/chain"], "@IN@/chain",
        scene=scene_bytes(with_value(context("chain"), "ring.inner_diameter", 0.0032)))
    add("control.run.grid", RUN + ["--out", "@IN@/grid"], "@IN@/grid",
        scene=scene_bytes(context("grid")))
    add("control.run.reference-none", RUN + ["--reference", "none", "--out", "@IN@/noref"],
        "@IN@/noref")
    add("control.run.budget-flags",
        RUN + ["--max-memory", "1", "--max-hours", "0.1", "--out", "@IN@/budget"], "@IN@/budget")
    add("control.sweep.out", OUT_COMMANDS["sweep"] + ["--out", "@IN@/sweep"], "@IN@/sweep")
    add("control.stability.out", OUT_COMMANDS["stability"] + ["--out", "@IN@/stability"],
        "@IN@/stability")
    add("control.bench.out", OUT_COMMANDS["bench"] + ["--out", "@IN@/bench"], "@IN@/bench")


def all_cases(absent=()):
    cases = []
    scene_key_cases(cases)
    missing_cases(cases)
    unknown_cases(cases)
    duplicate_cases(cases)
    nesting_cases(cases)
    ring_reference_cases(cases)
    geometry_cases(cases)
    budget_cases(cases, absent)
    knob_cases(cases, absent)
    syntax_cases(cases)
    scene_path_cases(cases)
    flag_cases(cases)
    out_cases(cases)
    control_cases(cases)
    ids = [c.id for c in cases]
    assert len(ids) == len(set(ids)), sorted({i for i in ids if ids.count(i) > 1})
    return cases


# ---------------------------------------------------------------------------------------------
# running


def expand(text, dirs):
    return (text.replace("@SCENE@", os.path.join(dirs["in"], SCENE))
            .replace("@IN@", dirs["in"]).replace("@CWD@", dirs["cwd"]))


def make_inputs(ops, dirs):
    for op in ops:
        path = os.path.join(dirs["in"], op[1])
        if op[0] == "file":
            with open(path, "wb") as f:
                f.write(op[2])
        elif op[0] == "dir":
            os.mkdir(path)
        elif op[0] == "symlink":
            os.symlink(expand(op[2], dirs), path)
        elif op[0] == "fifo":
            os.mkfifo(path)
        else:
            raise ValueError(op[0])


def chown_tree(top, uid, gid):
    for root, subdirs, files in os.walk(top):
        os.chown(root, uid, gid, follow_symlinks=False)
        for name in subdirs + files:
            os.chown(os.path.join(root, name), uid, gid, follow_symlinks=False)


def snapshot(top):
    """every entry under top (top included): kind, mode, size, times, inode, target or content"""
    listing = {}

    def visit(path, rel):
        st = os.lstat(path)
        entry = (stat.S_IFMT(st.st_mode), stat.S_IMODE(st.st_mode), st.st_size, st.st_mtime_ns,
                 st.st_ctime_ns, st.st_ino, st.st_uid, st.st_rdev)
        if stat.S_ISLNK(st.st_mode):
            entry += (os.readlink(path),)
        elif stat.S_ISREG(st.st_mode):
            with open(path, "rb") as f:
                entry += (hashlib.sha256(f.read()).hexdigest(),)
        listing[rel] = entry
        if stat.S_ISDIR(st.st_mode):
            for name in sorted(os.listdir(path)):
                visit(os.path.join(path, name), f"{rel}/{name}")

    visit(top, "")
    return listing


def external_state(path):
    try:
        st = os.lstat(path)
    except OSError as e:
        return ("missing", e.errno)
    return (stat.S_IFMT(st.st_mode), stat.S_IMODE(st.st_mode), st.st_rdev, st.st_ino)


def describe_changes(name, before, after):
    changes = []
    for rel in sorted(set(before) | set(after)):
        if rel not in after:
            changes.append(f"{name}{rel} removed")
        elif rel not in before:
            changes.append(f"{name}{rel} added")
        elif before[rel] != after[rel]:
            fields = ["kind", "mode", "size", "mtime", "ctime", "inode", "owner", "rdev", "content"]
            diff = [fields[k] for k in range(len(before[rel]))
                    if k >= len(after[rel]) or before[rel][k] != after[rel][k]]
            changes.append(f"{name}{rel} changed ({', '.join(diff)})")
    return changes


class Runner:
    def __init__(self, binary, work, timeout, drop):
        self.binary = binary
        self.work = work
        self.timeout = timeout
        self.drop = drop
        self.active = set()  # running cases, killed when the corpus itself is stopped

    def kill_all(self):
        for proc in list(self.active):
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except OSError:
                pass

    def env(self, dirs):
        env = {
            "PATH": os.environ.get("PATH", "/usr/bin:/bin"),
            "HOME": dirs["home"],
            "XDG_CACHE_HOME": os.path.join(dirs["home"], ".cache"),
            "XDG_CONFIG_HOME": os.path.join(dirs["home"], ".config"),
            "XDG_DATA_HOME": os.path.join(dirs["home"], ".local", "share"),
            "TMPDIR": os.path.join(dirs["home"], "tmp"),
            "LC_ALL": "C",
            "LANG": "C",
        }
        for name in ("ASAN_OPTIONS", "UBSAN_OPTIONS", "LSAN_OPTIONS", "ASAN_SYMBOLIZER_PATH"):
            if name in os.environ:
                env[name] = os.environ[name]
        return env

    def spawn(self, argv, dirs):
        """(exit status or None on timeout, stdout, stderr, seconds)"""
        kwargs = {}
        if self.drop:
            kwargs = {"user": NOBODY, "group": NOBODY, "extra_groups": []}
        started = time.monotonic()
        proc = subprocess.Popen([self.binary] + argv, cwd=dirs["cwd"], env=self.env(dirs),
                                stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, start_new_session=True, **kwargs)
        self.active.add(proc)
        try:
            out, err = proc.communicate(timeout=self.timeout)
            status = proc.returncode
        except subprocess.TimeoutExpired:
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            out, err = proc.communicate()
            status = None
        finally:
            self.active.discard(proc)
        return status, out, err, time.monotonic() - started

    def run(self, case):
        root = tempfile.mkdtemp(prefix="case-", dir=self.work)
        dirs = {k: os.path.join(root, k) for k in ("in", "cwd", "home")}
        result = {"case": case, "argv": None, "status": None, "stderr": b"", "why": [],
                  "seconds": 0.0}
        try:
            for d in dirs.values():
                os.mkdir(d)
            os.mkdir(os.path.join(dirs["home"], ".cache"))
            os.mkdir(os.path.join(dirs["home"], "tmp"))
            if case.scene is not None:
                with open(os.path.join(dirs["in"], SCENE), "wb") as f:
                    f.write(case.scene)
            make_inputs(case.ops, dirs)
            if self.drop:
                chown_tree(root, NOBODY, NOBODY)
            for pre in case.pre:
                status, _, err, _ = self.spawn([expand(a, dirs) for a in pre], dirs)
                if status != 0:
                    result["why"].append(f"set-up command {pre} exited {status}: "
                                         f"{err.decode(errors='replace')[-500:]}")
                    return result
            if case.after_pre:
                make_inputs(case.after_pre, dirs)
                if self.drop:
                    chown_tree(root, NOBODY, NOBODY)
            before = {k: snapshot(d) for k, d in dirs.items()}
            outside = {p: external_state(p) for p in case.external}
            argv = [expand(a, dirs) for a in case.argv]
            result["argv"] = argv
            status, out, err, seconds = self.spawn(argv, dirs)
            result.update(status=status, stderr=err, seconds=seconds)
            why = result["why"]
            if status is None:
                why.append(f"timed out after {self.timeout:g} s")
            elif status < 0:
                why.append(f"killed by signal {-status} ({signal.Signals(-status).name})"
                           if -status in signal.valid_signals() else f"signal {-status}")
            elif status != case.expect:
                why.append(f"exit status {status}, expected {case.expect}")
            if case.expect == 0:
                if status == 0 and case.check:
                    problem = case.check(dirs)
                    if problem:
                        why.append(problem)
                return result
            text = err.decode("utf-8", errors="replace")
            body = text[:-1] if text.endswith("\n") else text
            if not body:
                why.append("stderr is empty")
            elif "\n" in body or "\r" in body:
                why.append(f"stderr has {body.count(chr(10)) + 1} lines, expected one")
            elif not body.startswith("chainmail: "):
                why.append("stderr does not start with 'chainmail: '")
            tokens = [expand(t, dirs) for t in case.tokens]
            if body and not any(t in body for t in tokens):
                why.append("stderr names none of " + " | ".join(repr(short(t)) for t in tokens))
            after = {k: snapshot(d) for k, d in dirs.items()}
            for k in dirs:
                why.extend(describe_changes(k, before[k], after[k]))
            for p, state in outside.items():
                if external_state(p) != state:
                    why.append(f"{p} changed: {state} -> {external_state(p)}")
            return result
        except Exception as e:  # a broken case set-up is a failure, not a crash of the corpus
            result["why"].append(f"corpus error: {type(e).__name__}: {e}")
            return result
        finally:
            shutil.rmtree(root, onerror=force_remove)


def force_remove(function, path, excinfo):
    try:
        os.chmod(os.path.dirname(path), 0o700)
        if os.path.isdir(path) and not os.path.islink(path):
            os.chmod(path, 0o700)
            shutil.rmtree(path, ignore_errors=True)
        else:
            os.unlink(path)
    except OSError:
        pass


def short(text, limit=160):
    if len(text) <= limit:
        return text
    return text[: limit // 2] + f"...<{len(text)} characters>..." + text[-limit // 4:]


def sanitized(binary):
    """True when the binary carries a sanitizer runtime (RLIMIT_AS would break it)"""
    marks = (b"__asan_init", b"__tsan_init", b"__msan_init", b"__hwasan_init")
    tail = b""
    with open(binary, "rb") as f:
        while True:
            block = f.read(1 << 20)
            if not block:
                return False
            if any(m in tail + block for m in marks):
                return True
            tail = block[-32:]


def probe_backends(runner):
    """backends this build lacks (it names them in a note and skips their knobs)"""
    absent = []
    for backend in OPTIONAL_BACKENDS:
        doc = base_scene()
        doc["backends"] = {backend: {"dt": "probe"}}
        case = Case("probe", "probe", RUN, (), scene_bytes(doc))
        result = runner.run(case)
        text = result["stderr"].decode(errors="replace")
        if f"backends.{backend}.dt" not in text and "built into this binary" in text:
            absent.append(backend)
    return absent


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--chainmail", help="the chainmail binary")
    parser.add_argument("--jobs", type=int, default=2, help="cases run in parallel (default 2)")
    parser.add_argument("--filter", default="", help="only cases whose id contains SUBSTR")
    parser.add_argument("--list", action="store_true", help="list the case ids and stop")
    parser.add_argument("--report-classes", action="store_true",
                        help="print the number of cases per class and stop")
    parser.add_argument("--timeout", type=float, default=30.0, help="seconds per case (30)")
    parser.add_argument("--max-memory-gib", type=float, default=4.0,
                        help="RLIMIT_AS per case, GiB (0: none; sanitizer builds: none)")
    parser.add_argument("--workdir", help="where the cases' temporary folders go (default: "
                        "/dev/shm when it is a writable folder, else the system's temporary folder)")
    parser.add_argument("--keep", action="store_true", help="keep the temporary folder")
    args = parser.parse_args()

    cases = [c for c in all_cases() if args.filter in c.id]
    if args.list:
        for c in cases:
            print(f"{c.id}\t{c.cls}")
        return 0
    classes = {}
    for c in cases:
        classes.setdefault(c.cls, 0)
        classes[c.cls] += 1
    if args.report_classes:
        for cls, count in classes.items():
            print(f"{cls:20s} {count:5d}")
        bad = sum(n for k, n in classes.items() if k != "control")
        print(f"{'bad input':20s} {bad:5d}")
        print(f"{'control':20s} {classes.get('control', 0):5d}")
        return 0
    if not args.chainmail:
        parser.error("--chainmail PATH is required")
    binary = os.path.abspath(args.chainmail)
    if not os.path.isfile(binary) or not os.access(binary, os.X_OK):
        print(f"bad_input_corpus: {binary}: not an executable file", file=sys.stderr)
        return 2

    # a crash leaves no core file in a case's cwd; the memory limit holds for every case
    resource.setrlimit(resource.RLIMIT_CORE, (0, resource.getrlimit(resource.RLIMIT_CORE)[1]))
    has_sanitizer = sanitized(binary)
    if args.max_memory_gib > 0 and not has_sanitizer:
        hard = resource.getrlimit(resource.RLIMIT_AS)[1]
        limit = int(args.max_memory_gib * (1 << 30))
        if hard != resource.RLIM_INFINITY:
            limit = min(limit, hard)
        resource.setrlimit(resource.RLIMIT_AS, (limit, hard))
    drop = os.geteuid() == 0
    workdir = args.workdir
    if workdir is None and os.path.isdir("/dev/shm") and os.access("/dev/shm", os.W_OK | os.X_OK):
        workdir = "/dev/shm"  # tmpfs: thousands of small folders made and removed quickly
    work = tempfile.mkdtemp(prefix="chainmail-corpus-", dir=workdir)
    os.chmod(work, 0o755)
    runner = Runner(binary, work, args.timeout, drop)

    def stop(signum, frame):  # ctest's timeout, Ctrl-C: no case outlives the corpus
        runner.kill_all()
        shutil.rmtree(work, onerror=force_remove)
        os._exit(128 + signum)

    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)
    started = time.monotonic()
    try:
        try:
            runner.spawn(["--help"], {"cwd": work, "home": work})
        except OSError as e:
            if not drop:
                print(f"bad_input_corpus: cannot run {binary}: {e}", file=sys.stderr)
                return 2
            # the binary or its tree is not readable by others (a checkout under a private home):
            # run as root, the victims all lie in the corpus's own temporary folders
            drop = runner.drop = False
            try:
                runner.spawn(["--help"], {"cwd": work, "home": work})
            except OSError as e2:
                print(f"bad_input_corpus: cannot run {binary}: {e2}", file=sys.stderr)
                return 2
        absent = probe_backends(runner)
        cases = [c for c in all_cases(absent) if args.filter in c.id]
        notes = []
        if drop:
            notes.append("running as root: cases run as uid/gid 65534")
        if has_sanitizer:
            notes.append("sanitizer build: no RLIMIT_AS")
        elif args.max_memory_gib > 0:
            notes.append(f"RLIMIT_AS {args.max_memory_gib:g} GiB")
        if absent:
            notes.append("not in this build (their knob cases left out): " +
                         ", ".join(absent))
        print(f"bad_input_corpus: {len(cases)} cases, {args.jobs} jobs, binary {binary}"
              + "".join(f"; {n}" for n in notes), flush=True)
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            results = list(pool.map(runner.run, cases))
    finally:
        if args.keep:
            print(f"bad_input_corpus: kept {work}")
        else:
            shutil.rmtree(work, onerror=force_remove)
    elapsed = time.monotonic() - started

    table = {}
    failed = 0
    for r in results:
        c = r["case"]
        row = table.setdefault(c.cls, [0, 0])
        row[0] += 1
        if r["why"]:
            failed += 1
            status = "timeout" if r["status"] is None and r["argv"] else r["status"]
            print(f"\nFAIL {c.id} [{c.cls}]")
            print("  command: " + " ".join(shlex.quote(short(a))
                                           for a in [binary] + (r["argv"] or c.argv)))
            if c.scene is not None and c.cls.startswith("scene."):
                print("  scene: " + short(repr(c.scene)[2:-1], 400))
            print(f"  exit status: {status}  ({r['seconds']:.2f} s)")
            err = r["stderr"].decode("utf-8", errors="replace")
            lines = err.splitlines() or [""]
            for line in lines[:8]:
                print("  stderr: " + short(line, 400))
            if len(lines) > 8:
                print(f"  stderr: ... {len(lines) - 8} more lines")
            for why in r["why"][:12]:
                print("  why: " + short(why, 600))
            if len(r["why"]) > 12:
                print(f"  why: ... {len(r['why']) - 12} more")
        else:
            row[1] += 1
    print()
    print(f"{'class':20s} {'cases':>6s} {'passed':>7s}")
    for cls, (count, passed) in table.items():
        print(f"{cls:20s} {count:6d} {passed:7d}")
    bad = [v for k, v in table.items() if k != "control"]
    print(f"{'bad input (total)':20s} {sum(v[0] for v in bad):6d} {sum(v[1] for v in bad):7d}")
    ctl = table.get("control", [0, 0])
    print(f"{'control (total)':20s} {ctl[0]:6d} {ctl[1]:7d}")
    print(f"took {elapsed:.1f} s")
    print(f"{len(results) - failed} passed, {failed} failed")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
