// SPDX-License-Identifier: MIT
#pragma once
/// @file NodesInit.h
/// Registration of bsdeform's Inventor classes.

namespace bsdeform {

/// Registers SoBSplineDeformSurface and SoForceField with Coin. Call after SoDB::init() (or
/// SoQt::init()). Idempotent: safe to call any number of times.
void initNodes();

/// Switches off Coin's dynamic loading of extension nodes (a library named after any unknown
/// node name in a file would otherwise be dlopened). Call before SoDB::init() in programs that
/// read untrusted files; our own programs do.
void disableDynamicNodeLoading();

}  // namespace bsdeform
