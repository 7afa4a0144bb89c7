// SPDX-License-Identifier: MIT
#include "StateFile.h"

#include <QDataStream>
#include <QFile>
#include <QIODevice>

#include "AtomicFile.h"

namespace bsdeform {

namespace {

const QByteArray kMagic = QByteArrayLiteral("bsdeform-states ");

void prepare(QDataStream& stream) {
  stream.setVersion(QDataStream::Qt_5_12);
  stream.setByteOrder(QDataStream::LittleEndian);
  stream.setFloatingPointPrecision(QDataStream::DoublePrecision);
}

void writeNet(QDataStream& out, const ControlNet& net) {
  for (Eigen::Index i = 0; i < net.size(); ++i) out << net.data()[i];
}

bool readNet(QDataStream& in, int rows, ControlNet& net) {
  net.resize(rows, 3);
  for (Eigen::Index i = 0; i < net.size(); ++i) in >> net.data()[i];
  return in.status() == QDataStream::Ok;
}

QString surfaceLabel(int index, const QString& name) {
  return name.isEmpty() ? QStringLiteral("surface %1 (no DEF name)").arg(index + 1)
                        : QStringLiteral("surface %1 '%2'").arg(index + 1).arg(name);
}

}  // namespace

std::vector<StateFileSurface> fileSurfacesOf(const std::vector<QString>& defNames, const StateFrame& frame) {
  std::vector<StateFileSurface> surfaces;
  for (std::size_t k = 0; k < defNames.size() && k < frame.surfaces.size(); ++k)
    surfaces.push_back({defNames[k], int(frame.surfaces[k].current.rows())});
  return surfaces;
}

bool writeStateFile(const QString& path, const std::vector<StateFileSurface>& surfaces, const StateHistory& history,
                    QString& error) {
  return saveFileAtomically(
      path,
      [&](QIODevice& device) {
        if (device.write(kMagic + QByteArray::number(kStateFileVersion) + '\n') < 0) return false;
        QDataStream out(&device);
        prepare(out);
        out << quint32(surfaces.size());
        for (const StateFileSurface& s : surfaces) out << s.name << qint32(s.netPoints);
        out << quint64(history.size());
        for (int f = 0; f < history.size(); ++f) {
          out << history[f].time;
          for (const SimulationState& s : history[f].surfaces) {
            out << s.time << qint64(s.steps) << s.subStepSize << s.startPending;
            writeNet(out, s.current);
            writeNet(out, s.previous);
          }
        }
        return out.status() == QDataStream::Ok;
      },
      error);
}

bool readStateFile(const QString& path, StateFileContents& contents, QString& error) {
  QFile file(path);
  if (!file.open(QIODevice::ReadOnly)) {
    error = QStringLiteral("cannot read '%1': %2").arg(path, file.errorString());
    return false;
  }
  auto refuse = [&](const QString& what) {
    error = QStringLiteral("'%1' is not a usable state file: %2").arg(path, what);
    return false;
  };
  const QByteArray header = file.readLine(64);
  if (!header.startsWith(kMagic)) return refuse(QStringLiteral("it does not start with 'bsdeform-states'"));
  const QByteArray version = header.mid(kMagic.size()).trimmed();
  if (version != QByteArray::number(kStateFileVersion))
    return refuse(QStringLiteral("version %1, this program reads version %2").arg(QString::fromLatin1(version)).arg(kStateFileVersion));
  QDataStream in(&file);
  prepare(in);
  StateFileContents read;
  quint32 count = 0;
  in >> count;
  // every count is checked against what the rest of the file can hold before anything is allocated
  const qint64 size = file.size();
  if (in.status() != QDataStream::Ok || count == 0 || qint64(count) * 8 > size)
    return refuse(QStringLiteral("surface count %1").arg(count));
  qint64 frameBytes = 8;
  for (quint32 k = 0; k < count; ++k) {
    StateFileSurface s;
    qint32 points = 0;
    in >> s.name >> points;
    if (in.status() != QDataStream::Ok || points <= 0 || qint64(points) * 48 > size)
      return refuse(QStringLiteral("%1: net points %2").arg(surfaceLabel(int(k), s.name)).arg(points));
    s.netPoints = points;
    frameBytes += 25 + qint64(points) * 48;
    read.surfaces.push_back(s);
  }
  quint64 frames = 0;
  in >> frames;
  if (in.status() != QDataStream::Ok || frames > quint64(size / frameBytes))
    return refuse(QStringLiteral("frame count %1 (the file holds at most %2)").arg(frames).arg(size / frameBytes));
  read.frames.reserve(frames);
  for (quint64 f = 0; f < frames; ++f) {
    double time = 0.0;
    in >> time;
    std::vector<SimulationState> states;
    for (quint32 k = 0; k < count; ++k) {
      SimulationState s;
      qint64 steps = 0;
      in >> s.time >> steps >> s.subStepSize >> s.startPending;
      s.steps = long(steps);
      if (!readNet(in, read.surfaces[k].netPoints, s.current) || !readNet(in, read.surfaces[k].netPoints, s.previous))
        return refuse(QStringLiteral("frame %1, %2: the file ends early").arg(f + 1).arg(surfaceLabel(int(k), read.surfaces[k].name)));
      states.push_back(std::move(s));
    }
    StateFrame frame = frameOf(std::move(states));
    if (!(frame.time == time) || (f > 0 && !comesBefore(read.frames.back(), frame)))
      return refuse(QStringLiteral("frame %1: time %2 is not that of its states or not after the frame before")
                        .arg(f + 1).arg(time, 0, 'g', 17));
    read.frames.push_back(std::move(frame));
  }
  if (!in.atEnd()) return refuse(QStringLiteral("%1 bytes after the last frame").arg(size - file.pos()));
  contents = std::move(read);
  return true;
}

QString stateFileMismatch(const QString& path, const std::vector<StateFileSurface>& file,
                          const std::vector<StateFileSurface>& scene) {
  if (file.size() != scene.size())
    return QStringLiteral("'%1' holds states of %2 surfaces, the scene has %3").arg(path).arg(file.size()).arg(scene.size());
  for (std::size_t k = 0; k < file.size(); ++k) {
    if (file[k].name != scene[k].name)
      return QStringLiteral("'%1': surface %2 is named '%3' in the file, '%4' in the scene")
          .arg(path).arg(k + 1).arg(file[k].name, scene[k].name);
    if (file[k].netPoints != scene[k].netPoints)
      return QStringLiteral("'%1': %2 has %3 control points in the file, %4 in the scene")
          .arg(path, surfaceLabel(int(k), file[k].name)).arg(file[k].netPoints).arg(scene[k].netPoints);
  }
  return QString();
}

}  // namespace bsdeform
