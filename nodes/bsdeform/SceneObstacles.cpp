// SPDX-License-Identifier: MIT
#include "bsdeform/SceneObstacles.h"

#include <Inventor/SbViewportRegion.h>
#include <Inventor/SoPath.h>
#include <Inventor/SoPrimitiveVertex.h>
#include <Inventor/actions/SoCallbackAction.h>
#include <Inventor/actions/SoGetMatrixAction.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/fields/SoMFNode.h>
#include <Inventor/fields/SoMFString.h>
#include <Inventor/elements/SoCoordinateElement.h>
#include <Inventor/elements/SoNormalElement.h>
#include <Inventor/nodes/SoIndexedShape.h>
#include <Inventor/nodes/SoNode.h>
#include <Inventor/nodes/SoVertexProperty.h>
#include <Inventor/nodes/SoShape.h>
#include <Inventor/sensors/SoNodeSensor.h>
#include <Inventor/sensors/SoPathSensor.h>

#include "bsdeform/CoinEigen.h"
#include "bsdeform/SceneText.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

struct SceneObstacles::Entry {
  SoNode* node = nullptr;  // ref'ed
  SoPath* path = nullptr;  // ref'ed; null when the node is not in the scene
  std::unique_ptr<SoSensor> sensor;
  std::shared_ptr<TriangleTree> tree;
  ~Entry() {
    sensor.reset();
    if (path) path->unref();
    if (node) node->unref();
  }
};

SceneObstacles::SceneObstacles() : m_world(std::make_shared<ContactWorld>()) {}
SceneObstacles::~SceneObstacles() = default;

void SceneObstacles::sensorFired(void* data, SoSensor*) { static_cast<SceneObstacles*>(data)->m_dirty = true; }

