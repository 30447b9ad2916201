// SPDX-License-Identifier: Apache-2.0
#include "render/TissueSceneView.h"

#include <algorithm>
#include <cmath>

#include <vtkActor.h>
#include <vtkAssignAttribute.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkContourFilter.h>
#include <vtkCylinderSource.h>
#include <vtkDoubleArray.h>
#include <vtkLight.h>
#include <vtkLookupTable.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSphereSource.h>
#include <vtkTextProperty.h>
#include <vtkTransform.h>

#include "mesh/TetMesh.h"
#include "render/MottledColour.h"
#include "render/TrayShadow.h"
#include "sim/SessionAssessment.h"
#include "springs/NodeStretch.h"

namespace tissuesim {
namespace {

constexpr double kWetFilmStrength = 0.8;
constexpr double kLampIntensity = 2.2;
constexpr double kLiverColour[3] = {0.30, 0.035, 0.025};  // red-brown, linear (PBR's colours)

void setPoints(vtkPoints* points, const Eigen::Matrix3Xd& x) {
  for (Eigen::Index i = 0; i < x.cols(); ++i) points->SetPoint(i, x(0, i), x(1, i), x(2, i));
  points->Modified();
}

vtkSmartPointer<vtkCellArray> triangleCells(const Eigen::Matrix3Xi& triangles) {
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->AllocateExact(triangles.cols(), 3 * triangles.cols());
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const vtkIdType ids[3] = {triangles(0, t), triangles(1, t), triangles(2, t)};
    cells->InsertNextCell(3, ids);
  }
  return cells;
}

}  // namespace

TissueSceneView::TissueSceneView(const SceneGeometry& geometry, const SpringMesh& springs,
                                 const SceneInstrument* instrument, const SceneTray* tray)
    : m_geometry(geometry),
      m_springs(springs),
      m_instrument(instrument),
      m_renderer(vtkSmartPointer<vtkRenderer>::New()) {
  // A plain, dark room: a gradient background cost llvmpipe an eighth of a frame, which the
  // organ's physically based shading spends better.
  m_renderer->SetBackground(0.20, 0.22, 0.25);
  // One light, at the eye (as a laparoscope's): every further light is paid per fragment, on
  // the CPU under llvmpipe. Brighter than VTK's default, which physically based shading wants.
  m_renderer->AutomaticLightCreationOff();
  auto light = vtkSmartPointer<vtkLight>::New();
  light->SetLightTypeToHeadlight();
  light->SetIntensity(kLampIntensity);
  m_renderer->AddLight(light);
  buildSurface();
  buildDamageOverlay();
  buildSprings();
  buildTray(tray);
  buildInstrument();
  updateSurfaceColouring();
  update(springs.restPositions_m,
         instrument != nullptr
             ? InstrumentPose{instrument->tipStart_m, instrument->direction, false}
             : InstrumentPose{});
  resetCamera();
}

TissueSceneView::~TissueSceneView() = default;

