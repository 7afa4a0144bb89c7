#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A pivy SoQt examiner viewer on a scene, with a slider bound to a weight of the surface.

The surface animates itself with Coin's timer (its field `on`), as in any Coin viewer; moving
the slider sets the weight (w10 and w01 together: the membrane stiffness) and the next step
uses it. Needs a display (or xvfb-run).

    python3 soqt_slider.py scenes/region_load.iv
    python3 soqt_slider.py scenes/region_load.iv --quit-after 3   # closes itself (tests)
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
slider.setRange(0, 100)  # w = 10^(slider/25 - 2): 0.01 .. 100
layout.addWidget(label)
layout.addWidget(slider)
window_layout = QtWidgets.QVBoxLayout(window)
window_layout.setContentsMargins(0, 0, 0, 0)
window_layout.addWidget(panel)


def show_state():
    # simulationTime and stepCount are live fields: current after every step
    label.setText("w10 = w01 = %.4g   (t = %.2f, steps %d)" % (
        node.w10.getValue(), node.simulationTime.getValue(), node.stepCount.getValue()))


def set_weight(position):
    w = 10 ** (position / 25.0 - 2)
    surface.set(w10=w, w01=w)  # a refused value would raise bsdeform.FieldError here
    show_state()


slider.setValue(int(round(25 * (2 + math.log10(min(max(node.w10.getValue(), 0.01), 100))))))
slider.valueChanged.connect(set_weight)
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
        print("steps %d, t = %.3g, w10 %.4g" % (node.stepCount.getValue(), node.simulationTime.getValue(),
                                                node.w10.getValue()))
        soqt.SoQt.exitMainLoop()
    QtCore.QTimer.singleShot(int(args.quit_after * 1000), quit_now)
    # and move the slider once, as a user would
    QtCore.QTimer.singleShot(int(args.quit_after * 500), lambda: slider.setValue(slider.maximum()))

soqt.SoQt.show(window)
soqt.SoQt.mainLoop()
