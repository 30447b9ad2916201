#include "numerics/BlockConjugateGradient.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tissuesim {

void BlockConjugateGradient::resize(const NodeBlockMatrix& a) {
  const Eigen::Index nodes = a.nodeCount();
  m_nodeCount = nodes;
  for (Eigen::VectorXd* v : {&m_r, &m_z, &m_p, &m_q}) v->resize(3 * nodes);
  m_inverseBlocks.resize(6 * nodes);
  m_bounds = a.balancedNodeRanges<kParts>();  // equal shares of the product's work
}

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

ConjugateGradientReport BlockConjugateGradient::solve(const NodeBlockMatrix& a,
                                                      const Eigen::VectorXd& b,
                                                      Eigen::VectorXd& x, double tolerance,
                                                      int maxIterations) {
  if (m_nodeCount != a.nodeCount()) resize(a);
  if (x.size() != b.size()) x.resize(b.size());
  ConjugateGradientReport report;
  double* const xs = x.data();
  const double* const bs = b.data();
  double* const r = m_r.data();
  double* const z = m_z.data();
  double* const p = m_p.data();
  double* const q = m_q.data();
  double* const inverseBlocks = m_inverseBlocks.data();

  // x = 0, r = b, z = M^-1 r, p = z; partial sums of b.b and r.z.
  auto start = [&](std::size_t part, Eigen::Index first, Eigen::Index last) {
    double bb = 0.0, rz = 0.0;
    for (Eigen::Index j = first; j < last; ++j) {
      double* inverse = inverseBlocks + 6 * j;
      invertDiagonalBlock(a.diagonalBlock(j), inverse);
      const double* bj = bs + 3 * j;
      double* zj = z + 3 * j;
      applyInverse(inverse, bj, zj);
      for (int c = 0; c < 3; ++c) {
        xs[3 * j + c] = 0.0;
        r[3 * j + c] = bj[c];
        p[3 * j + c] = zj[c];
        bb += bj[c] * bj[c];
        rz += bj[c] * zj[c];
      }
    }
    m_dotA[part] = bb;
    m_dotB[part] = rz;
  };
  forEachPart(start);
  const double bNorm2 = sumInOrder(m_dotA);
  if (bNorm2 == 0.0) {
    report.converged = true;
    return report;
  }
  const double threshold = std::max(tolerance * tolerance * bNorm2,
                                    std::numeric_limits<double>::min());
  double rz = sumInOrder(m_dotB);
  double alpha = 0.0, beta = 0.0;

  // q = A p on the part's rows; partial p.q.
  auto product = [&](std::size_t part, Eigen::Index first, Eigen::Index last) {
    a.multiplyNodes(first, last, p, q);
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

  double residualNorm2 = bNorm2;
  while (report.iterations < maxIterations) {
    forEachPart(product);
    const double pq = sumInOrder(m_dotA);
    if (!(pq > 0.0)) break;  // not positive definite along p (or NaN): give up, unconverged
    alpha = rz / pq;
    forEachPart(update);
    ++report.iterations;
    residualNorm2 = sumInOrder(m_dotA);
    if (!(residualNorm2 >= threshold)) break;  // converged, or NaN (reported below)
    const double rzNext = sumInOrder(m_dotB);
    beta = rzNext / rz;
    rz = rzNext;
    forEachPart(direction);
  }
  report.relativeResidual = std::sqrt(residualNorm2 / bNorm2);
  report.converged = residualNorm2 < threshold;
  return report;
}

}  // namespace tissuesim
