// SPDX-License-Identifier: Apache-2.0
#pragma once
// The force law of one spring, as a nominal stress P(lambda) (Pa) and its slope: a spring of
// rest length L0 and volume V_e at stretch lambda = L / L0 pulls its ends together with
//
//   |F| = (V_e / L0) P(lambda)                                                 (N)
//
// and its energy is V_e W(lambda) where W' = P (docs/model.md, "The spring network").
//   eesm        P = W_T'(lambda) from the StiffnessTable (energy-consistent, the default)
//   eesm-paper  P = k_s(lambda) lambda / v_ij, the published secant force (Eq. 10)
//   smm         P = E (lambda - 1), a linear spring with one fitted modulus E (Eq. 1)
// The EESM laws soften on unloading when the scene turns it on (StressSoftening).
//
// Softening in the simulator (a deviation from model.md, for the solvers only; the `sedf`
// reference curve keeps the exact law): with n = 1 the softened stress starts a little above the
// virgin one at lambda_max (model.md), a jump J = R(lambda_max)/lambda_max, about 1e-4 of the
// stress. A force that jumps has no equilibrium at the jump, and Newton stalls there. So within
// kJumpBlendWidth below lambda_max, J is faded out with a C1 smoothstep: the force is continuous
// and the curve changes only inside that sliver (1e-3 in stretch). And the unloading curve's
// vertical tangent at lambda_max is rounded off (StressSoftening's onset, q_0 =
// kSofteningOnsetMeasure): every spring that loaded in the last step sits at its peak, and with
// a tangent that has no bound just below it a Newton step that unloads one by a hair overshoots,
// and CG meets stiffnesses a million times the stress. The rounded curve is within 0.6 % of the
// exact one (b = 3.34) and equal to it past q_0 (about 1e-4 in stretch below a peak of 1.15,
// 1.4e-3 below 1.01).
//
// Locking: the material has no value past the table's range (StrainEnergy::usableRange()).
// There the law continues linearly with the end slope: a stiff, C1 barrier that resists
// further stretch, and the evaluation says so (isBeyondRange) so the caller can report it.

#include <algorithm>
#include <optional>
#include <string_view>

#include "material/StiffnessTable.h"
#include "material/StressSoftening.h"

namespace tissuesim {

enum class SpringLaw { Eesm, EesmPaper, Smm };

/// The laws' names in scene files and on the command line: eesm, eesm-paper, smm.
const char* springLawName(SpringLaw law);
/// The law of that name; nullopt for any other.
std::optional<SpringLaw> springLawNamed(std::string_view name);

struct SpringStress {
  double stress;       ///< P (Pa)
  double slope;        ///< dP/dlambda (Pa)
  bool isBeyondRange;  ///< lambda was outside the material's usable range
};

class SpringForceLaw {
 public:
  /// Stretch below lambda_max over which the n = 1 softening jump is faded out.
  static constexpr double kJumpBlendWidth = 1e-3;
  /// q_0 of the softening's rounded onset (StressSoftening.h; see the header).
  static constexpr double kSofteningOnsetMeasure = 1e-4;

  /// @param linearModulus_Pa E of the smm law (ignored by the others).
  /// @param isSoftening      whether the EESM laws apply the Mullins effect.
  SpringForceLaw(SpringLaw law, const StiffnessTable& table, const TissueParameters& parameters,
                 double linearModulus_Pa, bool isSoftening);

  /// P and dP/dlambda at stretch lambda for a spring whose largest stretch so far is `peak`.
  /// Inline: it runs once per spring per force evaluation, and a call that cannot be inlined
  /// cost a third of the spring loop (perf, 5k-spring slab).
  /// kWithSlope false: the stress alone (slope 0), the same to the bit, for force-only passes;
  /// past the usable range the barrier needs the slope, so that case takes the full path.
  template <bool kWithSlope = true>
  SpringStress evaluate(double lambda, const SofteningPeak& peak) const {
    if (m_law == SpringLaw::Smm) {
      return {m_linearModulus_Pa * (lambda - 1.0), m_linearModulus_Pa, false};
    }
    const double clamped = std::clamp(lambda, m_range.lower, m_range.upper);
    if constexpr (!kWithSlope) {
      if (clamped != lambda) return evaluate<true>(lambda, peak);
    }
    HermiteNode p = virgin<kWithSlope>(clamped);
    // Softening changes nothing at or above lambda_max, nor on a spring never stretched.
    if (m_isSoftening && clamped < peak.lambdaMax && peak.lambdaMax > 1.0) {
      p = softened<kWithSlope>(p, clamped, peak);
    }
    if (clamped != lambda) {
      // Linear continuation past the usable range: the barrier (see the header).
      return {p.value + p.slope * (lambda - clamped), p.slope, true};
    }
    return {p.value, p.slope, false};
  }
  /// The same for a peak stretch given as a number (computes its SofteningPeak).
  SpringStress evaluate(double lambda, double lambdaMax) const {
    return evaluate(lambda, peak(lambdaMax));
  }
  /// The peak quantities for lambda_max, kept at the usable range's end.
  SofteningPeak peak(double lambdaMax) const;

  SpringLaw law() const { return m_law; }
  const StiffnessTable& table() const { return m_table; }
  const StressSoftening& softening() const { return m_softening; }
  bool isSoftening() const { return m_isSoftening; }
  StretchRange range() const { return m_range; }

 private:
  template <bool kWithSlope>
  HermiteNode virgin(double lambda) const {
    if constexpr (!kWithSlope) {
      // The splines' value alone is the same expression as their value with slope.
      if (m_law == SpringLaw::Eesm) return {m_table.stress(lambda), 0.0};
      return {m_table.springStiffness(lambda) * lambda * m_inverseArea, 0.0};  // eesm-paper
    } else {
      if (m_law == SpringLaw::Eesm) return m_table.stressAndSlope(lambda);
      const HermiteNode k = m_table.springStiffnessAndSlope(lambda);  // eesm-paper
      return {k.value * lambda * m_inverseArea, (k.slope * lambda + k.value) * m_inverseArea};
    }
  }
  /// The Mullins branch below lambda_max, with the n = 1 jump faded out (see the header).
  template <bool kWithSlope>
  HermiteNode softened(HermiteNode virginStress, double lambda, const SofteningPeak& peak) const {
    HermiteNode p = m_softening.softenWithSlope<kWithSlope>(virginStress, lambda, peak);
    const double below = peak.lambdaMax - lambda;
    if (below > 0.0 && below < kJumpBlendWidth && lambda >= 1.0) {
      // Fade the jump out: weight 1 at lambda_max, 0 at lambda_max - width, C1 at both ends.
      const double s = 1.0 - below / kJumpBlendWidth;
      p.value -= peak.jumpAtPeak * s * s * (3.0 - 2.0 * s);
      if constexpr (kWithSlope) p.slope -= peak.jumpAtPeak * 6.0 * s * (1.0 - s) / kJumpBlendWidth;
    }
    return p;
  }

  SpringLaw m_law;
  const StiffnessTable& m_table;
  StressSoftening m_softening;
  double m_linearModulus_Pa;
  double m_inverseArea;  ///< 1 / v_ij (1/m^2)
  bool m_isSoftening;
  StretchRange m_range;
};

}  // namespace tissuesim
