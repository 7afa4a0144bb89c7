// SPDX-License-Identifier: MIT
#pragma once
/// @file FieldInfo.h
/// What each field of SoBSplineDeformSurface and SoForceField means: one table behind the
/// viewer's field editor (tooltips, spin box ranges, which fields a force type shows) and the
/// field reference in docs/nodes.md (fieldReferenceMarkdown(); a test keeps the document equal
/// to it).

#include <string>
#include <vector>

namespace bsdeform {

struct FieldInfo {
  const char* node;     ///< "SoBSplineDeformSurface" or "SoForceField"
  const char* name;     ///< the field, as the .iv keyword
  const char* meaning;  ///< one or two sentences
  const char* unit;     ///< "" when dimensionless or not a quantity
  const char* symbol;   ///< the paper's symbol (González-Hidalgo, Mir and Nicolau), "" when none
  const char* range;    ///< the valid values as text ("> 0", "1..7", "(u, v) in [0, 1]²"), "" when any
  double min, max;      ///< a number's (each component's) bounds for an editor; ±HUGE_VAL when open
  /// SoForceField: bit (1 << SoForceField::Type) set for each type that reads the field; 0
  /// for every type (type, on). SoBSplineDeformSurface: bit (1 << energy) for each energy
  /// model (PAPER, SHELL) that reads it; 0 for both
  unsigned usedBy;
  bool restarts;  ///< a change rebuilds the net: the simulation starts again from rest
  bool live;      ///< state the node keeps current; shown, not edited
  /// The core's name of the parameter the field sets (bsdeform::ParameterError::parameter())
  /// when it is not the field's own name ("numU" for numUControlPoints); nullptr otherwise
  const char* parameter = nullptr;
};

/// Every field of both nodes, in the nodes' field order.
const std::vector<FieldInfo>& fieldInfos();
/// The entry of `node`'s `field` (nullptr if there is none).
const FieldInfo* findFieldInfo(const char* node, const char* field);
/// The SoBSplineDeformSurface field that sets the core's parameter `parameter` (as
/// bsdeform::ParameterError names it), or nullptr when no field does.
const FieldInfo* surfaceFieldOfParameter(const std::string& parameter);
/// Whether a surface whose `energy` field is `energy` (PAPER 0, SHELL 1) reads `field`.
bool surfaceFieldUses(int energy, const char* field);
/// Whether a force field of `type` (SoForceField::Type) reads `field`.
bool forceFieldUses(int type, const char* field);
/// The reference of both nodes' fields as Markdown tables (what docs/nodes.md holds between
/// its `field-reference` markers).
std::string fieldReferenceMarkdown();

}  // namespace bsdeform
