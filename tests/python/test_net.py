# SPDX-License-Identifier: MIT
"""The control net as a NumPy array: shape, order and values match the .iv file."""
import re
import unittest

import numpy

import bsdeform
from support import scene


def field_values(text, field):
    """The numbers of `field [ ... ]` in .iv text, parsed here (not by Coin)."""
    m = re.search(r"\b%s\s*\[([^\]]*)\]" % field, text)
    return numpy.array([float(x) for x in m.group(1).replace(",", " ").split()])


class ControlNet(unittest.TestCase):
    def setUp(self):
        root = bsdeform.read_scene(scene("region_load.iv"))
        (self.surface,) = bsdeform.surfaces(root)
        self.surface.step(10)
        # the state as a file, read back: controlNet is in it
        self.text = bsdeform.scene_text(root)
        self.reread = bsdeform.read_scene_text(self.text)
        (self.resumed,) = bsdeform.surfaces(self.reread)

    def test_shape_dtype_and_order_match_the_file(self):
        net = self.surface.control_net()
        node = self.surface.node
        n1, n2 = node.numUControlPoints.getValue(), node.numVControlPoints.getValue()
        p1, p2 = node.uDegree.getValue(), node.vDegree.getValue()
        self.assertEqual(net.shape, (n1 + 2 * p1, n2 + 2 * p2, 3))
        self.assertEqual(net.dtype, numpy.float64)
        self.assertTrue(net.flags["C_CONTIGUOUS"])
        from_file = field_values(self.text, "controlNet").reshape(net.shape)
        # the file holds 15-digit values (snapped on writing): equal to that rounding
        numpy.testing.assert_allclose(net, from_file, rtol=1e-14, atol=1e-15)
        self.assertGreater(numpy.abs(net - self.surface.rest_net()).max(), 1e-4)  # it has moved

    def test_a_resumed_scene_gives_the_net_of_its_file(self):
        net = self.resumed.control_net()
        from_file = field_values(self.text, "controlNet").reshape(net.shape)
        # held points (clamped layers) are set to the rest net's, which the file rounds to 15
        # digits; the moving ones are the file's
        numpy.testing.assert_allclose(net, from_file, rtol=1e-14, atol=1e-15)
        n = self.resumed.node
        p1, p2 = n.uDegree.getValue(), n.vDegree.getValue()
        numpy.testing.assert_array_equal(net[p1:-p1, p2:-p2], from_file[p1:-p1, p2:-p2])
        # and pivy's view of the same field agrees
        values = numpy.array([list(v.getValue()) for v in n.controlNet.getValues()]).reshape(net.shape)
        numpy.testing.assert_array_equal(values[p1:-p1, p2:-p2], net[p1:-p1, p2:-p2])

    def test_the_array_is_a_snapshot_not_a_dangling_view(self):
        before = self.surface.control_net()
        copy = before.copy()
        self.surface.step(5)
        numpy.testing.assert_array_equal(before, copy)  # unchanged by stepping
        after = self.surface.control_net()
        self.assertGreater(numpy.abs(after - before).max(), 0.0)
        after[:] = 0.0  # writing to it does not touch the simulation
        self.assertGreater(numpy.abs(self.surface.control_net()).max(), 0.0)

    def test_evaluate_agrees_with_the_net(self):
        # at u = v = 0 a clamped surface sits at its held corner point S(0, 0) = (0, 0, 0)
        x, y, z = self.surface.evaluate(0.0, 0.0)
        self.assertAlmostEqual(x, 0.0, places=12)
        self.assertAlmostEqual(z, 0.0, places=12)


if __name__ == "__main__":
    unittest.main()
