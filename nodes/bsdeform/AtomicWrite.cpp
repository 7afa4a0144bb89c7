// SPDX-License-Identifier: MIT
#include "bsdeform/AtomicWrite.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace bsdeform {

bool writeFileAtomically(const std::string& path, const void* data, std::size_t size, std::string& error, bool syncToDisk) {
  std::string tmp = path + ".XXXXXX";
  const int fd = ::mkstemp(&tmp[0]);
  if (fd < 0) {
    error = "cannot write '" + path + "': " + std::strerror(errno);
    return false;
  }
  const auto* bytes = static_cast<const char*>(data);
  int why = 0;
  if (::fchmod(fd, 0644) != 0) why = errno;
  for (std::size_t done = 0; !why && done < size;) {
    const ssize_t n = ::write(fd, bytes + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) why = n < 0 ? errno : EIO;
    else done += std::size_t(n);
  }
  if (!why && syncToDisk && ::fsync(fd) != 0) why = errno;
  if (::close(fd) != 0 && !why) why = errno;
  if (!why && std::rename(tmp.c_str(), path.c_str()) != 0) why = errno;
  if (why) {
    error = "cannot write '" + path + "': " + std::strerror(why);
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

}  // namespace bsdeform
