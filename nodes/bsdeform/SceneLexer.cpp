// SPDX-License-Identifier: MIT
#include "bsdeform/SceneLexer.h"

#include <cstring>

#include "bsdeform/SceneGuard.h"

namespace bsdeform::guard {

namespace {
bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }
}  // namespace

bool SceneLexer::refuse(int line, std::string reason) {
  m_refusalLine = line;
  m_refusal = std::move(reason);
  return false;
}

void SceneLexer::skipSpaceAndComments() {
  while (m_p < m_end) {
    if (*m_p == '\n') {
      ++m_line;
      ++m_p;
    } else if (isSpace(*m_p)) {
      ++m_p;
    } else if (*m_p == '#') {
      while (m_p < m_end && *m_p != '\n') ++m_p;
    } else {
      break;
    }
  }
}

bool SceneLexer::next(Token& t) {
  skipSpaceAndComments();
  t = Token();
  t.line = m_line;
  if (m_p >= m_end) return true;
  const char c = *m_p;
  if (const std::string why = nulByte(c); !why.empty()) return refuse(t.line, why);
  switch (c) {
    case '{': t.kind = Token::Open; ++m_p; return true;
    case '}': t.kind = Token::Close; ++m_p; return true;
    case '[': t.kind = Token::OpenList; ++m_p; return true;
    case ']': t.kind = Token::CloseList; ++m_p; return true;
    case ',': t.kind = Token::Comma; ++m_p; return true;
    default: break;
  }
  if (c == '"') {
    ++m_p;
    const char* start = m_p;
    while (m_p < m_end && *m_p != '"') {
      if (*m_p == '\\' && m_p + 1 < m_end) ++m_p;
      if (*m_p == '\n') ++m_line;
      ++m_p;
    }
    if (m_p >= m_end) return refuse(t.line, "a string that is never closed (\")");
    const std::size_t n = std::size_t(m_p - start);
    ++m_p;
    if (const std::string why = longName(n, NameKind::QuotedString, m_limits); !why.empty()) return refuse(t.line, why);
    t.kind = Token::String;
    t.text.assign(start, n);
    return true;
  }
  // A word: up to whitespace, a comment, a string or punctuation. Coin's own readers may take a
  // longer run (a DEF name may contain '[' ',' '#'), so the run up to whitespace is what is bounded.
  const char* start = m_p;
  const char* run = m_p;
  while (run < m_end && !isSpace(*run) && *run != '"') ++run;
  if (const std::string why = longName(std::size_t(run - start), NameKind::Word, m_limits); !why.empty())
    return refuse(t.line, why);
  while (m_p < m_end && !isSpace(*m_p) && !std::strchr("{}[],\"#", *m_p)) ++m_p;
  t.kind = Token::Word;
  t.text.assign(start, std::size_t(m_p - start));
  return true;
}

bool SceneLexer::readBaseName(std::string& name, int& line, bool reference) {
  skipSpaceAndComments();
  line = m_line;
  const char* start = m_p;
  while (m_p < m_end && static_cast<unsigned char>(*m_p) > 0x20) ++m_p;
  if (const std::string why = longName(std::size_t(m_p - start), NameKind::BaseName, m_limits); !why.empty())
    return refuse(line, why);
  if (reference) {
    const char* dot = static_cast<const char*>(std::memchr(start, '.', std::size_t(m_p - start)));
    if (dot) m_p = dot;
  }
  name.assign(start, std::size_t(m_p - start));
  return true;
}

}  // namespace bsdeform::guard