void TissueSceneView::buildSurface() {
  m_surface = vtkSmartPointer<vtkPolyData>::New();
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  if (m_geometry.surface && m_geometry.embedding) {
    points->SetNumberOfPoints(m_geometry.surface->vertices_m.cols());
    m_surface->SetPolys(triangleCells(m_geometry.surface->triangles));
    m_surfaceX.resize(3, m_geometry.surface->vertices_m.cols());
  } else {
    // No visual surface in the scene: the tet mesh's own boundary (points = all nodes).
    points->SetNumberOfPoints(m_springs.nodeCount());
    m_surface->SetPolys(triangleCells(boundaryFaces(m_geometry.mesh)));
    m_surfaceX.resize(3, m_springs.nodeCount());
  }
  m_surface->SetPoints(points);
  m_surfaceStretch = vtkSmartPointer<vtkDoubleArray>::New();
  m_surfaceStretch->SetName("stretch");
  m_surfaceStretch->SetNumberOfTuples(points->GetNumberOfPoints());
  m_surfaceStretch->Fill(1.0);
  m_surface->GetPointData()->SetScalars(m_surfaceStretch);
  m_nodeStretch.resize(m_springs.nodeCount());
  // The liver's own colour, varied over its surface as it rests.
  m_surface->GetPointData()->AddArray(
      mottledColour(m_geometry.surface && m_geometry.embedding ? m_geometry.surface->vertices_m
                                                               : m_springs.restPositions_m,
                    Eigen::Vector3d(kLiverColour[0], kLiverColour[1], kLiverColour[2])));

  m_normals = vtkSmartPointer<vtkPolyDataNormals>::New();
  m_normals->SetInputData(m_surface);
  m_normals->SplittingOff();  // smooth shading across the whole organ
  m_normals->ConsistencyOff();
  m_normals->AutoOrientNormalsOff();

  m_stretchLut = vtkSmartPointer<vtkLookupTable>::New();
  vtkLookupTable* lut = m_stretchLut;
  lut->SetNumberOfTableValues(256);
  lut->SetTableRange(kStretchRange[0], kStretchRange[1]);
  for (int i = 0; i < 256; ++i) {
    // Diverging blue - white - red (compression - rest - tension).
    const double s = i / 255.0;
    const double r = s < 0.5 ? 0.23 + 1.54 * s : 1.0;
    const double g = s < 0.5 ? 0.30 + 1.40 * s : 1.0 - 1.6 * (s - 0.5);
    const double b = s < 0.5 ? 0.75 + 0.50 * s : 1.0 - 1.7 * (s - 0.5);
    lut->SetTableValue(i, std::clamp(r, 0.0, 1.0), std::clamp(g, 0.0, 1.0),
                       std::clamp(b, 0.0, 1.0));
  }
  lut->Build();
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputConnection(m_normals->GetOutputPort());
  mapper->SetScalarModeToUsePointFieldData();
  mapper->ScalarVisibilityOff();
  m_surfaceActor = vtkSmartPointer<vtkActor>::New();
  m_surfaceActor->SetMapper(mapper);
  vtkProperty* property = m_surfaceActor->GetProperty();
  property->SetColor(kLiverColour[0], kLiverColour[1], kLiverColour[2]);
  // Physically based: a rough, dielectric parenchyma under a thin, smooth wet film (VTK's clear
  // coat, with water's index): the film's sheen follows the light over the whole organ.
  property->SetInterpolationToPBR();
  property->SetMetallic(0.0);
  property->SetRoughness(0.55);
  property->SetCoatStrength(kWetFilmStrength);
  property->SetCoatRoughness(0.12);
  property->SetCoatIOR(1.33);
  m_renderer->AddActor(m_surfaceActor);

  m_scalarBar = vtkSmartPointer<vtkScalarBarActor>::New();
  m_scalarBar->SetLookupTable(lut);
  m_scalarBar->SetTitle("stretch");
  m_scalarBar->SetNumberOfLabels(5);
  m_scalarBar->SetLabelFormat("%.2f");
  m_scalarBar->SetPosition(0.88, 0.1);
  m_scalarBar->SetWidth(0.08);
  m_scalarBar->SetHeight(0.8);
  m_scalarBar->GetTitleTextProperty()->SetColor(0.9, 0.9, 0.9);  // on the dark room
  m_scalarBar->GetLabelTextProperty()->SetColor(0.9, 0.9, 0.9);
  m_scalarBar->VisibilityOff();
  m_renderer->AddViewProp(m_scalarBar);
}

