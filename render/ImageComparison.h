// SPDX-License-Identifier: Apache-2.0
#pragma once
// Compares a rendered image with a reference, for the image regression tests.
//
// Metric: a pixel differs when any channel differs by more than `channelTolerance` (of 255);
// the images match when the fraction of differing pixels is at most `pixelFraction`. Why this
// and not an RMS: antialiasing and rasteriser rounding move a few edge pixels by a lot, which an
// RMS over a large image hides and a per-pixel max punishes; a real change (a surface that did
// not move, a missing colour map) changes thousands of pixels. The mean absolute difference is
// reported alongside.

#include <filesystem>
#include <string>

#include <vtkSmartPointer.h>

class vtkImageData;

namespace tissuesim {

struct ImageTolerance {
  int channelTolerance = 24;     ///< of 255
  double pixelFraction = 0.002;  ///< 0.2 % of the pixels
};

struct ImageDifference {
  bool isSameSize = false;
  long differingPixels = 0;
  long pixels = 0;
  double meanAbsoluteDifference = 0.0;  ///< over all channels, of 255
  double differingFraction() const {
    return pixels > 0 ? static_cast<double>(differingPixels) / pixels : 1.0;
  }
  bool matches(const ImageTolerance& tolerance) const {
    return isSameSize && differingFraction() <= tolerance.pixelFraction;
  }
  std::string describe() const;
};

/// Compares two RGB(A) 8-bit images; `diff` (optional) receives |a - b| per channel, scaled x4.
ImageDifference compareImages(vtkImageData* actual, vtkImageData* reference,
                              const ImageTolerance& tolerance,
                              vtkSmartPointer<vtkImageData>* diff = nullptr);

}  // namespace tissuesim
