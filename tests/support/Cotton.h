// SPDX-License-Identifier: MIT
#pragma once
// The woven cotton of the shipped cloth scenes (docs/nodes.md's material table: Penava et al.
// 2014 as C-IPC gives it): E = 0.821 MPa, nu = 0.243, t = 0.318 mm, rho = 472.6 kg/m^3.
#include "bsdeform/energy/Shell.h"

namespace bsdeform::test {
inline const ShellMaterial kCotton{0.821e6, 0.243, 0.318e-3, 472.6};
}  // namespace bsdeform::test
