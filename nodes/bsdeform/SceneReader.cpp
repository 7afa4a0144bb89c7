// SPDX-License-Identifier: MIT
#include "bsdeform/SceneReader.h"
#include "bsdeform/CoinMessageCapture.h"

#include "bsdeform/SoBSplineDeformSurface.h"

#include <Inventor/SoDB.h>
#include <Inventor/SoInput.h>
#include <Inventor/SoPath.h>
#include <Inventor/SoType.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/engines/SoEngine.h>
#include <Inventor/fields/SoFieldContainer.h>
#include <Inventor/fields/SoFieldData.h>
#include <Inventor/fields/SoMFEngine.h>
#include <Inventor/fields/SoMFNode.h>
#include <Inventor/fields/SoSFEngine.h>
#include <Inventor/fields/SoSFNode.h>
#include <Inventor/nodes/SoFile.h>
#include <Inventor/nodes/SoNode.h>
#include <Inventor/nodes/SoSeparator.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <climits>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>
#include <vector>

namespace bsdeform {

std::string SceneCheck::message() const {
  if (ok) return std::string();
  return file + ":" + std::to_string(line) + ": " + reason;
}

namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }

// What a field of a known type holds, as far as the guard cares.
enum class FieldKind { Other, Node, Engine };

// What a field of the given field type holds.
FieldKind kindOfFieldType(SoType t) {
  if (t.isBad()) return FieldKind::Other;
  if (t.isDerivedFrom(SoSFEngine::getClassTypeId()) || t.isDerivedFrom(SoMFEngine::getClassTypeId()))
    return FieldKind::Engine;
  if (t.isDerivedFrom(SoSFNode::getClassTypeId()) || t.isDerivedFrom(SoMFNode::getClassTypeId())) return FieldKind::Node;
  return FieldKind::Other;
}

// Field kinds of a known type by field name (from one instance's field data), cached per type.
const std::map<std::string, FieldKind>& fieldKinds(SoType type) {
  static std::map<int, std::map<std::string, FieldKind>> cache;
  auto it = cache.find(type.getKey());
  if (it != cache.end()) return it->second;
  std::map<std::string, FieldKind>& kinds = cache[type.getKey()];
  // Only field containers have fields; createInstance() of a field or event type is no SoBase.
  if (!type.canCreateInstance() || !type.isDerivedFrom(SoFieldContainer::getClassTypeId())) return kinds;
  auto* instance = static_cast<SoFieldContainer*>(type.createInstance());
  if (!instance) return kinds;
  instance->ref();
  if (const SoFieldData* fd = instance->getFieldData()) {
    for (int i = 0; i < fd->getNumFields(); ++i) {
      kinds[fd->getFieldName(i).getString()] = kindOfFieldType(fd->getField(instance, i)->getTypeId());
    }
  }
  instance->unref();
  return kinds;
}

// A type name as Coin's reader resolves it (with or without the "So" prefix).
SoType typeFromName(const std::string& word) {
  SoType t = SoType::fromName(SbName(word.c_str()));
  if (t.isBad()) t = SoType::fromName(SbName(("So" + word).c_str()));
  return t;
}

bool isEngineType(SoType t) { return !t.isBad() && t.isDerivedFrom(SoEngine::getClassTypeId()); }
bool isNodeType(SoType t) { return !t.isBad() && t.isDerivedFrom(SoNode::getClassTypeId()); }

struct Token {
  enum Kind { End, Word, String, Open, Close, OpenList, CloseList, Comma } kind = End;
  std::string text;  // word text, or string contents (raw, without quotes)
  int line = 0;
};

// One scan of one text (a File include is scanned by a nested Scanner).
class Scanner {
 public:
  Scanner(const char* data, std::size_t size, std::string name, std::string directory, const SceneLimits& limits,
          int baseDepth, std::set<std::string>& includeChain)
      : m_p(data),
        m_end(data + size),
        m_name(std::move(name)),
        m_dir(std::move(directory)),
        m_limits(limits),
        m_baseDepth(baseDepth),
        m_chain(includeChain) {}

  SceneCheck run();

 private:
  // ---- lexing
  bool fail(int line, std::string reason) {
    if (m_result.ok) {
      m_result.ok = false;
      m_result.file = m_name;
      m_result.line = line;
      m_result.reason = std::move(reason);
    }
    return false;
  }
  void skipSpaceAndComments();
  bool next(Token& t);
  bool readBaseName(std::string& name, int& line, bool reference);

