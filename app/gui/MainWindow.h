// SPDX-License-Identifier: Apache-2.0
#pragma once
// The trainee's and instructor's window: the 3D view (QVTKOpenGLNativeWidget), a live force
// plot, the tissue's stress-stretch chart (VTK charts), a status bar, and the menus.
//
// Threads: the physics runs on RealTimeLoop's thread at the scene's fixed step; a 60 Hz timer
// here takes the newest snapshot (never waiting for the physics) and renders it. The instrument
// pose goes the other way through a LiveInstrument. Anything that changes the simulation itself
// (new tissue, reset, toggles) pauses the loop, changes it, and resumes.
//
// Errors (a bad tissue or scene file) open a non-blocking error dialog (object name
// "errorDialog") and leave the running simulation as it was.

#include <atomic>
#include <memory>
#include <optional>
#include <vector>

#include <vtkSmartPointer.h>
#include <QElapsedTimer>
#include <QMainWindow>
#include <QTimer>

#include "analysis/TissueFit.h"
#include "app/SceneSession.h"
#include "render/CurveChart.h"
#include "render/TissueSceneView.h"

class QAction;
class QLabel;
class QVTKOpenGLNativeWidget;
class vtkGenericOpenGLRenderWindow;

namespace tissuesim::app {

class ForcePlotWidget;
class InstrumentInteractorStyle;

class MainWindow : public QMainWindow {
  Q_OBJECT
 public:
  explicit MainWindow(const QString& scenePath, QWidget* parent = nullptr);
  ~MainWindow() override;

  /// Each returns false (after showing the error dialog) when the file is refused.
  bool loadScene(const QString& path);
  bool loadTissue(const QString& path);
  bool saveImage(const QString& path);
  /// File > Save recording: the session so far (sim/SessionRecording.h), for `tissuesim
  /// replay`. False (after the error dialog) when it cannot be written or there is nothing to
  /// record (a scene without an instrument).
  bool saveRecording(const QString& path);
  /// File > Open recording: the recorded session played in the window, its scene loaded and
  /// the recorded inputs applied at their steps (the mouse does not drive the tool meanwhile);
  /// it pauses at its end. False (after the error dialog) when refused.
  bool openRecording(const QString& path);
  /// The playback moved to `time_s` of the recording (stepped again from its start, the
  /// window waiting), paused or running as it was. Nothing without a playback.
  void seekRecording(double time_s);
  bool isPlayingBack() const { return m_playback.has_value(); }
  /// The playback's place (s of simulated session time) and its length.
  double playbackTime_s() const;
  double playbackLength_s() const;
  /// Tools > Fit tissue from test data: fits the CSV (analysis/TissueFit.h, starting from the
  /// running tissue), draws the fit over the data in the Material panel and opens the result's
  /// dialog (objectName "fitDialog"). False (after the error dialog) for bad data.
  bool fitTissueFromTestData(const QString& csvPath);
  /// The last fit's tissue into the running scene, or to a tissue file. False when there is none
  /// or it cannot be written (after the error dialog).
  bool applyFittedTissue();
  bool saveFittedTissue(const QString& path);

  void setPaused(bool isPaused);
  bool isPaused() const;
  void resetSimulation();
  void setSoftening(bool isOn);
  void setGravity(bool isOn);
  void setColourMap(bool isOn);
  /// View > Tissue damage: the regions the session stretched past the damage threshold.
  void setDamageOverlay(bool isOn);
  /// Simulation > End session: the session's assessment (docs/assessment.md) in a dialog
  /// (objectName "sessionSummaryDialog") that can save it, then a fresh organ for the next
  /// session (a reset). Returns the ended session's figures.
  AssessmentSummary endSession();
  /// The last ended session's figures as JSON (the scene's name and run's "assessment" object).
  /// False (after the error dialog) without one, or when the file cannot be written.
  bool saveSessionSummary(const QString& path);

  /// Puts the tool tip under display point (x, y) (pixels, origin bottom-left) at its depth.
  void moveInstrumentToDisplay(int x, int y);
  /// Puts the cursor where the tool tip is drawn (after a camera move: the tip stays where it
  /// is, and the next hover steers it from there); nothing where the tip is not in the view.
  void putCursorOnInstrument();
  /// Moves the tool along its shaft by `distance_m` (positive: deeper).
  void pushInstrument(double distance_m);
  /// Tilts the shaft about its tip by the given angles (rad): `right` turns the tip towards
  /// the screen's right, `forward` away from the viewer; at most 80 degrees off the scene's
  /// start direction.
  void tiltInstrument(double right_rad, double forward_rad);
  /// Where the tool is now (the GUI's side of the live pose).
  InstrumentPose instrumentPose() const { return m_pose; }

