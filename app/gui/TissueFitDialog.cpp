// SPDX-License-Identifier: Apache-2.0
#include "app/gui/TissueFitDialog.h"

#include <cmath>

#include <QDialogButtonBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QFontDatabase>
#include <QLabel>
#include <QPlainTextEdit>
#include <QPushButton>
#include <QVBoxLayout>

namespace tissuesim::app {

namespace {

QString reportOf(const TissueFitResult& result) {
  QString text = QString("%1 %2 %3\n").arg("", -8).arg("value", 14).arg("std. error", 14);
  for (const FittedParameter& entry : result.table) {
    QString error;
    if (entry.isFixed) {
      error = "(held)";
    } else if (std::isfinite(entry.uncertainty)) {
      error = QString::number(entry.uncertainty, 'g', 3);
    } else {
      error = "inf";
    }
    text += QString("%1 %2 %3%4\n")
                .arg(QString::fromStdString(entry.name), -8)
                .arg(QString::number(entry.value, 'g', 6), 14)
                .arg(error, 14)
                .arg(entry.isFixed || entry.isIdentified ? "" : "  not identified");
  }
  text += "\n";
  for (const BranchFit& branch : result.branches) {
    text += QString("cycle %1 %2 R^2 = %3\n")
                .arg(branch.cycle)
                .arg(phaseName(branch.phase), -9)
                .arg(QString::number(branch.rSquared, 'f', 6));
  }
  for (const std::string& note : result.notes) text += "\nnote: " + QString::fromStdString(note);
  for (const std::string& warning : result.warnings)
    text += "\nwarning: " + QString::fromStdString(warning);
  return text;
}

}  // namespace

TissueFitDialog::TissueFitDialog(const TissueFitResult& result, const QString& dataPath,
                                 std::function<bool(const QString&)> save,
                                 std::function<bool()> apply, QWidget* parent)
    : QDialog(parent), m_report(reportOf(result)) {
  setObjectName("fitDialog");
  setWindowTitle("Fitted tissue: " + QFileInfo(dataPath).fileName());
  auto* layout = new QVBoxLayout(this);
  layout->addWidget(new QLabel("Fitted to " + dataPath + " (curves in the Material panel)", this));
  auto* report = new QPlainTextEdit(m_report, this);
  report->setReadOnly(true);
  report->setFont(QFontDatabase::systemFont(QFontDatabase::FixedFont));
  report->setMinimumSize(560, 320);
  layout->addWidget(report);
  auto* buttons = new QDialogButtonBox(this);
  QPushButton* saveButton = buttons->addButton("Save tissue file...", QDialogButtonBox::ActionRole);
  saveButton->setObjectName("saveFittedTissue");
  QPushButton* applyButton = buttons->addButton("Apply to the scene", QDialogButtonBox::ApplyRole);
  applyButton->setObjectName("applyFittedTissue");
  buttons->addButton(QDialogButtonBox::Close);
  layout->addWidget(buttons);
  connect(saveButton, &QPushButton::clicked, this, [this, save] {
    const QString path = QFileDialog::getSaveFileName(this, "Save tissue file",
                                                      "fitted-tissue.json", "Tissue (*.json)");
    if (!path.isEmpty()) save(path);
  });
  connect(applyButton, &QPushButton::clicked, this, [apply] { apply(); });
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::close);
  setAttribute(Qt::WA_DeleteOnClose);
}

}  // namespace tissuesim::app
