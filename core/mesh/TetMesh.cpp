// SPDX-License-Identifier: Apache-2.0
#include "mesh/TetMesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

namespace tissuesim {

Eigen::Matrix3Xi boundaryFaces(const TetMesh& mesh) {
  // Each face keyed by its sorted nodes; the face opposite vertex k of a positively oriented
  // tet (a, b, c, d) is outward as (b, c, d), (a, d, c), (a, b, d), (a, c, b) for k = 0..3.
  struct Face {
    std::array<int, 3> key;
    std::array<int, 3> oriented;
  };
  std::vector<Face> faces;
  faces.reserve(static_cast<std::size_t>(4 * mesh.tetCount()));
  constexpr int kOpposite[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    for (const auto& local : kOpposite) {
      Face face{};
      for (int i = 0; i < 3; ++i)
        face.oriented[static_cast<std::size_t>(i)] = mesh.tets(local[i], t);
      face.key = face.oriented;
      std::sort(face.key.begin(), face.key.end());
      faces.push_back(face);
    }
  }
  std::sort(faces.begin(), faces.end(), [](const Face& x, const Face& y) { return x.key < y.key; });
  std::vector<std::array<int, 3>> boundary;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i == 1) boundary.push_back(faces[i].oriented);
    i = j;
  }
  Eigen::Matrix3Xi out(3, static_cast<Eigen::Index>(boundary.size()));
  for (std::size_t f = 0; f < boundary.size(); ++f) {
    out.col(static_cast<Eigen::Index>(f)) << boundary[f][0], boundary[f][1], boundary[f][2];
  }
  return out;
}

std::vector<int> faceNodes(const Eigen::Matrix3Xi& faces) {
  std::vector<int> nodes(faces.data(), faces.data() + faces.size());
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

Eigen::Index countUniqueEdges(const TetMesh& mesh) {
  std::vector<std::pair<int, int>> edges;
  edges.reserve(static_cast<std::size_t>(6 * mesh.tetCount()));
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        edges.emplace_back(std::min(mesh.tets(i, t), mesh.tets(j, t)),
                           std::max(mesh.tets(i, t), mesh.tets(j, t)));
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  return std::unique(edges.begin(), edges.end()) - edges.begin();
}

namespace {
/// Dihedral angles (degrees, min and max) and radius ratio of one tet.
void tetShape(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
              const Eigen::Vector3d& p3, double& minAngle, double& maxAngle, double& radiusRatio) {
  const std::array<Eigen::Vector3d, 4> p = {p0, p1, p2, p3};
  // Face k is opposite vertex k; its outward normal points away from p[k].
  std::array<Eigen::Vector3d, 4> normals;
  double area = 0.0;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d& a = p[static_cast<std::size_t>((k + 1) % 4)];
    const Eigen::Vector3d& b = p[static_cast<std::size_t>((k + 2) % 4)];
    const Eigen::Vector3d& c = p[static_cast<std::size_t>((k + 3) % 4)];
    Eigen::Vector3d n = (b - a).cross(c - a);
    area += 0.5 * n.norm();
    if (n.dot(a - p[static_cast<std::size_t>(k)]) < 0.0) n = -n;
    normals[static_cast<std::size_t>(k)] = n.normalized();
  }
  minAngle = 180.0;
  maxAngle = 0.0;
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) {
      const double cosine = std::clamp(
          -normals[static_cast<std::size_t>(i)].dot(normals[static_cast<std::size_t>(j)]), -1.0,
          1.0);
      const double angle = std::acos(cosine) * 180.0 / std::numbers::pi;
      minAngle = std::min(minAngle, angle);
      maxAngle = std::max(maxAngle, angle);
    }
  }
  const Eigen::Vector3d a = p1 - p0, b = p2 - p0, c = p3 - p0;
  const double volume = std::abs(a.dot(b.cross(c))) / 6.0;
  const double inradius = area > 0.0 ? 3.0 * volume / area : 0.0;
  const double circumradius = volume > 0.0
                                  ? (a.squaredNorm() * b.cross(c) + b.squaredNorm() * c.cross(a) +
                                     c.squaredNorm() * a.cross(b))
                                            .norm() /
                                        (12.0 * volume)
                                  : std::numeric_limits<double>::infinity();
  radiusRatio = 3.0 * inradius / circumradius;
}
}  // namespace

TetQualityReport inspectTets(const TetMesh& mesh, double sliverFraction) {
  TetQualityReport report;
  report.minVolume_m3 = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    const double volume = signedTetVolume(mesh.nodes_m, mesh.tets, t);
    double meanEdge = 0.0;
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        meanEdge += (mesh.nodes_m.col(mesh.tets(i, t)) - mesh.nodes_m.col(mesh.tets(j, t))).norm();
      }
    }
    meanEdge /= 6.0;
    // Regular tet of edge a: a^3 / (6 sqrt 2).
    const double regular = meanEdge * meanEdge * meanEdge / (6.0 * std::sqrt(2.0));
    if (volume < 0.0) report.invertedTets.push_back(t);
    if (std::abs(volume) < sliverFraction * regular) report.slivers.push_back(t);
    report.minVolume_m3 = std::min(report.minVolume_m3, volume);
    report.totalVolume_m3 += volume;
    double minAngle = 0.0, maxAngle = 0.0, ratio = 0.0;
    tetShape(mesh.nodes_m.col(mesh.tets(0, t)), mesh.nodes_m.col(mesh.tets(1, t)),
             mesh.nodes_m.col(mesh.tets(2, t)), mesh.nodes_m.col(mesh.tets(3, t)), minAngle,
             maxAngle, ratio);
    report.minDihedral_deg = std::min(report.minDihedral_deg, minAngle);
    report.maxDihedral_deg = std::max(report.maxDihedral_deg, maxAngle);
    report.minRadiusRatio = std::min(report.minRadiusRatio, ratio);
  }
  return report;
}

