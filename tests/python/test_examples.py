# SPDX-License-Identifier: MIT
"""The examples in examples/python run and give the runner's numbers; the SoQt one under
xvfb-run when it is installed."""
import csv
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import matplotlib
matplotlib.use("Agg")
import matplotlib.image
import numpy

from support import RUN, scene

EXAMPLES = os.environ["BSDEFORM_EXAMPLES_DIR"]


def example(name, *args, cwd=None, wrapper=()):
    r = subprocess.run(list(wrapper) + [sys.executable, os.path.join(EXAMPLES, name)] + list(args),
                       capture_output=True, text=True, cwd=cwd, timeout=600)
    if r.returncode != 0:
        raise AssertionError("%s failed (%d):\n%s\n%s" % (name, r.returncode, r.stdout, r.stderr))
    return r.stdout


def assert_picture(test, path):
    img = matplotlib.image.imread(path)
    test.assertGreater(img.shape[0] * img.shape[1], 10000)
    test.assertGreater(img[:, :, :3].std(), 0.05)  # not one colour


class Examples(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp()

    def tearDown(self):
        shutil.rmtree(self.dir)

    def test_run_and_plot(self):
        png = os.path.join(self.dir, "norm.png")
        out = example("run_and_plot.py", scene("region_load.iv"), "--until", "1", "-o", png)
        self.assertIn("surface0: 10 steps", out)
        assert_picture(self, png)

    @unittest.skipUnless(RUN, "bsdeform-run is not built")
    def test_sweep_gives_the_runners_sweep(self):
        png = os.path.join(self.dir, "sweep.png")
        out = example("sweep_sec7.py", scene("paper_sec7_central_square.iv"), "-o", png)
        assert_picture(self, png)
        got = {}
        for line in out.splitlines():
            if line.startswith("w10 = "):
                parts = line.split()
                got[float(parts[2])] = float(parts[4])
        self.assertEqual(len(got), 18)
        values = ",".join(repr(v) if v != int(v) else str(int(v)) for v in sorted(got))
        subprocess.run([RUN, scene("paper_sec7_central_square.iv"), "--until", "1", "--sweep",
                        "Surface.w10=" + values, "-o", os.path.join(self.dir, "run"), "--quiet"],
                       check=True, capture_output=True, timeout=600)
        with open(os.path.join(self.dir, "run", "sweep.csv")) as f:
            expected = {float(r["value"]): float(r["norm"]) for r in csv.DictReader(f)}
        self.assertEqual(got, expected)
        norms = [got[v] for v in sorted(got)]
        self.assertTrue(all(a >= b for a, b in zip(norms, norms[1:])))  # stiffer deforms less

    def test_build_and_render(self):
        png = os.path.join(self.dir, "cloth.png")
        out = example("build_and_render.py", "-o", png, "--until", "1")
        self.assertIn("Cloth: 50 steps", out)
        # the cloth is the SHELL cotton (issue 37, item 5), and its middle rests on the box's top (z = -0.1)
        self.assertIn("energy SHELL", out)
        lowest = float(out.split("lowest point over the box z = ")[1].split()[0])
        self.assertGreater(lowest, -0.12)
        self.assertLess(lowest, -0.05)
        assert_picture(self, png)

    @unittest.skipUnless(shutil.which("xvfb-run"), "xvfb-run is not installed")
    def test_soqt_viewer_with_a_slider(self):
        out = example("soqt_slider.py", scene("region_load.iv"), "--quit-after", "4",
                      wrapper=("xvfb-run", "-a", "-s", "-screen 0 1280x1024x24"))
        steps, t, w = out.split("steps ")[1].split(",")[0], None, out.split("w10 ")[1].split(",")[0]
        self.assertGreater(int(steps), 5)   # Coin's timer animated the surface in the viewer
        self.assertEqual(float(w), 100.0)  # the slider moved to its end set the weight

    @unittest.skipUnless(shutil.which("xvfb-run"), "xvfb-run is not installed")
    def test_soqt_slider_on_a_shell_sets_the_thickness(self):
        # issue 37, item 5: on a SHELL scene the slider bound to w10/w01 did nothing
        out = example("soqt_slider.py", scene("flag.iv"), "--quit-after", "4",
                      wrapper=("xvfb-run", "-a", "-s", "-screen 0 1280x1024x24"))
        self.assertIn("energy SHELL", out)
        steps = int(out.split("steps ")[1].split(",")[0])
        thickness = float(out.split("thickness ")[1].split(",")[0])
        self.assertGreater(steps, 5)
        self.assertAlmostEqual(thickness, 5e-3, places=12)  # the slider at its end: 5 mm


if __name__ == "__main__":
    unittest.main()
