// SPDX-License-Identifier: Apache-2.0
#include "springs/NodeStretch.h"

#include <cmath>

namespace tissuesim {

void nodeStretch(const SpringMesh& mesh, const Eigen::Matrix3Xd& x, Eigen::VectorXd& stretch) {
  if (stretch.size() != mesh.nodeCount()) stretch.resize(mesh.nodeCount());
  stretch.setOnes();
  for (Eigen::Index s = 0; s < mesh.springCount(); ++s) {
    const int a = mesh.springs(0, s), b = mesh.springs(1, s);
    const double lambda = (x.col(b) - x.col(a)).norm() / mesh.restLength_m[s];
    for (const int node : {a, b}) {
      if (std::abs(lambda - 1.0) > std::abs(stretch[node] - 1.0)) stretch[node] = lambda;
    }
  }
}

}  // namespace tissuesim
