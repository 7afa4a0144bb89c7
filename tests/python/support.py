# SPDX-License-Identifier: MIT
"""Paths the Python tests get from CTest (tests/CMakeLists.txt)."""
import os

SCENES = os.environ["BSDEFORM_SCENES_DIR"]
RUN = os.environ.get("BSDEFORM_RUN", "")  # bsdeform-run, when the front ends are built


def scene(name):
    return os.path.join(SCENES, name)
