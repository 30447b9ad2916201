// SPDX-License-Identifier: Apache-2.0
#include "forces/ForceField.h"

namespace tissuesim {

void addStiffnessAt(const ForceField& field, const Eigen::Matrix3Xd& x, bool isProjected,
                    NodeBlockMatrix& matrix, Eigen::Matrix3Xd& forces,
                    const std::vector<char>* fixedDofs) {
  ForcePass pass;
  pass.stiffness = StiffnessSlot::Current;
  pass.isProjected = isProjected;
  pass.fixedDofs = fixedDofs;
  ForceReport ignored;
  field.addForces(x, forces, pass, ignored);
  field.addStiffness(matrix);
}

}  // namespace tissuesim
