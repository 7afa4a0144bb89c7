// SPDX-License-Identifier: MIT
#pragma once
/// @file SceneText.h
/// A scene graph as .iv text (what SoWriteAction writes), e.g. to save it atomically, with
/// doubles written so that Coin's own reader gets them back.

#include <cstddef>
#include <functional>
#include <string>

class SoFieldContainer;
class SoNode;

namespace bsdeform {

/// Receives written text piece by piece (about a megabyte at a time); returns false on a write
/// error, which stops the writing.
using TextSink = std::function<bool(const char* data, std::size_t size)>;

/// Writes `root` (with every surface's current state) as ASCII Inventor text into `sink`,
/// streaming: the whole text is never held in memory. Coin lays the text out (SoWriteAction);
/// doubles are written as coinDoubleText() and everything reaches the sink in pieces of at most
/// a megabyte, whatever the process locale. Returns false if the sink failed.
bool writeSceneText(SoNode* root, const TextSink& sink);

/// The same text as one string (small scenes, tests).
std::string sceneToText(SoNode* root);

/// The double of the 15-significant-digit decimal form of x (x itself if not finite):
/// strtod(printf("%.15g", x)) in the "C" locale, whatever the process locale. The nodes snap
/// every double they read and every state value they write to it, so that
/// write -> read -> write is a fixed point.
double snap15(double x);

/// After Coin read `container` (a node's or an engine's readInstance): every double it read
/// snapped to snap15(), without notifying: the SoSFDouble, SoSFVec2d, SoSFVec3d, SoMFDouble,
/// SoMFVec2d and SoMFVec3d fields that are neither default nor connected, found from the
/// container's own field data (no list of fields to keep up to date). The one routine of the
/// surface and the force field.
void snapReadDoubles(SoFieldContainer& container);

/// What Coin 4.0's ASCII reader (SoInput_FileInfo::readReal) computes for `text`: it adds
/// the fraction digit by digit with a running factor 0.1 and scales by pow(10, exponent), so
/// it is off by up to a few ulps (0.000983542385712959 reads 3 ulps high).
/// @return false if `text` is not a number in Coin's syntax
bool coinReadReal(const char* text, double& value);

/// Text for x that Coin reads back to within a snap15() of x: the 15-digit decimal form
/// (printf's "%.15g") when Coin's reader recovers it (checked with coinReadReal), otherwise the
/// integer-mantissa form ("983542385712959e-18", whose only rounding is one product);
/// non-finite values as printf's "%g". Locale-independent.
std::string coinDoubleText(double x);

}  // namespace bsdeform
