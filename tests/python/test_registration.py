# SPDX-License-Identifier: MIT
"""`import bsdeform` registers the nodes in pivy's Coin without dlopen flags, in either order.

Each case runs in a fresh interpreter (registration happens once per process). Coin's dynamic
node loading is switched off (COIN_NO_SOTYPE_DYNLOAD) so that an installed plugin cannot make
the test pass: the nodes must come from the import.
"""
import os
import subprocess
import sys
import unittest

SCENE = """#Inventor V2.1 ascii
Separator { DEF Surf SoBSplineDeformSurface { numUControlPoints 6 on FALSE
  forces SoForceField { type UNIFORM force 0 0 5 } } }
"""

READ_WITH_PIVY = """
from pivy import coin
inp = coin.SoInput()
inp.setBuffer(%r)
root = coin.SoDB.readAll(inp)
if root is None:
    print("READ FAILED")
else:
    root.ref()
    node = coin.SoBase.getNamedBase(coin.SbName("Surf"), coin.SoNode.getClassTypeId())
    print("TYPE", node.getTypeId().getName().getString(), node.numUControlPoints.getValue())
""" % SCENE


def run(code):
    env = dict(os.environ, COIN_NO_SOTYPE_DYNLOAD="1")
    env.pop("LD_LIBRARY_PATH", None)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
    return r.returncode, r.stdout, r.stderr


class Registration(unittest.TestCase):
    def test_without_bsdeform_pivy_cannot_read_the_scene(self):
        code, out, err = run(READ_WITH_PIVY)
        self.assertEqual(code, 0, err)
        self.assertIn("READ FAILED", out)
        self.assertIn("SoBSplineDeformSurface", err)  # Coin: node type ... not recognized

    def test_bsdeform_imported_before_pivy(self):
        code, out, err = run("import bsdeform\n" + READ_WITH_PIVY)
        self.assertEqual(code, 0, err)
        self.assertIn("TYPE SoBSplineDeformSurface 6", out)

    def test_bsdeform_imported_after_pivy(self):
        code, out, err = run("from pivy import coin\nimport bsdeform\n" + READ_WITH_PIVY)
        self.assertEqual(code, 0, err)
        self.assertIn("TYPE SoBSplineDeformSurface 6", out)

    def test_no_dlopen_flags_are_set(self):
        code, out, err = run("import os, sys\nflags = sys.getdlopenflags()\nimport bsdeform\n"
                             "print('SAME', sys.getdlopenflags() == flags, bool(flags & os.RTLD_GLOBAL))")
        self.assertEqual(code, 0, err)
        self.assertIn("SAME True False", out)

    def test_the_node_pivy_returns_is_the_surface_the_module_works_on(self):
        code, out, err = run("import bsdeform\n" + READ_WITH_PIVY + """
s = bsdeform.Surface(node)
s.step(3)
print("STEPS", node.stepCount.getValue(), s.step_count, int(s.node.this) == int(node.this))
node.timeStep.setValue(0.05)  # a field set through pivy reaches the model
print("DT", s.time_step)
""")
        self.assertEqual(code, 0, err)
        self.assertIn("STEPS 3 3 True", out)
        self.assertIn("DT 0.05", out)


if __name__ == "__main__":
    unittest.main()
