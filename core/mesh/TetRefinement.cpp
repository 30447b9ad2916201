// SPDX-License-Identifier: Apache-2.0
#include "mesh/TetRefinement.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <queue>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mesh/ClosestSurfacePoint.h"

namespace tissuesim {

double TetMeshGrading::sizeAt(const Eigen::Vector3d& point_m) const {
  return std::min(coarsest_m, finest_m + growth * (point_m - centre_m).norm());
}

namespace {

using Tet = std::array<int, 4>;
using EdgeKey = std::uint64_t;

EdgeKey edgeKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<EdgeKey>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}
int firstNode(EdgeKey key) { return static_cast<int>(key >> 32); }
int secondNode(EdgeKey key) { return static_cast<int>(key & 0xffffffffu); }

constexpr std::array<std::array<int, 2>, 6> kTetEdges = {
    {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}}};

class Refiner {
 public:
  Refiner(const TetMesh& mesh, const TetMeshGrading& grading, const TriangleSurface* surface)
      : m_grading(grading) {
    if (surface != nullptr && surface->triangleCount() > 0) m_closest.emplace(*surface);
    m_nodes.reserve(static_cast<std::size_t>(mesh.nodeCount()));
    for (Eigen::Index i = 0; i < mesh.nodeCount(); ++i) m_nodes.emplace_back(mesh.nodes_m.col(i));
    for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
      if (!(signedTetVolume(mesh.nodes_m, mesh.tets, t) > 0.0))
        throw std::invalid_argument("tet " + std::to_string(t) +
                                    " is inverted or flat; a mesh to refine needs positive tets");
      addTet({mesh.tets(0, t), mesh.tets(1, t), mesh.tets(2, t), mesh.tets(3, t)});
    }
    for (const auto& [key, tets] : m_edgeTets) queueIfTooLong(key);
  }

  void run() {
    while (!m_queue.empty()) {
      const EdgeKey key = m_queue.top().second;
      m_queue.pop();
      // Queued only when too long, with its ends where they stay: split unless it already was.
      if (m_edgeTets.count(key) != 0) bisect(key);
    }
  }

  RefinedTetMesh result() const {
    RefinedTetMesh refined;
    refined.mesh.nodes_m.resize(3, static_cast<Eigen::Index>(m_nodes.size()));
    for (std::size_t i = 0; i < m_nodes.size(); ++i)
      refined.mesh.nodes_m.col(static_cast<Eigen::Index>(i)) = m_nodes[i];
    const auto alive = static_cast<Eigen::Index>(std::count(m_alive.begin(), m_alive.end(), 1));
    refined.mesh.tets.resize(4, alive);
    Eigen::Index column = 0;
    for (std::size_t t = 0; t < m_tets.size(); ++t) {
      if (m_alive[t] == 0) continue;
      for (int c = 0; c < 4; ++c)
        refined.mesh.tets(c, column) = m_tets[t][static_cast<std::size_t>(c)];
      ++column;
    }
    refined.splitEdges.resize(2, static_cast<Eigen::Index>(m_splitEdges.size()));
    for (std::size_t k = 0; k < m_splitEdges.size(); ++k) {
      refined.splitEdges(0, static_cast<Eigen::Index>(k)) = m_splitEdges[k][0];
      refined.splitEdges(1, static_cast<Eigen::Index>(k)) = m_splitEdges[k][1];
    }
    return refined;
  }

 private:
  double lengthSquared(EdgeKey key) const {
    return (m_nodes[static_cast<std::size_t>(firstNode(key))] -
            m_nodes[static_cast<std::size_t>(secondNode(key))])
        .squaredNorm();
  }

  /// A total order on edges (length, ties broken by the key), so each tet has one longest edge
  /// and the propagation below always climbs.
  bool isLonger(EdgeKey e, EdgeKey f) const {
    const double le = lengthSquared(e);
    const double lf = lengthSquared(f);
    return le > lf || (le == lf && e > f);
  }

  EdgeKey longestEdge(const Tet& tet) const {
    EdgeKey longest = edgeKey(tet[0], tet[1]);
    for (const auto& edge : kTetEdges) {
      const EdgeKey key =
          edgeKey(tet[static_cast<std::size_t>(edge[0])], tet[static_cast<std::size_t>(edge[1])]);
      if (isLonger(key, longest)) longest = key;
    }
    return longest;
  }

  bool isTooLong(EdgeKey key) const {
    const Eigen::Vector3d middle = 0.5 * (m_nodes[static_cast<std::size_t>(firstNode(key))] +
                                          m_nodes[static_cast<std::size_t>(secondNode(key))]);
    const double size = m_grading.sizeAt(middle);
    // Where the grading reaches its coarsest, the mesh is left as it is.
    return size < m_grading.coarsest_m && lengthSquared(key) > size * size;
  }

  void queueIfTooLong(EdgeKey key) {
    if (isTooLong(key)) m_queue.emplace(lengthSquared(key), key);
  }

  void addTet(const Tet& tet) {
    if (++m_aliveCount > kMaxRefinedTets) {
      throw std::invalid_argument("refined to this grading the mesh would pass " +
                                  std::to_string(kMaxRefinedTets) +
                                  " tets; make the finest size or the growth larger");
    }
    const int index = static_cast<int>(m_tets.size());
    m_tets.push_back(tet);
    m_alive.push_back(1);
    for (const auto& edge : kTetEdges) {
      m_edgeTets[edgeKey(tet[static_cast<std::size_t>(edge[0])],
                         tet[static_cast<std::size_t>(edge[1])])]
          .push_back(index);
    }
  }

  void removeTet(int index) {
    const Tet& tet = m_tets[static_cast<std::size_t>(index)];
    for (const auto& edge : kTetEdges) {
      const auto found = m_edgeTets.find(
          edgeKey(tet[static_cast<std::size_t>(edge[0])], tet[static_cast<std::size_t>(edge[1])]));
      std::vector<int>& tets = found->second;
      tets.erase(std::find(tets.begin(), tets.end(), index));
      if (tets.empty()) m_edgeTets.erase(found);
    }
    m_alive[static_cast<std::size_t>(index)] = 0;
    --m_aliveCount;
  }

  /// Longest-edge propagation: the tets round `key` whose longest edge is another are split at
  /// that one first, then `key` in all of them.
  void bisect(EdgeKey key) {
    for (;;) {
      const auto found = m_edgeTets.find(key);
      if (found == m_edgeTets.end()) return;
      EdgeKey longer = key;
      for (const int t : found->second) {
        longer = longestEdge(m_tets[static_cast<std::size_t>(t)]);
        if (longer != key) break;
      }
      if (longer == key) {
        split(key);
        return;
      }
      bisect(longer);
    }
  }

  /// The edge is on the boundary when one of the faces round it belongs to one tet only: each
  /// tet round it has two faces on it, named by their third node, and inside, each third node is
  /// named twice.
  bool isBoundaryEdge(EdgeKey key) const {
    const int a = firstNode(key);
    const int b = secondNode(key);
    std::vector<int> thirds;
    for (const int t : m_edgeTets.at(key)) {
      for (const int node : m_tets[static_cast<std::size_t>(t)])
        if (node != a && node != b) thirds.push_back(node);
    }
    std::sort(thirds.begin(), thirds.end());
    for (std::size_t i = 0; i < thirds.size();) {
      std::size_t j = i;
      while (j < thirds.size() && thirds[j] == thirds[i]) ++j;
      if (j - i != 2) return true;
      i = j;
    }
    return false;
  }

  void split(EdgeKey key) {
    const int a = firstNode(key);
    const int b = secondNode(key);
    const bool onBoundary = m_closest.has_value() && isBoundaryEdge(key);
    const int middle = static_cast<int>(m_nodes.size());
    const Eigen::Vector3d midpoint =
        0.5 * (m_nodes[static_cast<std::size_t>(a)] + m_nodes[static_cast<std::size_t>(b)]);
    m_nodes.push_back(midpoint);
    m_splitEdges.push_back({a, b});
    const std::vector<int> round = m_edgeTets.at(key);
    std::vector<int> children;
    for (const int t : round) {
      const Tet parent = m_tets[static_cast<std::size_t>(t)];
      removeTet(t);
      // The midpoint in b's place, then in a's: each child keeps the parent's orientation.
      for (const int replaced : {b, a}) {
        Tet child = parent;
        *std::find(child.begin(), child.end(), replaced) = middle;
        children.push_back(static_cast<int>(m_tets.size()));
        addTet(child);
      }
    }
    if (onBoundary) moveOntoSurface(middle, children, std::sqrt(lengthSquared(key)));
    for (const int t : children) {
      const Tet& tet = m_tets[static_cast<std::size_t>(t)];
      for (const int node : tet)
        if (node != middle) queueIfTooLong(edgeKey(node, middle));
    }
  }

  double tetVolume(const Tet& tet) const {
    return signedTetVolume(
        m_nodes[static_cast<std::size_t>(tet[0])], m_nodes[static_cast<std::size_t>(tet[1])],
        m_nodes[static_cast<std::size_t>(tet[2])], m_nodes[static_cast<std::size_t>(tet[3])]);
  }

  /// The new boundary node onto the drawn surface, or as far towards it as keeps each of its
  /// tets at least a fifth of its volume at the midpoint (halving the move up to twice).
  void moveOntoSurface(int node, const std::vector<int>& tets, double edgeLength_m) {
    Eigen::Vector3d& position = m_nodes[static_cast<std::size_t>(node)];
    const Eigen::Vector3d midpoint = position;
    const Eigen::Vector3d target = (*m_closest)(midpoint);
    if ((target - midpoint).norm() > 0.25 * edgeLength_m) return;
    std::vector<double> before;
    for (const int t : tets) before.push_back(tetVolume(m_tets[static_cast<std::size_t>(t)]));
    for (double share = 1.0; share >= 0.25; share *= 0.5) {
      position = midpoint + share * (target - midpoint);
      bool keepsShape = true;
      for (std::size_t k = 0; k < tets.size() && keepsShape; ++k)
        keepsShape = tetVolume(m_tets[static_cast<std::size_t>(tets[k])]) > 0.2 * before[k];
      if (keepsShape) return;
    }
    position = midpoint;
  }

  TetMeshGrading m_grading;
  std::optional<ClosestSurfacePoint> m_closest;
  std::vector<Eigen::Vector3d> m_nodes;
  std::vector<Tet> m_tets;
  std::vector<char> m_alive;
  long m_aliveCount = 0;
  std::unordered_map<EdgeKey, std::vector<int>> m_edgeTets;
  std::priority_queue<std::pair<double, EdgeKey>> m_queue;
  std::vector<std::array<int, 2>> m_splitEdges;
};

}  // namespace

RefinedTetMesh refineTetMesh(const TetMesh& mesh, const TetMeshGrading& grading,
                             const TriangleSurface* surface) {
  if (!(grading.finest_m > 0.0) || !(grading.growth >= 0.0) ||
      !(grading.coarsest_m >= grading.finest_m) || !grading.centre_m.allFinite())
    throw std::invalid_argument(
        "a grading needs finest > 0, growth >= 0, coarsest >= finest and a finite centre");
  Refiner refiner(mesh, grading, surface);
  refiner.run();
  return refiner.result();
}

}  // namespace tissuesim
