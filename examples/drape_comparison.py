"""Drape comparison, notebook style: a small Golden Curtain hung in two models, stepped from
Python, its final profiles plotted side by side with matplotlib.

    PYTHONPATH=build/release/python python3 examples/drape_comparison.py --out drape.png
"""
import argparse
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import chainmail  # noqa: E402

# %% the scene: the curtain at 12 x 12 rings, one simulated second
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--scene", default=os.path.join(os.path.dirname(__file__), "..", "bench",
                                                     "scenes", "curtain.json"))
parser.add_argument("--backends", default="plausible,ode")
parser.add_argument("--out", default="drape_comparison.png")
args = parser.parse_args()
built = {b["name"] for b in chainmail.backends() if b["built"]}
names = [n for n in args.backends.split(",") if n in built]
scene = chainmail.load_scene(args.scene, {"weave.rows": 12, "weave.cols": 12, "duration": 1.0})

# %% each model stepped to the end of the scene; the positions are views, copied to keep them
finals = {}
for name in names:
    sim = chainmail.Simulation(scene, name)
    sim.step(n=round(scene.duration / sim.dt))
    finals[name] = sim.positions.copy()
    m = sim.metrics()
    print(f"{name:10s} t = {sim.t:.3f} s  max_stretch {m['max_stretch']:.4f}  hash {sim.hash}")

# %% the profiles: every ring's height against its depth (the sheet seen from the side), and
# where each ring ended up against the first model
fig, (side, shift) = plt.subplots(1, 2, figsize=(10, 4))
for name, p in finals.items():
    side.scatter(p[:, 2] * 1e3, p[:, 1] * 1e3, s=6, label=name)
side.set(xlabel="z, mm", ylabel="y, mm", title="final drape, side view")
side.legend()
first = names[0]
for name in names[1:]:
    distance = np.linalg.norm(finals[name] - finals[first], axis=1) * 1e3
    shift.hist(distance, bins=30, alpha=0.7, label=f"{name} vs {first}")
    print(f"{name} vs {first}: RMS {np.sqrt(np.mean(distance ** 2)):.3f} mm")
shift.set(xlabel="ring distance, mm", ylabel="rings", title="where the models differ")
if len(names) > 1:
    shift.legend()
fig.tight_layout()
fig.savefig(args.out, dpi=120)
print("wrote", args.out)
