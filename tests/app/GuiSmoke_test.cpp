// SPDX-License-Identifier: Apache-2.0
// The window, driven as a trainee and an instructor would (QTest, under Xvfb when there is no
// display): start on the bundled scene, push the instrument into the liver with the mouse
// wheel, see the surface move and no error; load a bad tissue file, see the error dialog and
// the simulation carry on; load a good one; save an image; save the session's recording and
// step it again to the window's state; take the tool aside on a scene refined where it aims and
// see the body made again there, in the session and in its playback.

#include <algorithm>
#include <cmath>

#include <QVTKOpenGLNativeWidget.h>
#include <vtkRenderWindow.h>
#include <QAction>
#include <QApplication>
#include <QMessageBox>
#include <QScreen>
#include <QSurfaceFormat>
#include <QTemporaryDir>
#include <QWheelEvent>
#include <QtTest/QtTest>
#include <nlohmann/json.hpp>

#include "app/HeadlessDisplay.h"
#include "app/SessionSteps.h"
#include "app/gui/ForcePlotWidget.h"
#include "app/gui/MainWindow.h"
#include "app/gui/SoftwareOpenGL.h"
#include "app/gui/TissueFitDialog.h"
#include "material/TissueFile.h"

namespace tissuesim::app {

class GuiSmokeTest : public QObject {
  Q_OBJECT

 private:
  std::unique_ptr<MainWindow> m_window;
  QWidget* view() const { return m_window->findChild<QWidget*>("sceneView"); }
  long steps() const { return m_window->latestSnapshot() ? m_window->latestSnapshot()->step : 0; }
  void wheel(int notches) { wheelAt(notches, view()->rect().center()); }
  void wheelAt(int notches, const QPoint& centre) {
    // What the mouse wheel sends, one notch at a time, to the 3D view, the cursor at `centre`.
    for (int i = 0; i < std::abs(notches); ++i) {
      QWheelEvent event(centre, view()->mapToGlobal(centre), QPoint(),
                        QPoint(0, notches > 0 ? 120 : -120), Qt::NoButton, Qt::NoModifier,
                        Qt::NoScrollPhase, false);
      QApplication::sendEvent(view(), &event);
      QTest::qWait(25);
    }
  }
  QMessageBox* errorDialog() const { return m_window->findChild<QMessageBox*>("errorDialog"); }

