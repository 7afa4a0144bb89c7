// SPDX-License-Identifier: MIT
#pragma once
/// @file RunSetup.h
/// What a run and a sweep both do before they start: read the scene, apply --set, prepare the
/// output directory.

#include "RunFailure.h"
#include "bsdeform/NodeRef.h"

class SoSeparator;

namespace bsdeform::run {

struct RunOptions;

/// Reads the scene at `path` into `root` with the guarded reader (bsdeform/SceneReader.h); a
/// missing, unreadable or malformed file is bad input with the reason.
Failure loadScene(const QString& path, NodeRef<SoSeparator>& root);

/// NAME.field=value: sets the field of the node or engine DEF'ed as NAME in the scene read last.
Failure applySet(const QString& spec);

/// Reads the scene of `options` and applies its --set options.
Failure loadSceneWithSets(const RunOptions& options, NodeRef<SoSeparator>& root);

/// Makes the output directory (new, empty, or --overwrite) and checks that it is writable.
Failure prepareOutDir(const RunOptions& options);

/// The progress bar on stderr (only when stderr is a terminal, and not --quiet or a sweep child).
class ProgressBar {
 public:
  explicit ProgressBar(const RunOptions& options);
  /// Shows `done` of `total`, and the time `t`; redraws only when the percentage changes.
  void show(long done, long total, double t);

 private:
  bool m_visible;
  int m_last = -1;
};

}  // namespace bsdeform::run