  // ---- structure
  struct Frame {
    enum Kind { Body, ItemList } kind = Body;
    std::string typeName;  // Body: the type word before '{' ("" for a PROTO body and the like)
    SoType type;           // Body: the known type, or bad
    int defId = -1;        // Body: the definition this body belongs to
    int openLine = 0;
    int bracketDepth = 0;  // Body: '[' of ordinary field values not yet closed
    bool justOpened = true;
    FieldKind listKind = FieldKind::Other;  // ItemList: nodes or engines
    std::string listField;                  // ItemList: the field, for messages
    // File includes: the `name` value of a File node
    bool wantFileName = false;
    std::string fileName;
  };
  bool item(const Token& t, FieldKind kind, const std::string& field);  // one node/engine value
  bool openBody(const Token& brace, const std::string& typeName, int defId);
  bool closeBody();
  // `fields [ … ]`: for a known type only fields it has; for an unknown type, its node and
  // engine fields are kept for kindsOf()
  bool readDeclaration(const Frame& f);
  const std::map<std::string, FieldKind>& kindsOf(const Frame& f);
  bool use(const std::string& name, int line, FieldKind kind, const std::string& field);
  bool include(const Frame& f);
  int depth() const { return m_baseDepth + m_bodies; }

  const char* m_p;
  const char* m_end;
  int m_line = 1;
  std::string m_name, m_dir;
  const SceneLimits& m_limits;
  int m_baseDepth;
  std::set<std::string>& m_chain;
  SceneCheck m_result;

  std::vector<Frame> m_stack;
  int m_bodies = 0;
  struct Definition {
    SoType type;
    bool open = true;
  };
  std::vector<Definition> m_defs;
  std::map<std::string, int> m_names;  // DEF name -> latest definition
  // A DEF name read at body token m_defAt; it names the body whose '{' is two tokens later.
  int m_pendingDef = -1;
  long m_defAt = -10;
  long m_tokens = 0;
  // An SF node/engine field waiting for its one value (kind Other when none).
  FieldKind m_expectItem = FieldKind::Other;
  std::string m_expectField;
  // Node and engine fields that `fields [ … ]` declared for unknown type names, kept for the whole
  // file (Coin reads the declaration of each instance; the union is the cautious reading).
  std::map<std::string, std::map<std::string, FieldKind>> m_declared;
};

void Scanner::skipSpaceAndComments() {
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

bool Scanner::next(Token& t) {
  skipSpaceAndComments();
  t = Token();
  t.line = m_line;
  if (m_p >= m_end) return true;
  const char c = *m_p;
  if (c == '\0') return fail(t.line, "a NUL byte (character 0), which an ASCII Inventor file never holds");
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
    if (m_p >= m_end) return fail(t.line, "a string that is never closed (\")");
    const std::size_t n = std::size_t(m_p - start);
    ++m_p;
    if (n > m_limits.maxStringLength)
      return fail(t.line, "a quoted string of " + std::to_string(n) + " characters (at most " +
                              std::to_string(m_limits.maxStringLength) +
                              "; Coin 4.0 overflows its name table on names of 65,503 or more)");
    t.kind = Token::String;
    t.text.assign(start, n);
    return true;
  }
  // A word: up to whitespace, a comment, a string or punctuation. Coin's own readers may take a
  // longer run (a DEF name may contain '[' ',' '#'), so the run up to whitespace is what is bounded.
  const char* start = m_p;
  const char* run = m_p;
  while (run < m_end && !isSpace(*run) && *run != '"') ++run;
  if (std::size_t(run - start) > m_limits.maxWordLength)
    return fail(t.line, "a word of " + std::to_string(run - start) + " characters (at most " +
                            std::to_string(m_limits.maxWordLength) +
                            "; Coin 4.0's SbName overflows a heap buffer at 65,503)");
  while (m_p < m_end && !isSpace(*m_p) && !std::strchr("{}[],\"#", *m_p)) ++m_p;
  t.kind = Token::Word;
  t.text.assign(start, std::size_t(m_p - start));
  return true;
}

