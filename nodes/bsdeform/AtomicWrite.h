// SPDX-License-Identifier: MIT
#pragma once
/// @file AtomicWrite.h
/// All-or-nothing file writes for the nodes library (no Qt here; the front ends use
/// ui/common/AtomicFile.h). Internal to the nodes library, not installed.

#include <cstddef>
#include <string>

namespace bsdeform {

/// Writes `size` bytes to `path` through a unique temporary file in the same directory
/// (`mkstemp`, mode 0644), with checked write(2) calls, optionally fsync'ed, then renamed over
/// `path`. On any failure the temporary file is removed, a previous `path` is kept byte for
/// byte, and `error` is "cannot write 'PATH': <the system's reason>".
bool writeFileAtomically(const std::string& path, const void* data, std::size_t size, std::string& error,
                         bool syncToDisk = true);

}  // namespace bsdeform
