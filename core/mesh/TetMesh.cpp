#include "mesh/TetMesh.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace tissuesim {

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

}  // namespace tissuesim
