# SPDX-License-Identifier: MIT
# Run by deb_install_test.sh as `freecad freecad_macro.py` in the throw-away root: FreeCAD
# opens an installed scene through Coin's dynamic node loading alone (bsdeform is not
# imported), then the GUI runs for a few seconds and the surface's live stepCount field, read
# generically through pivy, must have advanced. Writes the result to freecad.out.
import os
import time

import FreeCAD
import FreeCADGui
from PySide2 import QtWidgets
from pivy import coin

out = open("/tmp/bsdeform-test/freecad.out", "w")
try:
    doc = FreeCAD.newDocument("Scene")
    FreeCADGui.insert("/usr/share/bsdeform/scenes/region_load.iv", doc.Name)
    graph = FreeCADGui.ActiveDocument.ActiveView.getSceneGraph()
    search = coin.SoSearchAction()
    search.setType(coin.SoType.fromName("SoBSplineDeformSurface"))
    search.setSearchingAll(True)
    search.apply(graph)
    path = search.getPath()
    if path is None:
        out.write("no SoBSplineDeformSurface in FreeCAD's scene graph\n")
    else:
        node = path.getTail()
        out.write("type %s\n" % node.getTypeId().getName().getString())
        start = time.time()
        while time.time() - start < 4.0:  # FreeCAD's event loop drives Coin's timer
            QtWidgets.QApplication.processEvents()
            time.sleep(0.01)
        out.write("steps %d time %.2f\n" % (node.getField("stepCount").getValue(),
                                           node.getField("simulationTime").getValue()))
except Exception:
    import traceback
    out.write("ERROR " + traceback.format_exc())
out.close()
# Closing the window would ask whether to save the document (a modal dialog): leave at once.
os._exit(0)
