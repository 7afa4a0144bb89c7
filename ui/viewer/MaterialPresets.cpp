// SPDX-License-Identifier: MIT
#include "MaterialPresets.h"

#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

const std::vector<MaterialPreset>& materialPresets() {
  // Denim and silk are not here: no source giving E, ν, t and ρ of one measured fabric was found
  // (docs/nodes.md, "Named materials", says what was looked at and why it was not used).
  static const std::vector<MaterialPreset> presets = {
      {"Cotton cloth", 0.821e6, 0.243, 0.318e-3, 472.6,
       "100 % cotton plain-woven fabric of Penava, Šimić Penava, Nakić 2014, \"Determination of the "
       "elastic constants of plain woven fabrics by a tensile test in various directions\" (Fibres & "
       "Textiles in Eastern Europe): 150.3 g/m² and 0.318 mm (their Table 1), E = 0.821 MPa (their "
       "Table 3), ν = 0.243; ρ = 150.3 g/m² / 0.318 mm; read second-hand, as C-IPC's cotton "
       "(ipc-sim/Codim-IPC), see docs/nodes.md"},
      {"Rubber sheet (1 mm)", 1.495e6, 0.495, 1e-3, 950.0,
       "natural rubber, vulcanized: density 0.950 g/cm³ and shear modulus G = 0.5 MPa from MatWeb's "
       "datasheet \"Natural Rubber, Vulcanized (NR, IR, Polyisoprene)\"; ν = 0.495 as the Altair "
       "Radioss reference guide (\"Poisson's ratio\", 2022.1) advises for nearly incompressible "
       "materials (its table: rubber 0.48 – ~0.5); E = 2G(1 + ν); thickness 1 mm our choice"},
      {"Steel plate (1 mm)", 210e9, 0.3, 1e-3, 7850.0,
       "structural steel: E = 210 GPa, ν = 0.3 (EN 1993-1-1 §3.2.6), ρ = 7850 kg/m³ "
       "(EN 1991-1-1 Annex A); thickness 1 mm our choice"},
      {"Aluminium plate (1 mm)", 70e9, 0.3, 1e-3, 2700.0,
       "aluminium alloys: E = 70 GPa, ν = 0.3, ρ = 2700 kg/m³ (EN 1999-1-1 §3.2.5); "
       "thickness 1 mm our choice"},
  };
  return presets;
}

void applyMaterialPreset(SoBSplineDeformSurface* surface, const MaterialPreset& preset) {
  surface->energy = SoBSplineDeformSurface::SHELL;
  surface->youngsModulus = preset.youngsModulus;
  surface->poissonRatio = preset.poissonRatio;
  surface->thickness = preset.thickness;
  surface->density = preset.density;
}

}  // namespace bsdeform
