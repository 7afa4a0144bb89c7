#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The paper's section 7 study: the deformation norm at t = 1 against the weight w10
(bsdeform-run --sweep does the same; docs/sweep_w10.csv holds its numbers).

    python3 sweep_sec7.py scenes/paper_sec7_central_square.iv -o sweep_w10.png
"""
import argparse

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

import bsdeform

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("scene")
parser.add_argument("--weight", default="w10", help="the field swept (w10 or w01)")
parser.add_argument("-o", "--output", default="sweep.png")
args = parser.parse_args()

values = [0, 0.0001, 0.001, 0.01, 0.1, 0.3, 0.5, 1, 2, 5, 7, 10, 25, 50, 75, 100, 150, 200]
norms = []
for w in values:
    bsdeform.simulated_clock()
    root = bsdeform.read_scene(args.scene)
    (surface,) = bsdeform.surfaces(root)
    surface.set(**{args.weight: w})
    history = bsdeform.run(root, until=1.0)[surface.name]
    norms.append(history.norm[-1])
    print("%s = %-8g norm %.17g" % (args.weight, w, norms[-1]))

plt.plot(values, norms, "o-")
plt.xscale("symlog", linthresh=0.1)
plt.xlabel(args.weight)
plt.ylabel("deformation norm at t = 1 (eq. 15)")
plt.savefig(args.output, dpi=100)
print("wrote", args.output)
