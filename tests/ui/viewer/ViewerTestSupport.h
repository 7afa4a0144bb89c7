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
/// A non-interactive window showing `scene`, exposed on the screen; its clock moves only by
/// passTime() (ViewerClock::setWallClock(false)).
std::unique_ptr<bsdeform::MainWindow> makeWindow(const char* scene);
/// Lets `seconds` of the window's clock pass (it plays only when playing) in frames of 1/60 s,
/// each followed by Coin's sensor queue and Qt's events (the surfaces step, the window
/// refreshes and draws): no wall-clock time is waited for.
void passTime(bsdeform::MainWindow& w, double seconds);
/// Qt's and Coin's pending events, without letting time pass.
void processEvents();
/// The window's first surface (the test fails without one).
SoBSplineDeformSurface* firstSurface(bsdeform::MainWindow& w);
/// Writes a test's input file (a scene, a broken file) through the front ends' atomic writer;
/// the test fails when it cannot.
void writeFile(const QString& path, const QByteArray& contents);
/// Fraction of pixels that differ from the top-left corner's colour.
double nonBackgroundFraction(const QImage& img);

}  // namespace viewer_test
