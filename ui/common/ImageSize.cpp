// SPDX-License-Identifier: MIT
#include "ImageSize.h"

#include <QStringList>

namespace bsdeform {

bool parseImageSize(const QString& text, QSize& size) {
  const QStringList wh = text.split(QLatin1Char('x'));
  if (wh.size() != 2) return false;
  bool okW = false, okH = false;
  const int w = wh[0].trimmed().toInt(&okW), h = wh[1].trimmed().toInt(&okH);
  if (!okW || !okH || w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide) return false;
  size = QSize(w, h);
  return true;
}

}  // namespace bsdeform
