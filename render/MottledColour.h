// SPDX-License-Identifier: Apache-2.0
#pragma once
// An organ's colour varied over its surface, as a living liver's is (paler and darker patches a
// centimetre or so across, redder and browner): smooth value noise of the rest positions, two
// octaves (15 and 5 mm), scaling the base colour by 0.8-1.15 and shifting its hue a little.
// Deterministic (a fixed hash, no random state), so images compare across runs.
//
// Shapes: rest_m 3 by #V (m); the result is #V RGB triples of the base colour's space, 0-255.

#include <vtkSmartPointer.h>
#include <Eigen/Core>

class vtkUnsignedCharArray;

namespace tissuesim {

vtkSmartPointer<vtkUnsignedCharArray> mottledColour(const Eigen::Matrix3Xd& rest_m,
                                                    const Eigen::Vector3d& baseColour);

/// The noise itself at a point (m), in [-1, 1] (tests).
double smoothNoise(const Eigen::Vector3d& point_m, double cell_m);

}  // namespace tissuesim
