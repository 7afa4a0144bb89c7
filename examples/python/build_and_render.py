#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Build a scene from code (a cloth, gravity, collision with a Cube), run it and render it
offscreen (no X server needed), to a PNG and as a NumPy image.

    python3 build_and_render.py -o cloth.png
"""
import argparse

from pivy import coin

import bsdeform

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("-o", "--output", default="cloth.png")
parser.add_argument("--until", type=float, default=2.0)
args = parser.parse_args()

root = coin.SoSeparator()

# The obstacle: an ordinary Cube, moved below the cloth.
cube_place = coin.SoSeparator()
move = coin.SoTranslation()
move.translation.setValue(0.5, 0.5, -0.4)
cube = coin.SoCube()
cube.width = cube.height = cube.depth = 0.6
material = coin.SoMaterial()
material.diffuseColor.setValue(0.8, 0.5, 0.2)
cube_place.addChild(move)
cube_place.addChild(material)
cube_place.addChild(cube)
root.addChild(cube_place)

# The cloth: free edges, gravity and contact with the Cube (SoForceField engines).
cloth = bsdeform.new_node("SoBSplineDeformSurface", numUControlPoints=20, numVControlPoints=20,
                          boundaryUMin="FREE", boundaryUMax="FREE", boundaryVMin="FREE", boundaryVMax="FREE",
                          massModel="LUMPED", damping=3.0, timeStep=0.02, w10=5, w01=5, w11=0.002, w20=0.002,
                          w02=0.002, on=False)
cloth.setName("Cloth")
gravity = bsdeform.new_node("SoForceField", type="GRAVITY", force=(0, 0, -9.81))
contact = bsdeform.new_node("SoForceField", type="COLLISION", thickness=0.015, stiffness=1e5, damping=0,
                            friction=0.3)
contact.obstacles.setValue(cube)
cloth.forces.setValues(0, [gravity, contact])
cloth_material = coin.SoMaterial()
cloth_material.diffuseColor.setValue(0.3, 0.55, 0.9)
root.addChild(cloth_material)
root.addChild(cloth)

history = bsdeform.run(root, until=args.until)["Cloth"]
print("Cloth: %d steps, t = %.3g, norm %.4g" % (history.step[-1], history.time[-1], history.norm[-1]))

bsdeform.render_png(root, args.output, 640, 480)
image = bsdeform.render(root, 640, 480)  # numpy uint8 (480, 640, 3)
print("wrote %s; mean colour %s" % (args.output, image.reshape(-1, 3).mean(axis=0).round(1)))
