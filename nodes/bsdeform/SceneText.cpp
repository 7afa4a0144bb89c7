// SPDX-License-Identifier: MIT
#include "bsdeform/SceneText.h"

#include <Inventor/SoOutput.h>
#include <Inventor/actions/SoWriteAction.h>
#include <Inventor/fields/SoMFDouble.h>
#include <Inventor/fields/SoMFVec2d.h>
#include <Inventor/fields/SoMFVec3d.h>
#include <Inventor/fields/SoSFDouble.h>
#include <Inventor/fields/SoSFVec2d.h>
#include <Inventor/fields/SoSFVec3d.h>
#include <Inventor/lists/SoFieldList.h>
#include <Inventor/misc/SoBase.h>
#include <Inventor/fields/SoFieldContainer.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <locale.h>
#include <vector>

namespace bsdeform {

// ---------------------------------------------------------------------------------------------
// 15-significant-digit decimals, without the C library's locale-dependent conversions.
//
// Every conversion here is exact (std::to_chars, and strtod_l in the "C" locale: correctly
// rounded, whatever the process locale). The fast paths take the digits of the shortest round-trip
// form (Ryu, std::to_chars without a precision) and decide from them, with an error bound, what
// the correctly rounded 15-digit decimal is; when the bound cannot decide they fall back to
// to_chars with precision 14 (printf's %.14e, several times slower). The results are those of
// the former definitions (to_chars %.15g, then strtod in the "C" locale), which the tests check
// value by value.

namespace {

constexpr double kExactPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                  1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
constexpr std::uint64_t kPow10Int[] = {1ULL, 10ULL, 100ULL, 1000ULL, 10000ULL, 100000ULL, 1000000ULL,
                                       10000000ULL, 100000000ULL, 1000000000ULL, 10000000000ULL,
                                       100000000000ULL, 1000000000000ULL, 10000000000000ULL,
                                       100000000000000ULL, 1000000000000000ULL};

/// A decimal  (-1)^negative * digits * 10^(exponent - (numDigits - 1)): `digits` has numDigits
/// digits (1..15), no trailing zero; `exponent` is that of the leading digit.
struct Decimal {
  bool negative = false;
  std::uint64_t digits = 0;
  int numDigits = 0;
  int exponent = 0;
};

void stripZeros(Decimal& d) {
  while (d.numDigits > 1 && d.digits % 10 == 0) d.digits /= 10, --d.numDigits;
}

/// Reads "[-]d[.ddd]e(+|-)xx" as to_chars(scientific) writes it: up to 17 digits.
void parseScientific(const char* p, Decimal& d) {
  d.negative = *p == '-';
  if (d.negative) ++p;
  d.digits = 0;
  d.numDigits = 0;
  for (; *p != 'e'; ++p) {
    if (*p == '.') continue;
    d.digits = d.digits * 10 + std::uint64_t(*p - '0');
    ++d.numDigits;
  }
  ++p;  // 'e'
  const bool negExp = *p == '-';
  ++p;
  int e = 0;
  for (; *p; ++p) e = e * 10 + (*p - '0');
  d.exponent = negExp ? -e : e;
}

/// The 15-digit rounding of x for 1e-7 <= |x| < 1e15 (control nets, times, weights) by
/// arithmetic: t = |x| 10^k with k = 14 - exponent in 0..22 (10^k exact) lies in [1e14, 1e15),
/// and the product y rounds t by at most ulp(y)/2 <= 1/16 (y < 2^50), so round(t) = round(y)
/// unless y lies within 0.07 of a halfway point, or within 1 of 1e14 (t might be just below, with
/// one digit less). Returns false when it cannot decide.
bool decimal15Fast(double x, Decimal& d) {
  const double a = std::fabs(x);
  if (!(a >= 1e-7 && a < 1e15)) return false;
  std::uint64_t bits;
  std::memcpy(&bits, &a, sizeof bits);
  const int e2 = int(bits >> 52) - 1023;
  int E = (e2 * 78913) >> 18;  // floor(e2 log10(2)): 10^E <= 2^e2 <= a, E in -8..14
  double y = a * kExactPow10[14 - E];
  if (y >= 1e15) {
    if (++E > 14) return false;
    y = a * kExactPow10[14 - E];
  }
  if (!(y >= 1e14 + 1.0 && y < 1e15)) return false;
  const double whole = std::floor(y), frac = y - whole;  // exact: y < 2^50
  if (std::fabs(frac - 0.5) <= 0.07) return false;
  d.negative = std::signbit(x);
  d.digits = std::uint64_t(whole) + (frac > 0.5 ? 1 : 0);
  d.numDigits = 15;
  d.exponent = E;
  if (d.digits == kPow10Int[15]) {
    d.digits = kPow10Int[14];
    ++d.exponent;
  }
  stripZeros(d);
  return true;
}

/// The correctly rounded 15-significant-digit decimal of a finite, non-zero x.
Decimal decimal15(double x) {
  char buf[40];
  Decimal d;
  if (decimal15Fast(x, d)) return d;
  if (std::isnormal(x)) {
    *std::to_chars(buf, buf + sizeof buf - 1, x, std::chars_format::scientific).ptr = '\0';
    parseScientific(buf, d);
    if (d.numDigits <= 15) {
      // The shortest form S is the 15-digit rounding of x: |x - S| <= ulp(x)/2 <= 2^-53 |x|,
      // less than half the 15-digit spacing around S (>= 5e-16 |S|, also below a power of ten).
      stripZeros(d);
      return d;
    }
    // 16 or 17 digits: round them to 15 unless x could lie on the other side of the halfway
    // point than its shortest form D. The part dropped, scaled to two digits (units of the 17th
    // digit, u = 10^(exponent - 16) ~ |x| / digits17), is t; |x - D| <= ulp(x)/2, so the
    // rounding of D is that of x when |t - 50| u > ulp(x)/2 (a 1e-9 relative margin covers
    // the approximations of u).
    const int drop = d.numDigits - 15;
    const std::uint64_t div = drop == 1 ? 10 : 100;
    const std::uint64_t kept = d.digits / div;
    const std::uint64_t t = (d.digits % div) * (drop == 1 ? 10 : 1);
    const double digits17 = double(d.digits) * (drop == 1 ? 10.0 : 1.0);
    const double halfUlp = std::ldexp(1.0, std::ilogb(x) - 53);
    const double distance = double(t > 50 ? t - 50 : 50 - t) * std::fabs(x);
    if (distance > halfUlp * digits17 * (1.0 + 1e-9)) {
      d.digits = kept + (t > 50 ? 1 : 0);
      d.numDigits = 15;
      if (d.digits == kPow10Int[15]) {  // 999999999999999.6 -> 1000000000000000
        d.digits = kPow10Int[14];
        ++d.exponent;
      }
      stripZeros(d);
      return d;
    }
  }
  // Subnormal, or too close to a halfway point to decide from the shortest form: printf's
  // %.14e, correctly rounded.
  *std::to_chars(buf, buf + sizeof buf - 1, x, std::chars_format::scientific, 14).ptr = '\0';
  parseScientific(buf, d);
  stripZeros(d);
  return d;
}

/// The double nearest to the decimal (correctly rounded).
double decimalValue(const Decimal& d) {
  const int power = d.exponent - (d.numDigits - 1);
  double v;
  if (power >= -22 && power <= 22) {
    // Clinger's fast path: digits < 10^15 < 2^53 and 10^|power| are exact doubles, so one
    // IEEE multiplication or division rounds correctly.
    v = power >= 0 ? double(d.digits) * kExactPow10[power] : double(d.digits) / kExactPow10[-power];
  } else {
    // strtod's results (infinity beyond the largest double, subnormals, zero below them) in the
    // "C" locale whatever the process's; std::from_chars reports the first two as errors
    static const locale_t cLocale = newlocale(LC_ALL_MASK, "C", locale_t(nullptr));
    char buf[40];
    char* p = std::to_chars(buf, buf + 20, d.digits).ptr;
    *p++ = 'e';
    p = std::to_chars(p, buf + sizeof buf - 1, power).ptr;
    *p = '\0';
    v = strtod_l(buf, nullptr, cLocale);
  }
  return d.negative ? -v : v;
}

/// The decimal as printf("%.15g") writes it (trailing zeros are already gone). Returns the end.
char* writeGeneral15(const Decimal& d, char* out) {
  char digits[16];
  char* end = std::to_chars(digits, digits + sizeof digits, d.digits).ptr;
  const int n = int(end - digits), X = d.exponent;
  if (d.negative) *out++ = '-';
  if (X < -4 || X >= 15) {
    *out++ = digits[0];
    if (n > 1) {
      *out++ = '.';
      std::memcpy(out, digits + 1, size_t(n - 1));
      out += n - 1;
    }
    *out++ = 'e';
    *out++ = X < 0 ? '-' : '+';
    const int a = X < 0 ? -X : X;
    if (a < 10) *out++ = '0';
    return std::to_chars(out, out + 4, a).ptr;
  }
  if (X < 0) {
    *out++ = '0';
    *out++ = '.';
    for (int i = 0; i < -X - 1; ++i) *out++ = '0';
    std::memcpy(out, digits, size_t(n));
    return out + n;
  }
  if (n <= X + 1) {
    std::memcpy(out, digits, size_t(n));
    out += n;
    for (int i = n; i < X + 1; ++i) *out++ = '0';
    return out;
  }
  std::memcpy(out, digits, size_t(X + 1));
  out += X + 1;
  *out++ = '.';
  std::memcpy(out, digits + X + 1, size_t(n - X - 1));
  return out + (n - X - 1);
}

constexpr std::size_t kMaxNumberText = 32;

/// Writes coinDoubleText(x) at `out` (room for kMaxNumberText characters); returns the end.
char* writeCoinDouble(double x, char* out) {
  if (!std::isfinite(x)) {
    // printf's %g, as before: "inf", "-inf", "nan", "-nan" (no locale involved)
    const char* s = std::isnan(x) ? (std::signbit(x) ? "-nan" : "nan") : (x < 0 ? "-inf" : "inf");
    const std::size_t n = std::strlen(s);
    std::memcpy(out, s, n);
    return out + n;
  }
  if (x == 0.0) {
    if (std::signbit(x)) *out++ = '-';
    *out++ = '0';
    return out;
  }
  const Decimal d = decimal15(x);
  const double target = decimalValue(d);  // == snap15(x)
  char* end = writeGeneral15(d, out);
  *end = '\0';
  double read = 0.0;
  if (coinReadReal(out, read) && (read == target || snap15(read) == target)) return end;
  // Integer mantissa: Coin sums the digits exactly (< 2^53) and multiplies once.
  char* p = out;
  if (d.negative) *p++ = '-';
  p = std::to_chars(p, p + 16, d.digits).ptr;
  const int exponent = d.exponent - (d.numDigits - 1);
  if (exponent != 0) {
    *p++ = 'e';
    p = std::to_chars(p, p + 6, exponent).ptr;
  }
  *p = '\0';
  if (coinReadReal(out, read) && snap15(read) == target) return p;
  // not met in practice; exact for strtod readers (printf's %.17g in the "C" locale)
  return std::to_chars(out, out + kMaxNumberText, x, std::chars_format::general, 17).ptr;
}

}  // namespace

double snap15(double x) {
  if (!std::isfinite(x) || x == 0.0) return x;
  return decimalValue(decimal15(x));
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

void snapReadDoubles(SoFieldContainer& container) {
  SoFieldList fields;
  const int count = container.getFields(fields);
  for (int i = 0; i < count; ++i) {
    SoField* f = fields[i];
    if (f->isDefault() || f->isConnected()) continue;
    const SbBool notify = f->enableNotify(FALSE);
    if (f->isOfType(SoSFDouble::getClassTypeId())) {
      auto* d = static_cast<SoSFDouble*>(f);
      d->setValue(snap15(d->getValue()));
    } else if (f->isOfType(SoSFVec2d::getClassTypeId())) {
      auto* d = static_cast<SoSFVec2d*>(f);
      const SbVec2d v = d->getValue();
      d->setValue(snap15(v[0]), snap15(v[1]));
    } else if (f->isOfType(SoSFVec3d::getClassTypeId())) {
      auto* d = static_cast<SoSFVec3d*>(f);
      const SbVec3d v = d->getValue();
      d->setValue(snap15(v[0]), snap15(v[1]), snap15(v[2]));
    } else if (f->isOfType(SoMFDouble::getClassTypeId())) {
      auto* d = static_cast<SoMFDouble*>(f);
      if (d->getNum()) {
        double* v = d->startEditing();
        for (int k = 0; k < d->getNum(); ++k) v[k] = snap15(v[k]);
        d->finishEditing();
      }
    } else if (f->isOfType(SoMFVec2d::getClassTypeId())) {
      auto* d = static_cast<SoMFVec2d*>(f);
      if (d->getNum()) {
        SbVec2d* v = d->startEditing();
        for (int k = 0; k < d->getNum(); ++k) v[k].setValue(snap15(v[k][0]), snap15(v[k][1]));
        d->finishEditing();
      }
    } else if (f->isOfType(SoMFVec3d::getClassTypeId())) {
      auto* d = static_cast<SoMFVec3d*>(f);
      if (d->getNum()) {
        SbVec3d* v = d->startEditing();
        for (int k = 0; k < d->getNum(); ++k) v[k].setValue(snap15(v[k][0]), snap15(v[k][1]), snap15(v[k][2]));
        d->finishEditing();
      }
    }
    f->enableNotify(notify);
  }
}

std::string coinDoubleText(double x) {
  char buf[kMaxNumberText + 1];
  return std::string(buf, writeCoinDouble(x, buf));
}

namespace {

// A FILE* whose writes go to a TextSink (glibc's fopencookie): Coin's SoOutput writes to a FILE*,
// so the text streams instead of growing one buffer.
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

// The SoOutput of writeSceneText. Coin still decides what is written and how it is laid out
// (headers, DEF names, field declarations, indentation, one value per line...), but:
// - its ASCII doubles are coinDoubleText(), which Coin reads back, formatted into place, never
//   touching the C locale (Coin's own write(double) switches it twice per number and writes
//   16 digits that its reader does not get back);
// - every byte Coin writes in ASCII passes through writeBinaryArray(const unsigned char*, int)
//   (SoOutput::writeBytesWithPadding, checkHeader), which this class overrides to collect the
//   text in a buffer of a megabyte handed to Coin's writer at once: Coin would otherwise call
//   fwrite for every number, space and comma.
class SceneTextOutput : public SoOutput {
 public:
  static constexpr std::size_t kChunk = std::size_t(1) << 20;

  explicit SceneTextOutput(const SinkCookie& cookie) : m_cookie(cookie) { m_buf.reserve(kChunk); }

  void write(const double d) override {
    if (isBinary()) {
      SoOutput::write(d);
      return;
    }
    char text[kMaxNumberText + 1];
    append(text, std::size_t(writeCoinDouble(d, text) - text));
  }
  using SoOutput::write;

  void writeBinaryArray(const unsigned char* c, const int length) override {
    if (isBinary()) {
      flush();
      SoOutput::writeBinaryArray(c, length);
      return;
    }
    // Coin writes its header before the first bytes (through this function): let it.
    if (!wroteHeader) SoOutput::writeBinaryArray(c, 0);
    const char* text = reinterpret_cast<const char*>(c);
    const std::size_t size = std::size_t(length);
    // Coin lays out a list of references as `USE A,` newline `USE B ]`, and its own reader then
    // looks for a node called "A,": the comma after a USE name gets a space before it, so that
    // every reader (Coin's included) reads what is written. Coin writes "USE", " ", the name and
    // ",\n" as separate pieces.
    if (m_use == Use::Name && size > 0 && text[0] == ',') append(" ", 1);
    if (size == 3 && std::memcmp(text, "USE", 3) == 0) m_use = Use::Keyword;
    else if (m_use == Use::Keyword && size == 1 && text[0] == ' ') m_use = Use::Space;
    else if (m_use == Use::Space && size > 0) m_use = Use::Name;
    else m_use = Use::None;
    append(text, size);
  }
  using SoOutput::writeBinaryArray;

  /// Hands what is buffered to Coin's writer.
  void flush() {
    if (m_buf.empty()) return;
    SoOutput::writeBinaryArray(reinterpret_cast<const unsigned char*>(m_buf.data()), int(m_buf.size()));
    m_buf.clear();
  }

 private:
  void append(const char* data, std::size_t size) {
    if (m_cookie.failed) return;  // the sink refused: the write is over (Coin has said so)
    if (m_buf.size() + size > kChunk) flush();
    while (size > kChunk) {  // a huge string field: in pieces of at most a megabyte
      SoOutput::writeBinaryArray(reinterpret_cast<const unsigned char*>(data), int(kChunk));
      data += kChunk;
      size -= kChunk;
    }
    m_buf.insert(m_buf.end(), data, data + size);
  }

  const SinkCookie& m_cookie;
  std::vector<char> m_buf;
  enum class Use { None, Keyword, Space, Name } m_use = Use::None;  ///< where in `USE name` the text is
};

}  // namespace

bool writeSceneText(SoNode* root, const TextSink& sink) {
  SinkCookie cookie{&sink};
  cookie_io_functions_t io{};
  io.write = sinkWrite;
  FILE* fp = fopencookie(&cookie, "w", io);
  if (!fp) return false;
  std::setvbuf(fp, nullptr, _IONBF, 0);  // SceneTextOutput hands over pieces of a megabyte
  {
    SceneTextOutput out(cookie);
    out.setFilePointer(fp);
    SoWriteAction wa(&out);
    wa.apply(root);
    out.flush();
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
