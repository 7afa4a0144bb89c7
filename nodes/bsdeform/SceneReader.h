// SPDX-License-Identifier: MIT
#pragma once
/// @file SceneReader.h
/// The one way our programs read a scene: a guard in front of Coin 4.0's reader that refuses,
/// with the file, line and reason, the constructs known to crash, hang or exhaust Coin's reader
/// (docs/reliability.md lists each with the Coin function at fault), then SoDB::readAll with
/// Coin's read errors collected into the message. Its parts (not installed): SceneLexer.h (tokens),
/// SceneGuard.h (one function per hazard, and the scan checkSceneText); SceneReader.cpp reads.

#include <cstddef>
#include <string>
#include <vector>

class SoSeparator;
class SoNode;
class SoBSplineDeformSurface;

namespace bsdeform {

/// Limits of the guard (docs/reliability.md says why each value).
struct SceneLimits {
  std::size_t maxWordLength = 65000;       ///< run of non-blank characters (names, identifiers, numbers)
  std::size_t maxStringLength = 65000;     ///< quoted string (may become an SbName)
  int maxNesting = 1000;                   ///< nodes/engines inside each other, across File includes
  std::size_t maxFileBytes = std::size_t(1) << 30;  ///< a scene file (or included file)
};

/// Why a text was refused: where and what. `ok` when the guard found nothing.
struct SceneCheck {
  bool ok = true;
  std::string file;  ///< the file (or buffer name) the problem is in; an included file's own path
  int line = 0;      ///< 1-based line of the offending token
  std::string reason;
  /// "FILE:LINE: REASON"
  std::string message() const;
};

/// Scans Inventor/VRML ASCII text without building anything. `name` is used in messages;
/// `directory` resolves `File { name "…" }` includes (checked recursively, they reach Coin's
/// reader too). Needs SoDB::init() and initNodes() (it asks Coin which types are built in).
SceneCheck checkSceneText(const char* data, std::size_t size, const std::string& name,
                          const std::string& directory = std::string(), const SceneLimits& limits = SceneLimits());

/// Where `text` says `USE NAME,` (a reference followed by a list's comma with no space between,
/// as people write `obstacles [ USE A, USE B ]` and as Coin 4.0's writer lays out a list of
/// references), Coin's reader takes "NAME," as the name and fails. Unless the text DEFs a name
/// with that comma, this puts a space before the comma: `out` gets the separated text and the
/// number of commas separated is returned (0: nothing to do, `out` untouched). Lines do not move.
std::size_t separateUseCommas(const char* text, std::size_t size, std::string& out,
                              const SceneLimits& limits = SceneLimits());

/// Guard + Coin's reader on a text in memory (after separateUseCommas). Returns the root (refcount 0) or nullptr with
/// `error` set to "NAME:LINE: reason" or "NAME: Coin's read errors".
SoSeparator* readSceneText(const char* data, std::size_t size, const std::string& name, std::string& error,
                           const std::string& directory = std::string(), const SceneLimits& limits = SceneLimits());

/// Reads the file at `path` (bytes first: a directory, a missing or unreadable file is named with
/// the system's reason), then readSceneText with the file's directory for includes.
SoSeparator* readSceneFile(const std::string& path, std::string& error, const SceneLimits& limits = SceneLimits());

/// The distinct SoBSplineDeformSurface nodes under `root`, depth first (a surface USEd twice is
/// listed once).
std::vector<SoBSplineDeformSurface*> sceneSurfaces(SoNode* root);

}  // namespace bsdeform
