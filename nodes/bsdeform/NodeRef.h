// SPDX-License-Identifier: MIT
#pragma once
/// @file NodeRef.h
/// One reference to a Coin object (node, path, engine: anything with ref()/unref()), given back
/// when the holder goes: no node leaks on an early return. Movable, not copyable.

namespace bsdeform {

template <class T>
class NodeRef {
public:
  NodeRef() = default;
  /// Takes a reference to `node` (may be null).
  explicit NodeRef(T* node) { reset(node); }
  ~NodeRef() { reset(); }

  NodeRef(const NodeRef&) = delete;
  NodeRef& operator=(const NodeRef&) = delete;
  NodeRef(NodeRef&& other) noexcept : m_node(other.m_node) { other.m_node = nullptr; }
  NodeRef& operator=(NodeRef&& other) noexcept {
    if (this != &other) {
      reset();
      m_node = other.m_node;
      other.m_node = nullptr;
    }
    return *this;
  }

  /// Holds `node` instead (referenced before the old one is given back: resetting to the same
  /// node keeps it alive).
  void reset(T* node = nullptr) {
    if (node) node->ref();
    T* old = m_node;
    m_node = node;
    if (old) old->unref();
  }

  T* get() const { return m_node; }
  T* operator->() const { return m_node; }
  T& operator*() const { return *m_node; }
  explicit operator bool() const { return m_node != nullptr; }

private:
  T* m_node = nullptr;
};

}  // namespace bsdeform
