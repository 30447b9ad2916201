// SPDX-License-Identifier: Apache-2.0
#pragma once
// Checking and repairing a triangle surface before it is meshed or embedded: welding duplicate
// vertices, counting what makes a surface unfit (open and non-manifold edges, degenerate
// triangles, unused vertices), finding its holes, and closing the small ones.

#include <string>
#include <vector>

#include "mesh/TriangleSurface.h"

namespace tissuesim {

/// A hole: a closed loop of boundary edges.
struct SurfaceHole {
  std::vector<int> loop;  ///< vertex indices in order
  double perimeter_m = 0.0;
  double diameter_m = 0.0;  ///< largest distance between two of its vertices
};

struct SurfaceReport {
  Eigen::Index vertices = 0;
  Eigen::Index triangles = 0;
  int openEdges = 0;            ///< edges with one triangle
  int nonManifoldEdges = 0;     ///< edges with three or more triangles
  int degenerateTriangles = 0;  ///< area below (1e-6 of the bounding-box diagonal)^2
  int unusedVertices = 0;
  std::vector<SurfaceHole> holes;
  double boundingDiagonal_m = 0.0;
  double enclosedVolume_m3 = 0.0;  ///< meaningful when closed

  bool isClosedManifold() const { return openEdges == 0 && nonManifoldEdges == 0; }
  /// One line: the counts, for reports and error messages.
  std::string summary() const;
};

/// Merges vertices closer than `tolerance_m` (spatial hashing), drops triangles that collapse,
/// and removes vertices no triangle uses. Returns how many vertices were merged.
int weldVertices(TriangleSurface& surface, double tolerance_m);

SurfaceReport inspectSurface(const TriangleSurface& surface);

/// Closes every hole whose diameter is at most `maxDiameter_m` with a fan around its centroid.
/// Returns the holes closed.
int closeSmallHoles(TriangleSurface& surface, double maxDiameter_m);

}  // namespace tissuesim
