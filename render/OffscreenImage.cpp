// SPDX-License-Identifier: Apache-2.0
#include "render/OffscreenImage.h"

#include <fstream>
#include <stdexcept>

#include <vtkImageData.h>
#include <vtkPNGReader.h>
#include <vtkPNGWriter.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkWindowToImageFilter.h>

#include "io/WholeFile.h"

namespace tissuesim {

OffscreenWindow::OffscreenWindow(vtkRenderer* renderer, int width, int height)
    : m_renderer(renderer), m_window(vtkSmartPointer<vtkRenderWindow>::New()) {
  m_window->SetOffScreenRendering(1);
  m_window->SetMultiSamples(0);  // the same pixels on every run and driver setting
  m_window->SetSize(width, height);
  m_window->AddRenderer(renderer);
}

OffscreenWindow::~OffscreenWindow() {
  m_window->RemoveRenderer(m_renderer);
  m_window->Finalize();
}

void OffscreenWindow::render() {
  m_window->Render();
  m_window->WaitForCompletion();  // glFinish: a timed frame is a drawn frame
}

vtkSmartPointer<vtkImageData> OffscreenWindow::image() {
  auto grab = vtkSmartPointer<vtkWindowToImageFilter>::New();
  grab->SetInput(m_window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(grab->GetOutput());
  return image;
}

vtkSmartPointer<vtkImageData> renderOffscreen(vtkRenderer* renderer, int width, int height) {
  OffscreenWindow window(renderer, width, height);
  window.render();
  return window.image();
}

void writePng(vtkImageData* image, const std::filesystem::path& path) {
  writeWholeFileWith(path, [&](const std::filesystem::path& partial) {
    {
      // vtkPNGWriter reports a failed open only through its error observer: check first.
      std::ofstream probe(partial, std::ios::binary);
      if (!probe) return false;
    }
    auto writer = vtkSmartPointer<vtkPNGWriter>::New();
    writer->SetFileName(partial.string().c_str());
    writer->SetInputData(image);
    writer->Write();
    return writer->GetErrorCode() == 0;
  });
}

vtkSmartPointer<vtkImageData> readPng(const std::filesystem::path& path) {
  auto reader = vtkSmartPointer<vtkPNGReader>::New();
  if (!std::filesystem::is_regular_file(path) || reader->CanReadFile(path.string().c_str()) == 0) {
    throw std::runtime_error("cannot read the PNG image " + path.string());
  }
  reader->SetFileName(path.string().c_str());
  reader->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(reader->GetOutput());
  return image;
}

}  // namespace tissuesim
