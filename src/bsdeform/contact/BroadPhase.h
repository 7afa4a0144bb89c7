// SPDX-License-Identifier: MIT
#pragma once
/// @file BroadPhase.h
/// The broad phase of barrier contact: which primitive pairs can come close over a step, from
/// axis-aligned boxes. Narrow phase: Distance.h (distances), AdditiveCCD.h (times of impact).

#include <Eigen/Core>
#include <array>
#include <functional>
#include <utility>
#include <vector>

namespace bsdeform {

/// An axis-aligned box, lo ≤ hi componentwise.
struct Box {
  Eigen::Vector3d lo, hi;
};

/// Every (i, j) with a[i] and b[j] overlapping (closed boxes: touching counts) after both are
/// inflated by `inflation` on every side, i.e. whose gap is at most 2·inflation. Appends to
/// `out` after clearing it, in no particular order.
void overlappingPairs(const std::vector<Box>& a, const std::vector<Box>& b, double inflation,
                      std::vector<std::pair<int, int>>& out);

/// Every (i, j), i < j, of one set, as overlappingPairs.
void selfOverlappingPairs(const std::vector<Box>& a, double inflation, std::vector<std::pair<int, int>>& out);

/// A triangle mesh whose vertices move on straight lines over a step.
struct ContactMesh {
  Eigen::MatrixX3d start, end;  ///< vertex positions at t = 0 and t = 1 (equal for a static obstacle)
  Eigen::MatrixX3i triangles;
  Eigen::MatrixX2i edges;  ///< each undirected edge once
};

/// Primitive pairs for the narrow phase, by index into the meshes' vertices, triangles and edges.
struct ContactCandidates {
  std::vector<std::array<int, 2>> vertexTriangle;  ///< (vertex of the first mesh, triangle of the second)
  std::vector<std::array<int, 2>> triangleVertex;  ///< (triangle of the first mesh, vertex of the second)
  std::vector<std::array<int, 2>> edgeEdge;        ///< (edge of the first, edge of the second)
};

/// Pairs whose boxes (each swept from start to end) come within `inflation` of each other.
/// The candidate lists come sorted (by the first index, then the second), the same for any number
/// of kernel threads. Coordinates must be finite: a box with a NaN may miss or find pairs.
void candidatePairs(const ContactMesh& a, const ContactMesh& b, double inflation, ContactCandidates& out);

/// A mesh against itself, leaving out pairs that share a vertex: each unordered edge pair once
/// (first < second), and vertexTriangle then holds all vertex–triangle pairs (triangleVertex
/// stays empty).
void candidatePairs(const ContactMesh& a, double inflation, ContactCandidates& out);

/// As candidatePairs(a, inflation, out), keeping only the vertex–triangle and edge–edge pairs
/// `keepVertexTriangle` and `keepEdgeEdge` accept: asked before the pairs are sorted, so pairs left
/// out cost no sorting. They are asked from the kernel threads, several at once: they must only
/// read.
void candidatePairs(const ContactMesh& a, double inflation, ContactCandidates& out,
                    const std::function<bool(const std::array<int, 2>&)>& keepVertexTriangle,
                    const std::function<bool(const std::array<int, 2>&)>& keepEdgeEdge);

/// The pairs of `wide` that candidatePairs(a, b, inflation) finds at the meshes' positions now,
/// in the same (index) order: the same set when `wide` holds every one of them (pairs found with
/// a larger inflation at positions that have since moved less than the difference allows, as a
/// cache of candidates keeps them). So a sum or a minimum over the pairs does not depend on
/// when `wide` was found.
void narrowCandidates(const ContactMesh& a, const ContactMesh& b, double inflation, const ContactCandidates& wide,
                      ContactCandidates& out);
/// A mesh against itself, as candidatePairs(a, inflation).
void narrowCandidates(const ContactMesh& a, double inflation, const ContactCandidates& wide, ContactCandidates& out);

}  // namespace bsdeform
