// SPDX-License-Identifier: MIT
#pragma once
// What the viewer's window tests share: the application, a window showing a scene.

#include <QString>
#include <memory>

#include "MainWindow.h"

class SoBSplineDeformSurface;

namespace bsdeform::test {

/// The QApplication with SoQt and the nodes, once per process; autosaves and settings go to a
/// temporary home. A SoQt fatal error aborts the test instead of opening a dialog.
void ensureApp();
/// A file of scenes/.
QString scenePath(const char* name);
/// A shown, non-interactive window with `scene` (a file of scenes/) open.
std::unique_ptr<MainWindow> makeWindow(const char* scene);
SoBSplineDeformSurface* firstSurface(MainWindow& w);

}  // namespace bsdeform::test
