// SPDX-License-Identifier: MIT
#pragma once
/// @file StateFile.h
/// The file of kept states that bsdeform-run writes (--keep-states) and the viewer opens
/// (--states, File > Open States): for each surface of the scene its DEF name and the size of
/// its net, then frames of every surface's state (StateHistory.h) as the same bits.
///
/// Layout: the text line "bsdeform-states <version>\n" (version 1), then a QDataStream (Qt 5.12
/// format, little-endian, doubles): quint32 surfaces; per surface QString name ("" without a DEF
/// name), qint32 net points; quint64 frames; per frame double time and per surface double time,
/// qint64 steps, double sub-step, bool start pending, then the current and the previous net,
/// points × 3 doubles each, u-major.

#include <QString>
#include <vector>

#include "StateHistory.h"

namespace bsdeform {

/// What a state file says about one surface.
struct StateFileSurface {
  QString name;      ///< DEF name, "" when it has none
  int netPoints = 0; ///< rows of its nets
  bool operator==(const StateFileSurface& o) const { return name == o.name && netPoints == o.netPoints; }
};

struct StateFileContents {
  std::vector<StateFileSurface> surfaces;
  std::vector<StateFrame> frames;  ///< times increasing
};

/// The surfaces of `frame` as a state file names them: `defNames` (in order, "" for none) and
/// the sizes of the frame's nets.
std::vector<StateFileSurface> fileSurfacesOf(const std::vector<QString>& defNames, const StateFrame& frame);

/// The version written and the only one read.
constexpr int kStateFileVersion = 1;

/// Writes `surfaces` and the frames of `history` to `path` atomically (AtomicFile.h); on
/// failure the old file is whole and `error` names the file and the reason.
bool writeStateFile(const QString& path, const std::vector<StateFileSurface>& surfaces, const StateHistory& history,
                    QString& error);
/// Reads a state file. A file that is not one, of another version, truncated or inconsistent
/// (a net of the wrong size, times that do not increase) is refused: false, and `error` names
/// the file, the entry and the value.
bool readStateFile(const QString& path, StateFileContents& contents, QString& error);
/// Why the states of `file` (read from `path`) do not fit a scene whose surfaces are `scene`
/// (their number, order, DEF names and net sizes must be the same); "" when they fit.
QString stateFileMismatch(const QString& path, const std::vector<StateFileSurface>& file,
                          const std::vector<StateFileSurface>& scene);

}  // namespace bsdeform
