// SPDX-License-Identifier: MIT
#pragma once
/// @file MaterialPresets.h
/// Named SHELL materials — Young's modulus, Poisson's ratio, thickness, density — each with the
/// source of its values: the one table behind the viewer's Insert > Surface presets and
/// docs/nodes.md's "Named materials" table (tests/ui/viewer/Editing_test.cpp checks that the two
/// agree). Only values with a source that can be named are here; a thickness that is our own
/// choice (the plates, the rubber sheet) says so in its name and source.

#include <vector>

class SoBSplineDeformSurface;

namespace bsdeform {

/// One named material for `energy SHELL` (docs/math.md §16), in SI units.
struct MaterialPreset {
  const char* name;      ///< as the menu shows it, e.g. "Steel plate (1 mm)"
  double youngsModulus;  ///< E (Pa)
  double poissonRatio;   ///< ν, in [0, 0.5)
  double thickness;      ///< t (m)
  double density;        ///< ρ (kg/m³)
  const char* source;    ///< where E, ν, t and ρ come from (one line, English)
};

/// Every preset, in menu order.
const std::vector<MaterialPreset>& materialPresets();

/// Makes `surface` a SHELL of `preset`'s material: sets `energy` to SHELL and `youngsModulus`,
/// `poissonRatio`, `thickness`, `density` to the preset's values; no other field changes.
void applyMaterialPreset(SoBSplineDeformSurface* surface, const MaterialPreset& preset);

}  // namespace bsdeform
