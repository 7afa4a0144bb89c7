// SPDX-License-Identifier: MIT
#pragma once
/// @file ParameterError.h
/// The error a model parameter's refused value raises: it names the parameter (as
/// bsdeform::ModelParameters, ShellMaterial and ShapeSize spell it: "numU", "degreeV", "w10",
/// "timeStep", "youngsModulus", "radius", "boundaryUMin", "pins", "restNet", ...) apart from
/// the sentence, so that a front end can show the refusal at its own field (the nodes map the
/// name through FieldInfo) without reading the text.
///
/// \code
/// try { Simulation sim(p); }
/// catch (const ParameterError& e) { std::cerr << e.parameter() << ": " << e.detail(); }
/// \endcode

#include <stdexcept>
#include <string>

namespace bsdeform {

class ParameterError : public std::invalid_argument {
 public:
  /// what() is "<label> <detail>", the label being the parameter's name unless given
  /// ("weight w10", "rest net").
  ParameterError(std::string parameter, std::string detail, const std::string& label = {})
      : std::invalid_argument((label.empty() ? parameter : label) + " " + detail),
        m_parameter(std::move(parameter)),
        m_detail(std::move(detail)) {}
  /// The parameter's name (see the file comment).
  const std::string& parameter() const { return m_parameter; }
  /// What is wrong with its value, without the name: "must be finite and > 0, got -1".
  const std::string& detail() const { return m_detail; }

 private:
  std::string m_parameter;
  std::string m_detail;
};

/// Throws ParameterError(parameter, detail, label) unless `ok`.
inline void requireParameter(bool ok, const char* parameter, const std::string& detail, const std::string& label = {}) {
  if (!ok) throw ParameterError(parameter, detail, label);
}

}  // namespace bsdeform