void TissueSceneView::buildDamageOverlay() {
  m_surfaceDamage = vtkSmartPointer<vtkDoubleArray>::New();
  m_surfaceDamage->SetName("damage");
  m_surfaceDamage->SetNumberOfTuples(m_surface->GetPoints()->GetNumberOfPoints());
  m_surfaceDamage->Fill(0.0);
  m_surface->GetPointData()->AddArray(m_surfaceDamage);
  m_nodeDamage.resize(m_springs.nodeCount());

  // The damaged part of the surface (damage >= 1/2) is painted by the surface's own mapper (a
  // lookup table that steps from the liver's colour to a pale, bloodless one at 1/2, the values
  // interpolated across each triangle before the lookup, so the step is sharp): a second surface
  // laid over the first flickered through it. Its border is a dark line, pulled towards the
  // camera by VTK's coincident-topology offset so it wins over the surface it lies on. The
  // outline contours the damage as the active scalars of a copy of the surface's attributes.
  m_damageLut = vtkSmartPointer<vtkLookupTable>::New();
  m_damageLut->SetNumberOfTableValues(2);
  m_damageLut->SetTableRange(0.0, 1.0);
  m_damageLut->SetTableValue(0, kLiverColour[0], kLiverColour[1], kLiverColour[2]);
  m_damageLut->SetTableValue(1, 0.80, 0.55, 0.38);  // linear: a pale, bloodless buff
  m_damageLut->Build();
  auto damage = vtkSmartPointer<vtkAssignAttribute>::New();
  damage->SetInputConnection(m_normals->GetOutputPort());
  damage->Assign("damage", vtkDataSetAttributes::SCALARS, vtkAssignAttribute::POINT_DATA);
  auto contour = vtkSmartPointer<vtkContourFilter>::New();
  contour->SetInputConnection(damage->GetOutputPort());
  contour->SetValue(0, 0.5);
  contour->ComputeScalarsOff();
  auto outlineMapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  outlineMapper->SetInputConnection(contour->GetOutputPort());
  outlineMapper->ScalarVisibilityOff();
  outlineMapper->SetRelativeCoincidentTopologyLineOffsetParameters(-2.0, -40.0);
  m_damageOutlineActor = vtkSmartPointer<vtkActor>::New();
  m_damageOutlineActor->SetMapper(outlineMapper);
  m_damageOutlineActor->GetProperty()->SetColor(0.12, 0.05, 0.05);
  m_damageOutlineActor->GetProperty()->SetLineWidth(3.0);
  m_damageOutlineActor->GetProperty()->LightingOff();
  m_damageOutlineActor->VisibilityOff();
  m_renderer->AddActor(m_damageOutlineActor);
}

void TissueSceneView::setSurfaceValues(const Eigen::VectorXd& nodeValues,
                                       vtkDoubleArray* surfaceValues) {
  const bool isEmbedded = m_geometry.surface && m_geometry.embedding;
  if (isEmbedded) m_geometry.embedding->interpolate(nodeValues, m_vertexValues);
  const Eigen::VectorXd& values = isEmbedded ? m_vertexValues : nodeValues;
  for (Eigen::Index v = 0; v < m_surfaceX.cols(); ++v) surfaceValues->SetValue(v, values[v]);
  surfaceValues->Modified();
}

void TissueSceneView::buildSprings() {
  m_springLines = vtkSmartPointer<vtkPolyData>::New();
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(m_springs.nodeCount());
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  lines->AllocateExact(m_springs.springCount(), 2 * m_springs.springCount());
  for (Eigen::Index s = 0; s < m_springs.springCount(); ++s) {
    const vtkIdType ids[2] = {m_springs.springs(0, s), m_springs.springs(1, s)};
    lines->InsertNextCell(2, ids);
  }
  m_springLines->SetPoints(points);
  m_springLines->SetLines(lines);
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputData(m_springLines);
  m_springActor = vtkSmartPointer<vtkActor>::New();
  m_springActor->SetMapper(mapper);
  m_springActor->GetProperty()->SetColor(0.15, 0.15, 0.2);
  m_springActor->GetProperty()->SetOpacity(0.35);
  m_springActor->GetProperty()->LightingOff();
  m_springActor->VisibilityOff();
  m_renderer->AddActor(m_springActor);
}

