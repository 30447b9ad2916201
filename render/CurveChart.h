// SPDX-License-Identifier: Apache-2.0
#pragma once
// A 2D line chart (VTK's charts: vtkChartXY in a context actor) in its own renderer, so the
// same chart renders in a window panel or offscreen into a PNG: stress-stretch curves
// (`--plot`, the GUI's material panel) and the live tool force.

#include <array>
#include <string>
#include <vector>

#include <vtkChartXY.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

class vtkChartXY;
class vtkContextActor;
class vtkRenderer;

namespace tissuesim {

struct ChartSeries {
  std::string name;
  std::vector<double> x;
  std::vector<double> y;
  std::array<unsigned char, 3> rgb{0, 0, 0};
  bool isDashed = false;
  float width = 2.0f;
  bool isPoints = false;  ///< markers at the points (one point is enough), no line
};

class CurveChart {
 public:
  CurveChart(const std::string& title, const std::string& xTitle, const std::string& yTitle);
  ~CurveChart();
  CurveChart(const CurveChart&) = delete;
  CurveChart& operator=(const CurveChart&) = delete;

  /// Replaces every line. Lines with fewer than two points, and empty series, are skipped.
  void setSeries(const std::vector<ChartSeries>& series);
  void setLegend(bool isShown);
  /// Logarithmic axes (every value drawn on such an axis must be > 0).
  void setLogScale(bool isLogX, bool isLogY);
  /// Fixed axis ranges, in data units (on a log axis too), instead of the data's own bounds.
  void setRanges(double xMin, double xMax, double yMin, double yMax);

  vtkRenderer* renderer() const { return m_renderer; }
  vtkChartXY* chart() const { return m_chart; }

 private:
  vtkSmartPointer<vtkRenderer> m_renderer;
  vtkSmartPointer<vtkContextActor> m_actor;
  vtkSmartPointer<vtkChartXY> m_chart;
};

}  // namespace tissuesim