  /// The newest physics snapshot (refreshed by each frame).
  const SimulationSnapshot* latestSnapshot() const { return m_latest; }
  const Simulation* simulation() const { return m_session ? &m_session->simulation() : nullptr; }
  /// Renders a frame now (the timer does this at 60 Hz).
  void renderFrame();
  double framesPerSecond() const { return m_fps; }
  double physicsHz() const { return m_physicsHz; }

 private:
  void buildMenus();
  void buildDocks();
  void showError(const QString& title, const QString& text);
  /// The same for what the user should know but need not fix (a guessed unit): information.
  void showNotice(const QString& title, const QString& text);
  void updateMaterialChart();
  /// The Material panel with the last fit's curves (solid) over its test data (dashed).
  void drawFitOnChart();
  void updateStatus(const SimulationSnapshot& snapshot);
  void publishPose();
  /// Stops the physics loop, applies `change`, and restarts the loop if it was running.
  template <typename Change>
  void whilePaused(const Change& change);

  /// A change between steps into the session's recording (its step: the live pose's clock).
  void noteChange(RecordedEvent event);
  /// The scene's view of the session's geometry, made afresh; keepCamera: where the old view's
  /// camera was (a body made again), else the view's default (a scene opened).
  void buildView(bool keepCamera);
  /// The body made again where the tool aims (Simulation::refineTowardsTool), the physics
  /// paused meanwhile, the view rebuilt for the new mesh: when the physics asks for it, or when
  /// a playback reaches the step its recording made it at.
  void refineWhereTheToolAims();
  /// A change of the user's own to the physics: ends a playback (`why` says which change),
  /// then applies `change` with the physics paused and records `event` at that step.
  template <typename Change>
  void changePhysics(const char* why, RecordedEvent event, const Change& change);

  std::unique_ptr<SceneSession> m_session;
  std::unique_ptr<SessionRecorder> m_recorder;  ///< null: the scene cannot be recorded
  /// Loads the playback's scene afresh (the loop not started), its source set, at step 0.
  bool restartPlayback(const SessionRecording& recording);
  /// The loop's before-step call for the playback: the recorded inputs, and its end.
  void installPlaybackHook();
  /// A change the user makes to the physics ends the playback: the session is theirs now.
  void leavePlayback(const char* why);
  std::optional<SessionRecording> m_playback;
  std::size_t m_playbackNext = 0;       ///< the next recorded event (physics thread)
  std::atomic<long> m_playbackStep{0};  ///< steps played (physics thread; read by the GUI)
  /// The playback reached a step where its recording made the body again: its loop ended there
  /// for the window to do it (physics thread; read by the GUI).
  std::atomic<bool> m_playbackRefinementDue{false};
  std::unique_ptr<RealTimeLoop> m_loop;
  std::unique_ptr<TissueSceneView> m_view;
  std::unique_ptr<CurveChart> m_materialChart;
  std::optional<TissueFitResult> m_fit;  ///< the last fit, and the data it was fitted to
  std::vector<CurveBranch> m_fitData;
  QString m_scenePath;

  QVTKOpenGLNativeWidget* m_vtkWidget = nullptr;
  QVTKOpenGLNativeWidget* m_chartWidget = nullptr;
  vtkSmartPointer<vtkGenericOpenGLRenderWindow> m_renderWindow;
  vtkSmartPointer<vtkGenericOpenGLRenderWindow> m_chartWindow;
  vtkSmartPointer<InstrumentInteractorStyle> m_style;
  ForcePlotWidget* m_forcePlot = nullptr;
  QLabel* m_statusLabel = nullptr;
  QAction* m_pauseAction = nullptr;
  QAction* m_softeningAction = nullptr;
  QAction* m_gravityAction = nullptr;
  QAction* m_colourMapAction = nullptr;
  QAction* m_wireframeAction = nullptr;
  QAction* m_damageAction = nullptr;
  std::optional<AssessmentSummary> m_endedSession;  ///< the last ended session's figures

  QTimer m_frameTimer;
  QElapsedTimer m_clock;
  InstrumentPose m_pose;
  const SimulationSnapshot* m_latest = nullptr;
  double m_fps = 0.0;
  double m_physicsHz = 0.0;
  long m_framesInWindow = 0;
  long m_stepsAtWindowStart = 0;
  double m_windowStart_s = 0.0;
};

}  // namespace tissuesim::app
