"""Cost against size, one line per backend and thread count, with the O(n) line (scaling.csv -> PNG)."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path, png_path):
    rows = [r for r in csv.DictReader(open(csv_path)) if float(r["ms_per_step"] or 0) > 0]
    fig, ax = plt.subplots(figsize=(7, 5), dpi=120)
    for key in sorted({(r["backend"], int(r["threads"])) for r in rows}):
        mine = sorted((int(r["rings"]), float(r["ms_per_step"])) for r in rows
                      if (r["backend"], int(r["threads"])) == key)
        label = f"{key[0]}, {key[1]} thread{'s' if key[1] > 1 else ''}"
        ax.plot([n for n, _ in mine], [ms for _, ms in mine], "o-", label=label)
    # the O(n) line through plausible's 32 x 32 point on one thread (or its smallest)
    base = [r for r in rows if r["backend"] == "plausible" and r["threads"] == "1"]
    anchor = [r for r in base if r["side"] == "32"] or base[:1]
    if anchor:
        n0, ms0 = int(anchor[0]["rings"]), float(anchor[0]["ms_per_step"])
        sizes = sorted({int(r["rings"]) for r in rows})
        ax.plot(sizes, [ms0 * n / n0 for n in sizes], "k--", lw=1, label="O(n)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("rings")
    ax.set_ylabel("ms per step")
    ax.set_title("curtain: cost against size")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(png_path)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
