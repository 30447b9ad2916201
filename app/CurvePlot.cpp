// SPDX-License-Identifier: Apache-2.0
#include "app/CurvePlot.h"

#include <stdexcept>

#include <vtkImageData.h>

#include "app/CommandError.h"
#include "app/HeadlessDisplay.h"
#include "render/CurveChart.h"
#include "render/OffscreenImage.h"

namespace tissuesim::app {
namespace {

ChartSeries seriesOf(const std::string& name, const std::vector<CurveBranch>& branches,
                     std::array<unsigned char, 3> rgb, bool isDashed) {
  ChartSeries series;
  series.name = name;
  series.rgb = rgb;
  series.isDashed = isDashed;
  for (const CurveBranch& branch : branches) {
    for (std::size_t i = 0; i < branch.stretch.size(); ++i) {
      series.x.push_back(branch.stretch[i]);
      series.y.push_back(branch.stress_Pa[i] / 1000.0);  // kPa on the axis
    }
  }
  return series;
}

}  // namespace

void writeCurvePlot(const std::string& path, const std::string& title,
                    const std::vector<std::pair<std::string, std::vector<CurveBranch>>>& models,
                    const std::vector<CurveBranch>& reference, const std::string& referenceName) {
  const HeadlessDisplay display;
  CurveChart chart(title, "stretch lambda", "engineering stress (kPa)");
  static constexpr std::array<std::array<unsigned char, 3>, 3> kColours = {
      {{200, 40, 30}, {30, 90, 200}, {30, 150, 60}}};
  std::vector<ChartSeries> series;
  for (std::size_t m = 0; m < models.size(); ++m) {
    series.push_back(
        seriesOf(models[m].first, models[m].second, kColours[m % kColours.size()], false));
  }
  series.push_back(seriesOf(referenceName, reference, {0, 0, 0}, true));
  chart.setSeries(series);
  const vtkSmartPointer<vtkImageData> image = renderOffscreen(chart.renderer(), 900, 600);
  try {
    writePng(image, path);
  } catch (const std::runtime_error& error) {
    throw CommandError(error.what());
  }
}

}  // namespace tissuesim::app
