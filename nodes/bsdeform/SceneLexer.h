// SPDX-License-Identifier: MIT
#pragma once
/// @file SceneLexer.h
/// The guard's tokeniser of Inventor/VRML ASCII text (internal to the nodes library, not
/// installed): words, quoted strings and punctuation, and DEF/USE names read as Coin's reader
/// reads them. It refuses the lexical hazards of docs/reliability.md (SceneGuard.h: longName,
/// nulByte) with their line.

#include <cstddef>
#include <string>

#include "bsdeform/SceneReader.h"

namespace bsdeform::guard {

struct Token {
  enum Kind { End, Word, String, Open, Close, OpenList, CloseList, Comma } kind = End;
  std::string text;  ///< word text, or string contents (raw, without quotes)
  int line = 0;
};

class SceneLexer {
 public:
  /// Tokens of `size` bytes at `data` (not copied: the text must outlive the lexer).
  SceneLexer(const char* data, std::size_t size, const SceneLimits& limits) : m_p(data), m_end(data + size), m_limits(limits) {}

  /// The next token (kind End at the end of the text). False when the text is refused there:
  /// refusalLine() and refusal() say where and why.
  bool next(Token& t);
  /// The name after DEF (`reference` false) or USE (true), as Coin reads it: every byte above 0x20
  /// up to white space (SoInput::read(SbName&, FALSE)); after USE a '.' starts a field name and is
  /// left for next(). `line` is the name's line. False when refused, as next().
  bool readBaseName(std::string& name, int& line, bool reference);

  int line() const { return m_line; }
  int refusalLine() const { return m_refusalLine; }
  const std::string& refusal() const { return m_refusal; }

  /// A place to come back to after looking one token ahead.
  struct Mark {
    const char* p;
    int line;
  };
  Mark mark() const { return {m_p, m_line}; }
  void reset(const Mark& m) {
    m_p = m.p;
    m_line = m.line;
  }

 private:
  void skipSpaceAndComments();
  bool refuse(int line, std::string reason);

  const char* m_p;
  const char* m_end;
  int m_line = 1;
  const SceneLimits& m_limits;
  int m_refusalLine = 0;
  std::string m_refusal;
};

}  // namespace bsdeform::guard
