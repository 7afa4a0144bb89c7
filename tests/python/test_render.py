# SPDX-License-Identifier: MIT
"""Offscreen rendering through the EGL renderer, to NumPy and PNG (no X server needed)."""
import os
import tempfile
import unittest

import numpy

import bsdeform
from support import scene

BACKGROUND = (0.0, 0.0, 0.0)


class Render(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        os.environ.pop("DISPLAY", None)  # the EGL route works without X
        cls.root = bsdeform.read_scene(scene("region_load.iv"))
        bsdeform.surfaces(cls.root)[0].step(15)

    @classmethod
    def tearDownClass(cls):
        del cls.root

    def test_image_shows_the_surface(self):
        img = bsdeform.render(self.root, 320, 240, background=BACKGROUND)
        self.assertEqual(img.shape, (240, 320, 3))
        self.assertEqual(img.dtype, numpy.uint8)
        lit = (img.max(axis=2) > 20).mean()
        self.assertGreater(lit, 0.05)  # the surface covers part of the picture ...
        self.assertLess(lit, 0.95)     # ... and the background the rest
        self.assertGreater(img.std(), 10.0)

    def test_background_colour_is_used(self):
        img = bsdeform.render(self.root, 64, 48, background=(1.0, 0.0, 0.0))
        self.assertEqual(tuple(img[0, 0]), (255, 0, 0))

    def test_png_matches_the_array(self):
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.image
        img = bsdeform.render(self.root, 160, 120, background=BACKGROUND)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "frame.png")
            bsdeform.render_png(self.root, path, 160, 120, background=BACKGROUND)
            png = matplotlib.image.imread(path)
        numpy.testing.assert_array_equal((png[:, :, :3] * 255).round().astype(numpy.uint8), img)

    def test_the_picture_changes_as_the_surface_moves(self):
        root = bsdeform.read_scene(scene("region_load.iv"))
        first = bsdeform.render(root, 160, 120).astype(int)
        bsdeform.surfaces(root)[0].step(25)
        second = bsdeform.render(root, 160, 120).astype(int)
        self.assertGreater(numpy.abs(second - first).sum(), 1000)


if __name__ == "__main__":
    unittest.main()
