// SPDX-License-Identifier: MIT
#include "bsdeform/CoinMessageCapture.h"

#include <Inventor/errors/SoDebugError.h>
#include <Inventor/errors/SoReadError.h>

namespace bsdeform {

CoinMessageCapture::CoinMessageCapture(int kinds) : m_kinds(kinds) {
  if (m_kinds & ReadErrors) {
    m_oldRead = SoReadError::getHandlerCallback();
    m_oldReadData = SoReadError::getHandlerData();
    SoReadError::setHandlerCallback(collect, this);
  }
  if (m_kinds & DebugErrors) {
    m_oldDebug = SoDebugError::getHandlerCallback();
    m_oldDebugData = SoDebugError::getHandlerData();
    SoDebugError::setHandlerCallback(collect, this);
  }
}

CoinMessageCapture::~CoinMessageCapture() {
  if (m_kinds & ReadErrors) SoReadError::setHandlerCallback(m_oldRead, m_oldReadData);
  if (m_kinds & DebugErrors) SoDebugError::setHandlerCallback(m_oldDebug, m_oldDebugData);
}

void CoinMessageCapture::collect(const SoError* error, void* self) {
  static_cast<CoinMessageCapture*>(self)->messages.push_back(error->getDebugString().getString());
}

std::string CoinMessageCapture::joined(const std::string& separator) const {
  std::string text;
  for (const std::string& m : messages) {
    if (!text.empty()) text += separator;
    text += m;
  }
  return text;
}

}  // namespace bsdeform
