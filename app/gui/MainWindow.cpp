// SPDX-License-Identifier: Apache-2.0
#include "app/gui/MainWindow.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <QVTKOpenGLNativeWidget.h>
#include <vtkCamera.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkImageData.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkWindowToImageFilter.h>
#include <QAction>
#include <QCursor>
#include <QDockWidget>
#include <QFileDialog>
#include <QFileInfo>
#include <QKeySequence>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QPushButton>
#include <QStatusBar>
#include <QStringList>

#include "analysis/TensileTestData.h"
#include "analysis/UniaxialExperiment.h"
#include "app/AssessmentReport.h"
#include "app/CommandError.h"
#include "app/ElasticModelWords.h"
#include "app/SessionSteps.h"
#include "app/gui/ForcePlotWidget.h"
#include "app/gui/InstrumentInteractorStyle.h"
#include "app/gui/SoftwareOpenGL.h"
#include "app/gui/TissueFitDialog.h"
#include "io/WholeFile.h"
#include "material/TissueFile.h"
#include "render/OffscreenImage.h"

namespace tissuesim::app {

namespace {

/// A branch's stresses (Pa) as a chart line in kPa: loading red, unloading blue.
ChartSeries branchLine(const CurveBranch& branch, const std::vector<double>& stress_Pa) {
  const bool isLoading = branch.phase == LoadPhase::Loading;
  ChartSeries line{
      std::string(isLoading ? "loading " : "unloading ") + std::to_string(branch.cycle),
      {},
      {},
      isLoading ? std::array<unsigned char, 3>{200, 40, 30}
                : std::array<unsigned char, 3>{30, 90, 200},
      false,
      2.0f};
  for (std::size_t i = 0; i < branch.stretch.size(); ++i) {
    line.x.push_back(branch.stretch[i]);
    line.y.push_back(stress_Pa[i] / 1000.0);
  }
  return line;
}

constexpr int kFrameInterval_ms = 16;   ///< about 60 frames per second
constexpr double kWheelStep_m = 0.002;  ///< tool travel per wheel notch

}  // namespace

template <typename Change>
void MainWindow::whilePaused(const Change& change) {
  const bool wasRunning = m_loop->isRunning();
  m_loop->stop();
  change();
  if (wasRunning) m_loop->start();
}

template <typename Change>
void MainWindow::changePhysics(const char* why, RecordedEvent event, const Change& change) {
  leavePlayback(why);
  whilePaused([&] {
    change();
    noteChange(std::move(event));
  });
}

MainWindow::MainWindow(const QString& scenePath, QWidget* parent) : QMainWindow(parent) {
  setWindowTitle("TissueSim");
  resize(1280, 800);
  m_vtkWidget = new QVTKOpenGLNativeWidget(this);
  m_renderWindow = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
  if (isSoftwareOpenGL()) m_renderWindow->SetMultiSamples(0);  // SoftwareOpenGL.h: why
  m_vtkWidget->setRenderWindow(m_renderWindow);
  m_vtkWidget->setObjectName("sceneView");
  setCentralWidget(m_vtkWidget);
  m_style = vtkSmartPointer<InstrumentInteractorStyle>::New();
  m_style->onHover = [this](int x, int y) { moveInstrumentToDisplay(x, y); };
  m_style->onWheel = [this](int notches) { pushInstrument(notches * kWheelStep_m); };
  m_style->onCameraMoved = [this] { putCursorOnInstrument(); };
  m_renderWindow->GetInteractor()->SetInteractorStyle(m_style);

  m_statusLabel = new QLabel(this);
  m_statusLabel->setObjectName("statusText");
  statusBar()->addPermanentWidget(m_statusLabel, 1);
  buildDocks();
  buildMenus();

  connect(&m_frameTimer, &QTimer::timeout, this, &MainWindow::renderFrame);
  m_clock.start();
  if (!loadScene(scenePath)) {
    statusBar()->showMessage("no scene loaded: File > Open scene");
  }
  m_frameTimer.start(kFrameInterval_ms);
}

MainWindow::~MainWindow() {
  m_frameTimer.stop();
  if (m_loop) m_loop->stop();
}

void MainWindow::buildDocks() {
  m_forcePlot = new ForcePlotWidget(this);
  auto* forceDock = new QDockWidget("Tool force", this);
  forceDock->setObjectName("forceDock");
  forceDock->setWidget(m_forcePlot);
  addDockWidget(Qt::RightDockWidgetArea, forceDock);

  m_chartWidget = new QVTKOpenGLNativeWidget(this);
  m_chartWindow = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
  if (isSoftwareOpenGL()) m_chartWindow->SetMultiSamples(0);
  m_chartWidget->setRenderWindow(m_chartWindow);
  m_chartWidget->setMinimumSize(320, 260);
  m_materialChart =
      std::make_unique<CurveChart>("Tissue: uniaxial stress-stretch", "stretch", "stress (kPa)");
  m_chartWindow->AddRenderer(m_materialChart->renderer());
  auto* chartDock = new QDockWidget("Material", this);
  chartDock->setObjectName("materialDock");
  chartDock->setWidget(m_chartWidget);
  addDockWidget(Qt::RightDockWidgetArea, chartDock);
}

void MainWindow::buildMenus() {
  QMenu* file = menuBar()->addMenu("&File");
  file->addAction("Open &tissue parameters...", this, [this] {
    const QString path =
        QFileDialog::getOpenFileName(this, "Open tissue parameters", QString(), "Tissue (*.json)");
    if (!path.isEmpty()) loadTissue(path);
  });
  file->addAction(
      "Open &scene...", this,
      [this] {
        const QString path =
            QFileDialog::getOpenFileName(this, "Open scene", QString(), "Scene (*.json)");
        if (!path.isEmpty()) loadScene(path);
      },
      QKeySequence::Open);
  file->addAction(
      "Save &image...", this,
      [this] {
        const QString path =
            QFileDialog::getSaveFileName(this, "Save image", "tissuesim.png", "PNG (*.png)");
        if (!path.isEmpty()) saveImage(path);
      },
      QKeySequence::Save);
  file->addAction("Open re&cording...", this, [this] {
    const QString path =
        QFileDialog::getOpenFileName(this, "Open recording", QString(), "Recording (*.jsonl)");
    if (!path.isEmpty()) openRecording(path);
  });
  file->addAction("Save &recording...", this, [this] {
    const QString path = QFileDialog::getSaveFileName(this, "Save recording", "session.jsonl",
                                                      "Recording (*.jsonl)");
    if (!path.isEmpty()) saveRecording(path);
  });
  file->addSeparator();
  file->addAction("&Quit", this, &QWidget::close, QKeySequence::Quit);

  QMenu* simulation = menuBar()->addMenu("&Simulation");
  m_pauseAction = simulation->addAction(
      "&Pause", this, [this](bool on) { setPaused(on); }, Qt::Key_Space);
  m_pauseAction->setCheckable(true);
  simulation->addAction(
      "&Reset", this, [this] { resetSimulation(); }, Qt::Key_R);
  simulation->addAction(
      "Playback: back 5 s", this, [this] { seekRecording(playbackTime_s() - 5.0); },
      Qt::Key_BracketLeft);
  simulation->addAction(
      "Playback: forward 5 s", this, [this] { seekRecording(playbackTime_s() + 5.0); },
      Qt::Key_BracketRight);
  simulation->addAction(
      "Toggle &grasper", this,
      [this] {
        if (m_playback) return;
        m_pose.isGrasping = !m_pose.isGrasping;
        publishPose();
      },
      Qt::Key_G);
  // Tilting about the tip, in the screen's axes: 5 degrees a press.
  constexpr double kTilt_rad = 5.0 * 3.14159265358979323846 / 180.0;
  simulation->addAction(
      "Tilt tool &left", this, [this] { tiltInstrument(-kTilt_rad, 0.0); }, Qt::Key_Left);
  simulation->addAction(
      "Tilt tool r&ight", this, [this] { tiltInstrument(kTilt_rad, 0.0); }, Qt::Key_Right);
  simulation->addAction(
      "Tilt tool &away", this, [this] { tiltInstrument(0.0, kTilt_rad); }, Qt::Key_Up);
  simulation->addAction(
      "Tilt tool &towards me", this, [this] { tiltInstrument(0.0, -kTilt_rad); }, Qt::Key_Down);
  simulation->addSeparator();
  m_softeningAction =
      simulation->addAction("Stress &softening", this, [this](bool on) { setSoftening(on); });
  m_softeningAction->setCheckable(true);
  m_gravityAction = simulation->addAction("Gra&vity", this, [this](bool on) { setGravity(on); });
  m_gravityAction->setCheckable(true);
  simulation->addSeparator();
  simulation->addAction(
      "&End session...", this, [this] { endSession(); }, Qt::Key_E);

  QMenu* tools = menuBar()->addMenu("&Tools");
  tools->addAction("&Fit tissue from test data...", this, [this] {
    const QString path = QFileDialog::getOpenFileName(this, "Fit tissue from test data", QString(),
                                                      "Uniaxial test (*.csv);;All files (*)");
    if (!path.isEmpty()) fitTissueFromTestData(path);
  });

  QMenu* view = menuBar()->addMenu("&View");
  m_colourMapAction = view->addAction(
      "Stretch &colour map", this, [this](bool on) { setColourMap(on); }, Qt::Key_C);
  m_colourMapAction->setCheckable(true);
  m_wireframeAction = view->addAction(
      "&Springs", this,
      [this](bool on) {
        if (m_view) m_view->setWireframe(on);
      },
      Qt::Key_W);
  m_wireframeAction->setCheckable(true);
  m_damageAction = view->addAction(
      "Tissue &damage", this, [this](bool on) { setDamageOverlay(on); }, Qt::Key_D);
  m_damageAction->setCheckable(true);
  view->addAction("Reset &camera", this, [this] {
    if (m_view) m_view->resetCamera();
  });
}

void MainWindow::showError(const QString& title, const QString& text) {
  // Not modal-blocking: the simulation keeps running behind it (and tests can see it).
  auto* box = new QMessageBox(QMessageBox::Critical, title, text, QMessageBox::Ok, this);
  box->setObjectName("errorDialog");
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
  statusBar()->showMessage(text, 10000);
}

void MainWindow::showNotice(const QString& title, const QString& text) {
  auto* box = new QMessageBox(QMessageBox::Information, title, text, QMessageBox::Ok, this);
  box->setObjectName("noticeDialog");
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
}

bool MainWindow::loadScene(const QString& path) {
  std::unique_ptr<SceneSession> session;
  try {
    session =
        std::make_unique<SceneSession>(path.toStdString(), std::string(), InstrumentDriver::Live);
  } catch (const std::exception& error) {
    showError("Scene refused", error.what());
    return false;
  }
  if (m_loop) m_loop->stop();
  m_frameTimer.stop();
  if (m_view) m_renderWindow->RemoveRenderer(m_view->renderer());
  m_latest = nullptr;
  m_loop.reset();
  m_view.reset();
  m_session = std::move(session);
  m_scenePath = path;
  m_playback.reset();  // a scene opened is the user's
  // The recording starts with the scene: every input the physics sees from its first step.
  m_recorder.reset();
  if (m_session->liveInstrument() != nullptr) {
    try {
      m_recorder = std::make_unique<SessionRecorder>(path.toStdString());
      m_session->liveInstrument()->setRecorder(m_recorder.get());
    } catch (const std::exception& error) {
      statusBar()->showMessage(QString("not recording: ") + error.what(), 10000);
    }
  }
  Simulation& simulation = m_session->simulation();
  buildView(false);
  m_forcePlot->setThreshold(simulation.assessment().summary().thresholds.toolForce_N);
  m_pose = simulation.instrumentPose();
  m_softeningAction->setChecked(simulation.isSoftening());
  // The FEM on the lattice's tets has no stress softening to turn on (the FEM at its own rate
  // softens per material point).
  const bool isLatticeFem = simulation.scene().model == "fem";
  m_softeningAction->setEnabled(!isLatticeFem);
  m_softeningAction->setToolTip(isLatticeFem ? "The FEM on the lattice has no stress softening"
                                             : "");
  m_gravityAction->setChecked(simulation.gravity().squaredNorm() > 0.0);
  // The FEM at its own rate settles under the scene's gravity as it is made (docs/scene-file.md):
  // the switch shows the scene's, and does not change it.
  const bool isFixedGravity = simulation.scene().model == "fem-haptic-rate";
  m_gravityAction->setEnabled(!isFixedGravity);
  m_gravityAction->setToolTip(
      isFixedGravity ? "The FEM at its own rate takes its gravity from the scene file" : "");
  m_forcePlot->clear();
  updateMaterialChart();
  m_loop = std::make_unique<RealTimeLoop>(simulation);
  m_stepsAtWindowStart = 0;
  m_windowStart_s = m_clock.elapsed() / 1000.0;
  if (!m_pauseAction->isChecked()) m_loop->start();
  m_frameTimer.start(kFrameInterval_ms);
  setWindowTitle("TissueSim - " + QString::fromStdString(m_session->scene().name));
  // A guessed unit is said in the window, where the user looks, and on stderr.
  QStringList assumptions;
  for (const std::string& line : m_session->assumptions()) {
    std::fprintf(stderr, "tissuesim: %s\n", line.c_str());
    assumptions << QString::fromStdString(line);
  }
  if (!assumptions.isEmpty()) showNotice("Scene loaded with an assumption", assumptions.join("\n"));
  renderFrame();
  return true;
}

void MainWindow::buildView(bool keepCamera) {
  vtkNew<vtkCamera> camera;
  if (m_view) {
    camera->DeepCopy(m_view->renderer()->GetActiveCamera());
    m_renderWindow->RemoveRenderer(m_view->renderer());
    m_view.reset();
  }
  const Simulation& simulation = m_session->simulation();
  const auto& instrument = m_session->scene().instrument;
  m_view = std::make_unique<TissueSceneView>(
      simulation.geometry(), simulation.springMesh(), instrument ? &*instrument : nullptr,
      simulation.scene().tray ? &*simulation.scene().tray : nullptr);
  m_view->setColourMap(m_colourMapAction->isChecked());
  m_view->setWireframe(m_wireframeAction->isChecked());
  m_view->setDamageOverlay(m_damageAction->isChecked());
  if (keepCamera) m_view->renderer()->GetActiveCamera()->DeepCopy(camera);
  m_renderWindow->AddRenderer(m_view->renderer());
}

void MainWindow::refineWhereTheToolAims() {
  const qint64 started = m_clock.elapsed();
  const bool isPlayback = m_playback.has_value();
  bool isMade = false, isRefused = false;
  const auto refine = [&] {
    try {
      if (isPlayback) {
        // The recorded changes of the step the playback stopped before, the body's among them.
        const long step = m_playbackStep.load(std::memory_order_relaxed);
        const long before = m_session->simulation().refinements();
        applyRecordedChanges(*m_playback, m_playbackNext, step, *m_session);
        isMade = m_session->simulation().refinements() > before;
      } else {
        isMade = m_session->refineTowardsTool();
      }
    } catch (const std::exception& error) {
      isRefused = true;
      statusBar()->showMessage(
          QString("the body was not refined where the tool aims: ") + error.what(), 10000);
    }
    if (isMade && !isPlayback) {
      RecordedEvent event;
      event.isRefinedTowardsTool = true;
      noteChange(std::move(event));
    }
    // A fresh first snapshot, sized to the new mesh.
    m_loop = std::make_unique<RealTimeLoop>(m_session->simulation());
    m_latest = nullptr;
  };
  if (isPlayback) {
    m_playbackRefinementDue = false;
    refine();
    // A recording whose body cannot be made again no longer plays back as it was recorded.
    if (isRefused) {
      m_playback.reset();
    } else {
      installPlaybackHook();
      if (!m_pauseAction->isChecked()) m_loop->start();
    }
  } else {
    whilePaused(refine);
  }
  if (isMade) {
    buildView(true);
    statusBar()->showMessage(
        QString("the body refined where the tool aims (%1 quadratic tets) in %2 ms")
            .arg(m_session->simulation().geometry().mesh.tetCount())
            .arg(m_clock.elapsed() - started),
        5000);
  }
}

bool MainWindow::loadTissue(const QString& path) {
  if (!m_session) return false;
  TissueParameters parameters;
  try {
    parameters = loadTissueFile(path.toStdString());  // every check a tissue file gets
  } catch (const std::exception& error) {
    showError("Tissue refused", error.what());
    return false;
  }
  RecordedEvent event;
  event.tissue = parameters;
  changePhysics("a new tissue", std::move(event), [&] { m_session->replaceTissue(parameters); });
  updateMaterialChart();
  statusBar()->showMessage("tissue: " + QString::fromStdString(parameters.name) + " (" + path + ")",
                           10000);
  return true;
}

void MainWindow::noteChange(RecordedEvent event) {
  if (!m_recorder || !m_session || m_session->liveInstrument() == nullptr) return;
  event.step = m_session->liveInstrument()->steps();
  m_recorder->noteChange(std::move(event));
}

bool MainWindow::saveRecording(const QString& path) {
  if (!m_recorder || !m_session || m_session->liveInstrument() == nullptr) {
    showError("Nothing to record",
              "This scene has no instrument, or its files could not be read "
              "when it was opened: there is no session to record.");
    return false;
  }
  SessionRecording recording;
  // Paused, so that no step begins between the count and the events.
  whilePaused([&] { recording = m_recorder->recording(m_session->liveInstrument()->steps()); });
  try {
    writeRecording(path.toStdString(), recording);
  } catch (const std::exception& error) {
    showError("Recording not saved", error.what());
    return false;
  }
  statusBar()->showMessage(QString("saved %1: %2 steps, %3 inputs (tissuesim replay --recording "
                                   "%1)")
                               .arg(path)
                               .arg(recording.steps)
                               .arg(recording.events.size()),
                           10000);
  return true;
}

bool MainWindow::openRecording(const QString& path) {
  SessionRecording recording;
  try {
    recording = readRecording(path.toStdString());
    checkFingerprints(recording, path.toStdString());
  } catch (const std::exception& error) {
    showError("Recording refused", error.what());
    return false;
  }
  const bool wasPaused = isPaused();
  setPaused(true);
  if (!restartPlayback(recording)) {
    setPaused(wasPaused);
    return false;
  }
  installPlaybackHook();
  setPaused(wasPaused);
  statusBar()->showMessage("playing " + path + " ([ and ] move 5 s, R restarts)", 10000);
  return true;
}

bool MainWindow::restartPlayback(const SessionRecording& recording) {
  // The window is paused, so loadScene leaves the new loop stopped.
  if (!loadScene(QString::fromStdString(recording.scenePath.string()))) return false;
  m_recorder.reset();  // a playback is not a session of its own
  if (m_session->liveInstrument() != nullptr) m_session->liveInstrument()->setRecorder(nullptr);
  if (!recording.isLive && !recording.script.empty())
    m_session->useScript(InstrumentScript(recording.script));
  m_playback = recording;
  m_playbackNext = 0;
  m_playbackStep = 0;
  return true;
}

void MainWindow::installPlaybackHook() {
  m_loop->setBeforeStep([this] {
    const long step = m_playbackStep.load(std::memory_order_relaxed);
    if (step >= m_playback->steps) return false;  // its end: the loop stops there
    // The body made again changes what the window draws: the loop stops before this step and
    // the window makes it, paused (refineWhereTheToolAims).
    for (std::size_t e = m_playbackNext;
         e < m_playback->events.size() && m_playback->events[e].step <= step; ++e) {
      if (m_playback->events[e].isRefinedTowardsTool) {
        m_playbackRefinementDue = true;
        return false;
      }
    }
    applyRecordedChanges(*m_playback, m_playbackNext, step, *m_session);
    m_playbackStep.store(step + 1, std::memory_order_relaxed);
    return true;
  });
}

void MainWindow::seekRecording(double time_s) {
  if (!m_playback) return;
  const bool wasPaused = isPaused();
  setPaused(true);
  const SessionRecording recording = *m_playback;
  const double step_s = m_session->simulation().timeStep_s();
  const long target =
      std::clamp(std::lround(time_s / step_s), 0L, static_cast<long>(recording.steps));
  if (!restartPlayback(recording)) return;
  statusBar()->showMessage(QString("playback: stepping to %1 s").arg(target * step_s, 0, 'f', 2));
  for (long step = 0; step < target; ++step) {
    applyRecordedChanges(*m_playback, m_playbackNext, step, *m_session);
    m_session->simulation().step();
  }
  if (m_session->simulation().refinements() > 0) buildView(true);
  m_playbackStep = target;
  m_loop = std::make_unique<RealTimeLoop>(m_session->simulation());  // from the state reached
  m_forcePlot->clear();
  installPlaybackHook();
  setPaused(wasPaused);
  renderFrame();
}

void MainWindow::leavePlayback(const char* why) {
  if (!m_playback) return;
  whilePaused([&] { m_loop->setBeforeStep(nullptr); });
  m_playback.reset();
  statusBar()->showMessage(QString("playback left (%1): the session is yours now").arg(why), 10000);
}

double MainWindow::playbackTime_s() const {
  return m_playback && m_session
             ? static_cast<double>(m_playbackStep.load()) * m_session->simulation().timeStep_s()
             : 0.0;
}

double MainWindow::playbackLength_s() const {
  return m_playback && m_session
             ? static_cast<double>(m_playback->steps) * m_session->simulation().timeStep_s()
             : 0.0;
}

bool MainWindow::saveImage(const QString& path) {
  auto grab = vtkSmartPointer<vtkWindowToImageFilter>::New();
  grab->SetInput(m_renderWindow);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  try {
    writePng(grab->GetOutput(), path.toStdString());
  } catch (const std::exception& error) {
    showError("Image not saved", error.what());
    return false;
  }
  statusBar()->showMessage("saved " + path, 5000);
  return true;
}

void MainWindow::setPaused(bool isPaused) {
  m_pauseAction->setChecked(isPaused);
  if (!m_loop) return;
  if (isPaused) {
    m_loop->stop();
  } else {
    m_loop->start();
  }
}

bool MainWindow::isPaused() const { return !m_loop || !m_loop->isRunning(); }

void MainWindow::resetSimulation() {
  if (!m_session) return;
  if (m_playback) {
    seekRecording(0.0);
    return;
  }
  whilePaused([&] {
    m_session->simulation().reset();
    RecordedEvent event;
    event.isReset = true;
    noteChange(std::move(event));
    m_loop = std::make_unique<RealTimeLoop>(m_session->simulation());  // a fresh first snapshot
    m_latest = nullptr;
    m_forcePlot->clear();
  });
  // The tool goes back to where the scene starts it too (through the proxy, at bounded speed).
  if (const std::optional<SceneInstrument>& tool = m_session->scene().instrument) {
    m_pose = InstrumentPose{tool->tipStart_m, tool->direction};
    publishPose();
  }
  renderFrame();
}

void MainWindow::setSoftening(bool isOn) {
  m_softeningAction->setChecked(isOn);
  if (!m_session) return;
  RecordedEvent event;
  event.softening = isOn;
  changePhysics("softening switched", std::move(event),
                [&] { m_session->simulation().setSoftening(isOn); });
  updateMaterialChart();
}

void MainWindow::setGravity(bool isOn) {
  m_gravityAction->setChecked(isOn);
  if (!m_session) return;
  // The scene's gravity when it has one, else 9.81 m/s^2 down the bundled scenes' -y.
  Eigen::Vector3d gravity = m_session->scene().gravity_m_s2;
  if (gravity.squaredNorm() == 0.0) gravity = {0.0, -9.81, 0.0};
  RecordedEvent event;
  event.gravity_m_s2 = isOn ? gravity : Eigen::Vector3d::Zero();
  changePhysics("gravity switched", event,
                [&] { m_session->simulation().setGravity(*event.gravity_m_s2); });
}

void MainWindow::setColourMap(bool isOn) {
  m_colourMapAction->setChecked(isOn);
  if (m_view) m_view->setColourMap(isOn);
}

void MainWindow::setDamageOverlay(bool isOn) {
  m_damageAction->setChecked(isOn);
  if (m_view) m_view->setDamageOverlay(isOn);
  renderFrame();
}

AssessmentSummary MainWindow::endSession() {
  if (!m_session) return {};
  AssessmentSummary summary;
  whilePaused([&] { summary = m_session->simulation().assessment().summary(); });
  m_endedSession = summary;
  auto* box =
      new QMessageBox(QMessageBox::Information, "Session summary",
                      QString::fromStdString(assessmentText(summary)), QMessageBox::Close, this);
  box->setObjectName("sessionSummaryDialog");
  box->setInformativeText("The organ is reset for the next session.");
  QPushButton* save = box->addButton("Save...", QMessageBox::ActionRole);
  connect(save, &QPushButton::clicked, this, [this] {
    const QString path = QFileDialog::getSaveFileName(this, "Save session summary",
                                                      "session-summary.json", "JSON (*.json)");
    if (!path.isEmpty()) saveSessionSummary(path);
  });
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
  resetSimulation();  // the next session starts on a fresh organ (and a fresh assessment)
  return summary;
}

bool MainWindow::saveSessionSummary(const QString& path) {
  if (!m_endedSession || !m_session) {
    showError("No session summary", "End a session first (Simulation > End session).");
    return false;
  }
  nlohmann::json json;
  json["scene"] = m_session->scene().name;
  json["assessment"] = assessmentJson(*m_endedSession);
  try {
    writeWholeFile(path.toStdString(), json.dump(2) + "\n");
  } catch (const std::exception& error) {
    showError("Session summary not saved", error.what());
    return false;
  }
  statusBar()->showMessage("saved " + path, 5000);
  return true;
}

void MainWindow::publishPose() {
  if (m_playback) return;  // the recording drives the tool
  if (m_session && m_session->liveInstrument() != nullptr)
    m_session->liveInstrument()->setPose(m_pose);
}

void MainWindow::moveInstrumentToDisplay(int x, int y) {
  if (!m_view || !m_session || m_session->liveInstrument() == nullptr) return;
  if (m_playback) return;  // the recording drives the tool
  vtkRenderer* renderer = m_view->renderer();
  // The tip's depth on screen, then the cursor's point at that depth.
  renderer->SetWorldPoint(m_pose.tip_m.x(), m_pose.tip_m.y(), m_pose.tip_m.z(), 1.0);
  renderer->WorldToDisplay();
  const double depth = renderer->GetDisplayPoint()[2];
  renderer->SetDisplayPoint(x, y, depth);
  renderer->DisplayToWorld();
  const double* world = renderer->GetWorldPoint();
  if (world[3] == 0.0) return;
  const Eigen::Vector3d tip(world[0] / world[3], world[1] / world[3], world[2] / world[3]);
  if (!tip.allFinite()) return;
  m_pose.tip_m = tip;
  publishPose();
}

void MainWindow::putCursorOnInstrument() {
  if (!m_view || !m_session || m_session->liveInstrument() == nullptr) return;
  if (m_playback) return;  // the recording drives the tool
  vtkRenderer* renderer = m_view->renderer();
  renderer->SetWorldPoint(m_pose.tip_m.x(), m_pose.tip_m.y(), m_pose.tip_m.z(), 1.0);
  renderer->WorldToDisplay();
  const double* display = renderer->GetDisplayPoint();
  if (!std::isfinite(display[0]) || !std::isfinite(display[1]) || display[2] <= 0.0 ||
      display[2] >= 1.0)
    return;  // behind the camera or past its clipping range
  // VTK's display pixels (origin bottom-left, device pixels) to the widget's (top-left,
  // logical), as QVTKInteractorAdapter maps them the other way.
  const double ratio = m_vtkWidget->devicePixelRatioF();
  const int heightPixels = m_renderWindow->GetSize()[1];
  const QPoint onWidget(static_cast<int>(std::lround(display[0] / ratio)),
                        static_cast<int>(std::lround((heightPixels - 1 - display[1]) / ratio)));
  if (!m_vtkWidget->rect().contains(onWidget)) return;
  QCursor::setPos(m_vtkWidget->mapToGlobal(onWidget));
}

void MainWindow::pushInstrument(double distance_m) {
  if (!m_session || m_session->liveInstrument() == nullptr) return;
  if (m_playback) return;  // the recording drives the tool
  m_pose.tip_m += distance_m * m_pose.direction.normalized();
  publishPose();
}

void MainWindow::tiltInstrument(double right_rad, double forward_rad) {
  if (!m_view || !m_session || m_session->liveInstrument() == nullptr) return;
  if (m_playback) return;  // the recording drives the tool
  vtkCamera* camera = m_view->renderer()->GetActiveCamera();
  double up[3], forward[3];
  camera->GetViewUp(up);
  camera->GetDirectionOfProjection(forward);
  const Eigen::Vector3d viewUp(up[0], up[1], up[2]);
  const Eigen::Vector3d away(forward[0], forward[1], forward[2]);
  const Eigen::Vector3d screenRight = away.cross(viewUp).normalized();
  // The shaft's direction points tip-first. For a tool pointing down the screen, a turn of -a
  // about the viewing axis swings its tip a to the right, and a turn of +a about the screen's
  // right axis swings it away from the viewer.
  const Eigen::Vector3d turned =
      (Eigen::AngleAxisd(forward_rad, screenRight) *
       Eigen::AngleAxisd(-right_rad, away.normalized()) * m_pose.direction.normalized())
          .normalized();
  const Eigen::Vector3d start = m_session->scene().instrument->direction.normalized();
  if (!turned.allFinite() || turned.dot(start) < std::cos(80.0 * 3.14159265358979323846 / 180.0))
    return;
  m_pose.direction = turned;
  publishPose();
}

void MainWindow::updateMaterialChart() {
  if (!m_session) return;
  // The current tissue's uniaxial cycles, as the `uniaxial` command computes them.
  // The running simulation's own material and tables: read-only, replaced only while paused.
  const Simulation& simulation = m_session->simulation();
  const TissueParameters& parameters = simulation.parameters();
  const StiffnessTable& table = simulation.table();
  const UniaxialExperiment test(simulation.energy(), table);
  std::vector<double> peaks;
  for (const double peak : {1.15, 1.23, 1.30}) {
    if (peak < table.range().upper) peaks.push_back(peak);
  }
  // Without softening (switched off, or the lattice FEM, which has none) the tissue unloads down
  // its virgin loading curve: that curve alone, to the largest peak. The FEM at its own rate
  // softens per material point without the residual strain: its own curves.
  const bool isSoftening = simulation.isSoftening();
  const UniaxialModel model =
      simulation.hapticRateBody() != nullptr ? UniaxialModel::Fem : UniaxialModel::Sedf;
  if (!isSoftening && !peaks.empty()) peaks.erase(peaks.begin(), peaks.end() - 1);
  std::vector<ChartSeries> series;
  if (!peaks.empty()) {
    const std::vector<CurveBranch> curve = test.run(model, {peaks, 60});
    for (const CurveBranch& branch : curve) {
      if (!isSoftening && branch.phase != LoadPhase::Loading) continue;
      // One line per branch (a joined line would draw chords between cycles).
      series.push_back(branchLine(branch, branch.stress_Pa));
    }
    // Reloading follows the unloading path below the previous peak (the Mullins model): draw
    // the unloading lines last so they are not hidden.
    std::stable_partition(series.begin(), series.end(), [](const ChartSeries& line) {
      return line.name.rfind("loading", 0) == 0;
    });
  }
  // Two lines: at the default window size the dock is narrower than name and legend together.
  m_materialChart->chart()->SetTitle(parameters.name + (isSoftening
                                                            ? "\nloading (red), unloading (blue)"
                                                            : "\nno softening: one elastic curve"));
  m_materialChart->setLegend(false);
  m_materialChart->setSeries(series);
  m_chartWindow->Render();
}

bool MainWindow::fitTissueFromTestData(const QString& csvPath) {
  if (!m_session) return false;
  std::vector<CurveBranch> measured;
  TissueFitResult result;
  try {
    measured = readTensileTestCsv(csvPath.toStdString());
    TissueFitOptions options;
    // Density, v_ij and f come from the tissue the scene runs, and so does the first start.
    options.base = m_session->simulation().parameters();
    options.base.name = QFileInfo(csvPath).completeBaseName().toStdString() + " (fitted)";
    result = fitTissue(measured, options);
  } catch (const TestDataError& error) {
    showError("Test data refused", error.what());
    return false;
  } catch (const std::invalid_argument& error) {
    showError("Fit refused", csvPath + ": " + error.what());
    return false;
  }
  result.parameters.source = "fitted in TissueSim to " + csvPath.toStdString();
  m_fit = std::move(result);
  m_fitData = std::move(measured);
  drawFitOnChart();
  auto* dialog = new TissueFitDialog(
      *m_fit, csvPath, [this](const QString& path) { return saveFittedTissue(path); },
      [this] { return applyFittedTissue(); }, this);
  dialog->show();
  return true;
}

bool MainWindow::applyFittedTissue() {
  if (!m_session || !m_fit) return false;
  RecordedEvent event;
  event.tissue = m_fit->parameters;
  changePhysics("a fitted tissue", std::move(event),
                [&] { m_session->replaceTissue(m_fit->parameters); });
  drawFitOnChart();
  statusBar()->showMessage("tissue: " + QString::fromStdString(m_fit->parameters.name), 10000);
  return true;
}

bool MainWindow::saveFittedTissue(const QString& path) {
  if (!m_fit) return false;
  try {
    writeWholeFile(path.toStdString(), tissueFileText(m_fit->parameters, fitSummary(*m_fit)));
  } catch (const std::exception& error) {
    showError("Tissue file not saved", error.what());
    return false;
  }
  statusBar()->showMessage("saved " + path, 5000);
  return true;
}

void MainWindow::drawFitOnChart() {
  if (!m_fit) return;
  std::vector<ChartSeries> series;
  for (std::size_t b = 0; b < m_fitData.size(); ++b) {
    const CurveBranch& branch = m_fitData[b];
    ChartSeries measured = branchLine(branch, branch.stress_Pa);
    measured.name = "test " + measured.name;
    measured.rgb = {0, 0, 0};
    measured.isDashed = true;
    measured.width = 1.5f;
    series.push_back(std::move(measured));
    series.push_back(branchLine(branch, m_fit->branches[b].model_Pa));
  }
  m_materialChart->chart()->SetTitle(m_fit->parameters.name +
                                     "\nfit (solid) over the test (dashed)");
  m_materialChart->setLegend(false);
  m_materialChart->setSeries(series);
  m_chartWindow->Render();
}

void MainWindow::updateStatus(const SimulationSnapshot& snapshot) {
  const double now = m_clock.elapsed() / 1000.0;
  ++m_framesInWindow;
  if (now - m_windowStart_s >= 0.5) {
    // Steps taken by the simulation in the window (a reset starts its count again: skip it).
    m_fps = m_framesInWindow / (now - m_windowStart_s);
    const long steps = snapshot.step - m_stepsAtWindowStart;
    if (steps >= 0) m_physicsHz = steps / (now - m_windowStart_s);
    m_stepsAtWindowStart = snapshot.step;
    m_framesInWindow = 0;
    m_windowStart_s = now;
  }
  const Simulation& simulation = m_session->simulation();
  // The events in words: how many, and what the latest was (the list stays with the physics).
  const QString events = snapshot.eventCount == 0 || snapshot.latestEventKind == nullptr
                             ? QString("no instability events")
                             : QString("%1 instability events, the latest: %2")
                                   .arg(snapshot.eventCount)
                                   .arg(eventKindWords(snapshot.latestEventKind));
  // The model, and whether the physics keeps up with the clock (the FEM does not at the
  // bundled size): simulated time then runs slow, and the status says so.
  const QString model =
      QString("%1 %2")
          .arg(simulation.scene().model != "springs" ? simulation.geometry().mesh.tetCount()
                                                     : simulation.springMesh().springCount())
          .arg(QString::fromStdString(elasticModelWords(simulation.scene())));
  const bool isBehind =
      !isPaused() && m_physicsHz > 0.0 && m_physicsHz < 0.9 / simulation.timeStep_s();
  const QString state = m_playback ? QString("playback %1 / %2 s%3")
                                         .arg(playbackTime_s(), 0, 'f', 2)
                                         .arg(playbackLength_s(), 0, 'f', 2)
                                         .arg(isPaused() ? " (paused)" : "")
                        : isPaused() ? QString("paused")
                                     : QString("running");
  m_statusLabel->setText(QString("%1   physics %2 Hz%9   %3 fps   %4   tool force %5 N%10   max "
                                 "stretch %6   t = %7 s   %8")
                             .arg(state)
                             .arg(m_physicsHz, 0, 'f', 0)
                             .arg(m_fps, 0, 'f', 0)
                             .arg(model)
                             .arg(snapshot.toolForce_N.norm(), 0, 'f', 3)
                             .arg(snapshot.maxStretch, 0, 'f', 3)
                             .arg(snapshot.time_s, 0, 'f', 2)
                             .arg(events)
                             .arg(isBehind ? " (slower than real time)" : "")
                             .arg(snapshot.instrument.isGrasping ? "   jaws closed" : ""));
}

void MainWindow::renderFrame() {
  if (!m_loop || !m_view) return;
  if (m_playback ? m_playbackRefinementDue.load() && !m_loop->isRunning()
                 : m_loop->snapshot().wantsRefinement) {
    refineWhereTheToolAims();
  }
  const SimulationSnapshot& snapshot = m_loop->snapshot();
  m_latest = &snapshot;
  m_view->update(snapshot.positions_m, snapshot.instrument, &snapshot.damagedSprings);
  m_forcePlot->addSample(snapshot.time_s, snapshot.toolForce_N.norm());
  updateStatus(snapshot);
  m_renderWindow->Render();
}

}  // namespace tissuesim::app
