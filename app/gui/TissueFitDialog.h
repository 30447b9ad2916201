// SPDX-License-Identifier: Apache-2.0
#pragma once
// Tools > Fit tissue from test data: the fit's constants, their errors and R^2 per branch
// (analysis/TissueFit.h), with the two things an instructor does next: save the tissue file,
// apply it to the running scene. Non-modal: the simulation runs behind it. The window draws
// the fitted curves over the data in its Material panel.

#include <functional>

#include <QDialog>

#include "analysis/TissueFit.h"

class QPushButton;

namespace tissuesim::app {

class TissueFitDialog : public QDialog {
  Q_OBJECT
 public:
  /// `save` is given the path chosen; `apply` puts the tissue into the scene. Each returns
  /// whether it succeeded (its failure already shown by the window).
  TissueFitDialog(const TissueFitResult& result, const QString& dataPath,
                  std::function<bool(const QString&)> save, std::function<bool()> apply,
                  QWidget* parent);

  /// The table as shown (for tests and for copying).
  QString reportText() const { return m_report; }

 private:
  QString m_report;
};

}  // namespace tissuesim::app
