#!/usr/bin/env python3
"""Writes the fuzz targets' seed inputs into OUT/<target>/ (standard library only):

  scene_file   the bench scenes, and every scene file of the command line's bad-input corpus
               (tests/cli/bad_input_corpus.py) with its --set overrides, NUL-separated
  frame_stream small valid streams (1 and 3 rings, 0 to 3 records) and cut ones
  saved_run    summary.json, metrics.csv and a frame CSV of a small run, and variations

Usage: seeds.py OUT
"""
import glob
import json
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.normpath(os.path.join(HERE, "..", ".."))


def write(folder, name, data):
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


def scene_seeds(out):
    for path in sorted(glob.glob(os.path.join(SOURCE, "bench", "scenes", "*.json"))):
        with open(path, "rb") as f:
            write(out, "bench-" + os.path.basename(path), f.read())
    sys.path.insert(0, os.path.join(SOURCE, "tests", "cli"))
    import bad_input_corpus  # noqa: E402 (beside the command line's tests)
    for case in bad_input_corpus.all_cases():
        if not case.scene:
            continue
        sets = [case.argv[k + 1] for k, a in enumerate(case.argv[:-1]) if a == "--set"]
        write(out, "corpus-" + case.id.replace("/", "_")[:120],
              b"\0".join([case.scene] + [s.encode() for s in sets]))


def stream(rings, times):
    data = b"CMFRM001" + struct.pack("<3q", rings, 1 + 7 * rings, 0)
    for t in times:
        data += struct.pack("<d", t) + struct.pack(f"<{3 * rings}d", *[0.01 * k for k in range(3 * rings)])
        data += struct.pack(f"<{4 * rings}d", *([1.0, 0.0, 0.0, 0.0] * rings))
    return data


def stream_seeds(out):
    for rings in (1, 3):
        for count in range(4):
            data = stream(rings, [0.05 * k for k in range(count)])
            write(out, f"stream-{rings}-{count}", bytes([rings - 1]) + data)
            if count:
                write(out, f"stream-{rings}-{count}-cut", bytes([rings - 1]) + data[:-5])


def saved_run_seeds(out):
    scene = {"name": "seed", "weave": {"type": "4in1", "rows": 2, "cols": 2, "plane": "xy"},
             "duration": 0.1, "sample_interval": 0.05}
    summary = {"scene": scene, "backends": {"plausible": {"ms_per_step": 0.1, "steps": 10}}}
    metrics = "backend,t,max_stretch,step_wall_ms\nplausible,0,0.9,0.1\nplausible,0.05,0.9,0.1\n"
    frame = "ring,i,j,x,y,z,qw,qx,qy,qz\n" + "".join(
        f"{r},{r // 2},{r % 2},{0.01 * r},0,0,1,0,0,0\n" for r in range(4))
    parts = [json.dumps(summary).encode(), metrics.encode(), frame.encode()]
    write(out, "run", b"\0".join(parts))
    write(out, "run-no-frame", b"\0".join(parts[:2]))
    write(out, "run-only-summary", parts[0])


def main():
    out = sys.argv[1]
    scene_seeds(os.path.join(out, "scene_file"))
    stream_seeds(os.path.join(out, "frame_stream"))
    saved_run_seeds(os.path.join(out, "saved_run"))
    for target in ("scene_file", "frame_stream", "saved_run"):
        print(target, len(os.listdir(os.path.join(out, target))), "seeds")


if __name__ == "__main__":
    main()