void TissueSceneView::buildTray(const SceneTray* tray) {
  // The scene's tray, where the organ rests on it; without one, a tray just under the organ's rest
  // position. Wider than the organ: the eye judges depth against it and the shadows on it.
  const Eigen::Matrix3Xd& rest = m_springs.restPositions_m;
  const Eigen::Vector3d lo = rest.rowwise().minCoeff();
  const Eigen::Vector3d hi = rest.rowwise().maxCoeff();
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const double size = (hi - lo).maxCoeff() * 2.2;
  const bool isSceneTray = tray != nullptr && tray->up.y() > 1.0 - 1e-9;
  const double height_m = isSceneTray ? tray->height_m : lo.y() - 0.002;
  m_tray = std::make_unique<TrayShadow>(
      height_m, Eigen::Vector2d(centre.x() - 0.5 * size, centre.z() - 0.5 * size), size);
  m_renderer->AddActor(m_tray->actor());
}

void TissueSceneView::buildInstrument() {
  if (m_instrument == nullptr) return;
  m_toolTransform = vtkSmartPointer<vtkTransform>::New();
  const double radius = m_instrument->shaftRadius_m;
  const double length = m_instrument->shaftLength_m;
  // In tool coordinates the tip is at the origin and the shaft runs up +y (the cylinder's axis).
  auto cylinder = vtkSmartPointer<vtkCylinderSource>::New();
  cylinder->SetRadius(radius);
  cylinder->SetHeight(length);
  cylinder->SetCenter(0.0, 0.5 * length, 0.0);
  cylinder->SetResolution(32);
  auto sphere = vtkSmartPointer<vtkSphereSource>::New();
  sphere->SetRadius(radius);
  sphere->SetThetaResolution(32);
  sphere->SetPhiResolution(16);
  for (auto [actor, port] : {std::pair{&m_shaftActor, cylinder->GetOutputPort()},
                             std::pair{&m_tipActor, sphere->GetOutputPort()}}) {
    auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
    mapper->SetInputConnection(port);
    *actor = vtkSmartPointer<vtkActor>::New();
    (*actor)->SetMapper(mapper);
    (*actor)->SetUserTransform(m_toolTransform);
    // Stainless steel. Metallic 0.6, not 1: a pure metal shows only what it mirrors, and with
    // no environment to mirror (image-based lighting tripled llvmpipe's frame) it would be black
    // but for its highlight.
    (*actor)->GetProperty()->SetInterpolationToPBR();
    (*actor)->GetProperty()->SetColor(0.80, 0.80, 0.82);
    (*actor)->GetProperty()->SetMetallic(0.6);
    (*actor)->GetProperty()->SetRoughness(0.3);
    m_renderer->AddActor(*actor);
  }
}

void TissueSceneView::update(const Eigen::Matrix3Xd& x, const InstrumentPose& pose,
                             const std::vector<std::uint8_t>* damagedSprings) {
  const bool isEmbedded = m_geometry.surface && m_geometry.embedding;
  if (isEmbedded) {
    m_geometry.embedding->apply(x, m_surfaceX);
  } else {
    m_surfaceX = x;
  }
  setPoints(m_surface->GetPoints(), m_surfaceX);
  if (m_isColourMap) {
    nodeStretch(m_springs, x, m_nodeStretch);
    setSurfaceValues(m_nodeStretch, m_surfaceStretch);
  }
  if (m_isDamageOverlay && damagedSprings != nullptr) {
    damagedNodes(m_springs, *damagedSprings, m_nodeDamage);
    setSurfaceValues(m_nodeDamage, m_surfaceDamage);
  }
  m_surface->Modified();
  m_tray->update(m_surfaceX, pose.tip_m, pose.direction,
                 m_instrument != nullptr ? m_instrument->shaftRadius_m : 0.0,
                 m_instrument != nullptr ? m_instrument->shaftLength_m : 0.0);
  if (m_isWireframe) {
    setPoints(m_springLines->GetPoints(), x);
    m_springLines->Modified();
  }

  if (m_toolTransform) {
    // Tool y axis along -direction (the shaft goes back from the tip).
    const Eigen::Vector3d axis = -pose.direction.normalized();
    const Eigen::Vector3d y = Eigen::Vector3d::UnitY();
    const Eigen::Vector3d cross = y.cross(axis);
    const double angle = std::atan2(cross.norm(), y.dot(axis)) * 180.0 / M_PI;
    m_toolTransform->Identity();
    m_toolTransform->Translate(pose.tip_m.data());
    if (cross.norm() > 1e-12) {
      m_toolTransform->RotateWXYZ(angle, cross.x(), cross.y(), cross.z());
    } else if (y.dot(axis) < 0.0) {
      m_toolTransform->RotateWXYZ(180.0, 1.0, 0.0, 0.0);
    }
    m_toolTransform->Modified();
    const double colour = pose.isGrasping ? 0.45 : 0.72;  // jaws closed: darker steel
    m_tipActor->GetProperty()->SetColor(colour, colour + 0.02, colour + 0.06);
  }
}

