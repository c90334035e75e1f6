"""Error against run time, one curve per backend, the Pareto front marked (sweep.csv -> PNG)."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path, png_path, title):
    rows = [r for r in csv.DictReader(open(csv_path)) if r["stable"] == "true" and r["error_m"]]
    fig, ax = plt.subplots(figsize=(7, 5), dpi=120)
    points = []
    for backend in sorted({r["backend"] for r in rows}):
        mine = sorted((float(r["wall_per_sim_s"]), float(r["error_m"]) * 1e3) for r in rows
                      if r["backend"] == backend)
        # a zero error (the reference against itself) cannot sit on a log axis
        mine = [(t, e) for t, e in mine if e > 0 and t > 0]
        if not mine:
            continue
        ax.plot([t for t, _ in mine], [e for _, e in mine], "o-", label=backend)
        points += [(t, e, backend) for t, e in mine]
    # pareto front: no other point is both faster and more accurate
    front = [p for p in points if not any(q[0] <= p[0] and q[1] < p[1] or q[0] < p[0] and q[1] <= p[1]
                                          for q in points)]
    front.sort()
    if front:
        ax.plot([p[0] for p in front], [p[1] for p in front], "k--", lw=1, label="Pareto front")
        ax.scatter([p[0] for p in front], [p[1] for p in front], s=120, facecolors="none",
                   edgecolors="k")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall seconds per simulated second")
    ax.set_ylabel("drape error against the reference, RMS (mm)")
    ax.set_title(f"{title}: error against run time")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(png_path)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3] if len(sys.argv) > 3 else "sweep")
