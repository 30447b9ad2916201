// SPDX-License-Identifier: Apache-2.0
// Image regression: the bundled scene rendered offscreen (llvmpipe under Xvfb) against reference
// PNGs in tests/images. Metric and tolerance: render/ImageComparison.h (a pixel differs when a
// channel is off by more than 24/255; at most 0.2 % of the pixels may differ). On a failure the
// actual image and an amplified difference are written to <build>/image-failures/.
// To re-record the references after an intended change: TISSUESIM_UPDATE_IMAGES=1 ctest -R image

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <vtkActor.h>
#include <vtkActorCollection.h>
#include <vtkImageData.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <CLI/CLI.hpp>

#include "app/CommandError.h"
#include "app/HeadlessDisplay.h"
#include "app/ReplayCommand.h"
#include "app/RunCommand.h"
#include "app/SceneSession.h"
#include "app/SceneSnapshot.h"
#include "render/ImageComparison.h"
#include "render/OffscreenImage.h"
#include "render/TissueSceneView.h"

namespace tissuesim::app {
namespace {

constexpr int kWidth = 480;
constexpr int kHeight = 300;

class ImageRegression : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { s_display = std::make_unique<HeadlessDisplay>(true); }
  static void TearDownTestSuite() { s_display.reset(); }

  /// The bundled poke scene after `frames` frames of 1/60 s, rendered as `snapshot` does.
  static vtkSmartPointer<vtkImageData> render(int frames, bool isColourMap) {
    SceneSession session(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json", "",
                         InstrumentDriver::Script);
    const SceneSnapshot snapshot =
        takeSceneSnapshot(session, {frames, {kWidth, kHeight}, isColourMap, false});
    EXPECT_EQ(snapshot.badSteps, 0);
    return snapshot.image;
  }

  static std::filesystem::path referencePath(const std::string& name) {
    return std::filesystem::path(TISSUESIM_TEST_IMAGE_DIR) / (name + ".png");
  }

  static void expectMatchesReference(const std::string& name, vtkImageData* actual) {
    const std::filesystem::path reference = referencePath(name);
    if (const char* update = std::getenv("TISSUESIM_UPDATE_IMAGES");
        update != nullptr && std::string(update) == "1") {
      writePng(actual, reference);
      GTEST_SKIP() << "recorded " << reference;
    }
    ASSERT_TRUE(std::filesystem::exists(reference)) << reference << " is missing";
    vtkSmartPointer<vtkImageData> diff;
    const ImageDifference difference =
        compareImages(actual, readPng(reference), ImageTolerance{}, &diff);
    if (!difference.matches(ImageTolerance{})) {
      const std::filesystem::path failures =
          std::filesystem::path(TISSUESIM_BUILD_DIR) / "image-failures";
      std::filesystem::create_directories(failures);
      writePng(actual, failures / (name + "-actual.png"));
      if (diff) writePng(diff, failures / (name + "-diff.png"));
      ADD_FAILURE() << name << ": " << difference.describe() << "; actual and diff in " << failures;
    }
  }

