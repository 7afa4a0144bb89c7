// SPDX-License-Identifier: MIT
#include "bsdeform/SceneText.h"

#include <Inventor/SoOutput.h>
#include <Inventor/actions/SoWriteAction.h>

#include <charconv>
#include <cmath>
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

std::string sceneToText(SoNode* root) {
  PreciseOutput out;
  out.setBuffer(nullptr, 0, [](void* p, size_t n) { return std::realloc(p, n); });
  SoWriteAction wa(&out);
  wa.apply(root);
  void* buf = nullptr;
  size_t size = 0;
  out.getBuffer(buf, size);
  std::string text(static_cast<const char*>(buf), size);
  std::free(buf);  // SoOutput does not free a buffer it was given a realloc function for
  return text;
}

}  // namespace bsdeform
