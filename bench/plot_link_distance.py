"""The largest centre distance of two linked rings over their relative orientation
(chainmail_link_table CSV -> PNG): equal tilts against the twist, the two tilts at a quarter-turn
twist, and a few cuts against the twist."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path, png_path):
    rows = list(csv.DictReader(open(csv_path)))
    aspect = rows[0]["aspect_ratio"]
    value = {(int(r["tilt_first_deg"]), int(r["tilt_second_deg"]), int(r["twist_deg"])):
             float(r["max_distance_over_id"]) for r in rows}
    tilts = sorted({k[0] for k in value})
    twists = sorted({k[2] for k in value})
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8), dpi=110)

    equal = [[value[(t, t, w)] for w in twists] for t in tilts]
    image = axes[0].imshow(equal, origin="lower", aspect="auto", vmin=0, vmax=1, cmap="viridis",
                           extent=[twists[0], twists[-1], tilts[0], tilts[-1]])
    axes[0].set(xlabel="twist (deg)", ylabel="tilt of both rings (deg)",
                title="both rings tilted alike")

    quarter = [[value[(a, b, 90)] for a in tilts] for b in tilts]
    axes[1].imshow(quarter, origin="lower", aspect="auto", vmin=0, vmax=1, cmap="viridis",
                   extent=[tilts[0], tilts[-1], tilts[0], tilts[-1]])
    axes[1].set(xlabel="tilt of the first ring (deg)", ylabel="tilt of the second ring (deg)",
                title="a quarter turn apart (twist 90 deg)")
    fig.colorbar(image, ax=axes[:2], label="largest centre distance / inner diameter")

    for first, second in [(0, 0), (0, 35), (35, 35), (0, 60), (20, 50)]:
        axes[2].plot(twists, [value[(first, second, w)] for w in twists],
                     label=f"tilts {first} / {second} deg")
    axes[2].set(xlabel="twist (deg)", ylabel="largest centre distance / inner diameter",
                ylim=(0, 1.05), title="cuts")
    axes[2].axhline(1.0, color="k", lw=0.8, ls=":")
    axes[2].legend(fontsize=8)
    fig.suptitle(f"Two linked rings, aspect ratio {aspect}: how far apart can their centres be? "
                 "(0: never linked and clear)")
    fig.savefig(png_path, bbox_inches="tight")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: plot_link_distance.py TABLE.csv OUT.png")
    main(sys.argv[1], sys.argv[2])
