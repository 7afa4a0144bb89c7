// SPDX-License-Identifier: MIT
#pragma once
/// @file AuthoredClock.h
/// The `on` and `speed` of each SoBSplineDeformSurface as the scene's author gave them.
///
/// A front end that drives the clock itself changes those fields at run time (the viewer's
/// Play / Pause and speed box, bsdeform-run, which steps the surfaces with `on FALSE`). Written
/// as they are, a paused viewer's save or the runner's final.iv would carry `on FALSE` and the
/// toolbar's speed, and the file would no longer animate in another Coin viewer. An
/// AuthoredClock remembers the authored values; an AuthoredClock::Scope puts them into the
/// fields for the time of a write (without notifying anyone: no timer starts or stops) and
/// restores the run-time values afterwards.
///
/// \code
/// bsdeform::AuthoredClock clock(root);    // right after reading
/// surface->on = FALSE;                     // the front end drives time
/// { bsdeform::AuthoredClock::Scope authored(clock); writeSceneText(root, sink); }
/// \endcode

#include <vector>

class SoField;
class SoNode;
class SoBSplineDeformSurface;

namespace bsdeform {

class AuthoredClock {
  /// One surface's clock fields, with their default flags (a default field is not written).
  struct Values {
    SoBSplineDeformSurface* surface;
    bool on, onDefault;
    float speed;
    bool speedDefault;
    static Values of(SoBSplineDeformSurface* surface);
    /// Puts these values into the surface's fields without notification.
    void apply() const;
  };

 public:
  AuthoredClock() = default;
  /// Remembers the current values of every surface under `root`.
  explicit AuthoredClock(SoNode* root);
  ~AuthoredClock();
  AuthoredClock(const AuthoredClock&) = delete;
  AuthoredClock& operator=(const AuthoredClock&) = delete;

  /// Remembers the current `on` and `speed` of every surface under `root` not yet known
  /// (surfaces already known keep their remembered values).
  void capture(SoNode* root);
  /// Forgets everything.
  void clear();
  /// The author changed `field` (e.g. in a field editor): if it is the `on` or `speed` of a
  /// known surface, its current value becomes the authored one. Returns whether it was.
  bool noteEdited(const SoField* field);
  /// The remembered `on` of `surface` (its current value if unknown).
  bool authoredOn(SoBSplineDeformSurface* surface) const;
  float authoredSpeed(SoBSplineDeformSurface* surface) const;

  /// While it lives, every known surface holds its authored `on` and `speed` (set without
  /// notification, the fields' default flags as they were); the destructor restores the
  /// run-time values the same way.
  class Scope {
   public:
    explicit Scope(const AuthoredClock& clock);
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    std::vector<Values> m_runTime;
  };

 private:
  std::vector<Values> m_entries;  ///< the surfaces are ref'ed: a deleted one may come back (undo)
  const Values* find(const SoBSplineDeformSurface* surface) const;
};

}  // namespace bsdeform
