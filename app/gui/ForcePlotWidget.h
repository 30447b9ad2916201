// SPDX-License-Identifier: Apache-2.0
#pragma once
// The small live plot of the tool force magnitude (N) over the last seconds, drawn with
// QPainter: it repaints at the frame rate, where a second OpenGL chart would cost a render.
// The session's force threshold (docs/assessment.md) is a dashed line, always in the scale, so
// the trainee sees how near it each push comes.

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
  /// The force threshold drawn (N); 0: none.
  void setThreshold(double force_N);
  double threshold() const { return m_threshold_N; }
  QSize sizeHint() const override { return {320, 140}; }

 protected:
  void paintEvent(QPaintEvent* event) override;

 private:
  static constexpr double kWindow_s = 5.0;
  std::deque<std::pair<double, double>> m_samples;
  double m_threshold_N = 0.0;
};

}  // namespace tissuesim::app
