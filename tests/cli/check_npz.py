#!/usr/bin/env python3
"""The .npz export read by NumPy: a 16 x 16 curtain run with --frames --export npz, its arrays
checked for their shapes and against the frame CSVs, metrics.csv and summary.json; then the same
export made by `chainmail render --no-images` from the saved CSVs, which must equal them exactly.
Exit 0 when all holds, 1 on a mismatch, 77 (skipped) without NumPy."""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile

try:
    import numpy as np
except ImportError:
    print("check_npz: NumPy is not installed (python3-numpy): skipped")
    sys.exit(77)

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def run(chainmail, *arguments):
    done = subprocess.run([chainmail, *arguments], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"check_npz: {' '.join(arguments)}: exit {done.returncode}\n{done.stderr}")


def frame_csvs(folder, backend):
    """(F, N, 10) array of ring,i,j,x,y,z,qw,qx,qy,qz over every frame CSV, in order"""
    names = sorted(os.listdir(os.path.join(folder, "frames", backend)))
    return np.stack([np.loadtxt(os.path.join(folder, "frames", backend, name), delimiter=",",
                                skiprows=1, ndmin=2) for name in names])


def check(condition, what):
    if not condition:
        sys.exit(f"check_npz: {what}")


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--chainmail", required=True)
    chainmail = parser.parse_args().chainmail
    with tempfile.TemporaryDirectory() as work:
        out = os.path.join(work, "run")
        run(chainmail, "run", os.path.join(SOURCE, "bench/scenes/curtain.json"), "--backends",
            "plausible", "--reference", "none", "--cache", "none", "--quiet", "--set",
            "weave.rows=16", "--set", "weave.cols=16", "--set", "duration=0.2", "--frames",
            "--export", "npz", "--out", out)
        npz = np.load(os.path.join(out, "export", "plausible.npz"))
        frames = frame_csvs(out, "plausible")
        count, rings = frames.shape[0], frames.shape[1]
        check(rings == 256, f"{rings} rings in the CSVs, not 256")
        check(npz["t"].shape == (count,), f"t {npz['t'].shape}, not ({count},)")
        check(npz["position"].shape == (count, rings, 3), f"position {npz['position'].shape}")
        check(npz["orientation"].shape == (count, rings, 4), f"orientation {npz['orientation'].shape}")
        check(npz["grid"].shape == (rings, 2), f"grid {npz['grid'].shape}")
        check(npz["position"].dtype == np.float64 and npz["grid"].dtype == np.int64, "dtypes")
        # the export is at full precision, the CSVs at 9 significant digits
        check(np.allclose(npz["position"], frames[:, :, 3:6], rtol=1e-8, atol=1e-12),
              "positions differ from the frame CSVs")
        check(np.allclose(npz["orientation"], frames[:, :, 6:10], rtol=1e-8, atol=1e-12),
              "orientations differ from the frame CSVs")
        check((npz["grid"] == frames[0, :, 1:3]).all(), "grid differs from the CSVs' i, j")
        with open(os.path.join(out, "metrics.csv")) as f:
            times = [float(row["t"]) for row in csv.DictReader(f)]
        check(np.allclose(npz["t"], times[:count], rtol=1e-8, atol=0), "t differs from metrics.csv")
        with open(os.path.join(out, "summary.json")) as f:
            ring = json.load(f)["ring"]
        check(float(npz["wire_radius"]) == ring["wire_radius"], "wire_radius")
        check(float(npz["centre_radius"]) == ring["centre_radius"], "centre_radius")

        # from the saved CSVs: the same numbers the CSVs hold, exactly
        again = os.path.join(work, "again")
        run(chainmail, "render", out, "--no-images", "--export", "npz", "--out", again)
        saved = np.load(os.path.join(again, "export", "plausible.npz"))
        check((saved["position"] == frames[:, :, 3:6]).all(), "render's export != frame CSVs")
        check((saved["orientation"] == frames[:, :, 6:10]).all(), "render's export != CSVs")
        check((saved["t"] == np.array(times[:count])).all(), "render's t != metrics.csv")
    print(f"check_npz: {count} frames of {rings} rings match the frame CSVs")


if __name__ == "__main__":
    main()