 private slots:
  void initTestCase() {
    m_window =
        std::make_unique<MainWindow>(QString(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json");
    m_window->show();
    QVERIFY(QTest::qWaitForWindowExposed(m_window.get()));
    QVERIFY(view() != nullptr);
    QVERIFY(m_window->simulation() != nullptr);
    QTRY_VERIFY_WITH_TIMEOUT(steps() > 20, 10000);  // the physics runs on its own
    QVERIFY(errorDialog() == nullptr);
  }

  void softwareOpenGLDrawsWithoutMultisampling() {
    // Under Xvfb this is Mesa's llvmpipe, where VTK's default multisampling made every frame
    // about four times dearer; on a GPU it stays as VTK sets it.
    const QString renderer = openGLRendererName();
    QVERIFY2(!renderer.isEmpty(), "no OpenGL renderer found");
    if (!isSoftwareOpenGL()) QSKIP(qPrintable("a GPU (" + renderer + "): multisampling stays on"));
    auto* widget = qobject_cast<QVTKOpenGLNativeWidget*>(view());
    QVERIFY(widget != nullptr);
    QCOMPARE(widget->renderWindow()->GetMultiSamples(), 0);
  }

  void hoverMovesTheTool() {
    const Eigen::Vector3d before = m_window->instrumentPose().tip_m;
    const QPoint target = view()->rect().center() + QPoint(30, 0);
    QMouseEvent move(QEvent::MouseMove, target, Qt::NoButton, Qt::NoButton, Qt::NoModifier);
    QApplication::sendEvent(view(), &move);
    const Eigen::Vector3d after = m_window->instrumentPose().tip_m;
    QVERIFY2((after - before).norm() > 1e-3, "the tip did not follow the cursor");
    // Back over the poke point, for the next test.
    QMouseEvent back(QEvent::MouseMove, view()->rect().center(), Qt::NoButton, Qt::NoButton,
                     Qt::NoModifier);
    QApplication::sendEvent(view(), &back);
  }

  void aCameraMoveLeavesTheToolWhereItIs() {
    // The tip follows the cursor at its depth, so after the camera moves, the cursor is put where
    // the tip is now drawn: the next hover steers the tool on from where it was, not from the
    // point of the scene the move brought under the cursor.
    const auto send = [&](QEvent::Type type, const QPoint& at, Qt::MouseButton button,
                          Qt::MouseButtons held) {
      QMouseEvent event(type, at, view()->mapToGlobal(at), button, held, Qt::NoModifier);
      QApplication::sendEvent(view(), &event);
    };
    const QPoint centre = view()->rect().center();
    send(QEvent::MouseMove, centre, Qt::NoButton, Qt::NoButton);
    const Eigen::Vector3d before = m_window->instrumentPose().tip_m;
    // A right drag upwards zooms in (VTK's trackball dolly), about the view's centre, where the
    // tip is drawn; the tool stays meanwhile.
    send(QEvent::MouseButtonPress, centre, Qt::RightButton, Qt::RightButton);
    QPoint at = centre;
    for (int i = 0; i < 8; ++i) {
      at += QPoint(0, -12);
      send(QEvent::MouseMove, at, Qt::NoButton, Qt::RightButton);
      QTest::qWait(10);
    }
    QCursor::setPos(view()->mapToGlobal(at));  // where the pointer is as the drag ends
    QTRY_COMPARE_WITH_TIMEOUT(view()->mapFromGlobal(QCursor::pos()), at, 2000);
    send(QEvent::MouseButtonRelease, at, Qt::RightButton, Qt::NoButton);
    QCOMPARE(m_window->instrumentPose().tip_m, before);
    // The cursor is back over the tip, near the view's centre.
    QPoint cursor;
    QTRY_VERIFY_WITH_TIMEOUT(
        (cursor = view()->mapFromGlobal(QCursor::pos()), (cursor - at).manhattanLength() > 60),
        2000);
    send(QEvent::MouseMove, cursor, Qt::NoButton, Qt::NoButton);
    const double moved_m = (m_window->instrumentPose().tip_m - before).norm();
    QVERIFY2(moved_m < 5e-4, qPrintable(QString("the tip jumped %1 mm").arg(1e3 * moved_m)));
    // And steers on from there.
    send(QEvent::MouseMove, cursor + QPoint(20, 0), Qt::NoButton, Qt::NoButton);
    QVERIFY((m_window->instrumentPose().tip_m - before).norm() > 1e-3);
    // Back to the scene's view, the pointer off the window (the tests after send their own
    // events) and the tool over the poke point.
    for (QAction* action : m_window->findChildren<QAction*>()) {
      if (action->text() == "Reset &camera") action->trigger();
    }
    const QPoint offWindow = QGuiApplication::primaryScreen()->geometry().bottomRight();
    QVERIFY(!m_window->frameGeometry().contains(offWindow));
    QCursor::setPos(offWindow);
    QTRY_COMPARE_WITH_TIMEOUT(QCursor::pos(), offWindow, 2000);
    QTest::qWait(50);
    send(QEvent::MouseMove, centre, Qt::NoButton, Qt::NoButton);
  }

  void arrowKeysTiltTheToolAboutItsTip() {
    // The menu actions bound to the arrow keys (triggered directly: under Xvfb without a
    // window manager the window never becomes active, so key shortcuts do not reach it).
    const auto press = [&](Qt::Key key) {
      for (QAction* action : m_window->findChildren<QAction*>()) {
        if (action->shortcut() == QKeySequence(key)) {
          action->trigger();
          return true;
        }
      }
      return false;
    };
    const InstrumentPose before = m_window->instrumentPose();
    QVERIFY(press(Qt::Key_Right));
    const InstrumentPose right = m_window->instrumentPose();
    QCOMPARE(right.tip_m, before.tip_m);
    // 5 degrees about the viewing axis: the shaft turns by up to that (all of it when it lies
    // across the view).
    const double degrees = std::acos(std::clamp(right.direction.dot(before.direction), -1.0, 1.0)) *
                           180.0 / 3.14159265358979323846;
    QVERIFY2(degrees > 1.0 && degrees <= 5.0 + 1e-9,
             qPrintable(QString("Right tilted the shaft %1 degrees").arg(degrees)));
    QVERIFY(press(Qt::Key_Up));
    QVERIFY(m_window->instrumentPose().direction.dot(right.direction) < 1.0 - 1e-6);
    // Back: Down and Left undo them (the view has not turned meanwhile).
    QVERIFY(press(Qt::Key_Down));
    QVERIFY(press(Qt::Key_Left));
    QVERIFY((m_window->instrumentPose().direction - before.direction).norm() < 1e-9);
  }

  void wheelPushesTheToolIntoTheLiver() {
    m_window->resetSimulation();  // the tool too: back over the liver, where the scene starts it
    const SceneInstrument& tool = *m_window->simulation()->scene().instrument;
    QCOMPARE(m_window->instrumentPose().tip_m, tool.tipStart_m);
    QTRY_VERIFY_WITH_TIMEOUT(m_window->latestSnapshot() != nullptr, 5000);
    const Eigen::Matrix3Xd rest = m_window->latestSnapshot()->positions_m;
    const double startHeight = m_window->instrumentPose().tip_m.y();
    wheel(20);  // 2 mm a notch, down the shaft: through the 1.7 cm gap and into the liver
    QVERIFY(m_window->instrumentPose().tip_m.y() < startHeight - 0.03);
    double force = 0.0;
    double moved = 0.0;
    QTRY_VERIFY_WITH_TIMEOUT(
        (m_window->renderFrame(), force = m_window->latestSnapshot()->toolForce_N.norm(),
         moved = (m_window->latestSnapshot()->positions_m - rest).colwise().norm().maxCoeff(),
         force > 0.05 && moved > 1e-3),
        20000);
    QVERIFY(errorDialog() == nullptr);
    QVERIFY(m_window->framesPerSecond() > 0.0);  // the 60 Hz timer has been drawing all along
    QVERIFY(m_window->physicsHz() > 0.0);
  }

  void aBadTissueFileShowsAnErrorAndTheSimulationGoesOn() {
    const std::string before = m_window->simulation()->parameters().name;
    QVERIFY(
        !m_window->loadTissue(QString(TISSUESIM_TEST_DATA_DIR) + "/tissues/negative-modulus.json"));
    QMessageBox* dialog = errorDialog();
    QVERIFY(dialog != nullptr);
    QVERIFY(dialog->isVisible());
    QVERIFY(dialog->text().contains("mu_kpa"));
    QCOMPARE(m_window->simulation()->parameters().name, before);
    const long stepsThen = steps();
    QTRY_VERIFY_WITH_TIMEOUT((m_window->renderFrame(), steps() > stepsThen + 20), 10000);
    dialog->close();
  }

  void aGoodTissueFileIsApplied() {
    QVERIFY(
        m_window->loadTissue(QString(TISSUESIM_TEST_DATA_DIR) + "/tissues/valid-exact-n2.json"));
    QCOMPARE(QString::fromStdString(m_window->simulation()->parameters().name), QString("test"));
    const long stepsThen = steps();
    QTRY_VERIFY_WITH_TIMEOUT((m_window->renderFrame(), steps() > stepsThen + 20), 10000);
  }

  void aBadSceneKeepsTheOldOne() {
    const Simulation* before = m_window->simulation();
    QVERIFY(
        !m_window->loadScene(QString(TISSUESIM_TEST_DATA_DIR) + "/scenes/unknown-integrator.json"));
    QCOMPARE(m_window->simulation(), before);
    if (QMessageBox* dialog = errorDialog()) dialog->close();
  }

  void filesReplacedOrDeletedWhileRunningKeepTheRunningScene() {
    // A scene and its files in a folder of their own, loaded; then, while it runs, its tissue
    // and its scene replaced by garbage and its mesh deleted, each reloaded: an error dialog
    // naming the file each time, and the running scene goes on with what it had.
    QTemporaryDir folder;
    const QString assets = QString(TISSUESIM_ASSET_DIR);
    for (const auto& [from, to] :
         {std::pair{assets + "/tissues/porcine-liver.json", QString("tissue.json")},
          std::pair{assets + "/meshes/liver-smooth.obj", QString("liver-smooth.obj")},
          std::pair{assets + "/meshes/liver-5300.msh", QString("liver-5300.msh")}}) {
      QVERIFY(QFile::copy(from, folder.filePath(to)));
    }
    QFile bundled(assets + "/scenes/liver-poke.json");
    QVERIFY(bundled.open(QIODevice::ReadOnly));
    QByteArray scene = bundled.readAll();
    scene.replace("../tissues/porcine-liver.json", "tissue.json");
    scene.replace("../meshes/", "");
    const auto write = [&](const QString& name, const QByteArray& bytes) {
      QFile file(folder.filePath(name));
      QVERIFY(file.open(QIODevice::WriteOnly | QIODevice::Truncate));
      QCOMPARE(file.write(bytes), bytes.size());
    };
    write("scene.json", scene);
    QVERIFY(m_window->loadScene(folder.filePath("scene.json")));
    QVERIFY(m_window->loadTissue(folder.filePath("tissue.json")));
    const Simulation* running = m_window->simulation();
    const std::string tissueName = running->parameters().name;
    const QByteArray garbage("\x00\xff{\"mu_kpa\": [oops", 19);
    const auto expectRefusedAndRunning = [&](bool isLoaded, const QString& named) {
      QVERIFY(!isLoaded);
      QMessageBox* dialog = errorDialog();
      QVERIFY(dialog != nullptr);
      QVERIFY2(dialog->text().contains(named), qPrintable(dialog->text()));
      QCOMPARE(m_window->simulation(), running);
      QCOMPARE(m_window->simulation()->parameters().name, tissueName);
      const long stepsThen = steps();
      QTRY_VERIFY_WITH_TIMEOUT((m_window->renderFrame(), steps() > stepsThen + 20), 10000);
      dialog->close();
      QTest::qWait(20);  // deleted on close
    };
    write("tissue.json", garbage);
    expectRefusedAndRunning(m_window->loadTissue(folder.filePath("tissue.json")), "tissue.json");
    write("scene.json", garbage);
    expectRefusedAndRunning(m_window->loadScene(folder.filePath("scene.json")), "scene.json");
    write("scene.json", scene);
    QVERIFY(QFile::remove(folder.filePath("liver-5300.msh")));
    expectRefusedAndRunning(m_window->loadScene(folder.filePath("scene.json")), "liver-5300.msh");
  }

  void pauseStopsThePhysics() {
    m_window->setPaused(true);
    QVERIFY(m_window->isPaused());
    m_window->renderFrame();
    const long stepsThen = steps();
    QTest::qWait(200);
    m_window->renderFrame();
    QCOMPARE(steps(), stepsThen);
    m_window->setPaused(false);
    QTRY_VERIFY_WITH_TIMEOUT((m_window->renderFrame(), steps() > stepsThen), 5000);
  }

  void savesAnImage() {
    QTemporaryDir directory;
    const QString path = directory.filePath("view.png");
    m_window->setColourMap(true);
    QVERIFY(m_window->saveImage(path));
    QVERIFY(QFileInfo(path).size() > 1000);
    // A picture of the whole window on request (for the README and for looking at it by eye).
    if (const QString shot = qEnvironmentVariable("TISSUESIM_GUI_SCREENSHOT"); !shot.isEmpty()) {
      QVERIFY(m_window->grab().save(shot));
    }
  }

  void aSavedRecordingReplaysToTheWindowsState() {
    // A session on the bundled scene: pushes, a new tissue, gravity off, a reset, more pushes;
    // saved, then stepped again from the file alone (as `tissuesim replay` steps it): the same
    // positions to the bit as the window's, the physics paused.
    QVERIFY(m_window->loadScene(QString(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json"));
    QTRY_VERIFY_WITH_TIMEOUT((m_window->renderFrame(), steps() > 20), 10000);
    wheel(12);
    QTest::qWait(150);
    QVERIFY(
        m_window->loadTissue(QString(TISSUESIM_TEST_DATA_DIR) + "/tissues/valid-exact-n2.json"));
    wheel(-4);
    m_window->setGravity(false);
    QTest::qWait(150);
    m_window->resetSimulation();
    wheel(8);
    QTest::qWait(200);
    m_window->setPaused(true);
    QTemporaryDir directory;
    const QString path = directory.filePath("session.jsonl");
    QVERIFY(m_window->saveRecording(path));
    const Eigen::Matrix3Xd live = m_window->simulation()->state().x;
    const SessionRecording recording = readRecording(path.toStdString());
    QVERIFY(recording.isLive);
    QVERIFY(recording.steps > 100);
    const auto count = [&](const auto& has) {
      return std::count_if(recording.events.begin(), recording.events.end(), has);
    };
    QVERIFY(count([](const RecordedEvent& e) { return e.pose.has_value(); }) >= 10);
    QCOMPARE(count([](const RecordedEvent& e) { return e.tissue.has_value(); }), 1L);
    QCOMPARE(count([](const RecordedEvent& e) { return e.gravity_m_s2.has_value(); }), 1L);
    QCOMPARE(count([](const RecordedEvent& e) { return e.isReset; }), 1L);

    SceneSession replay(recording.scenePath.string(), "", InstrumentDriver::Live);
    std::size_t next = 0;
    for (long step = 0; step < recording.steps; ++step) {
      applyRecordedChanges(recording, next, step, replay);
      replay.simulation().step();
    }
    QCOMPARE(replay.simulation().state().x.cols(), live.cols());
    QCOMPARE((replay.simulation().state().x - live).cwiseAbs().maxCoeff(), 0.0);
    QVERIFY((live - replay.simulation().startState().x).cwiseAbs().maxCoeff() > 1e-4);  // it moved

    // File > Open recording plays it in the window: running, it stops at its end, where the
    // window's positions are the session's; the mouse does not move the tool meanwhile.
    m_window->setPaused(false);
    QVERIFY(m_window->openRecording(path));
    QVERIFY(m_window->isPlayingBack());
    QTRY_VERIFY_WITH_TIMEOUT((m_window->renderFrame(), m_window->isPaused()), 20000);
    QCOMPARE(m_window->playbackTime_s(), m_window->playbackLength_s());
    QCOMPARE((m_window->simulation()->state().x - live).cwiseAbs().maxCoeff(), 0.0);
    const InstrumentPose held = m_window->instrumentPose();
    wheel(3);
    QCOMPARE(m_window->instrumentPose().tip_m, held.tip_m);
    // Seeking back re-steps it from the start: the state at 0.1 s is the replay's at step 100.
    m_window->seekRecording(0.1);
    QVERIFY(m_window->isPaused());
    QCOMPARE(m_window->playbackTime_s(), 0.1);
    SceneSession again(recording.scenePath.string(), "", InstrumentDriver::Live);
    next = 0;
    for (long step = 0; step < 100; ++step) {
      applyRecordedChanges(recording, next, step, again);
      again.simulation().step();
    }
    QCOMPARE(
        (m_window->simulation()->state().x - again.simulation().state().x).cwiseAbs().maxCoeff(),
        0.0);
    // A change of the user's own ends the playback.
    m_window->setGravity(true);
    QVERIFY(!m_window->isPlayingBack());
    m_window->setPaused(false);
  }

  void aGuessedUnitIsShownInTheWindow() {
    // minimal.json gives its mesh no metres_per_unit: the window says what it assumed.
    QVERIFY(m_window->loadScene(QString(TISSUESIM_TEST_DATA_DIR) + "/scenes/minimal.json"));
    QMessageBox* notice = m_window->findChild<QMessageBox*>("noticeDialog");
    QVERIFY(notice != nullptr);
    QVERIFY2(notice->text().contains("liver-1000.msh: assumed metres"), qPrintable(notice->text()));
    notice->close();
    QVERIFY(errorDialog() == nullptr);
    // The bundled scene states its units: nothing to say.
    QVERIFY(m_window->loadScene(QString(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json"));
    QTRY_VERIFY(m_window->findChild<QMessageBox*>("noticeDialog") == nullptr);
  }

  void aTissueFittedToTestDataIsShownSavedAndApplied() {
    // Tools > Fit tissue from test data, on the paper's own curve: the dialog with R^2 per
    // branch, a saved file the parser reads, and the scene running on the fitted tissue.
    const QString data = QString(TISSUESIM_TEST_DATA_DIR) + "/fit/liver-uniaxial.csv";
    QVERIFY(m_window->fitTissueFromTestData(data));
    auto* dialog = m_window->findChild<TissueFitDialog*>("fitDialog");
    QVERIFY(dialog != nullptr);
    QVERIFY2(dialog->reportText().contains("cycle 3 unloading R^2 = 1.000000"),
             qPrintable(dialog->reportText()));
    // Pictures of the window and the dialog on request (for looking at them by eye).
    if (const QString shot = qEnvironmentVariable("TISSUESIM_GUI_FIT_SCREENSHOT");
        !shot.isEmpty()) {
      QTest::qWait(200);
      QVERIFY(m_window->grab().save(shot));
      QVERIFY(dialog->grab().save(shot + "-dialog.png"));
    }
    QTemporaryDir folder;
    const QString saved = folder.filePath("fitted.json");
    QVERIFY(m_window->saveFittedTissue(saved));
    const TissueParameters read = loadTissueFile(saved.toStdString());
    QVERIFY(std::abs(read.A2_Pa - 7543.6e3) < 0.01 * 7543.6e3);
    const long stepsBefore = steps();
    QVERIFY(m_window->applyFittedTissue());
    QCOMPARE(m_window->simulation()->parameters().A2_Pa, read.A2_Pa);
    QTRY_VERIFY_WITH_TIMEOUT(steps() > stepsBefore + 20, 10000);  // still running
    dialog->close();
    // Bad data: an error dialog naming the line, and nothing applied.
    QVERIFY(!m_window->fitTissueFromTestData(QString(TISSUESIM_TEST_DATA_DIR) +
                                             "/fit/not-numeric.csv"));
    QMessageBox* error = errorDialog();
    QVERIFY(error != nullptr);
    QVERIFY2(error->text().contains("not-numeric.csv:3"), qPrintable(error->text()));
    error->close();
  }

  void aSessionIsAssessedItsDamageDrawnAndItsSummarySaved() {
    // A scene with low thresholds: a 4 cm poke passes both.
    QVERIFY(m_window->loadScene(QString(TISSUESIM_TEST_DATA_DIR) + "/scenes/assessed-liver.json"));
    auto* plot = m_window->findChild<ForcePlotWidget*>("forcePlot");
    QVERIFY(plot != nullptr);
    QCOMPARE(plot->threshold(), 3.0);
    const auto damaged = [&] {
      m_window->renderFrame();
      const std::vector<std::uint8_t>& flags = m_window->latestSnapshot()->damagedSprings;
      return std::count(flags.begin(), flags.end(), std::uint8_t{1});
    };
    QTRY_VERIFY_WITH_TIMEOUT(steps() > 20, 10000);
    QCOMPARE(damaged(), 0);
    wheel(28);  // through the 1.7 cm gap and 4 cm into the liver
    QTRY_VERIFY_WITH_TIMEOUT(damaged() > 0, 20000);
    wheel(-28);  // out again: the damage stays
    QTRY_VERIFY_WITH_TIMEOUT(
        (m_window->renderFrame(), m_window->latestSnapshot()->toolForce_N.norm() == 0.0), 20000);
    const long damagedAfter = damaged();
    QVERIFY(damagedAfter > 0);

    // The overlay draws it: the same paused frame with and without it differs where it lies.
    m_window->setPaused(true);
    QTemporaryDir folder;
    m_window->setDamageOverlay(true);
    QVERIFY(m_window->saveImage(folder.filePath("overlay.png")));
    m_window->setDamageOverlay(false);
    QVERIFY(m_window->saveImage(folder.filePath("plain.png")));
    const QImage overlay(folder.filePath("overlay.png"));
    const QImage plain(folder.filePath("plain.png"));
    QCOMPARE(overlay.size(), plain.size());
    long changed = 0;
    for (int y = 0; y < overlay.height(); ++y) {
      for (int x = 0; x < overlay.width(); ++x) changed += overlay.pixel(x, y) != plain.pixel(x, y);
    }
    QVERIFY2(changed > 100, qPrintable(QString("%1 pixels changed").arg(changed)));
    if (const QString shot = qEnvironmentVariable("TISSUESIM_GUI_DAMAGE_SCREENSHOT");
        !shot.isEmpty()) {
      m_window->setDamageOverlay(true);
      QVERIFY(m_window->saveImage(shot));
    }

    // End session: the summary, a fresh organ and assessment, the summary saved as JSON.
    const AssessmentSummary summary = m_window->endSession();
    QCOMPARE(summary.damagedSpringCount, damagedAfter);
    QVERIFY(summary.peakToolForce_N > 3.0);
    QVERIFY(summary.aboveForceThreshold_s > 0.0);
    QVERIFY(summary.toolPathLength_m > 0.1);
    auto* dialog = m_window->findChild<QMessageBox*>("sessionSummaryDialog");
    QVERIFY(dialog != nullptr);
    QVERIFY2(dialog->text().contains("Tissue stretched past 1.14"), qPrintable(dialog->text()));
    if (const QString shot = qEnvironmentVariable("TISSUESIM_GUI_DAMAGE_SCREENSHOT");
        !shot.isEmpty()) {
      QTest::qWait(200);
      QVERIFY(dialog->grab().save(shot + "-summary.png"));
    }
    QCOMPARE(damaged(), 0);
    const QString saved = folder.filePath("summary.json");
    QVERIFY(m_window->saveSessionSummary(saved));
    QFile file(saved);
    QVERIFY(file.open(QIODevice::ReadOnly));
    const nlohmann::json json = nlohmann::json::parse(file.readAll().toStdString());
    QCOMPARE(json.at("assessment").at("damaged_springs").get<long>(), damagedAfter);
    QCOMPARE(json.at("scene").get<std::string>(), std::string("assessed liver"));
    dialog->close();
    m_window->setPaused(false);
  }

  void aRefinedBodyIsMadeAgainWhereTheToolGoesAndPlaysBackSo() {
    // The scene refined where its tool aims: the tool taken aside over the liver, the body made
    // again there, pressed there; the recording replays it, and plays back in the window.
    QVERIFY(m_window->loadScene(QString(TISSUESIM_ASSET_DIR) + "/scenes/liver-fem-refined.json"));
    m_window->setPaused(false);
    QTRY_VERIFY_WITH_TIMEOUT(steps() > 50, 10000);
    QCOMPARE(m_window->simulation()->refinements(), 0L);
    const Eigen::Vector3d centre = *m_window->simulation()->refinementCentre();
    // The view's centre: over the middle of the liver, a few centimetres from where the scene
    // starts the tool.
    const QPoint aside = view()->rect().center();
    QMouseEvent move(QEvent::MouseMove, aside, Qt::NoButton, Qt::NoButton, Qt::NoModifier);
    QApplication::sendEvent(view(), &move);
    QTRY_VERIFY_WITH_TIMEOUT(m_window->simulation()->refinements() >= 1, 10000);
    QVERIFY((*m_window->simulation()->refinementCentre() - centre).norm() >
            Simulation::kRefineAgainDistance_m);
    QTRY_VERIFY_WITH_TIMEOUT(
        (m_window->renderFrame(),
         steps() > 0 && m_window->latestSnapshot()->positions_m.cols() ==
                            m_window->simulation()->geometry().mesh.nodeCount()),
        5000);
    wheelAt(12, aside);
    double force = 0.0;
    QTRY_VERIFY_WITH_TIMEOUT((m_window->renderFrame(),
                              force = m_window->latestSnapshot()->toolForce_N.norm(), force > 0.05),
                             20000);
    QVERIFY(errorDialog() == nullptr);
    m_window->setPaused(true);
    QCOMPARE(m_window->simulation()->eventCount(), std::size_t{0});
    QTemporaryDir directory;
    const QString path = directory.filePath("refined.jsonl");
    QVERIFY(m_window->saveRecording(path));
    const Eigen::Matrix3Xd live = m_window->simulation()->state().x;
    const SessionRecording recording = readRecording(path.toStdString());
    // Made again once at least (as the tool came to rest over the new site; again wherever it
    // stopped over another on its way), each noted in the recording.
    const long made = m_window->simulation()->refinements();
    QVERIFY(made >= 1);
    QCOMPARE(std::count_if(recording.events.begin(), recording.events.end(),
                           [](const RecordedEvent& e) { return e.isRefinedTowardsTool; }),
             made);
    SceneSession replay(recording.scenePath.string(), "", InstrumentDriver::Live);
    std::size_t next = 0;
    for (long step = 0; step < recording.steps; ++step) {
      applyRecordedChanges(recording, next, step, replay);
      replay.simulation().step();
    }
    QCOMPARE(replay.simulation().refinements(), made);
    QCOMPARE(replay.simulation().state().x.cols(), live.cols());
    QCOMPARE((replay.simulation().state().x - live).cwiseAbs().maxCoeff(), 0.0);
    // Played back in the window: the body made again at the same step, the same state at its end.
    m_window->setPaused(false);
    QVERIFY(m_window->openRecording(path));
    QTRY_VERIFY_WITH_TIMEOUT(
        (m_window->renderFrame(),
         m_window->isPaused() && m_window->playbackTime_s() == m_window->playbackLength_s()),
        30000);
    QCOMPARE(m_window->simulation()->refinements(), made);
    QCOMPARE((m_window->simulation()->state().x - live).cwiseAbs().maxCoeff(), 0.0);
    QVERIFY(errorDialog() == nullptr);
  }

  void cleanupTestCase() { m_window.reset(); }
};

}  // namespace tissuesim::app

int main(int argc, char** argv) {
  const tissuesim::app::HeadlessDisplay display(true);
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication application(argc, argv);
  tissuesim::app::GuiSmokeTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "GuiSmoke_test.moc"
