// SPDX-License-Identifier: Apache-2.0
#include "analysis/IndentationExperiment.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>

#include "analysis/NetworkCalibration.h"
#include "analysis/SecondsSince.h"
#include "analysis/TensileExperiment.h"
#include "analysis/UniaxialExperiment.h"
#include "fem/FemModel.h"
#include "fem/FemStaticSolver.h"
#include "fem/QuadraticTetMesh.h"
#include "fem/QuadraticTetShape.h"
#include "fem/TetIsochoricForceField.h"
#include "forces/CapsulePenalty.h"
#include "integrators/IntegratorChoice.h"
#include "mesh/BlockMesher.h"
#include "mesh/TetLocator.h"
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
  const TetMesh corners = makeRectilinearMesh(xs, ys, zs);
  const QuadraticTetMesh mesh = makeQuadraticTetMesh(corners);
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
  // The top face's displacement: each sample located among the corner tets (the quadratic
  // tets' straight-edged geometry), interpolated by the quadratic shape functions.
  const TetLocator locator(corners);
  for (const Eigen::Vector2d& offset : setup.surfaceSamples_m) {
    const TetLocation location = locator.locate(Eigen::Vector3d(offset.x(), offset.y(), size.z()));
    const Eigen::Matrix<double, 10, 1> shape = quadraticTetShapeValues(location.weights);
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    for (int a = 0; a < 10; ++a) {
      const int node = mesh.tets(a, location.tet);
      u += shape(a) * (x.col(node) - mesh.nodes_m.col(node));
    }
    curve.surfaceDisplacement_m.push_back(u);
  }
  curve.seconds = secondsSince(start);
  return curve;
}

double indentationCellEdge(const IndentationSetup& setup, int targetSprings) {
  if (targetSprings < 100) throw std::invalid_argument("at least 100 springs");
  // A Kuhn cell has about 7 springs (3 edges, 3 face diagonals, 1 body diagonal).
  return std::cbrt(setup.size_m.prod() * 7.0 / targetSprings);
}

namespace {

/// The block's network and its probe, held together: the system refers to the rest.
struct BlockNetwork {
  TetMesh tetMesh;
  SpringMesh mesh;
  std::unique_ptr<SpringForceLaw> law;
  std::unique_ptr<SpringForceField> springs;
  std::unique_ptr<VolumeForceField> volume;
  std::unique_ptr<TetIsochoricForceField> tets;
  std::unique_ptr<MechanicalSystem> system;
  std::unique_ptr<CapsulePenalty> probe;
  Eigen::Vector2d axis_m = Eigen::Vector2d::Zero();
};

/// The top face's triangles near the probe's axis, sampled as the simulator's contacts sample
/// its drawn surface: points of the triangles, their forces shared by barycentric weights, each
/// with the stiffness of its share of the face. (The nodes alone let the probe pass between
/// them on a coarse lattice.)
std::vector<CapsulePenalty::Point> sampledTopFace(const TetMesh& tetMesh,
                                                  const IndentationSetup& setup) {
  const Eigen::Vector3d& size = setup.size_m;
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
  return points;
}

/// The sampled top face's points as contacts frozen for a step (sampledTopFaceContact).
class SampledTopFaceContact final : public ContactProvider {
 public:
  SampledTopFaceContact(std::vector<CapsulePenalty::Point> points, double radius_m)
      : m_points(std::move(points)), m_radius_m(radius_m) {}

  void findContacts(const Eigen::Matrix3Xd& x, const InstrumentPose& pose,
                    PenaltyContactSet& contacts) override {
    // The axis: from the tip's hemisphere centre back along the shaft.
    const Eigen::Vector3d a = pose.tip_m - m_radius_m * pose.direction;
    const Eigen::Vector3d b = a - kShaft_m * pose.direction;
    for (const CapsulePenalty::Point& point : m_points) {
      PenaltyContact contact;
      for (std::size_t k = 0; k < 3; ++k) {
        contact.nodes[k] = point.nodes[k];
        contact.weights[static_cast<Eigen::Index>(k)] = point.weights[static_cast<Eigen::Index>(k)];
      }
      contact.nodes[3] = point.nodes[0];
      const Eigen::Vector3d p = contact.point(x);
      const double along = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      const Eigen::Vector3d c = a + along * (b - a);
      const double distance = (p - c).norm();
      if (!(distance < 1.5 * m_radius_m) || distance == 0.0) continue;
      const Eigen::Vector3d u = (p - c) / distance;
      // |p - c| >= r along u: -u . p <= -u . c - r.
      contact.normal = -u;
      contact.offset_m = -u.dot(c) - m_radius_m;
      contact.stiffness_N_m = point.stiffness_N_m;
      contacts.add(contact);
    }
  }

