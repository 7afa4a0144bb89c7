// SPDX-License-Identifier: MIT
#include "bsdeform/SceneGuard.h"

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
#include <sys/stat.h>

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "bsdeform/SceneLexer.h"

namespace bsdeform::guard {

FieldKind kindOfFieldType(SoType t) {
  if (t.isBad()) return FieldKind::Other;
  if (t.isDerivedFrom(SoSFEngine::getClassTypeId()) || t.isDerivedFrom(SoMFEngine::getClassTypeId()))
    return FieldKind::Engine;
  if (t.isDerivedFrom(SoSFNode::getClassTypeId()) || t.isDerivedFrom(SoMFNode::getClassTypeId())) return FieldKind::Node;
  return FieldKind::Other;
}

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

SoType typeFromName(const std::string& word) {
  SoType t = SoType::fromName(SbName(word.c_str()));
  if (t.isBad()) t = SoType::fromName(SbName(("So" + word).c_str()));
  return t;
}

bool isEngineType(SoType t) { return !t.isBad() && t.isDerivedFrom(SoEngine::getClassTypeId()); }
bool isNodeType(SoType t) { return !t.isBad() && t.isDerivedFrom(SoNode::getClassTypeId()); }

// ---- the hazards, in the order of docs/reliability.md

std::string longName(std::size_t length, NameKind kind, const SceneLimits& limits) {
  const std::size_t limit = kind == NameKind::QuotedString ? limits.maxStringLength : limits.maxWordLength;
  if (length <= limit) return std::string();
  const std::string at = " characters (at most " + std::to_string(limit) + "; ";
  switch (kind) {
    case NameKind::QuotedString:
      return "a quoted string of " + std::to_string(length) + at + "Coin 4.0 overflows its name table on names of 65,503 or more)";
    case NameKind::Word: return "a word of " + std::to_string(length) + at + "Coin 4.0's SbName overflows a heap buffer at 65,503)";
    case NameKind::BaseName: break;
  }
  return "a name of " + std::to_string(length) + at + "Coin 4.0's SbName overflows a heap buffer at 65,503)";
}

std::string undeclaredField(const std::string& typeName, const std::map<std::string, FieldKind>& fieldsOfType,
                            const std::string& word, bool isFieldType) {
  if (isFieldType) {
    if (word == "field" || word == "exposedField" || word == "eventIn" || word == "eventOut")
      return "'fields [ … ]' of " + typeName + ", a type Coin knows, uses VRML '" + word + "'";
    return std::string();
  }
  if (fieldsOfType.count(word)) return std::string();
  return "'fields [ … ]' declares '" + word + "', which " + typeName + " does not have (Coin 4.0 would add it to every " +
         typeName + " through a wild field pointer)";
}

std::string selfReference(const std::string& name, bool isOpen) {
  if (!isOpen) return std::string();
  return "USE " + name + " inside the definition of " + name +
         " itself (a node or engine connected to itself; Coin 4.0 crashes on such a cycle)";
}

std::string deepNesting(int depth, const SceneLimits& limits) {
  if (depth <= limits.maxNesting) return std::string();
  return "nodes nested " + std::to_string(depth) + " deep (at most " + std::to_string(limits.maxNesting) +
         "; Coin 4.0's recursive reader and actions overflow the stack)";
}

std::string wrongItemInField(FieldKind kind, const std::string& field, const ItemValue& value) {
  if (kind == FieldKind::Other) return std::string();
  const bool engines = kind == FieldKind::Engine;
  switch (value.form) {
    case ItemValue::NotAWord:
      return "field '" + field + "' holds " + (engines ? "an engine" : "a node") + " (a DEF, USE, NULL or a type name), not '" +
             value.text + "' (Coin 4.0 loops allocating memory on it)";
    case ItemValue::Use:
      if (!value.defined)  // an unknown node reference Coin reports itself
        return engines ? "field '" + field + "': USE " + value.text + " refers to nothing DEF'ed before it" : std::string();
      if (engines && !isEngineType(value.type)) return "field '" + field + "': USE " + value.text + " is not an engine";
      if (!engines && !value.type.isBad() && !isNodeType(value.type))
        return "field '" + field + "': USE " + value.text + " is not a node";
      return std::string();
    case ItemValue::Type:
      if (engines && !isEngineType(value.type))
        return "field '" + field + "' holds engines; '" + value.text +
               "' is not an engine type (Coin 4.0 loops allocating memory on it)";
      if (!engines && !value.type.isBad() && !isNodeType(value.type))
        return "field '" + field + "' holds nodes; '" + value.text + "' is not a node type";
      return std::string();
  }
  return std::string();
}

FieldKind itemFieldOfUnknownType(const std::string& fieldType) { return kindOfFieldType(typeFromName(fieldType)); }

std::string notANodeOrEngine(SoType type, const std::string& typeName) {
  if (type.isBad() || type.isDerivedFrom(SoBase::getClassTypeId())) return std::string();
  return "'" + typeName + "' is a Coin type that is neither a node nor an engine " +
         "(Coin 4.0 writes through a wrong pointer when it reads one)";
}

std::string unnamedTopLevelEngine(SoType type, const std::string& typeName, bool atTopLevel, bool hasDefName) {
  if (!atTopLevel || hasDefName || !isEngineType(type)) return std::string();
  return "'" + typeName + "' at the top level of the file is an engine without a DEF name, " +
         "which nothing can use (Coin 4.0 reads it and never frees it)";
}

std::string nulByte(char c) {
  if (c != '\0') return std::string();
  return "a NUL byte (character 0), which an ASCII Inventor file never holds";
}

std::string binaryOrCompressed(const char* data, std::size_t size) {
  const char* e = data;
  while (e < data + size && *e != '\n') ++e;
  const std::string header(data, std::size_t(e - data));
  if (header.rfind("#Inventor", 0) == 0 && header.find("binary") != std::string::npos)
    return "binary Inventor files are not read (the guard in front of Coin's reader reads only ASCII); "
           "write the scene as ASCII";
  if (size >= 2 && (unsigned char)data[0] == 0x1f && (unsigned char)data[1] == 0x8b)
    return "a compressed (gzip) file; uncompress it first";
  return std::string();
}

bool largeFile(std::size_t bytes, const SceneLimits& limits) { return bytes > limits.maxFileBytes; }

std::string includesItself(const std::string& fileName, const std::string& key, const std::set<std::string>& chain) {
  if (!chain.count(key)) return std::string();
  return "File includes '" + fileName + "', which includes itself (Coin 4.0 recurses until it crashes)";
}

namespace {

// One scan of one text (a File include is scanned by a nested Scanner): the structure of bodies,
// field values and DEF/USE names, with the hazard checks above at the places they apply.
class Scanner {
 public:
  Scanner(const char* data, std::size_t size, std::string name, std::string directory, const SceneLimits& limits,
          int baseDepth, std::set<std::string>& includeChain)
      : m_data(data),
        m_size(size),
        m_lex(data, size, limits),
        m_name(std::move(name)),
        m_dir(std::move(directory)),
        m_limits(limits),
        m_baseDepth(baseDepth),
        m_chain(includeChain) {}