void TissueSceneView::setColourMap(bool isOn) {
  m_isColourMap = isOn;
  updateSurfaceColouring();
}

void TissueSceneView::setDamageOverlay(bool isOn) {
  m_isDamageOverlay = isOn;
  if (!isOn) m_surfaceDamage->Fill(0.0);
  m_damageOutlineActor->SetVisibility(isOn);
  updateSurfaceColouring();
}

void TissueSceneView::updateSurfaceColouring() {
  // The colour map, when on, colours the surface; the damage then is outlined only, so that the
  // stretch's colours stay readable.
  vtkMapper* mapper = m_surfaceActor->GetMapper();
  mapper->SetInterpolateScalarsBeforeMapping(!m_isColourMap && m_isDamageOverlay);
  mapper->SetColorModeToMapScalars();
  if (m_isColourMap) {
    mapper->SelectColorArray("stretch");
    mapper->SetLookupTable(m_stretchLut);
    mapper->SetScalarRange(kStretchRange[0], kStretchRange[1]);
  } else if (m_isDamageOverlay) {
    mapper->SelectColorArray("damage");
    mapper->SetLookupTable(m_damageLut);
    mapper->SetScalarRange(0.0, 1.0);
  } else {
    mapper->SelectColorArray("albedo");
    mapper->SetColorModeToDirectScalars();
  }
  mapper->ScalarVisibilityOn();
  // The colour map is data: shaded as before PBR (Phong, little specular), so that its colours
  // are the scalar bar's and no wet glare washes them out.
  vtkProperty* property = m_surfaceActor->GetProperty();
  if (m_isColourMap) {
    // The lamp is 2.2 times VTK's default for the PBR: the Phong weights are divided by it.
    property->SetInterpolationToPhong();
    property->SetSpecular(0.15 / kLampIntensity);
    property->SetSpecularPower(30.0);
    property->SetDiffuse(0.8 / kLampIntensity);
    property->SetAmbient(0.12);
  } else {
    property->SetInterpolationToPBR();
  }
  m_scalarBar->SetVisibility(m_isColourMap);
}

void TissueSceneView::setWireframe(bool isOn) {
  m_isWireframe = isOn;
  m_springActor->SetVisibility(isOn);
  m_surfaceActor->GetProperty()->SetOpacity(isOn ? 0.45 : 1.0);
}

void TissueSceneView::resetCamera() {
  const Eigen::Matrix3Xd& rest = m_springs.restPositions_m;
  const Eigen::Vector3d centre = 0.5 * (rest.rowwise().minCoeff() + rest.rowwise().maxCoeff());
  const double size = (rest.rowwise().maxCoeff() - rest.rowwise().minCoeff()).norm();
  vtkCamera* camera = m_renderer->GetActiveCamera();
  camera->SetFocalPoint(centre.data());
  // From the front, above and to the right: y is up in the bundled scenes.
  const Eigen::Vector3d eye = centre + size * Eigen::Vector3d(0.55, 0.75, 1.25);
  camera->SetPosition(eye.data());
  camera->SetViewUp(0.0, 1.0, 0.0);
  camera->SetViewAngle(30.0);
  m_renderer->ResetCameraClippingRange();
}

}  // namespace tissuesim