 private:
  static constexpr double kShaft_m = 0.3;
  std::vector<CapsulePenalty::Point> m_points;
  double m_radius_m;
};

/// With `withProbe`, the probe's penalty on the sampled top face as a field of the system.
std::unique_ptr<BlockNetwork> makeBlockNetwork(const StrainEnergy& energy,
                                               const StiffnessTable& table,
                                               const IndentationSetup& setup,
                                               const IndentationNetwork& settings, bool withProbe) {
  if (!(settings.cellEdge_m > 0.0)) throw std::invalid_argument("the cell edge must be > 0");
  const Eigen::Vector3d& size = setup.size_m;
  Eigen::Vector3i cells;
  for (int axis = 0; axis < 3; ++axis) {
    const long count = std::lround(size(axis) / settings.cellEdge_m);
    if (count > kIndentationMaxCells)
      throw std::invalid_argument("the cell edge is too small for the block");
    cells(axis) = static_cast<int>(std::max(1L, count));
  }
  const TissueParameters& parameters = energy.parameters();
  auto network = std::make_unique<BlockNetwork>();
  network->tetMesh = makeBlockMesh(size, cells);
  network->mesh = buildSpringMesh(network->tetMesh, parameters.density_kg_m3);
  const bool isTets = settings.model == LatticeModel::IsochoricTets;
  if (isTets && !(settings.bulkModulus_Pa > 0.0))
    throw std::invalid_argument("the isochoric tets need a volume term");
  // The tets' model keeps the springs for the mesh's structure only: no stiffness.
  network->mesh.volume_m3 *= isTets ? 0.0
                             : settings.stiffnessScale > 0.0
                                 ? settings.stiffnessScale
                                 : simulatorStiffnessScale(energy, table, settings.bulkModulus_Pa);
  network->law = std::make_unique<SpringForceLaw>(
      settings.law, table, parameters,
      UniaxialExperiment::springLawLinearModulus(settings.law, energy, table),
      /*isSoftening=*/false);
  network->springs = std::make_unique<SpringForceField>(network->mesh, *network->law);
  if (settings.bulkModulus_Pa > 0.0)
    network->volume = std::make_unique<VolumeForceField>(network->mesh, settings.bulkModulus_Pa);
  network->system = std::make_unique<MechanicalSystem>(*network->springs, network->volume.get());
  if (isTets) {
    network->tets = std::make_unique<TetIsochoricForceField>(network->tetMesh.nodes_m,
                                                             network->tetMesh.tets, energy);
    network->system->addField(*network->tets);
  }
  for (Eigen::Index i = 0; i < network->mesh.nodeCount(); ++i) {
    if (network->mesh.restPositions_m(2, i) < kOnPlane_m)
      network->system->fixNode(static_cast<int>(i));
  }
  network->axis_m = Eigen::Vector2d(0.5 * size.x(), 0.5 * size.y());
  if (!withProbe) return network;
  network->probe = std::make_unique<CapsulePenalty>(sampledTopFace(network->tetMesh, setup));
  network->probe->radius_m = setup.probeRadius_m;
  network->system->addField(*network->probe);
  return network;
}

/// The network's top-face displacement at the setup's samples (m), positions x.
std::vector<Eigen::Vector3d> networkSurfaceDisplacement(const BlockNetwork& network,
                                                        const IndentationSetup& setup,
                                                        const Eigen::Matrix3Xd& x) {
  const TetLocator locator(network.tetMesh);
  std::vector<Eigen::Vector3d> displacement;
  for (const Eigen::Vector2d& offset : setup.surfaceSamples_m) {
    const Eigen::Vector2d at = network.axis_m + offset;
    const TetLocation location = locator.locate(Eigen::Vector3d(at.x(), at.y(), setup.size_m.z()));
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) {
      const int node = network.tetMesh.tets(k, location.tet);
      u += location.weights(k) * (x.col(node) - network.mesh.restPositions_m.col(node));
    }
    displacement.push_back(u);
  }
  return displacement;
}

}  // namespace

