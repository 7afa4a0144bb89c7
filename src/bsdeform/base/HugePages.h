// SPDX-License-Identifier: MIT
#pragma once
/// @file HugePages.h
/// Large nets on transparent huge pages. A 2048^2 model's nets are 100 MB each; the first touch
/// of 100 MB in 4 KB pages is 25 600 page faults, measured at about 300 ms on the 2-core VM of
/// docs/benchmarks.md, against 10 ms in 2 MB pages (Linux THP in its "madvise" mode, Debian's
/// default, only gives huge pages to memory advised so). Advising is a hint: where it is not
/// supported, nothing changes but the time.

#include <cstddef>

#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

/// Asks for huge pages on the whole 2 MB pages of [data, data + bytes); for memory not yet
/// touched (a fresh large allocation). Does nothing below a few megabytes or off Linux.
void adviseHugePages(void* data, std::size_t bytes);

/// Makes `net` rows x 3. A new allocation is left uninitialised and, when large, advised to
/// use huge pages before anything touches it; a net of that size already is kept as it is.
void allocateNet(ControlNet& net, Eigen::Index rows);

}  // namespace bsdeform
