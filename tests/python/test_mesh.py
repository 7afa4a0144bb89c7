# SPDX-License-Identifier: MIT
"""bsdeform.export_mesh: the surfaces' triangles as OBJ and STL, as bsdeform-run --export-mesh."""
import os
import struct
import tempfile
import unittest

import bsdeform
from support import scene


def obj_counts(path):
    objects, vertices, faces = [], 0, 0
    with open(path) as f:
        for line in f:
            tag = line.split(" ", 1)[0]
            if tag == "o":
                objects.append(line[2:].strip())
            vertices += tag == "v"
            faces += tag == "f"
    return objects, vertices, faces


class ExportMesh(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.dir.cleanup()

    def path(self, name):
        return os.path.join(self.dir.name, name)

    def test_a_scene_gives_one_object_per_surface_and_the_stl_the_same_triangles(self):
        root = bsdeform.read_scene(scene("pressed_surfaces.iv"))
        bsdeform.export_mesh(root, self.path("both.obj"))
        objects, vertices, faces = obj_counts(self.path("both.obj"))
        self.assertEqual(objects, ["Lower", "Upper"])
        self.assertGreater(vertices, 0)
        bsdeform.export_mesh(root, self.path("both.STL"))
        with open(self.path("both.STL"), "rb") as f:
            data = f.read()
        (count,) = struct.unpack("<I", data[80:84])
        self.assertEqual(count, faces)
        self.assertEqual(len(data), 84 + 50 * count)

    def test_a_surface_alone(self):
        root = bsdeform.read_scene(scene("region_load.iv"))
        (surface,) = bsdeform.surfaces(root)
        surface.step(2)
        bsdeform.export_mesh(surface, self.path("one.obj"))
        bsdeform.export_mesh(surface.node, self.path("two.obj"))
        objects, vertices, faces = obj_counts(self.path("one.obj"))
        self.assertEqual(len(objects), 1)
        self.assertEqual(faces, 2 * 41 * 41)  # the tessellation of the 24 x 24 net (as bsdeform-run's)
        self.assertEqual(vertices, 42 * 42)
        with open(self.path("one.obj")) as a, open(self.path("two.obj")) as b:
            self.assertEqual(a.read(), b.read())

    def test_a_failure_names_the_file_and_keeps_the_old_one(self):
        root = bsdeform.read_scene(scene("region_load.iv"))
        with open(self.path("mesh.ply"), "w") as f:
            f.write("keep")
        with self.assertRaises(bsdeform.Error) as e:
            bsdeform.export_mesh(root, self.path("mesh.ply"))
        self.assertIn("mesh.ply: unknown mesh format 'ply'", str(e.exception))
        with open(self.path("mesh.ply")) as f:
            self.assertEqual(f.read(), "keep")
        with self.assertRaises(bsdeform.Error) as e:
            bsdeform.export_mesh(root, self.path("missing/mesh.obj"))
        self.assertIn("cannot write '%s': No such file or directory" % self.path("missing/mesh.obj"), str(e.exception))
        with self.assertRaises(bsdeform.Error) as e:
            bsdeform.export_mesh(bsdeform.new_node("Cube"), self.path("cube.obj"))
        self.assertIn("holds no SoBSplineDeformSurface", str(e.exception))
        with self.assertRaises(TypeError):
            bsdeform.export_mesh(5, self.path("x.obj"))


if __name__ == "__main__":
    unittest.main()