namespace {

SoPath* firstPath(SoNode* root, SoNode* node) {
  if (!root || !node) return nullptr;
  SoSearchAction sa;
  sa.setNode(node);
  sa.setInterest(SoSearchAction::FIRST);
  sa.apply(root);
  SoPath* p = sa.getPath();
  if (!p) return nullptr;
  p->ref();  // the action's path goes with the action
  return p;
}

struct Gathered {
  SoNode* self;
  TriangleMesh mesh;
  std::vector<std::string> skipped;  // indexed shapes refused by checkIndices
  bool proxies = false;              // other surfaces as their collision proxies
};

// The surface itself is never an obstacle. Another surface is its tessellation (its shape's
// triangles), or, for barrier contact, its collision proxy: the triangles its own barrier keeps
// the offset with, so that two surfaces measure the same distances to each other.
SoCallbackAction::Response surfaceObstacle(void* data, SoCallbackAction* action, const SoNode* node) {
  auto* g = static_cast<Gathered*>(data);
  if (node == g->self) return SoCallbackAction::PRUNE;
  if (!g->proxies) return SoCallbackAction::CONTINUE;
  auto* surface = const_cast<SoBSplineDeformSurface*>(static_cast<const SoBSplineDeformSurface*>(node));
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  surface->collisionProxyMesh(vertices, triangles);
  Eigen::Matrix3d linear;
  Eigen::Vector3d offset;
  affineOf(action->getModelMatrix(), linear, offset);
  const int first = int(g->mesh.vertices.size());
  for (const Eigen::Vector3d& p : vertices) g->mesh.vertices.push_back(linear * p + offset);
  for (const Eigen::Vector3i& t : triangles) g->mesh.triangles.emplace_back(t + Eigen::Vector3i::Constant(first));
  return SoCallbackAction::PRUNE;
}

// Coin's indexed shapes read coordinates and normals at their indices without a range check
// (an IndexedFaceSet with coordIndex beyond its Coordinate3 reads past the array while
// generating triangles). A shape with a coordIndex out of range, or a normalIndex out of the
// normals given (none given: Coin computes its own), is skipped, and said so.
SoCallbackAction::Response checkIndices(void* data, SoCallbackAction* action, const SoNode* node) {
  const auto* shape = static_cast<const SoIndexedShape*>(node);
  const auto* vp = static_cast<const SoVertexProperty*>(shape->vertexProperty.getValue());
  SoState* state = action->getState();
  const bool ownCoords = vp && vp->vertex.getNum() > 0;
  const int coords = ownCoords ? vp->vertex.getNum() : SoCoordinateElement::getInstance(state)->getNum();
  const bool ownNormals = vp && vp->normal.getNum() > 0;
  const int normals = ownNormals ? vp->normal.getNum() : SoNormalElement::getInstance(state)->getNum();
  auto bad = [](const SoMFInt32& index, int count) {
    for (int i = 0; i < index.getNum(); ++i)
      if (index[i] < -1 || index[i] >= count) return i;
    return -1;
  };
  std::string why;
  if (int i = bad(shape->coordIndex, coords); i >= 0)
    why = "coordIndex [" + std::to_string(i) + "] = " + std::to_string(shape->coordIndex[i]) + " with " +
          std::to_string(coords) + " coordinates";
  else if (int j = shape->normalIndex.getNum() && normals > 0 ? bad(shape->normalIndex, normals) : -1; j >= 0)
    why = "normalIndex [" + std::to_string(j) + "] = " + std::to_string(shape->normalIndex[j]) + " with " +
          std::to_string(normals) + " normals";
  if (why.empty()) return SoCallbackAction::CONTINUE;
  const SbName name = node->getName();
  static_cast<Gathered*>(data)->skipped.push_back(std::string(node->getTypeId().getName().getString()) +
                                                  (name.getLength() ? std::string(" '") + name.getString() + "'" : "") +
                                                  " skipped: " + why);
  return SoCallbackAction::PRUNE;
}

void addTriangle(void* data, SoCallbackAction* action, const SoPrimitiveVertex* a, const SoPrimitiveVertex* b,
                 const SoPrimitiveVertex* c) {
  auto* g = static_cast<Gathered*>(data);
  const SbMatrix& m = action->getModelMatrix();
  const int first = int(g->mesh.vertices.size());
  for (const SoPrimitiveVertex* v : {a, b, c}) {
    SbVec3f w;
    m.multVecMatrix(v->getPoint(), w);
    g->mesh.vertices.emplace_back(w[0], w[1], w[2]);
  }
  g->mesh.triangles.emplace_back(first, first + 1, first + 2);
}

std::string describe(const char* field, int i, SoNode* node) {
  const SbName name = node->getName();
  return std::string("field '") + field + "' [" + std::to_string(i) + "] (" + node->getTypeId().getName().getString() +
         (name.getLength() ? std::string(" '") + name.getString() + "'" : std::string()) + ")";
}

SoNode* findByName(SoNode* root, const SbName& name) {
  if (!root) return nullptr;
  SoSearchAction sa;
  sa.setName(name);
  sa.setInterest(SoSearchAction::FIRST);
  sa.setSearchingAll(TRUE);  // also below switches' inactive children
  sa.apply(root);
  return sa.getPath() ? sa.getPath()->getTail() : nullptr;
}

}  // namespace

