// SPDX-License-Identifier: Apache-2.0
#include "app/gui/ForcePlotWidget.h"

#include <algorithm>

#include <QPainter>
#include <QPainterPath>

namespace tissuesim::app {

ForcePlotWidget::ForcePlotWidget(QWidget* parent) : QWidget(parent) {
  setMinimumSize(200, 100);
  setObjectName("forcePlot");
}

void ForcePlotWidget::addSample(double time_s, double force_N) {
  if (!m_samples.empty() && time_s < m_samples.back().first) m_samples.clear();  // after a reset
  m_samples.emplace_back(time_s, force_N);
  while (!m_samples.empty() && m_samples.front().first < time_s - kWindow_s) m_samples.pop_front();
  update();
}

void ForcePlotWidget::clear() {
  m_samples.clear();
  update();
}

void ForcePlotWidget::setThreshold(double force_N) {
  m_threshold_N = force_N;
  update();
}

void ForcePlotWidget::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  painter.setRenderHint(QPainter::Antialiasing);
  painter.fillRect(rect(), Qt::white);
  const QRectF plot = QRectF(rect()).adjusted(44, 8, -8, -22);
  painter.setPen(QColor(120, 120, 120));
  painter.drawRect(plot);
  double top = std::max(0.5, 1.15 * m_threshold_N);  // N: at least half a newton of scale
  for (const auto& sample : m_samples) top = std::max(top, 1.1 * sample.second);
  painter.drawText(QRectF(0, plot.top() - 6, 40, 14), Qt::AlignRight, QString::number(top, 'f', 2));
  painter.drawText(QRectF(0, plot.bottom() - 8, 40, 14), Qt::AlignRight, "0 N");
  painter.drawText(QRectF(plot.left(), plot.bottom() + 4, plot.width(), 14), Qt::AlignCenter,
                   "tool force, last 5 s");
  if (m_threshold_N > 0.0) {
    const double y = plot.bottom() - m_threshold_N / top * plot.height();
    painter.setPen(QPen(QColor(230, 140, 0), 1.5, Qt::DashLine));
    painter.drawLine(QPointF(plot.left(), y), QPointF(plot.right(), y));
    painter.drawText(QRectF(plot.left() + 4, y - 15, plot.width() - 8, 14), Qt::AlignLeft,
                     QString("threshold %1 N").arg(m_threshold_N, 0, 'g', 3));
  }
  if (m_samples.size() < 2) return;
  const double end = m_samples.back().first;
  QPainterPath path;
  for (std::size_t i = 0; i < m_samples.size(); ++i) {
    const double x = plot.right() - (end - m_samples[i].first) / kWindow_s * plot.width();
    const double y = plot.bottom() - m_samples[i].second / top * plot.height();
    if (i == 0) {
      path.moveTo(x, y);
    } else {
      path.lineTo(x, y);
    }
  }
  painter.setPen(QPen(QColor(200, 40, 30), 2.0));
  painter.drawPath(path);
}

}  // namespace tissuesim::app
