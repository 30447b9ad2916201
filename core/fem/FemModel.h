// SPDX-License-Identifier: Apache-2.0
#pragma once
// A finite-element model of the tissue, the continuum the spring network stands for: quadratic
// (10-node) tets with a mean-dilatation volumetric term (P2/P0, Simo, Taylor and Pister 1985):
//
//   E(x) = sum_e [ integral_e W_T(I1bar(F)) dV  +  V_e U(theta_e) ]                       (J)
//   theta_e = v_e / V_e   (deformed over rest volume of element e),   U = kappa/2 (theta - 1)^2
//
// Why this element: the tissue is nearly incompressible, and linear tets with a pointwise
// volumetric term lock (their volume constraints outnumber their degrees of freedom); the
// quadratic tet with one dilatation per element is locking-free and keeps the energy a plain
// function of x, so Newton's Hessian is its exact second derivative. Scaling F to the element's
// mean dilatation (F-bar) leaves I1bar unchanged, so the isochoric part is W_T at F itself.
// The isochoric energy is integrated by the degree-2 rule (four points), v_e and V_e exactly by
// the degree-3 rule (det(dx/dxi) is cubic on a quadratic tet, its edges straight or curved),
// each point with its own dX/dxi (isoparametric): QuadraticTetShape.h.
//
// With stress softening (setSoftening; fem/IsochoricSoftening.h) each isochoric point below its
// peak has W_s in place of W_T, whose stress is the virgin one times the paper's F: its peak
// held between two calls of softenAt() (where the caller takes the history), E is still a plain
// energy of x, and its Hessian is that energy's.
//
// U is the spring model's volume-term form (VolumeForceField.h), here on the element's mean J.
// kappa (Pa) must hold the volume over the stretches used: the tissue stiffens about twenty-fold
// between lambda 1.1 and 1.3, so kappa is set against the stiffened modulus, not mu0
// (defaultFemBulkModulus).
//
// The Hessian is E's exact second derivative (FemTangent::Exact), or a definite stand-in for a
// caller that factorises it without a line search to catch an indefinite one
// (FemTangent::Definite, fem/HapticRateFem.h): each quadrature point's isochoric tangent dP/dF
// with its negative eigenvalues set to zero (in closed form, projectedIsochoricTangent), and the
// volumetric part's U'(theta) d2v/dx2 term left out, leaving kappa/V dv (x) dv. Energy and
// gradient are the same either way, so a Newton iteration on either settles where the other does.
// The whole element's 30 x 30 Hessian projected instead stiffens the elements a probe compresses.
//
// Shapes: x 3 by #V (m), gradients 3 by #V (N), the Hessian 3#V square (N/m, node-major DOFs).

#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "fem/IsochoricSoftening.h"
#include "fem/QuadraticTetMesh.h"
#include "forces/FemExtraEnergy.h"
#include "material/StrainEnergy.h"
#include "parallel/ForkJoinPool.h"

namespace tissuesim {

/// kappa = 200 times the stiffest uniaxial tangent dP/dlambda the tissue reaches up to lambda 1.3
/// (the paper's range; 3 mu0 at least): set against the stiffened tissue, where a kappa set from
/// mu0 leaves the stretched tissue compressible and soft (docs/model.md, "The FEM reference",
/// has the figures).
double defaultFemBulkModulus(const StrainEnergy& energy);
inline constexpr double kFemBulkModulusStretch = 1.3;
inline constexpr double kFemBulkModulusFactor = 200.0;

enum class FemTangent { Exact, Definite };

/// Where each element entry of a Hessian goes among its stored values, for the fixed DOFs it
/// was made with (FemModel::evaluate fills it).
struct FemHessianAssembly {
  std::vector<char> isFixed;
  std::vector<Eigen::Index> slots;        ///< per element entry, in the assembly's order
  std::vector<std::size_t> firstEntries;  ///< per element, its first entry among slots
};

struct FemState {
  bool isAdmissible = true;  ///< false: an element inverted or past the chain's locking
  double energy_J = 0.0;
  double minVolumeRatio = 1.0;  ///< min and max theta_e
  double maxVolumeRatio = 1.0;
};

class FemModel {
 public:
  /// `mesh` and `energy` must outlive this object. @param bulkModulus_Pa kappa > 0.
  FemModel(const QuadraticTetMesh& mesh, const StrainEnergy& energy, double bulkModulus_Pa);

  const QuadraticTetMesh& mesh() const { return m_mesh; }
  /// Adds `extra` (which must outlive its use here) to every evaluation; null: none.
  void setExtraEnergy(const FemExtraEnergy* extra) { m_extra = extra; }
  double bulkModulus() const { return m_bulkModulus_Pa; }
  /// Which Hessian evaluate() assembles (FemTangent::Exact unless set).
  void setTangent(FemTangent tangent) { m_tangent = tangent; }
  /// Threads an evaluation's elements are shared among (1 or 2; 2 unless set): a mesh of at least
  /// kElementsForTwoThreads elements is cut in two node-disjoint halves, run as two parts on a
  /// ForkJoinPool of two threads that the model keeps (the caller runs both where its worker is
  /// not running), the elements across the cut after both. The same count gives the same bits.
  /// With two, evaluate() is called from one thread at a time.
  /// @throws std::invalid_argument on another count.
  void setElementThreads(int threads);
  static constexpr Eigen::Index kElementsForTwoThreads = 256;

