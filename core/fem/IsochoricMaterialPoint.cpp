// SPDX-License-Identifier: Apache-2.0
#include "fem/IsochoricMaterialPoint.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>

namespace tissuesim {

double isochoricShift(const Eigen::Matrix3d& f) {
  return std::pow(f.determinant(), -2.0 / 3.0) * f.squaredNorm() - 3.0;
}

IsochoricResponse evaluateIsochoric(const StrainEnergy& energy, const Eigen::Matrix3d& f,
                                    bool withTangent) {
  if (!(f.determinant() > 0.0)) return {};
  const double shift = isochoricShift(f);  // I1bar - 3
  if (!(shift < energy.usableInvariantShift())) return {};
  return evaluateIsochoric(f, energy.atInvariantShift(std::max(shift, 0.0)), withTangent);
}

IsochoricResponse evaluateIsochoric(const Eigen::Matrix3d& f, const EnergyInI1& w,
                                    bool withTangent) {
  IsochoricResponse response;
  const double i1 = f.squaredNorm();
  const double scale = std::pow(f.determinant(), -2.0 / 3.0);  // J^(-2/3)
  const Eigen::Matrix3d inverseTranspose = f.inverse().transpose();
  const Eigen::Matrix3d a = scale * (2.0 * f - (2.0 / 3.0) * i1 * inverseTranspose);
  response.isAdmissible = true;
  response.energy_Pa = w.energy;
  response.stress_Pa = w.dEnergy * a;
  if (!withTangent) return response;
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < 3; ++l) {
      // dA along the unit dF = e_k e_l^T.
      const double traceInverse = inverseTranspose(k, l);  // F^-T : dF
      const double traceF = f(k, l);                       // F : dF
      Eigen::Matrix3d dF = Eigen::Matrix3d::Zero();
      dF(k, l) = 1.0;
      const Eigen::Matrix3d dA =
          scale * (-(2.0 / 3.0) * traceInverse * (2.0 * f - (2.0 / 3.0) * i1 * inverseTranspose) +
                   2.0 * dF - (4.0 / 3.0) * traceF * inverseTranspose +
                   (2.0 / 3.0) * i1 * inverseTranspose * dF.transpose() * inverseTranspose);
      const Eigen::Matrix3d dP = w.d2Energy * a(k, l) * a + w.dEnergy * dA;
      for (int i = 0; i < 3; ++i) {
        for (int jj = 0; jj < 3; ++jj) response.tangent_Pa(3 * i + jj, 3 * k + l) = dP(i, jj);
      }
    }
  }
  return response;
}

StressTangent projectedIsochoricTangent(const Eigen::Matrix3d& f, double dEnergy, double d2Energy) {
  const Eigen::JacobiSVD<Eigen::Matrix3d, Eigen::NoQRPreconditioner> svd(
      f, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  Eigen::Matrix3d v = svd.matrixV();
  const Eigen::Vector3d sigma = svd.singularValues();
  const double i1 = sigma.squaredNorm();
  const double scale = std::pow(sigma.prod(), -2.0 / 3.0);  // J^(-2/3)
  // dI1bar/dsigma_i and d2I1bar/dsigma_i dsigma_j.
  Eigen::Vector3d g;
  for (int i = 0; i < 3; ++i) g(i) = scale * (2.0 * sigma(i) - (2.0 / 3.0) * i1 / sigma(i));
  Eigen::Matrix3d h;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double delta = i == j ? 1.0 : 0.0;
      h(i, j) = -(2.0 / 3.0) * g(i) / sigma(j) +
                scale * (2.0 * delta - (4.0 / 3.0) * sigma(j) / sigma(i) +
                         delta * (2.0 / 3.0) * i1 / (sigma(i) * sigma(i)));
    }
  }
  const Eigen::Matrix3d scaling = d2Energy * g * g.transpose() + dEnergy * h;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(0.5 * (scaling + scaling.transpose()));
  StressTangent tangent = StressTangent::Zero();
  // vec of U M V^T in the tangent's order (index 3 i + J).
  const auto addMode = [&](double value, const Eigen::Matrix3d& m) {
    if (!(value > 0.0)) return;
    const Eigen::Matrix3d q = u * m * v.transpose();
    Eigen::Matrix<double, 9, 1> vq;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) vq(3 * i + j) = q(i, j);
    }
    tangent += value * vq * vq.transpose();
  };
  for (int k = 0; k < 3; ++k) {
    addMode(eigen.eigenvalues()(k), eigen.eigenvectors().col(k).asDiagonal().toDenseMatrix());
  }
  const double root = std::sqrt(0.5);
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      const double ratio = i1 / (sigma(i) * sigma(j));
      Eigen::Matrix3d twist = Eigen::Matrix3d::Zero();
      twist(i, j) = root;
      twist(j, i) = -root;
      addMode(dEnergy * scale * (2.0 - (2.0 / 3.0) * ratio), twist);
      Eigen::Matrix3d flip = Eigen::Matrix3d::Zero();
      flip(i, j) = root;
      flip(j, i) = root;
      addMode(dEnergy * scale * (2.0 + (2.0 / 3.0) * ratio), flip);
    }
  }
  return tangent;
}

EnergyInI1 continuedIsochoricEnergy(const StrainEnergy& energy, double shift, double limitShift,
                                    bool withEnergy) {
  const double at = std::clamp(shift, 0.0, limitShift);
  EnergyInI1 w = withEnergy ? energy.atInvariantShift(at) : energy.slopesAtInvariantShift(at);
  if (shift <= limitShift) return w;
  w.energy += withEnergy ? w.dEnergy * (shift - limitShift) : 0.0;
  w.d2Energy = 0.0;
  return w;
}

namespace {

/// F's entries in the tangent's order (index 3 i + J of F_iJ).
Eigen::Matrix<double, 9, 1> rowMajor(const Eigen::Matrix3d& m) {
  Eigen::Matrix<double, 9, 1> v;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) v(3 * i + j) = m(i, j);
  }
  return v;
}

}  // namespace

StressTangent exactIsochoricTangent(const Eigen::Matrix3d& f, const Eigen::Matrix3d& a, double i1,
                                    double scale, const EnergyInI1& w) {
  const Eigen::Matrix3d inverseTranspose = f.inverse().transpose();
  const Eigen::Matrix<double, 9, 1> av = rowMajor(a);
  const Eigen::Matrix<double, 9, 1> fv = rowMajor(f);
  const Eigen::Matrix<double, 9, 1> hv = rowMajor(inverseTranspose);
  StressTangent hessian = 2.0 * StressTangent::Identity() -
                          (4.0 / 3.0) * (fv * hv.transpose() + hv * fv.transpose()) +
                          (4.0 / 9.0) * i1 * hv * hv.transpose();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 3; ++k) {
        for (int l = 0; l < 3; ++l) {
          hessian(3 * i + j, 3 * k + l) +=
              (2.0 / 3.0) * i1 * inverseTranspose(i, l) * inverseTranspose(k, j);
        }
      }
    }
  }
  return (w.dEnergy * scale) * hessian + w.d2Energy * av * av.transpose();
}

}  // namespace tissuesim
