// SPDX-License-Identifier: MIT
#pragma once
/// @file ImageSize.h
/// "WxH" image sizes as the runner's --size and the viewer's Save Screenshot dialog read them.

#include <QSize>
#include <QString>

namespace bsdeform {

/// Largest width or height of a picture we render (offscreen buffers beyond this fail on Mesa).
constexpr int kMaxImageSide = 8192;

/// Reads "WxH" (spaces around the numbers allowed) with 1 <= W, H <= kMaxImageSide.
/// @return false, leaving `size` alone, for anything else
bool parseImageSize(const QString& text, QSize& size);

}  // namespace bsdeform