bool Scanner::readBaseName(std::string& name, int& line, bool reference) {
  // Coin reads the name after DEF or USE as every byte above 0x20 up to white space
  // (SoInput::read(SbName&, FALSE)); after USE, a '.' starts a field name and is put back.
  skipSpaceAndComments();
  line = m_line;
  const char* start = m_p;
  while (m_p < m_end && static_cast<unsigned char>(*m_p) > 0x20) ++m_p;
  if (std::size_t(m_p - start) > m_limits.maxWordLength)
    return fail(line, "a name of " + std::to_string(m_p - start) + " characters (at most " +
                          std::to_string(m_limits.maxWordLength) +
                          "; Coin 4.0's SbName overflows a heap buffer at 65,503)");
  if (reference) {
    const char* dot = static_cast<const char*>(std::memchr(start, '.', std::size_t(m_p - start)));
    if (dot) m_p = dot;
  }
  name.assign(start, std::size_t(m_p - start));
  return true;
}

bool Scanner::use(const std::string& name, int line, FieldKind kind, const std::string& field) {
  auto it = m_names.find(name);
  if (it == m_names.end()) {
    if (kind == FieldKind::Engine)
      return fail(line, "field '" + field + "': USE " + name + " refers to nothing DEF'ed before it");
    return true;  // Coin reports an unknown reference itself
  }
  const Definition& d = m_defs[std::size_t(it->second)];
  if (d.open)
    return fail(line, "USE " + name + " inside the definition of " + name +
                          " itself (a node or engine connected to itself; Coin 4.0 crashes on such a cycle)");
  if (kind == FieldKind::Engine && !isEngineType(d.type))
    return fail(line, "field '" + field + "': USE " + name + " is not an engine");
  if (kind == FieldKind::Node && !d.type.isBad() && !isNodeType(d.type))
    return fail(line, "field '" + field + "': USE " + name + " is not a node");
  return true;
}

bool Scanner::openBody(const Token& brace, const std::string& typeName, int defId) {
  Frame f;
  f.kind = Frame::Body;
  f.typeName = typeName;
  f.type = typeName.empty() ? SoType::badType() : typeFromName(typeName);
  f.defId = defId;
  f.openLine = brace.line;
  if (defId >= 0) m_defs[std::size_t(defId)].type = f.type;
  if (!f.type.isBad() && !f.type.isDerivedFrom(SoBase::getClassTypeId()))
    return fail(brace.line, "'" + typeName + "' is a Coin type that is neither a node nor an engine " +
                                "(Coin 4.0 writes through a wrong pointer when it reads one)");
  // Coin reads engines at the top level (SoDB::read skips them) but never frees one: only a DEF'ed
  // one can be used by anything.
  if (!f.type.isBad() && m_stack.size() == 1 && isEngineType(f.type) && defId < 0)
    return fail(brace.line, "'" + typeName + "' at the top level of the file is an engine without a DEF name, " +
                                "which nothing can use (Coin 4.0 reads it and never frees it)");
  ++m_bodies;
  if (depth() > m_limits.maxNesting)
    return fail(brace.line, "nodes nested " + std::to_string(depth()) + " deep (at most " +
                                std::to_string(m_limits.maxNesting) +
                                "; Coin 4.0's recursive reader and actions overflow the stack)");
  m_stack.push_back(f);
  return true;
}

bool Scanner::include(const Frame& f) {
  std::string path = f.fileName;
  if (path.empty()) return true;
  if (path[0] != '/' && !m_dir.empty()) {
    struct stat st {};
    const std::string inDir = m_dir + "/" + path;
    if (::stat(inDir.c_str(), &st) == 0) path = inDir;
  }
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return true;  // Coin reports it
  char resolved[PATH_MAX];
  const std::string key = ::realpath(path.c_str(), resolved) ? std::string(resolved) : path;
  if (m_chain.count(key))
    return fail(f.openLine, "File includes '" + f.fileName + "', which includes itself (Coin 4.0 recurses until it crashes)");
  if (std::size_t(st.st_size) > m_limits.maxFileBytes)
    return fail(f.openLine, "File '" + f.fileName + "' has " + std::to_string(st.st_size) + " bytes (at most " +
                                std::to_string(m_limits.maxFileBytes) + ")");
  std::FILE* fp = std::fopen(path.c_str(), "rb");
  if (!fp) return true;
  std::string text(std::size_t(st.st_size), '\0');
  const std::size_t got = std::fread(&text[0], 1, text.size(), fp);
  std::fclose(fp);
  text.resize(got);
  const std::size_t slash = key.rfind('/');
  m_chain.insert(key);
  Scanner inner(text.data(), text.size(), path, slash == std::string::npos ? std::string() : key.substr(0, slash),
                m_limits, depth(), m_chain);
  SceneCheck r = inner.run();
  m_chain.erase(key);
  if (!r.ok) {
    m_result = r;
    return false;
  }
  return true;
}

