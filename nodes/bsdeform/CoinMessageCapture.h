// SPDX-License-Identifier: MIT
#pragma once
/// @file CoinMessageCapture.h
/// Collects the messages Coin posts (SoReadError while reading, SoDebugError warnings of nodes,
/// fields and engines) instead of letting Coin print them, for as long as the capture lives.
/// The one way our programs and tests catch Coin's messages: the scene reader (read errors into
/// its message), bsdeform-run (warnings while the models are built are bad input) and the
/// node tests.

#include <string>
#include <vector>

class SoError;

namespace bsdeform {

class CoinMessageCapture {
 public:
  enum Kinds { ReadErrors = 1, DebugErrors = 2, AllErrors = ReadErrors | DebugErrors };

  /// Installs the handlers for `kinds`; the ones before are put back by the destructor, so
  /// captures nest (the innermost one collects). Destroy them in the reverse order of creation.
  explicit CoinMessageCapture(int kinds = AllErrors);
  ~CoinMessageCapture();
  CoinMessageCapture(const CoinMessageCapture&) = delete;
  CoinMessageCapture& operator=(const CoinMessageCapture&) = delete;

  /// Coin's debug strings of the messages posted since the capture began or was cleared.
  std::vector<std::string> messages;

  /// The messages joined by `separator` ("" when there are none).
  std::string joined(const std::string& separator) const;

 private:
  static void collect(const SoError* error, void* self);
  int m_kinds;
  void (*m_oldRead)(const SoError*, void*) = nullptr;
  void* m_oldReadData = nullptr;
  void (*m_oldDebug)(const SoError*, void*) = nullptr;
  void* m_oldDebugData = nullptr;
};

}  // namespace bsdeform