  /// Stress softening per isochoric quadrature point (fem/IsochoricSoftening.h), which must
  /// outlive its use here; null (the default): none, the virgin curve. softenAt(x) raises each
  /// point's peak to its I1bar at x; evaluate() takes each point below its peak on its softened
  /// energy W_s. The peaks are raised at the caller's pace (the FEM at its own rate raises them
  /// where each update starts), not within a solve, so that E stays one energy of x for Newton.
  void setSoftening(const StressSoftening* softening) { m_softening = softening; }
  void softenAt(const Eigen::Matrix3Xd& x);
  /// Every point back to the virgin curve (F = 1, no peak).
  void clearSoftening();
  /// Each point's peak I1bar - 3 (4 per element, in element order), and the same set again (a
  /// body taken up by another material: the peaks are strains; none without softening).
  std::vector<double> peakShifts() const;
  void setPeakShifts(const std::vector<double>& shifts);
  /// Where those points lie at rest (3 by 4 #tets, m, in the same order): X = sum_a N_a X_a
  /// at each point of the degree-2 rule.
  Eigen::Matrix3Xd energyPointsAtRest() const;

  /// E at x, and the element volume ratios.
  FemState evaluate(const Eigen::Matrix3Xd& x) const;
  /// The same, and dE/dx into gradient (3 by #V, resized): minus the internal forces.
  FemState evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& gradient) const;
  /// The same, and d^2E/dx^2 into hessian (3#V square), rows and columns of the DOFs flagged in
  /// isFixed (3#V, or empty) replaced by the identity's. With `assembly` (kept by the caller with
  /// the same hessian from call to call), the elements' entries go straight into hessian's
  /// values where its pattern is the one `assembly` was made for, in place of a new assembly
  /// from triplets.
  FemState evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& gradient,
                    Eigen::SparseMatrix<double>& hessian, const std::vector<char>& isFixed,
                    FemHessianAssembly* assembly = nullptr) const;

 private:
  /// What a quadrature point keeps of the rest geometry: dN/dX (10 by 3) and its weight (m^3).
  struct PointData {
    Eigen::Matrix<double, 10, 3> gradients;
    double weight_m3;
  };
  /// Where the elements' Hessian entries go when not into triplets: added to values[slots[e]]
  /// for the e-th entry (FemHessianAssembly's order).
  struct DirectAssembly {
    double* values;
    const Eigen::Index* slots;
    const std::size_t* firstEntries;  ///< per element, its first entry
  };
  /// elementEntries (when given): how many of the triplets are the elements' (the rest are the
  /// extra energy's), and firstEntries (when given, with triplets) where each element's begin
  /// among them. With direct.values, the elements' entries go there and triplets gets the extra
  /// energy's alone.
  FemState accumulate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient,
                      std::vector<Eigen::Triplet<double>>* triplets,
                      const std::vector<char>* isFixed, std::size_t* elementEntries = nullptr,
                      DirectAssembly direct = {nullptr, nullptr, nullptr},
                      std::vector<std::size_t>* firstEntries = nullptr) const;
  /// Element t's energy into state (and its volume ratio), its gradient into gradient, its
  /// Hessian's entries into triplets or direct's values from its first entry on (where given).
  /// @returns false where it is inverted or past the chain's locking (the caller's state is then
  /// inadmissible, whatever was added to it).
  bool addElement(Eigen::Index t, const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient,
                  std::vector<Eigen::Triplet<double>>* triplets, const std::vector<char>* isFixed,
                  DirectAssembly direct, FemState& state) const;
  /// The elements listed, in order, into a state of their own: inadmissible at the first that is.
  FemState addElements(const std::vector<Eigen::Index>& elements, const Eigen::Matrix3Xd& x,
                       Eigen::Matrix3Xd* gradient, const std::vector<char>* isFixed,
                       DirectAssembly direct) const;

  const QuadraticTetMesh& m_mesh;
  const StrainEnergy& m_energy;
  double m_bulkModulus_Pa;
  std::vector<PointData> m_energyPoints;  ///< 4 per element
  std::vector<PointData> m_volumePoints;  ///< 5 per element
  Eigen::VectorXd m_restVolume_m3;        ///< V_e
  const FemExtraEnergy* m_extra = nullptr;
  FemTangent m_tangent = FemTangent::Exact;
  const StressSoftening* m_softening = nullptr;
  std::vector<IsochoricPeak> m_peaks;  ///< one an isochoric point (empty: none)
  /// The elements cut in two along the rest mesh's longest side, at its nodes' median: those
  /// with every node below it, every node above, and the rest (setElementThreads).
  std::vector<Eigen::Index> m_lowerElements, m_upperElements, m_elementsAcross;
  std::unique_ptr<ForkJoinPool> m_pool;  ///< the halves' two threads; null: one thread
};

}  // namespace tissuesim