bool Scanner::readDeclaration(const Frame& f) {
  const bool known = !f.type.isBad();
  const auto& kinds = kindsOf(f);
  std::string type;  // the type of the pair being read ("" before it)
  Token t;
  while (next(t)) {
    if (t.kind == Token::CloseList) return true;
    if (t.kind == Token::Comma) continue;
    if (t.kind != Token::Word)
      return fail(t.line, "'fields [ … ]' of " + f.typeName + " holds something other than field types and names");
    if (type.empty()) {
      if (known && (t.text == "field" || t.text == "exposedField" || t.text == "eventIn" || t.text == "eventOut"))
        return fail(t.line, "'fields [ … ]' of " + f.typeName + ", a type Coin knows, uses VRML '" + t.text + "'");
      type = t.text;
      continue;
    }
    if (known && !kinds.count(t.text))
      return fail(t.line, "'fields [ … ]' declares '" + t.text + "', which " + f.typeName +
                              " does not have (Coin 4.0 would add it to every " + f.typeName +
                              " through a wild field pointer)");
    if (!known) {
      const FieldKind k = kindOfFieldType(typeFromName(type));
      if (k != FieldKind::Other) m_declared[f.typeName][t.text] = k;
    }
    type.clear();
  }
  if (m_result.ok) fail(m_line, "'fields [' of " + f.typeName + " is never closed");
  return false;
}

const std::map<std::string, FieldKind>& Scanner::kindsOf(const Frame& f) {
  if (!f.type.isBad()) return fieldKinds(f.type);
  static const std::map<std::string, FieldKind> none;
  auto it = m_declared.find(f.typeName);
  return it == m_declared.end() ? none : it->second;
}

bool Scanner::closeBody() {
  Frame f = m_stack.back();
  m_stack.pop_back();
  --m_bodies;
  if (f.defId >= 0) m_defs[std::size_t(f.defId)].open = false;
  if (!f.type.isBad() && f.type.isDerivedFrom(SoFile::getClassTypeId()) && !include(f)) return false;
  return true;
}

// `t` starts one value of a node or engine field: NULL, USE name, [DEF name] Type { … }.
bool Scanner::item(const Token& t, FieldKind kind, const std::string& field) {
  const char* what = kind == FieldKind::Engine ? "an engine" : "a node";
  if (t.kind != Token::Word)
    return fail(t.line, "field '" + field + "' holds " + what + " (a DEF, USE, NULL or a type name), not '" +
                            (t.kind == Token::String ? "\"" + t.text + "\"" : std::string(t.kind == Token::End ? "end of file" : "punctuation")) +
                            "' (Coin 4.0 loops allocating memory on it)");
  if (t.text == "NULL") return true;
  if (t.text == "USE") {
    std::string name;
    int line = 0;
    if (!readBaseName(name, line, true)) return false;
    return use(name, line, kind, field);
  }
  std::string typeWord = t.text;
  int typeLine = t.line;
  if (t.text == "DEF") {
    std::string name;
    int line = 0;
    if (!readBaseName(name, line, false)) return false;
    if (name.empty()) return fail(line, "DEF without a name");
    m_pendingDef = int(m_defs.size());
    m_defs.push_back(Definition{SoType::badType(), false});
    m_names[name] = m_pendingDef;
    Token w;
    if (!next(w)) return false;
    if (w.kind != Token::Word) return fail(w.line, "field '" + field + "': DEF " + name + " is not followed by a type name");
    typeWord = w.text;
    typeLine = w.line;
  }
  const SoType type = typeFromName(typeWord);
  if (kind == FieldKind::Engine && !isEngineType(type))
    return fail(typeLine, "field '" + field + "' holds engines; '" + typeWord +
                              "' is not an engine type (Coin 4.0 loops allocating memory on it)");
  if (kind == FieldKind::Node && !type.isBad() && !isNodeType(type))
    return fail(typeLine, "field '" + field + "' holds nodes; '" + typeWord + "' is not a node type");
  Token brace;
  if (!next(brace)) return false;
  if (brace.kind != Token::Open)
    return fail(brace.line, "field '" + field + "': '" + typeWord + "' is not followed by '{'");
  const int def = m_pendingDef;
  m_pendingDef = -1;
  if (def >= 0) m_defs[std::size_t(def)].open = true;
  return openBody(brace, typeWord, def);
}

