#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Read a scene, run it, plot the deformation norm (paper eq. 15) over time with matplotlib.

    python3 run_and_plot.py scenes/region_load.iv --until 3 -o norm.png
"""
import argparse

import matplotlib
matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt

import bsdeform

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("scene")
parser.add_argument("--until", type=float, default=3.0, help="simulated time to run to")
parser.add_argument("-o", "--output", default="norm.png")
args = parser.parse_args()

bsdeform.simulated_clock()  # engines in the scene follow simulated time, as in bsdeform-run
root = bsdeform.read_scene(args.scene)
histories = bsdeform.run(root, until=args.until)

fig, ax = plt.subplots(figsize=(7, 4))
for name, h in histories.items():
    ax.plot(h.time, h.norm, label=name)
    print("%s: %d steps, norm %.6g at t = %.4g" % (name, h.step[-1], h.norm[-1], h.time[-1]))
ax.set_xlabel("simulated time")
ax.set_ylabel("deformation norm (eq. 15)")
ax.set_title(args.scene.rsplit("/", 1)[-1])
ax.legend()
fig.tight_layout()
fig.savefig(args.output, dpi=100)
print("wrote", args.output)