  static std::unique_ptr<HeadlessDisplay> s_display;
};
std::unique_ptr<HeadlessDisplay> ImageRegression::s_display;

TEST_F(ImageRegression, LiverAtRest) { expectMatchesReference("liver-rest", render(0, false)); }

TEST_F(ImageRegression, LiverMidPoke) {
  expectMatchesReference("liver-mid-poke", render(36, false));
}

TEST_F(ImageRegression, LiverMidPokeColourMap) {
  expectMatchesReference("liver-mid-poke-colour-map", render(36, true));
}

TEST_F(ImageRegression, RenderingIsDeterministic) {
  const auto first = render(30, true);
  const auto second = render(30, true);
  const ImageDifference difference = compareImages(first, second, ImageTolerance{});
  EXPECT_TRUE(difference.isSameSize);
  EXPECT_EQ(difference.differingPixels, 0) << difference.describe();
  EXPECT_EQ(difference.meanAbsoluteDifference, 0.0);
}

TEST_F(ImageRegression, AReplayedRunDrawsTheSnapshotsImage) {
  // `run --record` over the default poke, then `replay --snapshot` at frame 36: the image
  // `snapshot` draws at that frame (the mid-poke reference's), pixel for pixel.
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / "tissuesim-replay-image-test";
  std::filesystem::create_directories(folder);
  const std::string recording = (folder / "run.jsonl").string();
  const std::string png = (folder / "frame36.png").string();
  const auto command = [](std::vector<std::string> arguments) {
    CLI::App app("tissuesim");
    registerRunCommand(app);
    registerReplayCommand(app);
    std::reverse(arguments.begin(), arguments.end());
    app.parse(arguments);
  };
  command({"run", "--scene", std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json",
           "--duration", "0.7", "--record", recording});
  command({"replay", "--recording", recording, "--snapshot", png, "--frames", "36", "--size",
           std::to_string(kWidth) + "x" + std::to_string(kHeight)});
  const ImageDifference difference = compareImages(readPng(png), render(36, false), {});
  EXPECT_TRUE(difference.isSameSize);
  EXPECT_EQ(difference.differingPixels, 0) << difference.describe();
  EXPECT_EQ(difference.meanAbsoluteDifference, 0.0);
  // And not some other frame's.
  EXPECT_GT(compareImages(readPng(png), render(30, false), {}).differingPixels, 0);
  std::filesystem::remove_all(folder);
}

TEST_F(ImageRegression, TheMetricSeesThePokeAndTheColourMap) {
  // The tolerance must not hide what the tests are for: a rest image does not pass for the
  // mid-poke reference, nor a plain one for the colour-mapped one.
  const auto rest = render(0, false);
  const auto poke = render(36, false);
  EXPECT_FALSE(compareImages(rest, poke, ImageTolerance{}).matches(ImageTolerance{}));
  EXPECT_FALSE(compareImages(poke, render(36, true), ImageTolerance{}).matches(ImageTolerance{}));
}

TEST_F(ImageRegression, TheDefaultViewDrawsNothingTranslucent) {
  // Any translucent actor makes VTK 9.1 run its order-independent transparency passes over the
  // whole window every frame: with llvmpipe a 60 ms frame instead of 30 at 1280 x 800 for the
  // tool's small shadow alone. Drawn once first, so that every mapper has its input.
  SceneSession session(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json", "",
                       InstrumentDriver::Script);
  Simulation& simulation = session.simulation();
  TissueSceneView view(simulation.geometry(), simulation.springMesh(), &*session.scene().instrument,
                       session.scene().tray ? &*session.scene().tray : nullptr);
  view.update(simulation.state().x, simulation.instrumentPose());
  renderOffscreen(view.renderer(), kWidth, kHeight);
  vtkActorCollection* actors = view.renderer()->GetActors();
  actors->InitTraversal();
  int visible = 0;
  while (vtkActor* actor = actors->GetNextActor()) {
    if (actor->GetVisibility() == 0) continue;
    ++visible;
    EXPECT_EQ(actor->HasTranslucentPolygonalGeometry(), 0)
        << "a visible actor with opacity " << actor->GetProperty()->GetOpacity();
  }
  EXPECT_GE(visible, 4);  // the liver, the tray, the tool's shaft and tip, its shadow
}

TEST(HeadlessDisplay, SaysHowToInstallXvfbWhenItIsMissing) {
  // No DISPLAY and no Xvfb on the PATH: a one-line error naming the package, not a crash.
  const char* display = std::getenv("DISPLAY");
  const std::string savedDisplay = display != nullptr ? display : "";
  const std::string savedPath = std::getenv("PATH") != nullptr ? std::getenv("PATH") : "";
  ::unsetenv("DISPLAY");
  ::setenv("PATH", "/nonexistent", 1);
  try {
    HeadlessDisplay headless(true);
    ADD_FAILURE() << "expected an error";
  } catch (const CommandError& error) {
    EXPECT_NE(std::string(error.what()).find("apt-get install xvfb"), std::string::npos)
        << error.what();
  }
  ::setenv("PATH", savedPath.c_str(), 1);
  if (!savedDisplay.empty()) ::setenv("DISPLAY", savedDisplay.c_str(), 1);
}

}  // namespace
}  // namespace tissuesim::app