SceneCheck Scanner::run() {
  // The header: binary files are not scanned, so not read.
  {
    const char* e = m_p;
    while (e < m_end && *e != '\n') ++e;
    const std::string header(m_p, std::size_t(e - m_p));
    if (header.rfind("#Inventor", 0) == 0 && header.find("binary") != std::string::npos) {
      fail(1, "binary Inventor files are not read (the guard in front of Coin's reader reads only ASCII); "
              "write the scene as ASCII");
      return m_result;
    }
    if (m_end - m_p >= 2 && (unsigned char)m_p[0] == 0x1f && (unsigned char)m_p[1] == 0x8b) {
      fail(1, "a compressed (gzip) file; uncompress it first");
      return m_result;
    }
  }
  Frame top;
  top.kind = Frame::Body;
  top.type = SoSeparator::getClassTypeId();
  top.justOpened = false;
  m_stack.push_back(top);
  std::string prevWord;  // the previous token when it was a word
  Token t;
  while (m_result.ok) {
    if (!next(t)) break;
    if (t.kind == Token::End) break;
    Frame& f = m_stack.back();

    if (f.kind == Frame::ItemList) {
      if (t.kind == Token::Comma) continue;
      if (t.kind == Token::CloseList) {
        m_stack.pop_back();
        prevWord.clear();
        continue;
      }
      const FieldKind k = f.listKind;
      const std::string field = f.listField;
      if (!item(t, k, field)) break;
      prevWord.clear();
      continue;
    }

    // ---- inside a body (or the top level)
    if (m_expectItem != FieldKind::Other) {
      const FieldKind k = m_expectItem;
      m_expectItem = FieldKind::Other;
      if (t.kind == Token::OpenList) {
        Frame list;
        list.kind = Frame::ItemList;
        list.listKind = k;
        list.listField = m_expectField;
        m_stack.push_back(list);
        continue;
      }
      if (t.kind == Token::Word && (t.text == "IS" || t.text == "=")) {  // VRML IS / a connection
        prevWord = t.text;
        continue;
      }
      if (!item(t, k, m_expectField)) break;
      prevWord.clear();
      continue;
    }
    const bool first = f.justOpened;
    f.justOpened = false;
    ++m_tokens;
    switch (t.kind) {
      case Token::Word: {
        if (t.text == "DEF") {
          std::string name;
          int line = 0;
          if (!readBaseName(name, line, false)) break;
          if (name.empty()) {
            fail(line, "DEF without a name");
            break;
          }
          m_pendingDef = int(m_defs.size());
          m_defAt = m_tokens;
          m_defs.push_back(Definition{SoType::badType(), false});
          m_names[name] = m_pendingDef;
          prevWord.clear();
          continue;
        }
        if (t.text == "USE") {
          std::string name;
          int line = 0;
          if (!readBaseName(name, line, true)) break;
          use(name, line, FieldKind::Other, std::string());
          prevWord.clear();
          continue;
        }
        if (first && t.text == "fields" && !f.typeName.empty() && !kindsOf(f).count("fields")) {
          // `fields [ … ]` declares the fields of a type the reader may not know.
          Token n;
          const char* save = m_p;
          const int saveLine = m_line;
          if (!next(n)) break;
          if (n.kind == Token::OpenList) {
            // Coin writes the declaration for extension types (ours), and it is harmless while it
            // names only fields the type has: SoFieldData::readFieldDescriptions adds any other
            // name to the class's field data with an offset from this one object.
            if (!readDeclaration(f)) break;
            continue;
          }
          m_p = save;
          m_line = saveLine;
        }
        if (f.bracketDepth == 0) {
          const auto& kinds = kindsOf(f);
          auto k = kinds.find(t.text);
          if (k != kinds.end() && k->second != FieldKind::Other) {
            m_expectItem = k->second;
            m_expectField = t.text;
            prevWord.clear();
            continue;
          }
          if (!f.type.isBad() && f.type.isDerivedFrom(SoFile::getClassTypeId()) && t.text == "name") f.wantFileName = true;
          else if (f.wantFileName) {
            f.fileName = t.text;
            f.wantFileName = false;
          }
        }
        prevWord = t.text;
        continue;
      }
      case Token::String:
        if (f.wantFileName) {
          f.fileName = t.text;
          f.wantFileName = false;
        }
        break;
      case Token::Open: {
        const std::string typeName = prevWord;
        const int def = m_tokens == m_defAt + 2 && !typeName.empty() ? m_pendingDef : -1;
        m_pendingDef = -1;
        if (def >= 0) m_defs[std::size_t(def)].open = true;
        openBody(t, typeName, def);
        prevWord.clear();
        continue;
      }
      case Token::Close:
        if (m_stack.size() == 1) {
          fail(t.line, "'}' without a matching '{'");
          break;
        }
        if (f.bracketDepth != 0) {
          fail(t.line, "'}' inside an unclosed '[' opened in " + (f.typeName.empty() ? std::string("this block") : f.typeName));
          break;
        }
        closeBody();
        break;
      case Token::OpenList: ++f.bracketDepth; break;
      case Token::CloseList:
        if (f.bracketDepth > 0) --f.bracketDepth;
        break;
      case Token::Comma:
      case Token::End: break;
    }
    prevWord.clear();
  }
  return m_result;
}

}  // namespace

