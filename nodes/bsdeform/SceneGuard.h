// SPDX-License-Identifier: MIT
#pragma once
/// @file SceneGuard.h
/// The hazards of Coin 4.0's reader that the guard refuses (internal to the nodes library, not
/// installed). One function per hazard, named as docs/reliability.md ("Reading files: a guard in
/// front of Coin's reader") names it; each returns the reason for refusing (a sentence saying what
/// was found and what Coin would do), or an empty string when the input is harmless. The scan that
/// calls them is checkSceneText (SceneReader.h); the lexical ones are called by SceneLexer.
/// All of them need SoDB::init() (they ask Coin about types).

#include <Inventor/SoType.h>

#include <cstddef>
#include <map>
#include <set>
#include <string>

#include "bsdeform/SceneReader.h"

namespace bsdeform::guard {

/// What a field holds, as far as the guard cares: node and engine fields read their values
/// through SoBase::read (the hazard wrongItemInField).
enum class FieldKind { Other, Node, Engine };

/// The kind of the values of a field type (SoSFEngine, SoMFNode, ...).
FieldKind kindOfFieldType(SoType fieldType);
/// The kinds of the fields of a known type by field name (cached per type; empty for a type that
/// is no field container).
const std::map<std::string, FieldKind>& fieldKinds(SoType type);
/// A type name as Coin's reader resolves it (with or without the "So" prefix); bad if unknown.
SoType typeFromName(const std::string& word);
bool isEngineType(SoType t);
bool isNodeType(SoType t);

/// Which run of characters longName measures (the messages differ).
enum class NameKind { Word, QuotedString, BaseName };

/// "a name, identifier or number of 65,503+ characters": Coin's SbName overflows a heap buffer.
/// Any run of non-blank characters, a DEF/USE name and a quoted string longer than the limit.
std::string longName(std::size_t length, NameKind kind, const SceneLimits& limits);

/// "`fields [ … ]` naming a field the type does not have": on a type Coin knows (`fieldsOfType`
/// are its fields), `word` is checked; `isFieldType` says whether it stands where a field type is
/// declared (then a VRML keyword is refused) or where a field name is (then a name the type lacks).
std::string undeclaredField(const std::string& typeName, const std::map<std::string, FieldKind>& fieldsOfType,
                            const std::string& word, bool isFieldType);

/// "a USE X inside X's own definition" (an engine input connected to its own output): `isOpen`
/// says whether the body of the definition `name` refers to is still being read.
std::string selfReference(const std::string& name, bool isOpen);

/// "12,000 nested Separators": `depth` nodes/engines inside each other, across includes.
std::string deepNesting(int depth, const SceneLimits& limits);

/// What stands where a node or engine field expects one value.
struct ItemValue {
  enum Form { NotAWord, Use, Type } form = NotAWord;
  std::string text;       ///< NotAWord: how to show it; Use: the name; Type: the type word
  bool defined = false;   ///< Use: the name was DEF'ed before
  SoType type;            ///< Use: the type of the DEF'ed body; Type: the type the word names
};
/// "anything but an engine in an engine field" (and anything but a node in a node field): a node
/// or engine field `field` of kind `kind` must hold NULL, USE of one, or [DEF name] Type { … } of one.
std::string wrongItemInField(FieldKind kind, const std::string& field, const ItemValue& value);

/// "an unknown type declaring an engine field": the kind of a field that `fields [ … ]` declares
/// as `fieldType` for an unknown type name; node and engine ones are kept for the whole file and
/// their values checked by wrongItemInField, as a known type's.
FieldKind itemFieldOfUnknownType(const std::string& fieldType);

/// "a Coin type that is no node or engine used as one": `type` (named `typeName`) before '{'.
std::string notANodeOrEngine(SoType type, const std::string& typeName);

/// "an engine without a DEF name at the top level": Coin reads it and never frees it.
std::string unnamedTopLevelEngine(SoType type, const std::string& typeName, bool atTopLevel, bool hasDefName);

/// "a NUL byte": `c` at the start of a token.
std::string nulByte(char c);

/// "binary or gzip-compressed files": the first bytes of a text.
std::string binaryOrCompressed(const char* data, std::size_t size);

/// The file size limit (`SceneLimits::maxFileBytes`) of a scene or an included file.
bool largeFile(std::size_t bytes, const SceneLimits& limits);

/// An include of itself: `File { name "fileName" }` whose real path `key` is already in the chain
/// of files being read.
std::string includesItself(const std::string& fileName, const std::string& key, const std::set<std::string>& chain);

}  // namespace bsdeform::guard