IndentationCurve indentSprings(const StrainEnergy& energy, const StiffnessTable& table,
                               const IndentationSetup& setup, const IndentationNetwork& settings) {
  const auto start = std::chrono::steady_clock::now();
  const std::unique_ptr<BlockNetwork> network =
      makeBlockNetwork(energy, table, setup, settings, true);
  CapsulePenalty& probe = *network->probe;
  IndentationCurve curve;
  curve.nodes = static_cast<int>(network->mesh.nodeCount());
  curve.elements =
      static_cast<int>(network->tets ? network->tets->tetCount() : network->mesh.springCount());
  NewtonSolver newton(LinearSolverKind::Cholesky);
  Eigen::Matrix3Xd x = network->mesh.restPositions_m;
  const auto force = [&] { return probe.reaction(x).z(); };
  load(
      setup, setup.size_m.z(), network->axis_m, probe, curve,
      [&] {
        const Eigen::Matrix3Xd previous = x;
        const NewtonReport report = newton.solve(*network->system, x, previous, 0.0, 0.0, 200,
                                                 1e-9 * std::max(1.0, force()));
        curve.worstResidual_N = std::max(curve.worstResidual_N, report.residual_N);
        return report.converged;
      },
      force);
  curve.surfaceDisplacement_m = networkSurfaceDisplacement(*network, setup, x);
  curve.seconds = secondsSince(start);
  return curve;
}

IndentationContactFactory sampledTopFaceContact(const IndentationSetup& setup) {
  return [setup](const TetMesh& block) -> std::unique_ptr<ContactProvider> {
    return std::make_unique<SampledTopFaceContact>(sampledTopFace(block, setup),
                                                   setup.probeRadius_m);
  };
}

IndentationCurve indentSpringsAtPace(const StrainEnergy& energy, const StiffnessTable& table,
                                     const IndentationSetup& setup,
                                     const IndentationNetwork& settings,
                                     const IndentationPace& pace,
                                     const IndentationContactFactory& makeContact) {
  if (!(pace.speed_m_s > 0.0) || !(pace.timeStep_s > 0.0))
    throw std::invalid_argument("the pace's speed and time step must be > 0");
  if (setup.depths_m.empty()) throw std::invalid_argument("no indentation depths");
  const auto start = std::chrono::steady_clock::now();
  const std::unique_ptr<BlockNetwork> network =
      makeBlockNetwork(energy, table, setup, settings, false);
  const std::unique_ptr<TimeIntegrator> integrator = makeIntegrator(pace.integrator, pace.settings);
  const std::unique_ptr<ContactProvider> contact = makeContact(network->tetMesh);
  MechanicalSystem& system = *network->system;
  IndentationCurve curve;
  curve.nodes = static_cast<int>(network->mesh.nodeCount());
  curve.elements =
      static_cast<int>(network->tets ? network->tets->tetCount() : network->mesh.springCount());
  MechanicalState state = system.restState();
  const double stepDepth_m = pace.speed_m_s * pace.timeStep_s;
  const auto steps = static_cast<long>(std::ceil(setup.depths_m.back() / stepDepth_m - 1e-9));
  InstrumentPose pose;   // axis vertical, tip down
  std::size_t next = 0;  // the next depth to record
  double previousDepth = 0.0;
  double previousForce = 0.0;
  for (long n = 1; n <= steps; ++n) {
    const double depth = std::min(static_cast<double>(n) * stepDepth_m, setup.depths_m.back());
    // The pose's tip is the instrument's lowest point (its hemisphere's centre is a radius up).
    pose.tip_m =
        Eigen::Vector3d(network->axis_m.x(), network->axis_m.y(), setup.size_m.z() - depth);
    system.contacts.clear();
    contact->findContacts(state.x, pose, system.contacts);
    const StepReport report = integrator->step(system, state, pace.timeStep_s);
    if (report.refused || !report.isFinite) ++curve.failedSteps;
    if (!report.converged) ++curve.unconvergedPoints;
    curve.worstResidual_N = std::max(curve.worstResidual_N, report.residual_N);
    // What the simulator reports as the tool's force (Simulation::step).
    Eigen::Vector3d toolForce_N = system.contacts.reaction(state.x, pose.tip_m).toolForce_N;
    if (report.toolImpulse_Ns && report.isFinite)
      toolForce_N = *report.toolImpulse_Ns / pace.timeStep_s;
    const double force = toolForce_N.z();
    while (next < setup.depths_m.size() && setup.depths_m[next] <= depth + 1e-12) {
      const double share = (setup.depths_m[next] - previousDepth) / (depth - previousDepth);
      curve.force_N.push_back(previousForce + share * (force - previousForce));
      ++next;
    }
    previousDepth = depth;
    previousForce = force;
  }
  curve.surfaceDisplacement_m = networkSurfaceDisplacement(*network, setup, state.x);
  curve.seconds = secondsSince(start);
  return curve;
}

std::vector<Eigen::Vector2d> IndentationSetup::defaultSurfaceSamples() {
  std::vector<Eigen::Vector2d> samples;
  const Eigen::Vector2d diagonal = Eigen::Vector2d(1.0, 1.0).normalized();
  for (int r = 0; r <= 15; ++r) {
    samples.emplace_back(1e-3 * r, 0.0);
    if (r > 0) samples.push_back(1e-3 * r * diagonal);
  }
  return samples;
}

}  // namespace tissuesim
