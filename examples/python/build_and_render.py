#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Build a scene from code (a cotton cloth, gravity, collision with a Cube), run it and render it
offscreen (no X server needed), to a PNG and as a NumPy image.

The cloth is a SHELL (Kirchhoff-Love thin shell) of cotton: Young's modulus 0.821 MPa, Poisson's
ratio 0.243, 0.318 mm thick, 472.6 kg/m^3, the values of scenes/cloth_on_cube.iv. (The paper's
energy, PAPER with weights w10..w02, makes a cloth with a stiff brim; docs/nodes.md.)

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

# The cloth, 1 m square: free edges, cotton (SI units), gravity and contact with the Cube
# (SoForceField engines; their vectors are in the world).
cloth = bsdeform.new_node("SoBSplineDeformSurface", numUControlPoints=16, numVControlPoints=16,
                          boundaryUMin="FREE", boundaryUMax="FREE", boundaryVMin="FREE", boundaryVMax="FREE",
                          energy="SHELL", youngsModulus=0.821e6, poissonRatio=0.243, thickness=0.318e-3,
                          density=472.6, damping=1.0, timeStep=0.02, on=False)
cloth.setName("Cloth")
gravity = bsdeform.new_node("SoForceField", type="GRAVITY", force=(0, 0, -9.81))
contact = bsdeform.new_node("SoForceField", type="COLLISION", thickness=0.015, stiffness=20000, damping=0,
                            friction=0.3)
contact.obstacles.setValue(cube)
cloth.forces.setValues(0, [gravity, contact])
cloth_material = coin.SoMaterial()
cloth_material.diffuseColor.setValue(0.3, 0.55, 0.9)
root.addChild(cloth_material)
root.addChild(cloth)

history = bsdeform.run(root, until=args.until)["Cloth"]
(surface,) = bsdeform.surfaces(root)
net = surface.control_net()
# the middle of the cloth (0.35 .. 0.65 in x and y) rests on the box's top, at z = -0.1
over = (abs(net[..., 0] - 0.5) < 0.15) & (abs(net[..., 1] - 0.5) < 0.15)
print("Cloth: %d steps, t = %.3g, norm %.4g, energy %s, lowest point over the box z = %.3f" % (
    history.step[-1], history.time[-1], history.norm[-1], "SHELL" if cloth.energy.getValue() == 1 else "PAPER",
    net[..., 2][over].min()))

bsdeform.render_png(root, args.output, 640, 480)
image = bsdeform.render(root, 640, 480)  # numpy uint8 (480, 640, 3)
print("wrote %s; mean colour %s" % (args.output, image.reshape(-1, 3).mean(axis=0).round(1)))
