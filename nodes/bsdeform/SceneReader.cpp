// SPDX-License-Identifier: MIT
#include "bsdeform/SceneReader.h"

#include <Inventor/SoDB.h>
#include <Inventor/SoInput.h>
#include <Inventor/SoPath.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/nodes/SoSeparator.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <set>

#include "bsdeform/CoinMessageCapture.h"
#include "bsdeform/SceneGuard.h"
#include "bsdeform/SceneLexer.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

std::string SceneCheck::message() const {
  if (ok) return std::string();
  return file + ":" + std::to_string(line) + ": " + reason;
}

std::size_t separateUseCommas(const char* data, std::size_t size, std::string& out, const SceneLimits& limits) {
  // Coin 4.0 reads the name after USE as every byte above 0x20 up to white space, so in
  // `obstacles [ USE A, USE B ]` (as people write lists, and as Coin's own writer lays out an
  // MFNode of references: `USE A,` newline) it looks for a node called "A,". A name Coin would
  // give a node never holds a comma (SoBase::setName replaces it), so unless the text DEFs a
  // name with the comma itself, the comma ends the reference: a space is put before it. Line
  // numbers do not move. The lexer is the guard's, so strings and comments are skipped alike.
  // most scenes (and the largest: saved nets) hold no reference at all: no second lexing pass
  if (!size || !::memmem(data, size, "USE", 3)) return 0;
  guard::SceneLexer lexer(data, size, limits);
  std::set<std::string> defined;
  std::vector<std::size_t> commas;  // offsets of the commas to separate
  guard::Token t;
  while (lexer.next(t) && t.kind != guard::Token::End) {
    if (t.kind != guard::Token::Word || (t.text != "DEF" && t.text != "USE")) continue;
    const bool reference = t.text == "USE";
    std::string base;
    int line = 0;
    if (!lexer.readBaseName(base, line, reference)) break;  // the guard refuses it, with its line
    if (!reference) {
      defined.insert(base);
      continue;
    }
    const std::size_t comma = base.find(',');
    if (comma == std::string::npos || comma == 0 || defined.count(base)) continue;
    const std::size_t start = std::size_t(lexer.mark().p - data) - base.size();
    commas.push_back(start + comma);
    // what follows the comma (`USE A,USE B`) is read again as tokens
    lexer.reset({data + start + comma + 1, line});
  }
  if (commas.empty()) return 0;
  out.clear();
  out.reserve(size + commas.size());
  std::size_t from = 0;
  for (const std::size_t at : commas) {
    out.append(data + from, at - from);
    out += ' ';
    from = at;
  }
  out.append(data + from, size - from);
  return commas.size();
}

SoSeparator* readSceneText(const char* data, std::size_t size, const std::string& name, std::string& error,
                           const std::string& directory, const SceneLimits& limits) {
  std::string separated;
  if (separateUseCommas(data, size, separated, limits) > 0) {
    data = separated.data();
    size = separated.size();
  }
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
  if (guard::largeFile(size, limits)) {
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
