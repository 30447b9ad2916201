// SPDX-License-Identifier: Apache-2.0
#include "numerics/BlockConjugateGradient.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

namespace tissuesim {

void BlockConjugateGradient::resize(const BlockLinearOperator& a) {
  const Eigen::Index nodes = a.nodeCount();
  m_nodeCount = nodes;
  for (Eigen::VectorXd* v : {&m_r, &m_z, &m_p, &m_q}) v->resize(3 * nodes);
  m_inverseBlocks.resize(6 * nodes);
  m_termDiagonals.resize(nodes, kMaxExactTerms);
  m_termW.reserve(kMaxExactTerms);
  m_capacitance.resize(kMaxExactTerms, kMaxExactTerms);
  m_termT.resize(kMaxExactTerms);
  m_termSolved.resize(kMaxExactTerms);
}

bool BlockConjugateGradient::listTerms(std::span<const RankOneTerm> terms) {
  if (terms.empty() || terms.size() > static_cast<std::size_t>(kMaxExactTerms)) return false;
  for (const RankOneTerm& term : terms) {
    // S needs 1/k; a term it cannot take (k <= 0, NaN, an infinite u) leaves block Jacobi plain.
    if (!(term.stiffness_N_m > 0.0) || !std::isfinite(1.0 / term.stiffness_N_m)) return false;
    for (const Eigen::Vector3d& u : term.blocks) {
      if (!u.allFinite()) return false;
    }
  }
  m_termDiagonals.set(terms);
  return true;
}

void BlockConjugateGradient::clearTerms() { m_termDiagonals.clear(); }

template <typename Pass>
void BlockConjugateGradient::forEachPart(Pass& pass) {
  const auto runPart = [&](int p) {
    pass(static_cast<std::size_t>(p), m_bounds[static_cast<std::size_t>(p)],
         m_bounds[static_cast<std::size_t>(p) + 1]);
  };
  runParts(m_pool, kParts, runPart);
}

namespace {
/// The preconditioner's block for one node: the inverse of the symmetric diagonal block B,
/// stored as its upper triangle (00, 01, 02, 11, 12, 22), by cofactors. A block that is not
/// positive definite (or has a zero pivot) gets the scalar Jacobi inverse instead, 1 where a
/// diagonal entry is 0 (as Eigen's Jacobi preconditioner).
void invertDiagonalBlock(const Eigen::Matrix3d& b, double* inverse) {
  const double c00 = b(1, 1) * b(2, 2) - b(1, 2) * b(1, 2);
  const double c01 = b(0, 2) * b(1, 2) - b(0, 1) * b(2, 2);
  const double c02 = b(0, 1) * b(1, 2) - b(0, 2) * b(1, 1);
  const double determinant = b(0, 0) * c00 + b(0, 1) * c01 + b(0, 2) * c02;
  const bool isPositiveDefinite = b(0, 0) > 0.0 && b(0, 0) * b(1, 1) - b(0, 1) * b(0, 1) > 0.0 &&
                                  determinant > 0.0 && std::isfinite(determinant);
  if (!isPositiveDefinite) {
    const auto scalar = [](double d) { return d != 0.0 ? 1.0 / d : 1.0; };
    inverse[0] = scalar(b(0, 0));
    inverse[3] = scalar(b(1, 1));
    inverse[5] = scalar(b(2, 2));
    inverse[1] = inverse[2] = inverse[4] = 0.0;
    return;
  }
  const double scale = 1.0 / determinant;
  inverse[0] = c00 * scale;
  inverse[1] = c01 * scale;
  inverse[2] = c02 * scale;
  inverse[3] = (b(0, 0) * b(2, 2) - b(0, 2) * b(0, 2)) * scale;
  inverse[4] = (b(0, 1) * b(0, 2) - b(0, 0) * b(1, 2)) * scale;
  inverse[5] = (b(0, 0) * b(1, 1) - b(0, 1) * b(0, 1)) * scale;
}

/// z = B^-1 r for one node, B^-1 as invertDiagonalBlock stores it.
inline void applyInverse(const double* inverse, const double* r, double* z) {
  z[0] = inverse[0] * r[0] + inverse[1] * r[1] + inverse[2] * r[2];
  z[1] = inverse[1] * r[0] + inverse[3] * r[1] + inverse[4] * r[2];
  z[2] = inverse[2] * r[0] + inverse[4] * r[1] + inverse[5] * r[2];
}

/// The parts' partial sums in part order: the same whatever thread computed each part.
template <std::size_t N>
double sumInOrder(const std::array<double, N>& partial) {
  double sum = 0.0;
  for (const double value : partial) sum += value;
  return sum;
}
}  // namespace

bool BlockConjugateGradient::factorCapacitance(std::span<const RankOneTerm> terms) {
  const auto count = static_cast<Eigen::Index>(terms.size());
  m_termW.resize(terms.size());  // within the reserved capacity
  for (std::size_t c = 0; c < terms.size(); ++c) {
    for (std::size_t i = 0; i < kMaxTermNodes; ++i) {
      applyInverse(m_inverseBlocks.data() + 6 * terms[c].nodes[i], terms[c].blocks[i].data(),
                   m_termW[c][i].data());
    }
  }
  // S = K^-1 + U^T W: entry (c, d) sums u_c . w_d over the nodes the two terms share.
  auto s = m_capacitance.topLeftCorner(count, count);
  for (Eigen::Index c = 0; c < count; ++c) {
    const RankOneTerm& tc = terms[static_cast<std::size_t>(c)];
    for (Eigen::Index d = c; d < count; ++d) {
      const RankOneTerm& td = terms[static_cast<std::size_t>(d)];
      double sum = c == d ? 1.0 / tc.stiffness_N_m : 0.0;
      for (std::size_t i = 0; i < kMaxTermNodes; ++i) {
        for (std::size_t j = 0; j < kMaxTermNodes; ++j) {
          if (tc.nodes[i] == td.nodes[j])
            sum += tc.blocks[i].dot(m_termW[static_cast<std::size_t>(d)][j]);
        }
      }
      s(c, d) = sum;
      s(d, c) = sum;
    }
  }
  // In place, in the preallocated corner: no allocation.
  Eigen::Ref<Eigen::MatrixXd> corner(s);
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> factor(corner);
  return factor.info() == Eigen::Success;
}

double BlockConjugateGradient::correctForTerms(std::span<const RankOneTerm> terms, double* z,
                                               double* alsoP) {
  const auto count = static_cast<Eigen::Index>(terms.size());
  auto t = m_termT.head(count);
  for (Eigen::Index c = 0; c < count; ++c) {
    const RankOneTerm& term = terms[static_cast<std::size_t>(c)];
    double sum = 0.0;
    for (std::size_t i = 0; i < kMaxTermNodes; ++i) {
      sum += term.blocks[i].dot(Eigen::Map<const Eigen::Vector3d>(z + 3 * term.nodes[i]));
    }
    t[c] = sum;
  }
  // S^-1 t from the factor in the corner's lower triangle; t stays for r . z's drop, t . S^-1 t.
  auto solved = m_termSolved.head(count);
  solved = t;
  const auto factor = m_capacitance.topLeftCorner(count, count).triangularView<Eigen::Lower>();
  factor.solveInPlace(solved);
  factor.transpose().solveInPlace(solved);
  const double drop = t.dot(solved);
  for (Eigen::Index c = 0; c < count; ++c) {
    const RankOneTerm& term = terms[static_cast<std::size_t>(c)];
    for (std::size_t i = 0; i < kMaxTermNodes; ++i) {
      const Eigen::Vector3d delta = solved[c] * m_termW[static_cast<std::size_t>(c)][i];
      Eigen::Map<Eigen::Vector3d>(z + 3 * term.nodes[i]) -= delta;
      if (alsoP != nullptr) Eigen::Map<Eigen::Vector3d>(alsoP + 3 * term.nodes[i]) -= delta;
    }
  }
  return drop;
}

ConjugateGradientReport BlockConjugateGradient::solve(const BlockLinearOperator& a,
                                                      const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                                      double tolerance, int maxIterations,
                                                      std::span<const RankOneTerm> terms,
                                                      bool isWarm) {
  if (m_nodeCount != a.nodeCount()) resize(a);
  m_bounds = a.partBounds();
  bool isExactTerms = listTerms(terms);
  isWarm = isWarm && x.size() == b.size() && x.allFinite();
  if (x.size() != b.size()) x.resize(b.size());
  ConjugateGradientReport report;
  double* const xs = x.data();
  const double* const bs = b.data();
  double* const r = m_r.data();
  double* const z = m_z.data();
  double* const p = m_p.data();
  double* const q = m_q.data();
  double* const inverseBlocks = m_inverseBlocks.data();

  // A warm start's A x, into q (every part's rows need all of x).
  auto guessProduct = [&](std::size_t part, Eigen::Index, Eigen::Index) {
    a.multiplyPart(static_cast<int>(part), xs, q);
  };
  if (isWarm) forEachPart(guessProduct);
  // x = 0 and r = b (or r = b - A x), z = M^-1 r, p = z; partial sums of b.b, r.z and r.r.
  auto start = [&](std::size_t part, Eigen::Index first, Eigen::Index last) {
    double bb = 0.0, rz = 0.0, rr = 0.0;
    for (Eigen::Index j = first; j < last; ++j) {
      double* inverse = inverseBlocks + 6 * j;
      if (const Eigen::Matrix3d* termDiagonal = m_termDiagonals.at(j)) {
        invertDiagonalBlock(a.preconditionerBlock(j) - *termDiagonal, inverse);
      } else {
        invertDiagonalBlock(a.preconditionerBlock(j), inverse);
      }
      const double* bj = bs + 3 * j;
      double* rj = r + 3 * j;
      for (int c = 0; c < 3; ++c) {
        rj[c] = isWarm ? bj[c] - q[3 * j + c] : bj[c];
        if (!isWarm) xs[3 * j + c] = 0.0;
        bb += bj[c] * bj[c];
        rr += rj[c] * rj[c];
      }
      double* zj = z + 3 * j;
      applyInverse(inverse, rj, zj);
      for (int c = 0; c < 3; ++c) {
        p[3 * j + c] = zj[c];
        rz += rj[c] * zj[c];
      }
    }
    m_dotA[part] = bb;
    m_dotB[part] = rz;
    m_dotC[part] = rr;
  };
  forEachPart(start);
  const double bNorm2 = sumInOrder(m_dotA);
  if (bNorm2 == 0.0) {
    x.setZero();  // a warm start's guess too
    clearTerms();
    report.converged = true;
    return report;
  }
  double rz = sumInOrder(m_dotB);
  if (isExactTerms) {
    isExactTerms = factorCapacitance(terms);
    if (isExactTerms) {
      rz -= correctForTerms(terms, z, p);
    } else {
      // S not positive definite (B was not): back to plain block Jacobi, B = blockdiag(A).
      clearTerms();
      forEachPart(start);
      rz = sumInOrder(m_dotB);
    }
  }
  const double threshold =
      std::max(tolerance * tolerance * bNorm2, std::numeric_limits<double>::min());
  double alpha = 0.0, beta = 0.0;
  double residualNorm2 = sumInOrder(m_dotC);

  // q = A p on the part's rows; partial p.q.
  auto product = [&](std::size_t part, Eigen::Index first, Eigen::Index last) {
    a.multiplyPart(static_cast<int>(part), p, q);
    double pq = 0.0;
    for (Eigen::Index d = 3 * first; d < 3 * last; ++d) pq += p[d] * q[d];
    m_dotA[part] = pq;
  };
  // x += alpha p, r -= alpha q, z = M^-1 r; partial r.r and r.z.
  auto update = [&](std::size_t part, Eigen::Index first, Eigen::Index last) {
    double rr = 0.0, rzPart = 0.0;
    for (Eigen::Index j = first; j < last; ++j) {
      double* rj = r + 3 * j;
      for (int c = 0; c < 3; ++c) {
        const Eigen::Index d = 3 * j + c;
        xs[d] += alpha * p[d];
        rj[c] -= alpha * q[d];
        rr += rj[c] * rj[c];
      }
      double* zj = z + 3 * j;
      applyInverse(inverseBlocks + 6 * j, rj, zj);
      rzPart += rj[0] * zj[0] + rj[1] * zj[1] + rj[2] * zj[2];
    }
    m_dotA[part] = rr;
    m_dotB[part] = rzPart;
  };
  // p = z + beta p.
  auto direction = [&](std::size_t, Eigen::Index first, Eigen::Index last) {
    for (Eigen::Index d = 3 * first; d < 3 * last; ++d) p[d] = z[d] + beta * p[d];
  };

  while (report.iterations < maxIterations && residualNorm2 >= threshold) {
    forEachPart(product);
    const double pq = sumInOrder(m_dotA);
    if (!(pq > 0.0)) break;  // not positive definite along p (or NaN): give up, unconverged
    alpha = rz / pq;
    forEachPart(update);
    ++report.iterations;
    residualNorm2 = sumInOrder(m_dotA);
    if (!(residualNorm2 >= threshold)) break;  // converged, or NaN (reported below)
    double rzNext = sumInOrder(m_dotB);
    if (isExactTerms) rzNext -= correctForTerms(terms, z, nullptr);
    beta = rzNext / rz;
    rz = rzNext;
    forEachPart(direction);
  }
  clearTerms();
  report.relativeResidual = std::sqrt(residualNorm2 / bNorm2);
  report.converged = residualNorm2 < threshold;
  return report;
}

}  // namespace tissuesim
