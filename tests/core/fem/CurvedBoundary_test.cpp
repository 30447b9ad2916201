// SPDX-License-Identifier: Apache-2.0
// A quadratic mesh's boundary bent onto the drawn surface (fem/CurvedBoundary.h): on a ball of
// twenty tets round its centre, every boundary edge's middle node goes onto the drawn sphere, the
// interior's stay, and the body's volume comes most of the way from the chords' to the surface's;
// an edge whose corner is off the surface stays straight; and the sampled Jacobian finds a middle
// node moved to its edge's quarter point (where the quadratic map folds) and none on a straight
// tet.

#include "fem/CurvedBoundary.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include "fem/FemModel.h"
#include "fem/QuadraticTetShape.h"
#include "fem/QuadraticTetWeight.h"
#include "mesh/ClosestSurfacePoint.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

constexpr double kBallRadius_m = 0.02;

/// The icosahedron's twelve corners and twenty faces, on the sphere of kBallRadius_m.
TriangleSurface icosahedron() {
  const double p = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleSurface surface;
  surface.vertices_m.resize(3, 12);
  surface.vertices_m << -1, 1, -1, 1, 0, 0, 0, 0, p, p, -p, -p,  //
      p, p, -p, -p, -1, 1, -1, 1, 0, 0, 0, 0,                    //
      0, 0, 0, 0, p, p, -p, -p, -1, 1, -1, 1;
  surface.vertices_m *= kBallRadius_m / std::sqrt(1.0 + p * p);
  surface.triangles.resize(3, 20);
  surface.triangles << 0, 0, 0, 0, 0, 1, 5, 11, 10, 7, 3, 3, 3, 3, 3, 4, 2, 6, 8, 9,  //
      11, 5, 1, 7, 10, 5, 11, 10, 7, 1, 9, 4, 2, 6, 8, 9, 4, 2, 6, 8,                 //
      5, 1, 7, 10, 11, 9, 4, 2, 6, 8, 4, 2, 6, 8, 9, 5, 11, 10, 7, 1;
  return surface;
}

/// Each triangle cut into four through its edges' middles pushed out onto the sphere, `levels`
/// times: the sphere drawn finer, through the coarse corners and the sphere over their chords.
TriangleSurface subdivided(TriangleSurface surface, int levels) {
  for (int level = 0; level < levels; ++level) {
    std::vector<Eigen::Vector3d> vertices;
    for (Eigen::Index v = 0; v < surface.vertexCount(); ++v)
      vertices.emplace_back(surface.vertices_m.col(v));
    std::map<std::pair<int, int>, int> middleOf;
    const auto middle = [&](int a, int b) {
      const auto [at, isNew] =
          middleOf.try_emplace({std::min(a, b), std::max(a, b)}, static_cast<int>(vertices.size()));
      if (isNew)
        vertices.push_back(kBallRadius_m * (vertices[static_cast<std::size_t>(a)] +
                                            vertices[static_cast<std::size_t>(b)])
                                               .normalized());
      return at->second;
    };
    Eigen::Matrix3Xi triangles(3, 4 * surface.triangleCount());
    for (Eigen::Index t = 0; t < surface.triangleCount(); ++t) {
      const int a = surface.triangles(0, t), b = surface.triangles(1, t),
                c = surface.triangles(2, t);
      const int ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
      triangles.middleCols<4>(4 * t) << a, ab, ca, ab,  //
          ab, b, bc, bc,                                //
          ca, bc, c, ca;
    }
    surface.vertices_m.resize(3, static_cast<Eigen::Index>(vertices.size()));
    for (std::size_t v = 0; v < vertices.size(); ++v)
      surface.vertices_m.col(static_cast<Eigen::Index>(v)) = vertices[v];
    surface.triangles = triangles;
  }
  return surface;
}

/// A closed surface round the origin filled with one tet a face, round a node at the origin (the
/// last node: 12 on the icosahedron).
TetMesh ballRoundCentre(const TriangleSurface& hull) {
  const Eigen::Index corners = hull.vertexCount();
  TetMesh ball;
  ball.nodes_m.resize(3, corners + 1);
  ball.nodes_m.leftCols(corners) = hull.vertices_m;
  ball.nodes_m.col(corners).setZero();
  ball.tets.resize(4, hull.triangleCount());
  for (Eigen::Index f = 0; f < hull.triangleCount(); ++f) {
    ball.tets.col(f) << static_cast<int>(corners), hull.triangles(0, f), hull.triangles(1, f),
        hull.triangles(2, f);
    if (signedTetVolume(ball.nodes_m, ball.tets, f) < 0.0)
      std::swap(ball.tets(2, f), ball.tets(3, f));
  }
  return ball;
}

