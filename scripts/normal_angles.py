#!/usr/bin/env python3
"""Ring orientations of one backend against another's, from a run's frame files.

    chainmail run bench/scenes/corner_hang.json --backends plausible,ode --frames --out RUN
    scripts/normal_angles.py RUN [--backend plausible] [--reference ode]

Reads the last frame of each backend (frames/<backend>/NNNNN.csv, the same simulated time when
both ran the whole scene) and prints, over the rings both have:

- the mean angle between their ring normals (the ring axis, local +Y; a normal and its opposite
  are the same ring plane, so the angle is at most 90 degrees);
- for rings with all four neighbours, the same split into the sheet's part (the angle between the
  two sheets' normals from the neighbour vectors) and the ring's lean out of its sheet.

Only the standard library is needed.
"""
import argparse
import csv
import math
import pathlib
import sys


def read_frame(folder, backend):
    files = sorted((folder / "frames" / backend).glob("*.csv"))
    if not files:
        sys.exit(f"normal_angles: no frames of '{backend}' in {folder} (run with --frames)")
    rings = {}
    with open(files[-1], newline="") as f:
        for row in csv.DictReader(f):
            w, x, y, z = (float(row[k]) for k in ("qw", "qx", "qy", "qz"))
            axis = (2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x))
            centre = (float(row["x"]), float(row["y"]), float(row["z"]))
            rings[(int(row["i"]), int(row["j"]))] = (centre, axis)
    return rings


def sub(p, q):
    return tuple(a - b for a, b in zip(p, q))


def dot(p, q):
    return sum(a * b for a, b in zip(p, q))


def cross(p, q):
    return (p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0])


def unit(p):
    n = math.sqrt(dot(p, p))
    return tuple(a / n for a in p)


def angle(p, q):
    """degrees between two lines (a direction and its opposite are the same line)"""
    return math.degrees(math.acos(min(1.0, abs(dot(unit(p), unit(q))))))


def sheet_normal(rings, key):
    i, j = key
    around = [rings.get(k) for k in ((i - 1, j), (i + 1, j), (i, j - 1), (i, j + 1))]
    if any(r is None for r in around):
        return None
    x, z = sub(around[1][0], around[0][0]), sub(around[3][0], around[2][0])
    return unit(cross(z, x))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("run", type=pathlib.Path, help="a run folder written with --frames")
    parser.add_argument("--backend", default="plausible")
    parser.add_argument("--reference", default="ode")
    args = parser.parse_args()
    mine, theirs = read_frame(args.run, args.backend), read_frame(args.run, args.reference)
    keys = [k for k in mine if k in theirs]
    if not keys:
        sys.exit("normal_angles: the two frames share no ring")
    rings = [angle(mine[k][1], theirs[k][1]) for k in keys]
    print(f"{args.backend} against {args.reference}, {len(keys)} rings: mean angle between ring "
          f"normals {sum(rings) / len(rings):.1f} deg")
    sheet, lean, count = 0.0, 0.0, 0
    for k in keys:
        a, b = sheet_normal(mine, k), sheet_normal(theirs, k)
        if a is None or b is None:
            continue
        sheet += angle(a, b)
        lean += abs(angle(mine[k][1], a) - angle(theirs[k][1], b))
        count += 1
    if count:
        print(f"  {count} rings with four neighbours: sheet normals {sheet / count:.1f} deg apart, "
              f"leans out of the sheet differ by {lean / count:.1f} deg")


if __name__ == "__main__":
    main()
