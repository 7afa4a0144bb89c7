// SPDX-License-Identifier: MIT
#include "Recorder.h"

#include <QFileInfo>
#include "AtomicFile.h"
#include "VideoWriter.h"

namespace bsdeform {

namespace {
/// At most this many repeated frames per capture (a jump of simulated time by minutes at a
/// high speed must not stall the window for seconds).
constexpr int kMaxFramesPerCapture = 250;
}  // namespace

Recorder::Recorder() = default;
Recorder::~Recorder() = default;

bool Recorder::start(const QString& path, double fps, const QSize& size, double simulatedTime, QString& error) {
  if (m_active) {
    error = tr("already recording to '%1'").arg(m_path);
    return false;
  }
  if (!(fps > 0.0) || fps > 1000.0) {
    error = tr("cannot record to '%1': frame rate %2 out of (0, 1000]").arg(path).arg(fps);
    return false;
  }
  const QString suffix = QFileInfo(path).suffix().toLower();
  m_pngSequence = suffix == QLatin1String("png");
  m_size = QSize(size.width() & ~1, size.height() & ~1);
  if (!m_pngSequence) {
    std::string why;
    m_video = VideoWriter::open(path.toStdString(), m_size.width(), m_size.height(), fps, why);
    if (!m_video) {
      error = QString::fromStdString(why);
      return false;
    }
  } else if (m_size.width() < 2 || m_size.height() < 2) {
    error = tr("cannot record to '%1': the view is %2 x %3 pixels").arg(path).arg(size.width()).arg(size.height());
    return false;
  }
  m_path = path;
  m_clock = FrameClock(fps, simulatedTime);
  m_frames = 0;
  m_active = true;
  return true;
}

bool Recorder::addFrame(const QImage& picture, QString& error) {
  // To the video's size first, to 3-byte pixels last: Qt's smooth scaling hands back 4-byte
  // pixels (RGB32) whatever it was given, which the encoder read as 3-byte ones (grey frames with
  // vertical stripes, stretched 4/3 sideways) whenever the view had an odd width or height. An
  // odd last row or column is cut (as `bsdeform-run --video` does), not scaled away; a view that
  // changed size while recording is scaled to the video's.
  QImage sized = picture;
  if (sized.size() != m_size) {
    const QSize extra = sized.size() - m_size;
    sized = extra.width() >= 0 && extra.width() <= 1 && extra.height() >= 0 && extra.height() <= 1
                ? sized.copy(QRect(QPoint(0, 0), m_size))
                : sized.scaled(m_size, Qt::IgnoreAspectRatio, Qt::SmoothTransformation);
  }
  const QImage rgb = sized.convertToFormat(QImage::Format_RGB888);
  if (rgb.format() != QImage::Format_RGB888 || rgb.size() != m_size) {
    error = tr("cannot record to '%1': the view's picture could not be converted").arg(m_path);
    return false;
  }
  if (m_pngSequence) {
    const QFileInfo info(m_path);
    const QString name = info.path() + QLatin1Char('/') + info.completeBaseName() +
                         QStringLiteral("_%1.png").arg(m_frames, 5, 10, QLatin1Char('0'));
    if (!savePngAtomically(name, rgb, error)) return false;
  } else {
    std::string why;
    if (!m_video->addFrame(rgb.constBits(), why, int(rgb.bytesPerLine()))) {  // QImage pads rows to 4 bytes
      error = QString::fromStdString(why);
      return false;
    }
  }
  ++m_frames;
  return true;
}

bool Recorder::capture(double simulatedTime, const std::function<QImage()>& grab, QString& error) {
  if (!m_active) return true;
  const long due = m_clock.due(simulatedTime, kMaxFramesPerCapture);
  if (!due) return true;
  const QImage picture = grab();
  if (picture.isNull()) {
    error = tr("cannot record to '%1': the view could not be read").arg(m_path);
  } else {
    for (int k = 0; k < due; ++k)
      if (!addFrame(picture, error)) break;
    if (error.isEmpty()) return true;
  }
  m_active = false;
  m_video.reset();  // discards the unfinished video; the previous file stays
  return false;
}

bool Recorder::stop(QString& error) {
  if (!m_active) return true;
  m_active = false;
  if (!m_video) return true;
  std::string why;
  const bool ok = m_video->finish(why);
  if (!ok) error = QString::fromStdString(why);
  m_video.reset();
  return ok;
}

}  // namespace bsdeform