/// The mesh's volume as a rule integrates det(dX/dxi): exactly with the degree-3 rule (the FEM's
/// V_e), as the isochoric energy's points weigh it with the degree-2 one.
template <std::size_t Points>
double ruleVolume(const QuadraticTetMesh& mesh,
                  const std::array<TetQuadraturePoint, Points>& rule) {
  double volume_m3 = 0.0;
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    for (const TetQuadraturePoint& point : rule)
      volume_m3 += point.weight * quadraticTetJacobian(mesh, t, point.xi).determinant();
  }
  return volume_m3;
}
double restVolume(const QuadraticTetMesh& mesh) { return ruleVolume(mesh, tetQuadratureDegree3()); }

TEST(CurvedBoundary, TheBoundarysMiddleNodesGoOntoTheDrawnSurfaceAndTheVolumeFollowsIt) {
  const TriangleSurface coarse = icosahedron();
  const TriangleSurface drawn = subdivided(coarse, 3);
  const TetMesh ball = ballRoundCentre(coarse);
  const QuadraticTetMesh straight = makeQuadraticTetMesh(ball);
  QuadraticTetMesh curved = straight;
  const CurvedBoundaryReport report = curveBoundaryOnto(curved, ball, drawn);

  EXPECT_EQ(report.boundaryEdges, 30);
  EXPECT_EQ(report.bent, 30);
  EXPECT_EQ(report.shortened + report.left, 0);
  // The sphere's sagitta over an edge: r (1 - cos(theta / 2)), theta the edge's angle.
  const double edge_m = (coarse.vertices_m.col(0) - coarse.vertices_m.col(11)).norm();
  const double sagitta_m =
      kBallRadius_m - std::sqrt(kBallRadius_m * kBallRadius_m - edge_m * edge_m / 4.0);
  EXPECT_GT(report.largestMove_m, 0.9 * sagitta_m);
  EXPECT_LT(report.largestMove_m, sagitta_m);

  const ClosestSurfacePoint closest(drawn);
  int onSurface = 0, kept = 0;
  for (Eigen::Index node = curved.cornerCount; node < curved.nodeCount(); ++node) {
    const Eigen::Vector3d at = curved.nodes_m.col(node);
    if (straight.nodes_m.col(node).norm() < 0.6 * kBallRadius_m) {  // a spoke's middle, inside
      EXPECT_TRUE(at.isApprox(straight.nodes_m.col(node), 0.0));
      ++kept;
    } else {
      EXPECT_LT((closest(at) - at).norm(), 1e-12 * kBallRadius_m);
      ++onSurface;
    }
  }
  EXPECT_EQ(onSurface, 30);
  EXPECT_EQ(kept, 12);
  EXPECT_TRUE(curved.nodes_m.leftCols(13).isApprox(straight.nodes_m.leftCols(13), 0.0));

  for (Eigen::Index t = 0; t < curved.tetCount(); ++t) {
    EXPECT_NEAR(leastJacobianShare(straight, t), 1.0, 1e-12);
    EXPECT_GE(leastJacobianShare(curved, t), kLeastJacobianShare);
  }
  // The chords' body holds about 61 % of the sphere's volume; the curved one most of the rest.
  const double drawnVolume_m3 = enclosedVolume(drawn);
  const double straightGap_m3 = std::abs(restVolume(straight) - drawnVolume_m3);
  EXPECT_GT(straightGap_m3, 0.3 * drawnVolume_m3);
  EXPECT_LT(std::abs(restVolume(curved) - drawnVolume_m3), 0.25 * straightGap_m3);
}

TEST(CurvedBoundary, TheFemTakesAHomogeneousDeformationOfTheCurvedBallExactly) {
  // x = F X at every node is x = F X everywhere on an isoparametric element, curved or not: the
  // energy per unit rest volume is the material's at F on both balls. Gradients taken from the
  // corners alone (as if the edges were straight) would see another F where the edges curve.
  const TriangleSurface coarse = icosahedron();
  const TetMesh ball = ballRoundCentre(coarse);
  const QuadraticTetMesh straight = makeQuadraticTetMesh(ball);
  QuadraticTetMesh curved = straight;
  ASSERT_EQ(curveBoundaryOnto(curved, ball, subdivided(coarse, 3)).bent, 30);
  // Isochoric (det F = 1: the volume term is zero), so the energy is the isochoric points' alone.
  const Eigen::Matrix3d f =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1.0, 2.0, 0.5).normalized()).toRotationMatrix() *
      (Eigen::Matrix3d() << 1.2, 0.1, -0.05, 0.0, 1.0 / 1.2, 0.2, 0.0, 0.0, 1.0).finished();
  const double kappa_Pa = 50.0 * test::liverEnergy().initialShearModulus();
  const FemModel straightModel(straight, test::liverEnergy(), kappa_Pa);
  const FemModel curvedModel(curved, test::liverEnergy(), kappa_Pa);
  const double straightDensity_J_m3 = straightModel.evaluate(f * straight.nodes_m).energy_J /
                                      ruleVolume(straight, tetQuadratureDegree2());
  const double curvedDensity_J_m3 = curvedModel.evaluate(f * curved.nodes_m).energy_J /
                                    ruleVolume(curved, tetQuadratureDegree2());
  ASSERT_GT(straightDensity_J_m3, 0.0);
  EXPECT_NEAR(curvedDensity_J_m3, straightDensity_J_m3, 1e-10 * straightDensity_J_m3);
  // At rest, no energy and no force.
  Eigen::Matrix3Xd gradient;
  EXPECT_NEAR(curvedModel.evaluate(curved.nodes_m, gradient).energy_J, 0.0, 1e-18);
  EXPECT_LT(gradient.cwiseAbs().maxCoeff(), 1e-12);
}

