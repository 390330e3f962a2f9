#include "quiet_vtk.hpp"

#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>

namespace pd::post {
namespace {

// An output window that keeps the text instead of showing it.
class CollectingOutputWindow : public vtkOutputWindow {
public:
  static CollectingOutputWindow* New();
  vtkTypeMacro(CollectingOutputWindow, vtkOutputWindow);
  void DisplayText(const char* text) override {
    if (text != nullptr) collected += text;
  }
  std::string collected;
};
vtkStandardNewMacro(CollectingOutputWindow);

}  // namespace

QuietVtk::QuietVtk()
    : previous_(vtkOutputWindow::GetInstance()),
      collector_(vtkSmartPointer<CollectingOutputWindow>::New()) {
  vtkOutputWindow::SetInstance(collector_);
  // VTK 9 also logs errors through its logger, straight to stderr. The
  // logger has no getter for that level, so it stays off: the tools never
  // want VTK's log lines.
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
}

QuietVtk::~QuietVtk() { vtkOutputWindow::SetInstance(previous_); }

bool QuietVtk::failed() const {
  return !static_cast<CollectingOutputWindow*>(collector_.Get())->collected.empty();
}

std::string QuietVtk::first_message() const {
  const std::string& text = static_cast<CollectingOutputWindow*>(collector_.Get())->collected;
  // VTK's form: "ERROR: In FILE, line N\nvtkClass (0xADDRESS): message\n\n".
  std::size_t begin = text.find('\n');
  begin = begin == std::string::npos ? 0 : begin + 1;
  const std::size_t address_end = text.find("): ", begin);
  const std::size_t line_end = text.find('\n', begin);
  if (address_end != std::string::npos && address_end < line_end) begin = address_end + 3;
  std::string message = text.substr(begin, line_end == std::string::npos ? std::string::npos : line_end - begin);
  // One line with single spaces (VTK puts two after a full stop).
  std::string line;
  for (char c : message)
    if (!(c == ' ' && !line.empty() && line.back() == ' ')) line += c == '\n' ? ' ' : c;
  while (!line.empty() && (line.back() == ' ' || line.back() == '.')) line.pop_back();
  return line;
}

}  // namespace pd::post