void SceneObstacles::gather(SoNode* sceneRoot, SoNode* self, const SoMFNode& obstacles, const SoMFString& names,
                            std::vector<std::string>& warnings) {
  std::vector<std::unique_ptr<Entry>> previous;
  previous.swap(m_entries);
  std::vector<ContactWorld::Obstacle> world;
  // the listed nodes, then the named ones, each with the field entry it came from
  std::vector<std::pair<SoNode*, std::string>> listed;
  for (int i = 0; i < obstacles.getNum(); ++i) {
    SoNode* node = obstacles[i];
    if (!node)
      warnings.push_back("field 'obstacles' [" + std::to_string(i) + "] is NULL; ignored");
    else
      listed.emplace_back(node, describe("obstacles", i, node));
  }
  // Names are looked up in the scene; before the surface knows it (no traversal yet) they wait
  // for the gathering that follows the first traversal.
  for (int i = 0; sceneRoot && i < names.getNum(); ++i) {
    const SbString& text = names[i];
    SoNode* node = text.getLength() ? findByName(sceneRoot, SbName(text)) : nullptr;
    if (!node)
      warnings.push_back("field 'obstacleNames' [" + std::to_string(i) + "] '" + text.getString() +
                         "': no node of that name in the scene; ignored");
    else
      listed.emplace_back(node, describe("obstacleNames", i, node));
  }
  for (const auto& [node, label] : listed) {
    if (node == self) {
      warnings.push_back(label + " is the surface itself (self-collision is not supported); ignored");
      continue;
    }
    auto e = std::make_unique<Entry>();
    e->node = node;
    node->ref();
    e->path = firstPath(sceneRoot, node);
    Gathered g{self, {}, {}, m_surfaceProxies};
    SoCallbackAction cb;
    cb.addPreCallback(SoBSplineDeformSurface::getClassTypeId(), surfaceObstacle, &g);
    cb.addPreCallback(SoIndexedShape::getClassTypeId(), checkIndices, &g);
    cb.addTriangleCallback(SoShape::getClassTypeId(), addTriangle, &g);
    if (e->path)
      cb.apply(e->path);
    else
      cb.apply(node);
    for (const std::string& why : g.skipped) warnings.push_back(label + ": " + why);
    TriangleMesh mesh = weldVertices(g.mesh);
    // at what a scene file keeps of a double (snap15, as the surfaces keep their state: see
    // Simulation::setStateRounding), so that where a barrier last saw an obstacle (its
    // forceState) reads back as the very pose, and a resumed run sweeps nothing the
    // uninterrupted one did not
    for (Eigen::Vector3d& v : mesh.vertices) v = v.unaryExpr([](double x) { return snap15(x); });
    // The same triangles as before (a moved Transform, the other surface's next step): refit.
    for (auto& p : previous) {
      if (!p || p->node != node || !p->tree || p->tree->mesh().vertices.size() != mesh.vertices.size()) continue;
      if (p->tree->mesh().triangles == mesh.triangles) {  // update() re-selects degenerate ones
        p->tree->update(mesh.vertices);
        e->tree = p->tree;
        ++m_refits;
      }
      break;
    }
    if (!e->tree) {
      e->tree = std::make_shared<TriangleTree>(mesh);
      ++m_builds;
    }
    if (e->tree->droppedTriangles() > 0)
      warnings.push_back(label + ": " + std::to_string(e->tree->droppedTriangles()) +
                         " degenerate or non-finite triangles dropped");
    if (e->tree->triangleCount() == 0) {
      warnings.push_back(label + " has no triangles; ignored");
    } else {
      const SbName name = node->getName();
      world.push_back({e->tree, isClosedMesh(e->tree->mesh()),
                       std::string(node->getTypeId().getName().getString()) +
                           (name.getLength() ? std::string(" '") + name.getString() + "'" : std::string())});
    }
    // Changes above the obstacle in the scene (a Transform) reach us through a path sensor;
    // changes inside it also through the force field's `obstacles` field.
    if (e->path) {
      auto sensor = std::make_unique<SoPathSensor>(sensorFired, this);
      sensor->setPriority(0);  // immediate: no delay queue needed (the runner has none)
      sensor->attach(e->path);
      e->sensor = std::move(sensor);
    } else {
      auto sensor = std::make_unique<SoNodeSensor>(sensorFired, this);
      sensor->setPriority(0);
      sensor->attach(node);
      e->sensor = std::move(sensor);
    }
    m_entries.push_back(std::move(e));
  }
  m_world->obstacles = std::move(world);
}

bool surfaceFrame(SoNode* sceneRoot, SoNode* surface, Eigen::Matrix3d& linear, Eigen::Vector3d& offset) {
  linear.setIdentity();
  offset.setZero();
  SoPath* path = firstPath(sceneRoot, surface);
  if (!path) return false;
  SoGetMatrixAction ma(SbViewportRegion(1, 1));
  ma.apply(path);
  path->unref();
  affineOf(ma.getMatrix(), linear, offset);
  return true;
}

void SceneObstacles::update(SoNode* sceneRoot, SoNode* self, const SoMFNode& obstacles, const SoMFString& names,
                            bool obstaclesChanged, std::vector<std::string>& warnings, bool surfaceProxies) {
  // the surface's own frame
  Eigen::Matrix3d linear;
  Eigen::Vector3d offset;
  if (surfaceFrame(sceneRoot, self, linear, offset)) {
    m_world->linear = linear;
    m_world->offset = offset;
  }
  if (sceneRoot != m_root) {
    m_root = sceneRoot;
    m_dirty = true;
  }
  if (surfaceProxies != m_surfaceProxies) {
    m_surfaceProxies = surfaceProxies;
    m_dirty = true;
  }
  if (m_dirty || obstaclesChanged) {
    m_dirty = false;
    gather(sceneRoot, self, obstacles, names, warnings);
    m_dirty = false;  // our own traversal does not count as a change
  }
}

}  // namespace bsdeform
