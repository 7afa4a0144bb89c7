// SPDX-License-Identifier: MIT
// A full disk for tests, without root: an LD_PRELOAD library that makes write(), writev(),
// pwrite() and pwritev() on regular files under one directory fail with ENOSPC.
//
//   BSDEFORM_ENOSPC_DIR    the directory (its files and those of its subdirectories); without
//                          it the library does nothing. Read at every write, so a test
//                          process can switch the full disk on and off with setenv().
//   BSDEFORM_ENOSPC_AFTER  bytes that may still be written there (in total, by this process)
//                          before the disk is "full"; default 0. A write that crosses the
//                          limit is short and the next one fails, as on a real file system.
//
// Files are matched through /proc/self/fd, so temporary files (QSaveFile's) are caught too.
// Writes through stdio are not: glibc's fwrite() calls its internal write, not this one.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

static long long g_written = 0;  // bytes written under the directory so far

// 1 when `fd` is a regular file under BSDEFORM_ENOSPC_DIR.
static int underFullDir(int fd) {
  const char* dir = getenv("BSDEFORM_ENOSPC_DIR");
  if (!dir || !*dir) return 0;
  struct stat st;
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) return 0;
  char link[64], target[PATH_MAX], root[PATH_MAX];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const ssize_t n = readlink(link, target, sizeof target - 1);
  if (n <= 0) return 0;
  target[n] = '\0';
  if (!realpath(dir, root)) return 0;
  const size_t len = strlen(root);
  return strncmp(target, root, len) == 0 && (target[len] == '/' || (len == 1 && root[0] == '/'));
}

// How many of `count` bytes may be written to `fd` (0: none, fail with ENOSPC); `*counted`
// tells whether the bytes written go against the budget.
static size_t allowance(int fd, size_t count, int* counted) {
  *counted = 0;
  if (count == 0 || !underFullDir(fd)) return count;
  *counted = 1;
  const char* after = getenv("BSDEFORM_ENOSPC_AFTER");
  const long long left = (after ? atoll(after) : 0) - __atomic_load_n(&g_written, __ATOMIC_SEQ_CST);
  if (left <= 0) return 0;
  return (unsigned long long)left < count ? (size_t)left : count;
}

static ssize_t account(ssize_t r, int counted) {
  if (r > 0 && counted) __atomic_add_fetch(&g_written, (long long)r, __ATOMIC_SEQ_CST);
  return r;
}

static size_t iovLength(const struct iovec* iov, int iovcnt) {
  size_t total = 0;
  for (int i = 0; i < iovcnt; ++i) total += iov[i].iov_len;
  return total;
}

// The first `allowed` bytes of `iov` in `out` (at most iovcnt entries); returns the count.
static int truncateIov(const struct iovec* iov, int iovcnt, size_t allowed, struct iovec* out) {
  int k = 0;
  for (int i = 0; i < iovcnt && allowed > 0; ++i) {
    out[k] = iov[i];
    if (out[k].iov_len > allowed) out[k].iov_len = allowed;
    allowed -= out[k].iov_len;
    ++k;
  }
  return k;
}

typedef ssize_t (*WriteFn)(int, const void*, size_t);
typedef ssize_t (*PwriteFn)(int, const void*, size_t, off_t);
typedef ssize_t (*WritevFn)(int, const struct iovec*, int);
typedef ssize_t (*PwritevFn)(int, const struct iovec*, int, off_t);

#define REAL(name, type) \
  static type real = NULL; \
  if (!real) real = (type)dlsym(RTLD_NEXT, name)

ssize_t write(int fd, const void* buf, size_t count) {
  REAL("write", WriteFn);
  int counted;
  const size_t allowed = allowance(fd, count, &counted);
  if (allowed == 0 && count > 0) return errno = ENOSPC, -1;
  return account(real(fd, buf, allowed), counted);
}

ssize_t pwrite(int fd, const void* buf, size_t count, off_t offset) {
  REAL("pwrite", PwriteFn);
  int counted;
  const size_t allowed = allowance(fd, count, &counted);
  if (allowed == 0 && count > 0) return errno = ENOSPC, -1;
  return account(real(fd, buf, allowed, offset), counted);
}

ssize_t pwrite64(int fd, const void* buf, size_t count, off_t offset) {
  REAL("pwrite64", PwriteFn);
  int counted;
  const size_t allowed = allowance(fd, count, &counted);
  if (allowed == 0 && count > 0) return errno = ENOSPC, -1;
  return account(real(fd, buf, allowed, offset), counted);
}

ssize_t writev(int fd, const struct iovec* iov, int iovcnt) {
  REAL("writev", WritevFn);
  int counted;
  const size_t total = iovLength(iov, iovcnt);
  const size_t allowed = allowance(fd, total, &counted);
  if (allowed == 0 && total > 0) return errno = ENOSPC, -1;
  if (allowed == total) return account(real(fd, iov, iovcnt), counted);
  struct iovec part[iovcnt > 0 ? iovcnt : 1];
  return account(real(fd, part, truncateIov(iov, iovcnt, allowed, part)), counted);
}

ssize_t pwritev(int fd, const struct iovec* iov, int iovcnt, off_t offset) {
  REAL("pwritev", PwritevFn);
  int counted;
  const size_t total = iovLength(iov, iovcnt);
  const size_t allowed = allowance(fd, total, &counted);
  if (allowed == 0 && total > 0) return errno = ENOSPC, -1;
  if (allowed == total) return account(real(fd, iov, iovcnt, offset), counted);
  struct iovec part[iovcnt > 0 ? iovcnt : 1];
  return account(real(fd, part, truncateIov(iov, iovcnt, allowed, part), offset), counted);
}
