// SPDX-License-Identifier: MIT
#include "bsdeform/SceneText.h"

#include <Inventor/SoOutput.h>
#include <Inventor/actions/SoWriteAction.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace bsdeform {

double snap15(double x) {
  if (!std::isfinite(x)) return x;
  char buf[40];
  const auto r = std::to_chars(buf, buf + sizeof buf - 1, x, std::chars_format::general, 15);
  *r.ptr = '\0';
  return std::strtod(buf, nullptr);
}

bool coinReadReal(const char* s, double& value) {
  // Same operations in the same order as Coin 4.0's SoInput_FileInfo::readReal.
  bool minus = false, gotNum = false;
  if (*s == '-') minus = true, ++s;
  else if (*s == '+') ++s;
  const char* digits = s;
  while (*s >= '0' && *s <= '9') ++s;
  double number = 0.0;
  if (s > digits) {
    gotNum = true;
    double mul = 1.0;
    for (const char* p = s - 1; p >= digits; --p) {
      number += (*p - '0') * mul;
      mul *= 10.0;
    }
  }
  if (*s == '.') {
    ++s;
    double mul = 0.1;
    for (; *s >= '0' && *s <= '9'; ++s) {
      gotNum = true;
      number += (*s - '0') * mul;
      mul *= 0.1;
    }
  }
  if (!gotNum) return false;
  if (minus) number = -number;
  if (*s == 'e' || *s == 'E') {
    ++s;
    bool negative = false;
    if (*s == '-') negative = true, ++s;
    else if (*s == '+') ++s;
    const char* exp = s;
    while (*s >= '0' && *s <= '9') ++s;
    if (s == exp) return false;
    double exponent = 0.0, mul = 1.0;
    for (const char* p = s - 1; p >= exp; --p) {
      exponent += (*p - '0') * mul;
      mul *= 10.0;
    }
    if (negative) exponent = -exponent;
    number *= std::pow(10.0, exponent);
  }
  value = number;
  return *s == '\0';
}

std::string coinDoubleText(double x) {
  char buf[48];
  if (!std::isfinite(x)) {
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
  }
  auto text = std::to_chars(buf, buf + sizeof buf - 1, x, std::chars_format::general, 15);
  *text.ptr = '\0';
  const double target = std::strtod(buf, nullptr);  // == snap15(x)
  double read = 0.0;
  if (coinReadReal(buf, read) && snap15(read) == target) return buf;
  // Integer mantissa: Coin sums the digits exactly (< 2^53) and multiplies once.
  auto sci = std::to_chars(buf, buf + sizeof buf - 1, target, std::chars_format::scientific, 14);
  *sci.ptr = '\0';
  const char* e = std::strchr(buf, 'e');
  std::string mantissa;
  for (const char* p = buf; p < e; ++p)
    if (*p != '.') mantissa += *p;
  int exponent = std::atoi(e + 1) - 14;
  while (mantissa.size() > 1 && mantissa.back() == '0') mantissa.pop_back(), ++exponent;
  std::string out = mantissa + (exponent ? "e" + std::to_string(exponent) : std::string());
  if (coinReadReal(out.c_str(), read) && snap15(read) == target) return out;
  std::snprintf(buf, sizeof buf, "%.17g", x);  // not met in practice; exact for strtod readers
  return buf;
}

namespace {
// An SoOutput whose ASCII doubles Coin reads back (coinDoubleText) and which never touches
// the C locale (Coin's own writer switches it twice per number).
class PreciseOutput : public SoOutput {
 public:
  void write(const double d) override {
    if (isBinary()) {
      SoOutput::write(d);
      return;
    }
    SoOutput::write(coinDoubleText(d).c_str());
  }
  using SoOutput::write;
};
}  // namespace

namespace {
// A FILE* whose writes go to a TextSink (glibc's fopencookie): Coin's SoOutput writes to a FILE*
// piece by piece, so the text streams instead of growing one buffer.
struct SinkCookie {
  const TextSink* sink;
  bool failed = false;
};

ssize_t sinkWrite(void* cookie, const char* data, size_t size) {
  auto* c = static_cast<SinkCookie*>(cookie);
  if (c->failed || !(*c->sink)(data, size)) {
    c->failed = true;
    errno = EIO;
    return -1;
  }
  return static_cast<ssize_t>(size);
}
}  // namespace

bool writeSceneText(SoNode* root, const TextSink& sink) {
  SinkCookie cookie{&sink};
  cookie_io_functions_t io{};
  io.write = sinkWrite;
  FILE* fp = fopencookie(&cookie, "w", io);
  if (!fp) return false;
  std::setvbuf(fp, nullptr, _IOFBF, std::size_t(1) << 20);
  {
    PreciseOutput out;
    out.setFilePointer(fp);
    SoWriteAction wa(&out);
    wa.apply(root);
  }
  const bool flushed = std::fflush(fp) == 0 && !std::ferror(fp);
  const bool closed = std::fclose(fp) == 0;
  return flushed && closed && !cookie.failed;
}

std::string sceneToText(SoNode* root) {
  std::string text;
  writeSceneText(root, [&text](const char* data, std::size_t size) {
    text.append(data, size);
    return true;
  });
  return text;
}

}  // namespace bsdeform
