// SPDX-License-Identifier: MIT
#pragma once
/// @file NumberText.h
/// How the core writes a number into an error message: 17 significant digits, so that the
/// value a user sees is the value that was refused.

#include <sstream>
#include <string>

namespace bsdeform {

inline std::string numberText(double x) {
  std::ostringstream os;
  os.precision(17);
  os << x;
  return os.str();
}

}  // namespace bsdeform
