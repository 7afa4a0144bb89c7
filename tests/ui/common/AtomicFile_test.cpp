// SPDX-License-Identifier: MIT
// saveFileAtomically and savePngAtomically (ui/common/AtomicFile.h) on a full disk: the previous
// file stays byte for byte, the temporary file is gone and the message names the file and the
// system's reason. Runs with tests/support/enospc_shim.c preloaded (tests/CMakeLists.txt); each
// case switches the full disk on for its own directory with setenv().
#include <QFile>
#include <QImage>
#include <QTemporaryDir>
#include <catch2/catch.hpp>

#include "AtomicFile.h"
#include "FullDiskFiles.h"

using bsdeform::saveFileAtomically;
using bsdeform::savePngAtomically;
using testsupport::checkKept;
using testsupport::entries;
using testsupport::slurp;
using FullDisk = testsupport::QtFullDisk;

namespace {

void put(const QString& path, const QByteArray& data) {
  QFile f(path);
  REQUIRE(f.open(QIODevice::WriteOnly));
  REQUIRE(f.write(data) == data.size());
}

}  // namespace

TEST_CASE("saveFileAtomically: a full disk keeps the previous file and gives the reason", "[ui]") {
  QTemporaryDir dir;
  const QString path = dir.filePath(QStringLiteral("data.csv"));
  const QByteArray old = "time,norm\n0,0\n1,0.5\n";
  put(path, old);
  QString error;
  SECTION("small contents (Qt buffers them; commit() alone reports success)") {
    FullDisk full(dir.path());
    CHECK(!saveFileAtomically(path, QByteArray("time,norm\n0,0\n1,0.7\n2,0.9\n"), error));
    checkKept(path, old, error);
  }
  SECTION("large contents, the disk fills part-way") {
    FullDisk full(dir.path(), 100000);
    CHECK(!saveFileAtomically(path, QByteArray(1 << 20, 'x'), error));
    checkKept(path, old, error);
  }
  SECTION("a writer function (PNG encoder)") {
    QImage image(64, 64, QImage::Format_RGB32);
    image.fill(Qt::red);
    FullDisk full(dir.path());
    CHECK(!saveFileAtomically(path, [&](QIODevice& d) { return image.save(&d, "PNG"); }, error));
    checkKept(path, old, error);
  }
  SECTION("a PNG encoded in memory first (savePngAtomically), full disk then room") {
    QImage image(40, 10, QImage::Format_ARGB32);  // converted by Qt's writer: the copy it leaked
    image.fill(Qt::blue);
    {
      FullDisk full(dir.path());
      CHECK(!savePngAtomically(path, image, error));
      checkKept(path, old, error);
    }
    REQUIRE(savePngAtomically(path, image, error));
    const QImage back(path, "PNG");
    CHECK(back.size() == image.size());
    CHECK(back.pixel(3, 3) == image.pixel(3, 3));
  }
  SECTION("the disk has room again: the file is replaced") {
    {
      FullDisk full(dir.path());
      CHECK(!saveFileAtomically(path, QByteArray("new"), error));
    }
    REQUIRE(saveFileAtomically(path, QByteArray("new"), error));
    CHECK(slurp(path) == "new");
  }
  SECTION("a writer that fails without an I/O error") {
    CHECK(!saveFileAtomically(path, [](QIODevice&) { return false; }, error));
    CHECK(error.contains(QStringLiteral("data.csv")));
    CHECK(slurp(path) == old);
    CHECK(entries(dir.path()) == QStringList{QStringLiteral("data.csv")});
  }
  SECTION("a missing directory") {
    CHECK(!saveFileAtomically(dir.filePath(QStringLiteral("nowhere/x.csv")), QByteArray("x"), error));
    CHECK(error.contains(QStringLiteral("x.csv")));
    CHECK(!error.contains(QStringLiteral("Unknown error")));
  }
}
