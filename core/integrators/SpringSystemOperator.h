#pragma once
// Newton's linear system for the spring network, applied without assembling it (matrix-free):
//
//   A = sum_e S_e^T [K_e, -K_e; -K_e, K_e] S_e + sum_t c_t g_t g_t^T + diag(d_j I)
//       + sum_c k_c u_c u_c^T                                                             (N/m)
//
// with K_e = c_e n_e n_e^T + l_e I spring e's stiffness block on its ends (a, b) (AxialBlocks,
// from the spring pass), c_t g_t g_t^T tet t's volume-term block on its four nodes
// (VolumeBlocks, when the system has the term), d_j = w m_j + s node j's inertia weight and
// shift, and the instrument's contacts as rank-one terms (RankOneTerm); the fixed DOFs' rows
// and columns are the identity's. A: 3#V by 3#V; x, y: 3#V.
//
// Why matrix-free: the assembled NodeBlockMatrix stores two 72-byte blocks a spring plus the
// diagonal, and filling it is a pass of its own after the spring pass; this reads the spring
// pass's 40 bytes a spring, and K_e (x_b - x_a) = c n (n . d) + l d costs about what a block
// row costs. Measured (one thread, micro-benchmark): a product on the liver (5.3k springs, the
// assembled matrix 0.8 MB, in cache) 26-28 us against 27-38; at 102k springs (a 16 MB matrix
// read from memory every product) 0.47-0.78 ms against 0.56-1.4. In the solver: the implicit
// step at 102k springs 33 -> 22 ms on one thread, 22 -> 15 ms on two; the held probe's step
// at 5.3k about 5 % faster (no assignment pass, less the preconditioner's blocks gathered per
// solve). docs/performance.md has the interleaved figures.
//
// Parallel parts: kParts node ranges of about equal incident springs. Part p evaluates every
// spring with an end among its nodes and adds its force to those ends only; a spring joining
// two parts is evaluated by both, each adding to its own end. Tets likewise: part p takes
// c_t g_t . x once for every tet with a node among its own, and adds to those nodes only. No two
// parts write the same row, and each row's sum runs in a fixed order, so products are bit-identical
// for any thread count.
//
// The product's precondition: x is zero on the fixed DOFs (CG's directions are, since its
// right-hand side and preconditioner are), so the fixed columns need no masking; the fixed rows
// of y are x's. No allocation once constructed, up to kReservedTerms contact terms.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "numerics/AxialBlocks.h"
#include "numerics/BlockLinearOperator.h"
#include "numerics/RankOneTerm.h"
#include "numerics/RankOneTermDiagonals.h"
#include "springs/SpringMesh.h"
#include "springs/VolumeForceField.h"

namespace tissuesim {

class SpringSystemOperator final : public BlockLinearOperator {
 public:
  static constexpr int kReservedTerms = 256;

  /// The pattern: `mesh`'s springs and nodes (the mesh must outlive this object).
  explicit SpringSystemOperator(const SpringMesh& mesh);

  /// K_e per spring (5 by #S; must outlive its use here, and is read, not copied).
  void setSpringBlocks(const AxialBlocks& blocks);
  /// The volume term's blocks (13 by #T; read, not copied), or null for none. The first
  /// non-null call builds the per-part tet lists (allocation once).
  void setVolumeBlocks(const VolumeBlocks* blocks);
  /// d_j = massWeight m_j + shift (N/m): massWeight (1/s^2), shift (N/m).
  void setDiagonal(double massWeight, double shift_N_m) {
    m_massWeight = massWeight;
    m_shift_N_m = shift_N_m;
  }
  /// 3#V flags; the per-part lists are rebuilt only when the flags change.
  void setFixedDofs(const std::vector<char>& isFixed);
  /// The contacts' terms (each u zero on the fixed DOFs; the vector must outlive its use here,
  /// and is read, not copied: call again after changing it). Null or empty: none.
  void setTerms(const std::vector<RankOneTerm>* terms);

  Eigen::Index nodeCount() const override { return m_mesh.nodeCount(); }
  const PartBounds& partBounds() const override { return m_bounds; }
  void multiplyPart(int part, const double* x, double* y) const override;
  Eigen::Matrix3d diagonalBlock(Eigen::Index j) const override;

  /// The largest diagonal entry of A (N/m; a scale for Levenberg-Marquardt shifts). A pass
  /// over the springs: not for every iteration.
  double largestDiagonalEntry() const;

 private:
  /// A spring as the product reads it: where its ends' rows start (3a, 3b) and its index.
  struct SpringEntry {
    int rowA;
    int rowB;
    int spring;
  };
  /// The springs [begin, end) of m_entries into y, each on its a row (when AddA) and its b row
  /// (when AddB).
  template <bool AddA, bool AddB>
  void addSpringProducts(std::size_t begin, std::size_t end, const double* x, double* y) const;

  /// A tet as the product reads it: where its nodes' rows start, its index, and which of its
  /// nodes (bit i: node i) lie in the part that lists it.
  struct TetEntry {
    std::array<int, 4> rows;
    int tet;
    unsigned ownNodes;
  };
  void buildTetLists();
  /// The tets [begin, end) of m_tetEntries into y; AllOwn: every node of each is the part's.
  template <bool AllOwn>
  void addTetProducts(std::size_t begin, std::size_t end, const double* x, double* y) const;

  const SpringMesh& m_mesh;
  PartBounds m_bounds{};
  // Per part, three lists in spring order: the springs with both ends among its nodes, those with
  // only a, those with only b; m_listStart[p] = {both, a only, b only, end} into m_entries. Three
  // lists, not one with flags: the loops then have no branch but the run's (measured 20 % faster).
  std::vector<SpringEntry> m_entries;
  std::array<std::array<std::size_t, 4>, kParts> m_listStart{};
  // Per node j, its springs are m_incident[m_incidentStart[j] .. m_incidentStart[j + 1]).
  std::vector<int> m_incidentStart;
  std::vector<int> m_incident;
  const AxialBlocks* m_blocks = nullptr;
  // Per part, its tets in two lists (all four nodes its own; some), m_tetListStart[p] = {all,
  // some, end} into m_tetEntries; and each node's tets (for the diagonal blocks).
  std::vector<TetEntry> m_tetEntries;
  std::array<std::array<std::size_t, 3>, kParts> m_tetListStart{};
  TetIncidence m_tetIncidence;
  const VolumeBlocks* m_volumeBlocks = nullptr;
  double m_massWeight = 0.0;
  double m_shift_N_m = 0.0;
  std::vector<char> m_isFixed;            ///< 3#V, as last set
  std::vector<Eigen::Index> m_fixedDofs;  ///< the fixed DOFs, part after part
  std::array<std::size_t, kParts + 1> m_fixedStart{};
  const std::vector<RankOneTerm>* m_terms = nullptr;
  RankOneTermDiagonals m_termDiagonals;
};

}  // namespace tissuesim