TEST(CurvedBoundary, TheCurvedBallWeighsWhatItsVolumeHolds) {
  // The consistent loads of its weight (fem/QuadraticTetWeight.h) integrated over the curved
  // elements: they sum to rho g V of the curved ball, not of the chords' one.
  const TriangleSurface coarse = icosahedron();
  const TetMesh ball = ballRoundCentre(coarse);
  QuadraticTetMesh curved = makeQuadraticTetMesh(ball);
  ASSERT_EQ(curveBoundaryOnto(curved, ball, subdivided(coarse, 3)).bent, 30);
  const Eigen::Vector3d g(0.0, -9.81, 0.0);
  const NodalLoads loads = quadraticTetWeight(curved, 1000.0, g);
  const Eigen::Vector3d total_N = loads.forces_N.rowwise().sum();
  const double expected_N = 1000.0 * 9.81 * restVolume(curved);
  EXPECT_NEAR(-total_N.y(), expected_N, 1e-12 * expected_N);
  EXPECT_GT(restVolume(curved), 1.3 * restVolume(makeQuadraticTetMesh(ball)));
}

TEST(CurvedBoundary, AnEdgeWithACornerOffTheSurfaceStaysStraight) {
  const TriangleSurface coarse = icosahedron();
  const TriangleSurface drawn = subdivided(coarse, 2);
  TetMesh ball = ballRoundCentre(coarse);
  ball.nodes_m.col(0) *= 1.05;  // a corner a millimetre outside the drawn sphere
  const QuadraticTetMesh straight = makeQuadraticTetMesh(ball);
  QuadraticTetMesh curved = straight;
  const CurvedBoundaryReport report = curveBoundaryOnto(curved, ball, drawn);
  EXPECT_EQ(report.left, 5);  // the icosahedron's five edges at that corner
  EXPECT_EQ(report.bent, 25);
  int straightBoundary = 0;
  for (Eigen::Index t = 0; t < curved.tetCount(); ++t) {
    for (int e = 0; e < 6; ++e) {
      const int a = curved.tets(kQuadraticTetEdges[e][0], t);
      const int b = curved.tets(kQuadraticTetEdges[e][1], t);
      if ((a == 0) != (b == 0) && a != 12 && b != 12) {
        const int middle = curved.tets(4 + e, t);
        EXPECT_TRUE(curved.nodes_m.col(middle).isApprox(straight.nodes_m.col(middle), 0.0));
        ++straightBoundary;
      }
    }
  }
  EXPECT_GT(straightBoundary, 0);
}

TEST(CurvedBoundary, AnEdgeSaggingMoreThanAQuarterOfItsLengthStaysStraight) {
  // A triangular bipyramid inscribed in the sphere, round a node at its centre: each equator
  // edge spans 120 degrees and its chord's middle lies 0.29 of its length inside the surface (it
  // stays straight); each edge to a pole spans 90 degrees, 0.21 (bent).
  TriangleSurface bipyramid;
  bipyramid.vertices_m.resize(3, 5);
  const double s = std::sqrt(3.0) / 2.0;
  bipyramid.vertices_m << 1, -0.5, -0.5, 0, 0,  //
      0, s, -s, 0, 0,                           //
      0, 0, 0, 1, -1;
  bipyramid.vertices_m *= kBallRadius_m;
  bipyramid.triangles.resize(3, 6);
  bipyramid.triangles << 0, 1, 2, 0, 2, 1,  //
      1, 2, 0, 2, 1, 0,                     //
      3, 3, 3, 4, 4, 4;
  const TetMesh ball = ballRoundCentre(bipyramid);
  QuadraticTetMesh quadratic = makeQuadraticTetMesh(ball);
  const QuadraticTetMesh straight = quadratic;
  const CurvedBoundaryReport report = curveBoundaryOnto(quadratic, ball, subdivided(bipyramid, 3));
  EXPECT_EQ(report.boundaryEdges, 9);
  EXPECT_EQ(report.left, 3);
  EXPECT_EQ(report.bent + report.shortened, 6);
  for (Eigen::Index t = 0; t < quadratic.tetCount(); ++t) {
    for (int e = 0; e < 6; ++e) {
      const int a = quadratic.tets(kQuadraticTetEdges[e][0], t);
      const int b = quadratic.tets(kQuadraticTetEdges[e][1], t);
      if (a < 3 && b < 3) {  // an equator edge
        const int middle = quadratic.tets(4 + e, t);
        EXPECT_TRUE(quadratic.nodes_m.col(middle).isApprox(straight.nodes_m.col(middle), 0.0));
      }
    }
  }
}

