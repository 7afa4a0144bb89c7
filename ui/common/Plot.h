// SPDX-License-Identifier: MIT
#pragma once
/// @file Plot.h
/// Line plots rendered to PNG with Qt Charts (needs a QApplication; headless programs use the
/// offscreen platform).

#include <QString>
#include <QVector>

namespace bsdeform {

struct PlotSeries {
  QString name;
  QVector<double> x, y;
};

/// Draws the series as lines with points and writes a PNG (atomically). Returns false with a
/// message naming the file on failure.
bool writePlotPng(const QString& path, const QString& title, const QString& xLabel, const QString& yLabel,
                  const QVector<PlotSeries>& series, int width, int height, QString& error);

}  // namespace bsdeform
