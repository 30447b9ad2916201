#include "analysis/IndentationTest.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>

#include "analysis/TensileTest.h"
#include "fem/FemModel.h"
#include "fem/FemStaticSolver.h"
#include "fem/QuadraticTetMesh.h"
#include "forces/CapsulePenalty.h"
#include "mesh/BlockMesher.h"
#include "springs/SpringMesh.h"
#include "system/NewtonSolver.h"

namespace tissuesim {
namespace {

constexpr double kOnPlane_m = 1e-12;
/// The springs' top face is sampled within this distance of the probe's axis (m): the probe's
/// radius with room for the surface drawn in, and about this finely (m).
constexpr double kSampledRadius_m = 0.012;
constexpr double kSampleSpacing_m = 2e-4;

/// Grid lines over [0, length]: cells of `finest` at 0, each kIndentationGrowth times the one
/// before, at most kIndentationCoarsest_m; the last cell ends at `length`.
std::vector<double> gradedLine(double length, double finest) {
  std::vector<double> line{0.0};
  double cell = finest;
  while (line.back() + cell < length - 0.5 * cell) {
    line.push_back(line.back() + cell);
    cell = std::min(cell * kIndentationGrowth, kIndentationCoarsest_m);
  }
  line.push_back(length);
  return line;
}

/// Each top-face node's share of the top face (m^2), on a rectilinear arrangement of the nodes
/// (true of the grid's corners and of a quadratic mesh's added nodes alike): half the gaps to its
/// neighbours along x times the same along y.
std::vector<double> topAreas(const Eigen::Matrix3Xd& nodes, const std::vector<int>& top) {
  // Per axis, each coordinate's share: half the gaps to the coordinates either side.
  const auto shares = [&](int axis) {
    std::set<double> line;
    for (const int node : top) line.insert(nodes(axis, node));
    const std::vector<double> sorted(line.begin(), line.end());
    std::map<double, double> share;
    for (std::size_t i = 0; i < sorted.size(); ++i) {
      const double before = i > 0 ? sorted[i] - sorted[i - 1] : 0.0;
      const double after = i + 1 < sorted.size() ? sorted[i + 1] - sorted[i] : 0.0;
      share[sorted[i]] = 0.5 * (before + after);
    }
    return share;
  };
  const std::map<double, double> shareX = shares(0);
  const std::map<double, double> shareY = shares(1);
  std::vector<double> areas;
  for (const int node : top) areas.push_back(shareX.at(nodes(0, node)) * shareY.at(nodes(1, node)));
  return areas;
}

/// The quasi-static loading: the probe lowered in steps of at most depthStep_m through every
/// asked depth, solve() (true when converged) after each; force() recorded at the asked depths.
template <typename Solve, typename Force>
void load(const IndentationSetup& setup, double top_m, const Eigen::Vector2d& axis_m,
          CapsulePenalty& probe, IndentationCurve& curve, const Solve& solve, const Force& force) {
  double depth = 0.0;
  for (const double target : setup.depths_m) {
    if (!(target > depth)) throw std::invalid_argument("indentation depths must increase");
    const int steps = static_cast<int>(std::ceil((target - depth) / setup.depthStep_m - 1e-9));
    const double start = depth;
    for (int s = 1; s <= steps; ++s) {
      depth = start + (target - start) * s / steps;
      probe.tip_m = Eigen::Vector3d(axis_m.x(), axis_m.y(), top_m - depth + setup.probeRadius_m);
      probe.top_m = probe.tip_m + Eigen::Vector3d(0.0, 0.0, 0.3);
      if (!solve()) ++curve.unconvergedPoints;
    }
    curve.force_N.push_back(force());
  }
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

IndentationCurve indentFem(const StrainEnergy& energy, const IndentationSetup& setup,
                           int refinement, double bulkModulus_Pa) {
  if (refinement < 1) throw std::invalid_argument("the FEM's refinement must be at least 1");
  const auto start = std::chrono::steady_clock::now();
  const Eigen::Vector3d& size = setup.size_m;
  const double finest = setup.probeRadius_m / refinement;
  const std::vector<double> xs = gradedLine(0.5 * size.x(), finest);
  const std::vector<double> ys = gradedLine(0.5 * size.y(), finest);
  std::vector<double> zs = gradedLine(size.z(), finest);  // from the top down
  for (double& z : zs) z = size.z() - z;
  std::reverse(zs.begin(), zs.end());
  const QuadraticTetMesh mesh = makeQuadraticTetMesh(makeRectilinearMesh(xs, ys, zs));
  FemModel model(mesh, energy, bulkModulus_Pa);

  std::vector<char> isFixed(static_cast<std::size_t>(3 * mesh.nodeCount()), 0);
  std::vector<int> top;
  for (Eigen::Index i = 0; i < mesh.nodeCount(); ++i) {
    const Eigen::Vector3d p = mesh.nodes_m.col(i);
    const auto dof = static_cast<std::size_t>(3 * i);
    if (p.x() < kOnPlane_m) isFixed[dof] = 1;      // symmetry plane x = 0
    if (p.y() < kOnPlane_m) isFixed[dof + 1] = 1;  // symmetry plane y = 0
    if (p.z() < kOnPlane_m) isFixed[dof] = isFixed[dof + 1] = isFixed[dof + 2] = 1;
    if (p.z() > size.z() - kOnPlane_m) top.push_back(static_cast<int>(i));
  }
  // The quadratic mesh's top nodes, each with its share of the face: dense where the grid is
  // graded towards the probe.
  const std::vector<double> areas = topAreas(mesh.nodes_m, top);
  std::vector<CapsulePenalty::Point> points;
  for (std::size_t i = 0; i < top.size(); ++i) {
    points.push_back(
        {{top[i], top[i], top[i]}, {1.0, 0.0, 0.0}, areas[i] * setup.pressureStiffness_Pa_m});
  }
  CapsulePenalty probe(std::move(points));
  probe.radius_m = setup.probeRadius_m;
  model.setExtraEnergy(&probe);

  IndentationCurve curve;
  curve.nodes = static_cast<int>(mesh.nodeCount());
  curve.elements = static_cast<int>(mesh.tetCount());
  FemStaticSolver solver;
  Eigen::Matrix3Xd x = mesh.nodes_m;
  const auto force = [&] { return 4.0 * probe.reaction(x).z(); };  // the quarter's, four times
  load(
      setup, size.z(), Eigen::Vector2d::Zero(), probe, curve,
      [&] {
        // Relative to the force, as the tensile test's: round-off grows with it.
        solver.setTolerance(1e-9 * std::max(1.0, force()));
        const FemSolveReport report = solver.solve(model, x, isFixed);
        curve.worstResidual_N = std::max(curve.worstResidual_N, report.residual_N);
        return report.converged;
      },
      force);
  curve.seconds = secondsSince(start);
  return curve;
}

IndentationCurve indentSprings(const StrainEnergy& energy, const StiffnessTable& table,
                               const IndentationSetup& setup, int targetSprings,
                               double bulkModulus_Pa) {
  if (targetSprings < 100) throw std::invalid_argument("at least 100 springs");
  const auto start = std::chrono::steady_clock::now();
  const Eigen::Vector3d& size = setup.size_m;
  // A Kuhn cell has about 7 springs (3 edges, 3 face diagonals, 1 body diagonal); cubic cells.
  const double cell = std::cbrt(size.prod() * 7.0 / targetSprings);
  const Eigen::Vector3i cells(std::max(1, static_cast<int>(std::lround(size.x() / cell))),
                              std::max(1, static_cast<int>(std::lround(size.y() / cell))),
                              std::max(1, static_cast<int>(std::lround(size.z() / cell))));
  const TissueParameters& parameters = energy.parameters();
  const TetMesh tetMesh = makeBlockMesh(size, cells);
  SpringMesh mesh = buildSpringMesh(tetMesh, parameters.density_kg_m3);
  // The simulator's calibration (Simulation::buildPhysics).
  mesh.volume_m3 *= TensileTest(energy, table, TensileSpecimen{})
                        .smallStrainCalibration(energy.initialShearModulus());
  const SpringForceLaw law(SpringLaw::Eesm, table, parameters, 0.0, /*isSoftening=*/false);
  SpringForceField springs(mesh, law);
  std::unique_ptr<VolumeForceField> volume;
  if (bulkModulus_Pa > 0.0) volume = std::make_unique<VolumeForceField>(mesh, bulkModulus_Pa);
  MechanicalSystem system(springs, volume.get());
  for (Eigen::Index i = 0; i < mesh.nodeCount(); ++i) {
    if (mesh.restPositions_m(2, i) < kOnPlane_m) system.fixNode(static_cast<int>(i));
  }
  // The top face's triangles near the probe, sampled as the simulator's contacts sample its
  // drawn surface: points of the triangles, their forces shared by barycentric weights. (The
  // nodes alone let the probe pass between them on a coarse lattice.)
  const Eigen::Vector2d axis(0.5 * size.x(), 0.5 * size.y());
  std::vector<CapsulePenalty::Point> points;
  const Eigen::Matrix3Xi faces = boundaryFaces(tetMesh);
  for (Eigen::Index f = 0; f < faces.cols(); ++f) {
    const Eigen::Vector3d a = tetMesh.nodes_m.col(faces(0, f));
    const Eigen::Vector3d b = tetMesh.nodes_m.col(faces(1, f));
    const Eigen::Vector3d c = tetMesh.nodes_m.col(faces(2, f));
    if (std::min({a.z(), b.z(), c.z()}) < size.z() - kOnPlane_m) continue;
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    const double reach = (a - centroid).norm() + (b - centroid).norm() + (c - centroid).norm();
    if ((centroid.head<2>() - axis).norm() > kSampledRadius_m + reach) continue;
    // m^2 sub-triangles of about kSampleSpacing_m, one point at each one's centroid.
    const double area = 0.5 * (b - a).cross(c - a).norm();
    const int m =
        std::max(1, static_cast<int>(std::ceil(std::sqrt(2.0 * area) / kSampleSpacing_m)));
    for (int i = 0; i < m; ++i) {
      for (int j = 0; i + j < m; ++j) {
        // The upward sub-triangle (i, j) and, where there is one, the downward one beside it.
        for (int flip = 0; flip < (i + j + 1 < m ? 2 : 1); ++flip) {
          const double u = (flip == 0 ? i + 1.0 / 3.0 : i + 2.0 / 3.0) / m;
          const double v = (flip == 0 ? j + 1.0 / 3.0 : j + 2.0 / 3.0) / m;
          points.push_back({{faces(0, f), faces(1, f), faces(2, f)},
                            {1.0 - u - v, u, v},
                            area / (m * m) * setup.pressureStiffness_Pa_m});
        }
      }
    }
  }
  CapsulePenalty probe(std::move(points));
  probe.radius_m = setup.probeRadius_m;
  system.addField(probe);

  IndentationCurve curve;
  curve.nodes = static_cast<int>(mesh.nodeCount());
  curve.elements = static_cast<int>(mesh.springCount());
  NewtonSolver newton(LinearSolverKind::Cholesky);
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  const auto force = [&] { return probe.reaction(x).z(); };
  load(
      setup, size.z(), axis, probe, curve,
      [&] {
        const Eigen::Matrix3Xd previous = x;
        const NewtonReport report =
            newton.solve(system, x, previous, 0.0, 0.0, 200, 1e-9 * std::max(1.0, force()));
        curve.worstResidual_N = std::max(curve.worstResidual_N, report.residual_N);
        return report.converged;
      },
      force);
  curve.seconds = secondsSince(start);
  return curve;
}

}  // namespace tissuesim
