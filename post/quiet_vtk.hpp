#pragma once
// VTK without its own console output. VTK prints its errors (and a dump of
// the pipeline request) to stderr before the caller can say what went wrong;
// pd-post reports one clean line naming the file instead. While a
// QuietVtk is alive, VTK's messages are collected here and not printed.
#include <string>

#include <vtkSmartPointer.h>

class vtkOutputWindow;

namespace pd::post {

class QuietVtk {
public:
  QuietVtk();
  ~QuietVtk();
  QuietVtk(const QuietVtk&) = delete;
  QuietVtk& operator=(const QuietVtk&) = delete;

  // True when VTK reported an error (or a warning) since construction.
  bool failed() const;
  // The first message's own text, without VTK's source position and object
  // address, on one line (empty if none).
  std::string first_message() const;

private:
  vtkSmartPointer<vtkOutputWindow> previous_;
  vtkSmartPointer<vtkOutputWindow> collector_;
};

}  // namespace pd::post
