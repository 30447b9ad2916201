// SPDX-License-Identifier: Apache-2.0
#pragma once
// The 3D scene a trainee sees, as a VTK renderer: the liver's visual surface (smooth-shaded,
// its vertices carried by the tet mesh through the barycentric embedding), an optional stretch
// colour map with a scalar bar, an optional spring wireframe, the instrument (a shaft with a
// blunt tip), and depth cues: a tray under the organ with the organ's and the tool's soft
// shadows on it (TrayShadow). The organ and the tool are shaded physically (VTK's PBR): a wet
// film over the liver, brushed steel.
//
// It reads positions (a snapshot of the physics state) and never touches the simulation, so a
// frame costs the physics nothing. Nothing here depends on Qt: the same view renders in the
// window and offscreen (snapshots, image tests).
//
// Colour map: per tet node, the stretch lambda of its incident spring farthest from rest
// (lambda < 1 compression, > 1 tension), interpolated to the surface with the embedding's
// weights; the colour range is fixed (kStretchRange) so images compare across frames.
//
// Damage overlay: the tissue the session has stretched past its damage threshold
// (sim/SessionAssessment.h), per tet node 1 where any of its springs is damaged, interpolated
// to the surface the same way. Where it reaches one half, the surface is painted pale (with the
// colour map off) and outlined in a dark line (always, so it reads over the colour map too).

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <Eigen/Core>

#include "forces/ContactProvider.h"
#include "sim/SceneFile.h"
#include "sim/SceneGeometry.h"
#include "springs/SpringMesh.h"

class vtkActor;
class vtkDoubleArray;
class vtkLookupTable;
class vtkPolyData;
class vtkPolyDataNormals;
class vtkRenderer;
class vtkScalarBarActor;
class vtkTransform;

namespace tissuesim {

class TrayShadow;

class TissueSceneView {
 public:
  /// Colour map limits (stretch): blue at the lower, white at 1, red at the upper.
  static constexpr double kStretchRange[2] = {0.9, 1.1};

  /// All must outlive the view. `instrument` null: none drawn. `tray` null (or not horizontal:
  /// the view's up is y): the tray is drawn just under the organ's rest position, as a depth cue.
  TissueSceneView(const SceneGeometry& geometry, const SpringMesh& springs,
                  const SceneInstrument* instrument, const SceneTray* tray);
  ~TissueSceneView();
  TissueSceneView(const TissueSceneView&) = delete;
  TissueSceneView& operator=(const TissueSceneView&) = delete;

  vtkRenderer* renderer() const { return m_renderer; }

  /// Moves the surface, springs and instrument to a state (x: 3 by #nodes, m); with the damage
  /// overlay on, `damagedSprings` (#springs, 1 damaged; null: none) is what it draws.
  void update(const Eigen::Matrix3Xd& x, const InstrumentPose& pose,
              const std::vector<std::uint8_t>* damagedSprings = nullptr);

  void setColourMap(bool isOn);
  bool isColourMap() const { return m_isColourMap; }
  void setWireframe(bool isOn);
  bool isWireframe() const { return m_isWireframe; }
  void setDamageOverlay(bool isOn);
  bool isDamageOverlay() const { return m_isDamageOverlay; }

  /// The default camera: a three-quarter view of the organ from above, fitted to the tray.
  void resetCamera();

 private:
  void buildSurface();
  void buildSprings();
  void buildInstrument();
  void buildDamageOverlay();
  /// Per-node values (#V) onto a per-vertex array of the drawn surface, through the embedding's
  /// weights (the tet mesh's boundary without one: the values as they are).
  void setSurfaceValues(const Eigen::VectorXd& nodeValues, vtkDoubleArray* surfaceValues);
  /// The surface's scalars from the colour map and overlay switches.
  void updateSurfaceColouring();
  void buildTray(const SceneTray* tray);

  const SceneGeometry& m_geometry;
  const SpringMesh& m_springs;
  const SceneInstrument* m_instrument;
  vtkSmartPointer<vtkRenderer> m_renderer;

  vtkSmartPointer<vtkPolyData> m_surface;  ///< points moved in place each update
  vtkSmartPointer<vtkDoubleArray> m_surfaceStretch;
  vtkSmartPointer<vtkPolyDataNormals> m_normals;
  vtkSmartPointer<vtkActor> m_surfaceActor;
  vtkSmartPointer<vtkScalarBarActor> m_scalarBar;

  vtkSmartPointer<vtkDoubleArray> m_surfaceDamage;
  vtkSmartPointer<vtkLookupTable> m_stretchLut;
  vtkSmartPointer<vtkLookupTable> m_damageLut;
  vtkSmartPointer<vtkActor> m_damageOutlineActor;

  vtkSmartPointer<vtkPolyData> m_springLines;
  vtkSmartPointer<vtkActor> m_springActor;

  vtkSmartPointer<vtkTransform> m_toolTransform;
  vtkSmartPointer<vtkActor> m_shaftActor;
  vtkSmartPointer<vtkActor> m_tipActor;
  std::unique_ptr<TrayShadow> m_tray;

  Eigen::Matrix3Xd m_surfaceX;     ///< scratch: surface vertices (m)
  Eigen::VectorXd m_nodeStretch;   ///< scratch: per tet node
  Eigen::VectorXd m_nodeDamage;    ///< scratch: per tet node
  Eigen::VectorXd m_vertexValues;  ///< scratch: per drawn vertex
  bool m_isColourMap = false;
  bool m_isDamageOverlay = false;
  bool m_isWireframe = false;
};

}  // namespace tissuesim
