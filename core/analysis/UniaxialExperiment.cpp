// SPDX-License-Identifier: Apache-2.0
#include "analysis/UniaxialExperiment.h"

#include <algorithm>
#include <sstream>

#include "analysis/GoodnessOfFit.h"
#include "fem/IsochoricSoftening.h"

namespace tissuesim {

const char* phaseName(LoadPhase phase) {
  return phase == LoadPhase::Loading ? "loading" : "unloading";
}

std::vector<CurveBranch> protocolStretches(const UniaxialProtocol& protocol) {
  std::vector<CurveBranch> branches;
  const int points = protocol.pointsPerBranch;
  const double last = static_cast<double>(points - 1);
  int cycle = 0;
  for (const double peak : protocol.lambdaMax) {
    ++cycle;
    CurveBranch loading{cycle, LoadPhase::Loading, {}, {}};
    CurveBranch unloading{cycle, LoadPhase::Unloading, {}, {}};
    for (int i = 0; i < points; ++i) {
      const double s = static_cast<double>(i) / last;
      loading.stretch.push_back(1.0 + (peak - 1.0) * s);
      unloading.stretch.push_back(peak - (peak - 1.0) * s * s);
    }
    branches.push_back(std::move(loading));
    branches.push_back(std::move(unloading));
  }
  return branches;
}

UniaxialExperiment::UniaxialExperiment(const StrainEnergy& energy, const StiffnessTable& table)
    : m_energy(energy),
      m_table(table),
      m_softening(energy.parameters()),
      m_roundedSoftening(energy.parameters(), kIsochoricSofteningOnsetMeasure) {}

void UniaxialExperiment::validate(const UniaxialProtocol& protocol) const {
  if (protocol.lambdaMax.empty()) throw std::invalid_argument("no lambda_max given");
  if (protocol.pointsPerBranch < 2) {
    throw std::invalid_argument("--points must be at least 2 (both ends of a branch), got " +
                                std::to_string(protocol.pointsPerBranch));
  }
  const StretchRange usable = m_table.range();
  const StretchRange locking = m_energy.lockingRange();
  for (const double peak : protocol.lambdaMax) {
    std::ostringstream message;
    if (!(peak > 1.0)) {
      message << "lambda_max " << peak << " must be greater than 1 (a tensile test)";
      throw std::invalid_argument(message.str());
    }
    if (peak > usable.upper) {
      message << "lambda_max " << peak << " is beyond what this tissue admits: its chains lock at "
              << "lambda = " << locking.upper << ", and stretches up to " << usable.upper
              << " are usable";
      throw std::invalid_argument(message.str());
    }
  }
}

double UniaxialExperiment::virginStress(UniaxialModel model, double lambda,
                                        double linearModulus_Pa) const {
  switch (model) {
    case UniaxialModel::Sedf:
    case UniaxialModel::Fem:
      return m_energy.stress(lambda);
    case UniaxialModel::Eesm:
      // One spring of volume V = A L0: |F| = V P / L0, so stress |F| / A = P.
      return m_table.stress(lambda);
    case UniaxialModel::EesmPaper:
      // F = k_s(lambda) lambda (Eq. 10), a stress once divided by the area v_ij.
      return m_table.springStiffness(lambda) * lambda / m_energy.parameters().springArea_m2;
    case UniaxialModel::Smm:
      return linearModulus_Pa * (lambda - 1.0);
  }
  return 0.0;
}

std::vector<CurveBranch> UniaxialExperiment::run(UniaxialModel model,
                                                 const UniaxialProtocol& protocol) const {
  validate(protocol);
  double linearModulus = 0.0;
  if (model == UniaxialModel::Smm) {
    linearModulus = fitLinearModulus(run(UniaxialModel::Sedf, protocol));
  }
  // The linear spring of Eq. 1 has no memory; every EESM law softens the same way.
  const bool softens = model != UniaxialModel::Smm;
  std::vector<CurveBranch> branches = protocolStretches(protocol);
  MullinsState state;
  for (CurveBranch& branch : branches) {
    branch.stress_Pa.reserve(branch.stretch.size());
    for (const double lambda : branch.stretch) {
      const double virgin = virginStress(model, lambda, linearModulus);
      if (model == UniaxialModel::Fem) {
        // Through I1bar, as the FEM's quadrature points soften: no residual strain.
        const auto shift = [](double stretch) {
          return StrainEnergy::firstInvariant(stretch) - 3.0;
        };
        const double peak = std::max(state.lambdaMax(), 1.0);
        branch.stress_Pa.push_back(virgin * isochoricSofteningFactor(m_roundedSoftening,
                                                                     shift(lambda),
                                                                     isochoricPeak(shift(peak))));
      } else {
        branch.stress_Pa.push_back(softens ? m_softening.soften(virgin, lambda, state.lambdaMax())
                                           : virgin);
      }
      state.observe(lambda);
    }
  }
  return branches;
}

double UniaxialExperiment::springLawLinearModulus(SpringLaw law, const StrainEnergy& energy,
                                                  const StiffnessTable& table) {
  if (law != SpringLaw::Smm) return 0.0;
  return fitLinearModulus(
      UniaxialExperiment(energy, table).run(UniaxialModel::Sedf, {{1.15, 1.23, 1.30}, 50}));
}

double UniaxialExperiment::fitLinearModulus(std::span<const CurveBranch> reference) {
  std::vector<double> strain;
  std::vector<double> stress;
  for (const CurveBranch& branch : reference) {
    for (std::size_t i = 0; i < branch.stretch.size(); ++i) {
      strain.push_back(branch.stretch[i] - 1.0);
      stress.push_back(branch.stress_Pa[i]);
    }
  }
  return slopeThroughOrigin(strain, stress);
}

}  // namespace tissuesim
