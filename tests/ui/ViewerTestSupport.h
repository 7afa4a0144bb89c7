// SPDX-License-Identifier: MIT
#pragma once
// What every test of bsdeform-viewer's window needs: one QApplication with SoQt and our nodes,
// settings and autosaves kept out of the user's home (XDG_DATA_HOME, XDG_CONFIG_HOME), and a shown window with a scene.
#include <QByteArray>
#include <QImage>
#include <QString>
#include <memory>

#include "MainWindow.h"

class SoBSplineDeformSurface;

namespace viewer_test {

/// Creates the application once (QApplication, SoQt, nodes; a failing GL canvas aborts).
void ensureApp();
/// Path of a file in scenes/.
QString scenePath(const char* name);
/// A non-interactive window showing `scene`, exposed on the screen.
std::unique_ptr<bsdeform::MainWindow> makeWindow(const char* scene);
/// The window's first surface (the test fails without one).
SoBSplineDeformSurface* firstSurface(bsdeform::MainWindow& w);
/// Writes a test's input file (a scene, a broken file) through the front ends' atomic writer;
/// the test fails when it cannot.
void writeFile(const QString& path, const QByteArray& contents);
/// Fraction of pixels that differ from the top-left corner's colour.
double nonBackgroundFraction(const QImage& img);

}  // namespace viewer_test
