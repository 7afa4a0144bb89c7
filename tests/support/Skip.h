// SPDX-License-Identifier: MIT
#pragma once
// A case that cannot run here (a locale that is not installed) says so on a line CTest knows:
// Catch2 2.13 has no SKIP, so such a case returns after BSDEFORM_TEST_SKIP(reason), and the
// CTest entries of the executable carry SKIP_REGULAR_EXPRESSION "${BSDEFORM_TEST_SKIP_MARKER}"
// (tests/CMakeLists.txt): ctest reports the entry as "Skipped" instead of "Passed".
#include <catch2/catch.hpp>
#include <cstdlib>
#include <string>

namespace testsupport {

/// The marker; tests/CMakeLists.txt matches the same text.
inline constexpr const char* kSkipMarker = "BSDEFORM-TEST-SKIPPED: ";

/// The locale with a decimal comma that the locale tests switch to: $BSDEFORM_TEST_LOCALE, or
/// de_DE.UTF-8 (what scripts/common.sh generates; setting the variable to a locale that does not
/// exist shows the skip).
inline std::string testLocale() {
  const char* name = std::getenv("BSDEFORM_TEST_LOCALE");
  return name && *name ? std::string(name) : std::string("de_DE.UTF-8");
}

}  // namespace testsupport

/// Prints the skip line (a Catch2 warning, shown whether or not the case passes); return after it.
#define BSDEFORM_TEST_SKIP(reason) WARN(std::string(testsupport::kSkipMarker) + (reason))
