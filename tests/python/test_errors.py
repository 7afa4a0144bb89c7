# SPDX-License-Identifier: MIT
"""Errors reach Python as exceptions whose message names the node, the field and the value."""
import os
import tempfile
import unittest

import bsdeform
from support import scene


class Errors(unittest.TestCase):
    def setUp(self):
        self.root = bsdeform.read_scene(scene("paper_fig2_point_force.iv"))
        (self.surface,) = bsdeform.surfaces(self.root)

    def test_a_refused_value_raises_field_error_at_the_next_step(self):
        self.surface.node.timeStep.setValue(-0.5)
        with self.assertRaises(bsdeform.FieldError) as cm:
            self.surface.step(1)
        msg = str(cm.exception)
        self.assertIn("SoBSplineDeformSurface 'Surface'", msg)
        self.assertIn("timeStep", msg)
        self.assertIn("-0.5", msg)
        self.assertIsInstance(cm.exception, ValueError)
        self.assertEqual(self.surface.step_count, 0)  # nothing was stepped
        self.surface.node.timeStep.setValue(0.1)  # fixed: steps again
        self.surface.step(1)
        self.assertEqual(self.surface.step_count, 1)

    def test_set_raises_at_once(self):
        with self.assertRaises(bsdeform.FieldError) as cm:
            self.surface.set(uDegree=9)
        self.assertIn("uDegree", str(cm.exception))
        self.assertIn("9", str(cm.exception))

    def test_unparsable_values_and_unknown_fields(self):
        with self.assertRaises(bsdeform.FieldError) as cm:
            bsdeform.set_field(self.surface.node, "integrator", "SIDEWAYS")
        self.assertIn("field 'integrator': 'SIDEWAYS' is not a valid value", str(cm.exception))
        with self.assertRaises(bsdeform.FieldError) as cm:
            bsdeform.set_field(self.surface.node, "stiffness", 1.0)
        self.assertIn("no field 'stiffness'", str(cm.exception))

    def test_a_bad_force_expression_names_the_force_field(self):
        push = [f for f in self.surface.node.forces.getValues()][0]
        bsdeform.set_field(push, "type", "EXPRESSION")
        bsdeform.set_field(push, "expression", ["0", "0", "sin(("])
        with self.assertRaises(bsdeform.FieldError) as cm:
            self.surface.step(1)
        self.assertIn("SoForceField", str(cm.exception))
        self.assertIn("sin((", str(cm.exception))

    def test_a_blow_up_raises_simulation_error_and_keeps_the_state_finite(self):
        push = self.surface.node.forces.getValues()[0]
        bsdeform.set_field(push, "type", "EXPRESSION")
        bsdeform.set_field(push, "expression", ["0", "0", "-1e7*z + 1"])
        with self.assertRaises(bsdeform.SimulationError) as cm:
            self.surface.step(200)
        self.assertIn("Surface", str(cm.exception))
        self.assertIn(self.surface.status, ("diverged", "nonfinite"))
        import numpy
        self.assertTrue(numpy.isfinite(self.surface.control_net()).all())
        with self.assertRaises(bsdeform.SimulationError):
            self.surface.step(1)  # stays stopped until reset
        self.surface.reset()
        self.assertEqual(self.surface.status, "ok")

    def test_unreadable_scenes(self):
        with self.assertRaises(bsdeform.SceneError) as cm:
            bsdeform.read_scene(scene("no_such_scene.iv"))
        self.assertIn("no_such_scene.iv", str(cm.exception))
        with self.assertRaises(bsdeform.SceneError) as cm:
            bsdeform.read_scene_text("#Inventor V2.1 ascii\nSeparator {\n  SoBSplineDeformSurface { uDegree x }\n}\n",
                                     name="broken.iv")
        self.assertIn("broken.iv", str(cm.exception))
        self.assertIn("uDegree", str(cm.exception))

    def test_wrong_objects_raise_type_error(self):
        from pivy import coin
        with self.assertRaises(TypeError) as cm:
            bsdeform.Surface(coin.SoCube())
        self.assertIn("SoBSplineDeformSurface", str(cm.exception))
        self.assertIn("Cube", str(cm.exception))
        with self.assertRaises(TypeError):
            bsdeform.Surface(42)
        with self.assertRaises(TypeError):
            bsdeform.render("scene")

    def test_render_errors(self):
        with self.assertRaises(bsdeform.RenderError) as cm:
            bsdeform.render(self.root, 0, 10)
        self.assertIn("0 x 10", str(cm.exception))
        with tempfile.TemporaryDirectory() as d:
            with self.assertRaises(bsdeform.RenderError) as cm:
                bsdeform.render_png(self.root, os.path.join(d, "missing", "x.png"), 32, 32)
            self.assertIn("x.png", str(cm.exception))

    def test_negative_steps(self):
        with self.assertRaises(ValueError):
            self.surface.step(-1)


if __name__ == "__main__":
    unittest.main()
