// SPDX-License-Identifier: MIT
#pragma once
/// @file NumberText.h
/// How the core writes a number into an error message: the shortest text that reads back to
/// the same double (std::to_chars), so that the value a user sees is the value that was refused
/// and reads as the user wrote it (0.7, not 0.69999999999999996).

#include <charconv>
#include <string>
#include <system_error>

namespace bsdeform {

inline std::string numberText(double x) {
  char buffer[64];
  const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof buffer, x);
  if (r.ec != std::errc()) return "?";
  return std::string(buffer, r.ptr);
}

/// How the core writes a computed quantity into a message (a distance found, a bound): four
/// significant digits (0.004084, 1.235e-05), not the last bits of a value no user wrote.
inline std::string measuredText(double x) {
  char buffer[64];
  const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof buffer, x, std::chars_format::general, 4);
  if (r.ec != std::errc()) return "?";
  return std::string(buffer, r.ptr);
}

}  // namespace bsdeform
