// SPDX-License-Identifier: Apache-2.0
#include "render/CurveChart.h"

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextActor.h>
#include <vtkContextScene.h>
#include <vtkDoubleArray.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkPlotPoints.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>

namespace tissuesim {

CurveChart::CurveChart(const std::string& title, const std::string& xTitle,
                       const std::string& yTitle)
    : m_renderer(vtkSmartPointer<vtkRenderer>::New()),
      m_actor(vtkSmartPointer<vtkContextActor>::New()),
      m_chart(vtkSmartPointer<vtkChartXY>::New()) {
  m_renderer->SetBackground(1.0, 1.0, 1.0);
  m_actor->GetScene()->AddItem(m_chart);
  m_renderer->AddActor(m_actor);
  m_actor->GetScene()->SetRenderer(m_renderer);
  m_chart->SetTitle(title);
  m_chart->GetTitleProperties()->SetFontSize(16);
  m_chart->GetAxis(vtkAxis::BOTTOM)->SetTitle(xTitle);
  m_chart->GetAxis(vtkAxis::LEFT)->SetTitle(yTitle);
  m_chart->SetShowLegend(true);
  m_chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::LEFT);
  m_chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
}

CurveChart::~CurveChart() = default;

void CurveChart::setSeries(const std::vector<ChartSeries>& series) {
  m_chart->ClearPlots();
  for (const ChartSeries& line : series) {
    if (line.x.size() < (line.isPoints ? 1u : 2u) || line.x.size() != line.y.size()) continue;
    auto table = vtkSmartPointer<vtkTable>::New();
    auto x = vtkSmartPointer<vtkDoubleArray>::New();
    x->SetName("x");
    auto y = vtkSmartPointer<vtkDoubleArray>::New();
    y->SetName(line.name.c_str());
    table->AddColumn(x);
    table->AddColumn(y);
    table->SetNumberOfRows(static_cast<vtkIdType>(line.x.size()));
    for (std::size_t i = 0; i < line.x.size(); ++i) {
      table->SetValue(static_cast<vtkIdType>(i), 0, line.x[i]);
      table->SetValue(static_cast<vtkIdType>(i), 1, line.y[i]);
    }
    vtkPlot* plot = m_chart->AddPlot(line.isPoints ? vtkChart::POINTS : vtkChart::LINE);
    plot->SetInputData(table, 0, 1);
    plot->SetColor(line.rgb[0], line.rgb[1], line.rgb[2], 255);
    plot->SetWidth(line.width);
    if (line.isPoints) vtkPlotPoints::SafeDownCast(plot)->SetMarkerSize(4.0f * line.width);
    if (line.isDashed) plot->GetPen()->SetLineType(vtkPen::DASH_LINE);
  }
  m_chart->RecalculateBounds();
}

void CurveChart::setLegend(bool isShown) { m_chart->SetShowLegend(isShown); }

void CurveChart::setRanges(double xMin, double xMax, double yMin, double yMax) {
  vtkAxis* x = m_chart->GetAxis(vtkAxis::BOTTOM);
  vtkAxis* y = m_chart->GetAxis(vtkAxis::LEFT);
  x->SetBehavior(vtkAxis::FIXED);
  y->SetBehavior(vtkAxis::FIXED);
  x->SetUnscaledRange(xMin, xMax);
  y->SetUnscaledRange(yMin, yMax);
}

void CurveChart::setLogScale(bool isLogX, bool isLogY) {
  m_chart->GetAxis(vtkAxis::BOTTOM)->SetLogScale(isLogX);
  m_chart->GetAxis(vtkAxis::LEFT)->SetLogScale(isLogY);
  m_chart->RecalculateBounds();
}

}  // namespace tissuesim