TEST(CurvedBoundary, AClosestPointOnAnotherSheetOfTheSurfaceLeavesTheEdgeStraight) {
  // The drawn ball hollow: a cavity of half a millimetre's radius a millimetre inside one edge's
  // chord, nearer the chord's middle than the sphere over it (3 mm out). The closest point is
  // on the cavity, inward, across the body from the face the edge bounds: that edge stays
  // straight, the other 29 go onto the sphere.
  const TriangleSurface coarse = icosahedron();
  const TetMesh ball = ballRoundCentre(coarse);
  const QuadraticTetMesh straight = makeQuadraticTetMesh(ball);
  int chosen = -1;
  for (Eigen::Index t = 0; t < straight.tetCount() && chosen < 0; ++t) {
    for (int e = 0; e < 6 && chosen < 0; ++e) {
      if (straight.tets(kQuadraticTetEdges[e][0], t) != 12 &&
          straight.tets(kQuadraticTetEdges[e][1], t) != 12)
        chosen = straight.tets(4 + e, t);
    }
  }
  ASSERT_GE(chosen, 0);
  const Eigen::Vector3d chordMiddle = straight.nodes_m.col(chosen);
  TriangleSurface cavity = subdivided(coarse, 1);
  cavity.vertices_m *= 0.0005 / kBallRadius_m;
  cavity.vertices_m.colwise() += chordMiddle - 0.001 * chordMiddle.normalized();
  cavity.triangles.row(1).swap(cavity.triangles.row(2));  // facing into the cavity
  const TriangleSurface sphere = subdivided(coarse, 3);
  TriangleSurface hollow;
  hollow.vertices_m.resize(3, sphere.vertexCount() + cavity.vertexCount());
  hollow.vertices_m << sphere.vertices_m, cavity.vertices_m;
  hollow.triangles.resize(3, sphere.triangleCount() + cavity.triangleCount());
  hollow.triangles << sphere.triangles,
      (cavity.triangles.array() + static_cast<int>(sphere.vertexCount())).matrix();
  QuadraticTetMesh curved = straight;
  const CurvedBoundaryReport report = curveBoundaryOnto(curved, ball, hollow);
  EXPECT_EQ(report.left, 1);
  EXPECT_EQ(report.bent, 29);
  EXPECT_TRUE(curved.nodes_m.col(chosen).isApprox(chordMiddle, 0.0));
}

TEST(CurvedBoundary, TheSampledJacobianFindsAMiddleNodeAtItsEdgesQuarterPoint) {
  TetMesh tet;
  tet.nodes_m =
      0.01 * Eigen::Matrix<double, 3, 4>(
                 (Eigen::Matrix<double, 3, 4>() << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1).finished());
  tet.tets = Eigen::Matrix4Xi::Zero(4, 1);
  tet.tets.col(0) << 0, 1, 2, 3;
  QuadraticTetMesh quadratic = makeQuadraticTetMesh(tet);
  EXPECT_NEAR(leastJacobianShare(quadratic, 0), 1.0, 1e-12);
  // The middle of edge (0, 1) moved along it: at the quarter point dX/dxi vanishes at corner 0.
  const int middle = quadratic.tets(4, 0);
  quadratic.nodes_m.col(middle) = Eigen::Vector3d(0.0025, 0.0, 0.0);
  EXPECT_NEAR(leastJacobianShare(quadratic, 0), 0.0, 1e-12);
  quadratic.nodes_m.col(middle) = Eigen::Vector3d(0.004, 0.0, 0.0);
  const double share = leastJacobianShare(quadratic, 0);
  EXPECT_GT(share, 0.0);
  EXPECT_LT(share, 1.0);
}

TEST(CurvedBoundary, RefusesAQuadraticMeshThatIsNotTheLinearOnes) {
  const TriangleSurface coarse = icosahedron();
  const TetMesh ball = ballRoundCentre(coarse);
  QuadraticTetMesh other = makeQuadraticTetMesh(ball);
  TetMesh fewer = ball;
  fewer.tets.conservativeResize(4, 19);
  EXPECT_THROW(curveBoundaryOnto(other, fewer, coarse), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
