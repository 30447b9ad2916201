// SPDX-License-Identifier: Apache-2.0
#include "render/ImageComparison.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include <vtkImageData.h>

namespace tissuesim {

std::string ImageDifference::describe() const {
  if (!isSameSize) return "the images differ in size or channels";
  char text[160];
  std::snprintf(text, sizeof text,
                "%ld of %ld pixels differ (%.3f %%), mean absolute difference %.3f / 255",
                differingPixels, pixels, 100.0 * differingFraction(), meanAbsoluteDifference);
  return text;
}

ImageDifference compareImages(vtkImageData* actual, vtkImageData* reference,
                              const ImageTolerance& tolerance,
                              vtkSmartPointer<vtkImageData>* diff) {
  ImageDifference result;
  int a[3], b[3];
  actual->GetDimensions(a);
  reference->GetDimensions(b);
  const int channels = actual->GetNumberOfScalarComponents();
  if (a[0] != b[0] || a[1] != b[1] || channels != reference->GetNumberOfScalarComponents() ||
      actual->GetScalarType() != VTK_UNSIGNED_CHAR ||
      reference->GetScalarType() != VTK_UNSIGNED_CHAR) {
    return result;
  }
  result.isSameSize = true;
  result.pixels = static_cast<long>(a[0]) * a[1];
  const auto* p = static_cast<const unsigned char*>(actual->GetScalarPointer());
  const auto* q = static_cast<const unsigned char*>(reference->GetScalarPointer());
  unsigned char* d = nullptr;
  if (diff != nullptr) {
    *diff = vtkSmartPointer<vtkImageData>::New();
    (*diff)->SetDimensions(a[0], a[1], 1);
    (*diff)->AllocateScalars(VTK_UNSIGNED_CHAR, channels);
    d = static_cast<unsigned char*>((*diff)->GetScalarPointer());
  }
  double sum = 0.0;
  for (long i = 0; i < result.pixels; ++i) {
    int worst = 0;
    for (int c = 0; c < channels; ++c) {
      const long k = i * channels + c;
      const int delta = std::abs(static_cast<int>(p[k]) - static_cast<int>(q[k]));
      worst = std::max(worst, delta);
      sum += delta;
      if (d != nullptr) d[k] = static_cast<unsigned char>(std::min(255, 4 * delta));
    }
    if (worst > tolerance.channelTolerance) ++result.differingPixels;
  }
  result.meanAbsoluteDifference = sum / static_cast<double>(result.pixels * channels);
  return result;
}

}  // namespace tissuesim
