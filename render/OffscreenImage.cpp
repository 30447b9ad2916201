#include "OffscreenImage.h"

#include <fstream>
#include <stdexcept>

#include <vtkImageData.h>
#include <vtkPNGReader.h>
#include <vtkPNGWriter.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkWindowToImageFilter.h>

namespace tissuesim {

vtkSmartPointer<vtkImageData> renderOffscreen(vtkRenderer* renderer, int width, int height) {
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);  // the same pixels on every run and driver setting
  window->SetSize(width, height);
  window->AddRenderer(renderer);
  window->Render();
  auto grab = vtkSmartPointer<vtkWindowToImageFilter>::New();
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(grab->GetOutput());
  window->RemoveRenderer(renderer);
  window->Finalize();
  return image;
}

void writePng(vtkImageData* image, const std::filesystem::path& path) {
  {
    // vtkPNGWriter reports a failed open only through its error observer: check first.
    std::ofstream probe(path, std::ios::binary);
    if (!probe) throw std::runtime_error("cannot write the image " + path.string());
  }
  auto writer = vtkSmartPointer<vtkPNGWriter>::New();
  writer->SetFileName(path.string().c_str());
  writer->SetInputData(image);
  writer->Write();
  if (writer->GetErrorCode() != 0) throw std::runtime_error("cannot write the image " + path.string());
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