SceneCheck checkSceneText(const char* data, std::size_t size, const std::string& name, const std::string& directory,
                          const SceneLimits& limits) {
  if (size > limits.maxFileBytes) {
    SceneCheck r;
    r.ok = false;
    r.file = name;
    r.line = 1;
    r.reason = std::to_string(size) + " bytes (at most " + std::to_string(limits.maxFileBytes) + ")";
    return r;
  }
  std::set<std::string> chain;
  Scanner s(data, size, name, directory, limits, 0, chain);
  return s.run();
}

SoSeparator* readSceneText(const char* data, std::size_t size, const std::string& name, std::string& error,
                           const std::string& directory, const SceneLimits& limits) {
  const SceneCheck check = checkSceneText(data, size, name, directory, limits);
  if (!check.ok) {
    error = check.message();
    return nullptr;
  }
  CoinMessageCapture errors(CoinMessageCapture::ReadErrors);
  SoInput in;
  if (!directory.empty()) SoInput::addDirectoryFirst(directory.c_str());
  in.setBuffer(data, size);
  SoSeparator* root = SoDB::readAll(&in);
  if (!directory.empty()) SoInput::removeDirectory(directory.c_str());
  if (!root) error = name + ": " + (errors.messages.empty() ? std::string("not an Inventor file") : errors.joined("\n"));
  return root;
}

SoSeparator* readSceneFile(const std::string& path, std::string& error, const SceneLimits& limits) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    error = path + ": " + std::strerror(errno);
    return nullptr;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    error = path + (S_ISDIR(st.st_mode) ? ": is a directory, not a scene file" : ": not a regular file");
    ::close(fd);
    return nullptr;
  }
  const std::size_t size = std::size_t(st.st_size);
  if (size > limits.maxFileBytes) {
    error = path + ": " + std::to_string(size) + " bytes (a scene file may have at most " +
            std::to_string(limits.maxFileBytes) + ")";
    ::close(fd);
    return nullptr;
  }
  // Mapped, not copied: a scene of hundreds of megabytes is scanned and read in place.
  void* map = size ? ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0) : nullptr;
  const int mapErrno = errno;
  ::close(fd);
  if (map == MAP_FAILED) {
    error = path + ": " + std::strerror(mapErrno);
    return nullptr;
  }
  std::string directory = ".";
  char resolved[PATH_MAX];
  if (::realpath(path.c_str(), resolved)) {
    const std::string full(resolved);
    const std::size_t slash = full.rfind('/');
    directory = slash == 0 ? std::string("/") : full.substr(0, slash);
  }
  SoSeparator* root = readSceneText(size ? static_cast<const char*>(map) : "", size, path, error, directory, limits);
  if (map) ::munmap(map, size);
  return root;
}

std::vector<SoBSplineDeformSurface*> sceneSurfaces(SoNode* root) {
  std::vector<SoBSplineDeformSurface*> out;
  if (!root) return out;
  SoSearchAction sa;
  sa.setType(SoBSplineDeformSurface::getClassTypeId());
  sa.setInterest(SoSearchAction::ALL);
  sa.apply(root);
  for (int i = 0; i < sa.getPaths().getLength(); ++i) {
    auto* s = static_cast<SoBSplineDeformSurface*>(sa.getPaths()[i]->getTail());
    if (std::find(out.begin(), out.end(), s) == out.end()) out.push_back(s);
  }
  return out;
}

}  // namespace bsdeform
