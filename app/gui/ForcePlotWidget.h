// SPDX-License-Identifier: Apache-2.0
#pragma once
// The small live plot of the tool force magnitude (N) over the last seconds, drawn with
// QPainter: it repaints at the frame rate, where a second OpenGL chart would cost a render.

#include <deque>
#include <utility>

#include <QWidget>

namespace tissuesim::app {

class ForcePlotWidget : public QWidget {
  Q_OBJECT
 public:
  explicit ForcePlotWidget(QWidget* parent = nullptr);
  /// Adds a sample (simulated time s, force N); keeps the last kWindow_s seconds.
  void addSample(double time_s, double force_N);
  void clear();
  QSize sizeHint() const override { return {320, 140}; }

 protected:
  void paintEvent(QPaintEvent* event) override;

 private:
  static constexpr double kWindow_s = 5.0;
  std::deque<std::pair<double, double>> m_samples;
};

}  // namespace tissuesim::app
