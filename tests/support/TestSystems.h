// SPDX-License-Identifier: Apache-2.0
#pragma once
// Shared fixtures for the engine tests: the liver's tables and small spring systems.

#include <array>
#include <cmath>
#include <memory>
#include <random>

#include "material/StiffnessTable.h"
#include "mesh/BlockMesher.h"
#include "springs/SpringForceLaw.h"
#include "springs/SpringMesh.h"
#include "support/TestTissues.h"
#include "system/MechanicalSystem.h"

namespace tissuesim::test {

/// The porcine liver's energy and tables, built once per test binary.
struct LiverMaterial {
  TissueParameters parameters = porcineLiver();
  StrainEnergy energy{parameters};
  StiffnessTable table{energy};

  static const LiverMaterial& instance() {
    static const LiverMaterial material;
    return material;
  }
};

/// The porcine liver's strain energy.
inline const StrainEnergy& liverEnergy() { return LiverMaterial::instance().energy; }

/// The porcine liver's softening with the spring law's rounded onset, as a scene takes it.
inline const StressSoftening& liverSoftening() {
  static const StressSoftening softening(LiverMaterial::instance().parameters,
                                         SpringForceLaw::kSofteningOnsetMeasure);
  return softening;
}

/// Positions `rest` (3 by #V) stretched 15 % along x, squeezed 6 % across and jiggled by up
/// to `jiggle_m`, and a random direction of the same shape: a deformed state for finite
/// differences.
struct DeformedPositions {
  Eigen::Matrix3Xd x;
  Eigen::Matrix3Xd direction;
};
inline DeformedPositions stretchedAndJiggled(const Eigen::Matrix3Xd& rest, unsigned seed,
                                             double jiggle_m) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  DeformedPositions out{rest, Eigen::Matrix3Xd(3, rest.cols())};
  out.x.row(0) *= 1.15;
  out.x.bottomRows(2) *= 0.94;
  for (Eigen::Index i = 0; i < out.x.size(); ++i) {
    out.x.data()[i] += jiggle_m * uniform(random);
    out.direction.data()[i] = uniform(random);
  }
  return out;
}

/// A block of springs with its force field and system, owning everything it refers to.
struct BlockSystem {
  SpringMesh mesh;
  SpringForceLaw law;
  SpringForceField springs;
  std::unique_ptr<VolumeForceField> volume;
  MechanicalSystem system;

  BlockSystem(const Eigen::Vector3d& size_m, const Eigen::Vector3i& cells,
              SpringLaw springLaw = SpringLaw::Eesm, bool isSoftening = false,
              double bulkModulus_Pa = 0.0)
      : mesh(buildSpringMesh(makeBlockMesh(size_m, cells),
                             LiverMaterial::instance().parameters.density_kg_m3)),
        law(springLaw, LiverMaterial::instance().table, LiverMaterial::instance().parameters,
            3.0 * LiverMaterial::instance().energy.initialShearModulus(), isSoftening),
        springs(mesh, law),
        volume(bulkModulus_Pa > 0.0 ? std::make_unique<VolumeForceField>(mesh, bulkModulus_Pa)
                                    : nullptr),
        system(springs, volume.get()) {}
};

/// The lattice cube (of edge h, from the origin) that tet t of a block mesh fills, from its rest
/// centroid: the volume term's cells found independently of VolumeCells.
inline std::array<long, 3> cubeOfTet(const SpringMesh& mesh, Eigen::Index t, double h) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int i = 0; i < 4; ++i) centroid += mesh.restPositions_m.col(mesh.tets(i, t)) / 4.0;
  return {std::lround(std::floor(centroid.x() / h)), std::lround(std::floor(centroid.y() / h)),
          std::lround(std::floor(centroid.z() / h))};
}

}  // namespace tissuesim::test
