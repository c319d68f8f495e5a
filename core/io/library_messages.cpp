#include "io/library_messages.h"

#include <gdcmTrace.h>
#include <itkObject.h>
#include <itkObjectFactory.h>
#include <itkOutputWindow.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <mutex>
#include <sstream>

#include "common/error.h"
#include "common/text.h"

namespace mpumesh {
namespace {

std::mutex& read_lock() {
  static std::mutex m;
  return m;
}

class CollectingWindow : public itk::OutputWindow {
 public:
  using Self = CollectingWindow;
  using Pointer = itk::SmartPointer<Self>;
  itkNewMacro(Self);
  void DisplayText(const char* t) override { text << t << "\n"; }
  std::ostringstream text;
};


// One message per non-empty line, whitespace collapsed; ITK's multi-line warnings
// ("WARNING: In file, line N / Class (0x...): text") keep only their text line.
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream is(text);
  std::string line;
  while (std::getline(is, line)) {
    std::string t;
    bool space = false;
    for (char c : line) {
      if (std::isspace(static_cast<unsigned char>(c))) space = !t.empty();
      else {
        if (space) t += ' ';
        t += c, space = false;
      }
    }
    if (t.empty() || t.rfind("WARNING: In ", 0) == 0 || t.rfind("ERROR: In ", 0) == 0) continue;
    const auto obj = t.find("): ");
    if (t.find(" (0x") != std::string::npos && obj != std::string::npos) t = t.substr(obj + 3);
    if (!t.empty()) out.push_back(t);
  }
  return out;
}

}  // namespace

bool reports_damage(const std::string& message) {
  const std::string m = lower_case(message);
  for (const char* word : {"not read completely", "truncat", "corrupt", "premature", "unexpected end", "short read",
                           "error", "fail", "cannot", "can't", "could not", "unable", "incomplete", "invalid"})
    if (m.find(word) != std::string::npos) return true;
  return false;
}

struct LibraryMessages::State {
  std::unique_lock<std::mutex> lock{read_lock()};
  CollectingWindow::Pointer window = CollectingWindow::New();
  itk::OutputWindow::Pointer previous = itk::OutputWindow::GetInstance();
  std::ostringstream gdcm;
  FILE* err_file = std::tmpfile();
  int saved_fd = -1;
  bool taken = false;

  State() {
    itk::OutputWindow::SetInstance(window);
    itk::Object::GlobalWarningDisplayOn();
    gdcm::Trace::SetStream(gdcm);
    gdcm::Trace::SetWarning(true);
    gdcm::Trace::SetError(true);
    gdcm::Trace::SetDebug(false);
    std::cerr.flush();
    std::fflush(stderr);
    if (err_file) {
      saved_fd = dup(2);
      if (saved_fd >= 0) dup2(fileno(err_file), 2);
    }
  }
  std::string restore() {
    std::cerr.flush();
    std::fflush(stderr);
    if (saved_fd >= 0) {
      dup2(saved_fd, 2);
      close(saved_fd);
      saved_fd = -1;
    }
    std::string err;
    if (err_file) {
      std::rewind(err_file);
      char buf[4096];
      size_t n;
      while ((n = std::fread(buf, 1, sizeof buf, err_file)) > 0 && err.size() < (1 << 20)) err.append(buf, n);
      std::fclose(err_file);
      err_file = nullptr;
    }
    itk::Object::GlobalWarningDisplayOff();
    itk::OutputWindow::SetInstance(previous);
    gdcm::Trace::SetWarning(false);
    gdcm::Trace::SetError(false);
    gdcm::Trace::SetStream(std::cerr);
    taken = true;
    return window->text.str() + gdcm.str() + err;
  }
  ~State() {
    if (!taken) restore();
  }
};

LibraryMessages::LibraryMessages() : state_(std::make_unique<State>()) {}
LibraryMessages::~LibraryMessages() = default;

std::vector<std::string> LibraryMessages::take(const std::string& name) {
  const std::vector<std::string> messages = lines_of(state_->restore());
  std::vector<std::string> notes;
  for (const auto& m : messages) {
    if (reports_damage(m)) throw InputError(name + ": the reader reports damage: " + m);
    notes.push_back("ITK: " + m);
  }
  return notes;
}

}  // namespace mpumesh