  SceneCheck run();

 private:
  bool fail(int line, std::string reason) {
    if (m_result.ok) {
      m_result.ok = false;
      m_result.file = m_name;
      m_result.line = line;
      m_result.reason = std::move(reason);
    }
    return false;
  }
  // fails with `reason` unless it is empty
  bool refuseIf(int line, std::string reason) { return reason.empty() || fail(line, std::move(reason)); }
  bool next(Token& t) { return m_lex.next(t) || fail(m_lex.refusalLine(), m_lex.refusal()); }
  bool readBaseName(std::string& name, int& line, bool reference) {
    return m_lex.readBaseName(name, line, reference) || fail(m_lex.refusalLine(), m_lex.refusal());
  }

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

  const char* m_data;
  std::size_t m_size;
  SceneLexer m_lex;
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

bool Scanner::use(const std::string& name, int line, FieldKind kind, const std::string& field) {
  ItemValue value;
  value.form = ItemValue::Use;
  value.text = name;
  auto it = m_names.find(name);
  if (it == m_names.end()) return refuseIf(line, wrongItemInField(kind, field, value));  // Coin reports the rest
  const Definition& d = m_defs[std::size_t(it->second)];
  if (!refuseIf(line, selfReference(name, d.open))) return false;
  value.defined = true;
  value.type = d.type;
  return refuseIf(line, wrongItemInField(kind, field, value));
}

bool Scanner::openBody(const Token& brace, const std::string& typeName, int defId) {
  Frame f;
  f.kind = Frame::Body;
  f.typeName = typeName;
  f.type = typeName.empty() ? SoType::badType() : typeFromName(typeName);
  f.defId = defId;
  f.openLine = brace.line;
  if (defId >= 0) m_defs[std::size_t(defId)].type = f.type;
  if (!refuseIf(brace.line, notANodeOrEngine(f.type, typeName))) return false;
  if (!refuseIf(brace.line, unnamedTopLevelEngine(f.type, typeName, m_stack.size() == 1, defId >= 0))) return false;
  ++m_bodies;
  if (!refuseIf(brace.line, deepNesting(depth(), m_limits))) return false;
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
  if (!refuseIf(f.openLine, includesItself(f.fileName, key, m_chain))) return false;
  if (largeFile(std::size_t(st.st_size), m_limits))
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
      if (known && !refuseIf(t.line, undeclaredField(f.typeName, kinds, t.text, true))) return false;
      type = t.text;
      continue;
    }
    if (known && !refuseIf(t.line, undeclaredField(f.typeName, kinds, t.text, false))) return false;
    if (!known) {
      const FieldKind k = itemFieldOfUnknownType(type);
      if (k != FieldKind::Other) m_declared[f.typeName][t.text] = k;
    }
    type.clear();
  }
  if (m_result.ok) fail(m_lex.line(), "'fields [' of " + f.typeName + " is never closed");
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
  if (t.kind != Token::Word) {
    ItemValue value;
    value.text = t.kind == Token::String ? "\"" + t.text + "\"" : std::string(t.kind == Token::End ? "end of file" : "punctuation");
    return refuseIf(t.line, wrongItemInField(kind, field, value));
  }
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
  ItemValue value;
  value.form = ItemValue::Type;
  value.text = typeWord;
  value.type = typeFromName(typeWord);
  if (!refuseIf(typeLine, wrongItemInField(kind, field, value))) return false;
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
  // binary files are not scanned, so not read
  if (!refuseIf(1, binaryOrCompressed(m_data, m_size))) return m_result;
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
          const SceneLexer::Mark save = m_lex.mark();
          if (!next(n)) break;
          if (n.kind == Token::OpenList) {
            // Coin writes the declaration for extension types (ours), and it is harmless while it
            // names only fields the type has: SoFieldData::readFieldDescriptions adds any other
            // name to the class's field data with an offset from this one object.
            if (!readDeclaration(f)) break;
            continue;
          }
          m_lex.reset(save);
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

}  // namespace bsdeform::guard

namespace bsdeform {

SceneCheck checkSceneText(const char* data, std::size_t size, const std::string& name, const std::string& directory,
                          const SceneLimits& limits) {
  if (guard::largeFile(size, limits)) {
    SceneCheck r;
    r.ok = false;
    r.file = name;
    r.line = 1;
    r.reason = std::to_string(size) + " bytes (at most " + std::to_string(limits.maxFileBytes) + ")";
    return r;
  }
  std::set<std::string> chain;
  guard::Scanner s(data, size, name, directory, limits, 0, chain);
  return s.run();
}

}  // namespace bsdeform