void validateTetMesh(const TetMesh& mesh, const std::string& name) {
  if (mesh.tetCount() == 0) throw std::invalid_argument(name + ": the mesh has no tets");
  if (!mesh.nodes_m.allFinite()) {
    for (Eigen::Index v = 0; v < mesh.nodeCount(); ++v) {
      if (!mesh.nodes_m.col(v).allFinite()) {
        throw std::invalid_argument(name + ": node " + std::to_string(v) +
                                    " has a coordinate that is not finite");
      }
    }
  }
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    for (int i = 0; i < 4; ++i) {
      const int node = mesh.tets(i, t);
      if (node < 0 || node >= mesh.nodeCount()) {
        throw std::invalid_argument(name + ": tet " + std::to_string(t) + " refers to node " +
                                    std::to_string(node) + ", outside 0.." +
                                    std::to_string(mesh.nodeCount() - 1));
      }
      for (int j = 0; j < i; ++j) {
        if (mesh.tets(j, t) == node) {
          throw std::invalid_argument(name + ": tet " + std::to_string(t) + " repeats node " +
                                      std::to_string(node));
        }
      }
    }
  }
}

NodeTetIncidence nodeTetIncidence(const Eigen::Matrix4Xi& tets, Eigen::Index nodeCount) {
  const auto count = static_cast<std::size_t>(nodeCount);
  NodeTetIncidence incidence;
  incidence.start.assign(count + 1, 0);
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    for (int c = 0; c < 4; ++c) ++incidence.start[static_cast<std::size_t>(tets(c, t)) + 1];
  }
  for (std::size_t j = 0; j < count; ++j) incidence.start[j + 1] += incidence.start[j];
  incidence.entries.resize(static_cast<std::size_t>(4 * tets.cols()));
  std::vector<int> next(incidence.start.begin(), incidence.start.end() - 1);
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    for (int c = 0; c < 4; ++c) {
      incidence.entries[static_cast<std::size_t>(next[static_cast<std::size_t>(tets(c, t))]++)] =
          static_cast<int>(4 * t + c);
    }
  }
  return incidence;
}

NodeStars nodeStars(const Eigen::Matrix4Xi& tets, const NodeTetIncidence& incidence) {
  const std::size_t count = incidence.start.size() - 1;
  NodeStars stars;
  stars.start.assign(count + 1, 0);
  std::vector<int> star;
  for (std::size_t j = 0; j < count; ++j) {
    star.assign(1, static_cast<int>(j));
    for (int e = incidence.start[j]; e < incidence.start[j + 1]; ++e) {
      const int t = incidence.entries[static_cast<std::size_t>(e)] / 4;
      for (int n = 0; n < 4; ++n) star.push_back(tets(n, t));
    }
    std::sort(star.begin(), star.end());
    star.erase(std::unique(star.begin(), star.end()), star.end());
    stars.nodes.insert(stars.nodes.end(), star.begin(), star.end());
    stars.start[j + 1] = static_cast<int>(stars.nodes.size());
  }
  return stars;
}

int starEntry(const NodeStars& stars, int a, int b) {
  const auto first = stars.nodes.begin() + stars.start[static_cast<std::size_t>(a)];
  const auto last = stars.nodes.begin() + stars.start[static_cast<std::size_t>(a) + 1];
  return static_cast<int>(std::lower_bound(first, last, b) - stars.nodes.begin());
}

std::vector<int> starMirror(const NodeStars& stars) {
  std::vector<int> mirror(stars.nodes.size());
  for (std::size_t a = 0; a + 1 < stars.start.size(); ++a) {
    for (int e = stars.start[a]; e < stars.start[a + 1]; ++e) {
      mirror[static_cast<std::size_t>(e)] =
          starEntry(stars, stars.nodes[static_cast<std::size_t>(e)], static_cast<int>(a));
    }
  }
  return mirror;
}

Eigen::Matrix2Xi starCouplings(const NodeStars& stars) {
  std::vector<std::uint64_t> keys;
  for (std::size_t a = 0; a + 1 < stars.start.size(); ++a) {
    for (int e = stars.start[a]; e < stars.start[a + 1]; ++e) {
      for (int f = e + 1; f < stars.start[a + 1]; ++f) {
        keys.push_back(static_cast<std::uint64_t>(stars.nodes[static_cast<std::size_t>(e)]) << 32 |
                       static_cast<std::uint64_t>(stars.nodes[static_cast<std::size_t>(f)]));
      }
    }
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  Eigen::Matrix2Xi pairs(2, static_cast<Eigen::Index>(keys.size()));
  for (std::size_t k = 0; k < keys.size(); ++k) {
    pairs(0, static_cast<Eigen::Index>(k)) = static_cast<int>(keys[k] >> 32);
    pairs(1, static_cast<Eigen::Index>(k)) = static_cast<int>(keys[k] & 0xffffffffu);
  }
  return pairs;
}

}  // namespace tissuesim
