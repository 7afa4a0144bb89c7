#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A pivy SoQt examiner viewer on a scene, with a slider bound to the surface's stiffness.

The surface animates itself with Coin's timer (its field `on`), as in any Coin viewer; moving
the slider sets the stiffness and the next step uses it: for a SHELL surface (cloth, plates) the
sheet's thickness, 0.05 mm to 5 mm (membrane stiffness grows with t, bending with t^3); for the
paper's energy the weights w10 and w01 together. Needs a display (or xvfb-run).

    python3 soqt_slider.py scenes/flag.iv
    python3 soqt_slider.py scenes/flag.iv --quit-after 3   # closes itself (tests)
"""
import argparse
import math
import sys

from pivy import coin
from pivy.gui import soqt
from PySide2 import QtCore, QtWidgets

import bsdeform

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("scene")
parser.add_argument("--quit-after", type=float, default=0, help="seconds; 0: run until closed")
args = parser.parse_args()

window = soqt.SoQt.init(sys.argv[0])  # the QApplication and a top-level QWidget (PySide2)
root = bsdeform.read_scene(args.scene)
surface = bsdeform.surfaces(root)[0]
node = surface.node

panel = QtWidgets.QWidget(window)
layout = QtWidgets.QVBoxLayout(panel)
view_area = QtWidgets.QWidget(panel)
view_area.setMinimumSize(640, 480)
layout.addWidget(view_area, 1)
label = QtWidgets.QLabel(panel)
slider = QtWidgets.QSlider(QtCore.Qt.Horizontal, panel)
slider.setRange(0, 100)
shell = node.energy.getValue() == 1  # SHELL


# slider position <-> value, logarithmic: thickness 5e-5 .. 5e-3 m (SHELL), weight 0.01 .. 100
def value_at(position):
    return 5e-5 * 10 ** (position / 50.0) if shell else 10 ** (position / 25.0 - 2)


def position_of(value):
    if shell:
        return int(round(50 * math.log10(min(max(value, 5e-5), 5e-3) / 5e-5)))
    return int(round(25 * (2 + math.log10(min(max(value, 0.01), 100)))))
layout.addWidget(label)
layout.addWidget(slider)
window_layout = QtWidgets.QVBoxLayout(window)
window_layout.setContentsMargins(0, 0, 0, 0)
window_layout.addWidget(panel)


def setting():
    if shell:
        return "thickness %.4g mm" % (1000 * node.thickness.getValue())
    return "w10 = w01 = %.4g" % node.w10.getValue()


def show_state():
    # simulationTime and stepCount are live fields: current after every step
    label.setText("%s   (t = %.2f, steps %d)" % (setting(), node.simulationTime.getValue(), node.stepCount.getValue()))


def set_stiffness(position):
    v = value_at(position)
    # a refused value would raise bsdeform.FieldError here
    if shell:
        surface.set(thickness=v)
    else:
        surface.set(w10=v, w01=v)
    show_state()


slider.setValue(position_of(node.thickness.getValue() if shell else node.w10.getValue()))
slider.valueChanged.connect(set_stiffness)
show_state()

viewer = soqt.SoQtExaminerViewer(view_area)
viewer.setSceneGraph(root)
viewer.viewAll()
viewer.show()

timer = QtCore.QTimer()
timer.timeout.connect(show_state)
timer.start(200)

if args.quit_after > 0:
    def quit_now():
        print("steps %d, t = %.3g, w10 %.4g, thickness %.4g, energy %s" % (
            node.stepCount.getValue(), node.simulationTime.getValue(), node.w10.getValue(),
            node.thickness.getValue(), "SHELL" if shell else "PAPER"))
        soqt.SoQt.exitMainLoop()
    QtCore.QTimer.singleShot(int(args.quit_after * 1000), quit_now)
    # and move the slider once, as a user would
    QtCore.QTimer.singleShot(int(args.quit_after * 500), lambda: slider.setValue(slider.maximum()))

soqt.SoQt.show(window)
soqt.SoQt.mainLoop()
