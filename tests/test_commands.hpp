#pragma once
// What tests that drive the tools as a user does need: the text of a file
// the tool wrote, a shell command's exit status, a tool started in the
// background (to be interrupted or killed).
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <vector>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>

namespace pd::test_support {

// The hardware threads this process may run on (its CPU affinity, which a
// child inherits): pd-solve caps its threads to them (solver/main.cpp), so
// a test that expects the machine's whole count needs all of them.
inline int processors_allowed() {
  cpu_set_t set;
  CPU_ZERO(&set);
  return sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : 0;
}

// The whole content of a file, byte for byte; "" when it cannot be opened
// (a log the tool never wrote reads as empty).
inline std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The same for a file that must exist: a missing output is a failure, not
// an empty file that could compare equal to another missing one.
inline std::string existing_file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot be opened (not written?)");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Runs `command` through the shell: its exit status, or -1 after a signal.
inline int run_shell(const std::string& command) {
  const int raw = std::system(command.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

// Starts `command` (the executable's path, then its arguments) as a child
// process, its stdout and stderr into `log`; returns its PID (-1 if the fork failed).
inline pid_t start_process(const std::vector<std::string>& command, const std::string& log) {
  const pid_t child = ::fork();
  if (child != 0) return child;
  std::FILE* to = std::freopen(log.c_str(), "w", stdout);
  if (!to || ::dup2(::fileno(stdout), 2) < 0) ::_exit(127);
  std::vector<char*> argv;
  for (const auto& a : command) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  ::execv(argv[0], argv.data());
  ::_exit(127);
}

// Sends `signal` to the child process `pid` and waits for it to end: its exit
// status, or -1 when a signal ended it (the Ctrl-C tests: a run that catches
// SIGINT ends with a status of its own).
inline int interrupt_and_wait(pid_t pid, int signal) {
  ::kill(pid, signal);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The value in column `column` (by its header name) of the last non-empty
// row of a CSV file such as energy.csv.
inline double last_csv_value(const std::string& path, const std::string& column) {
  std::ifstream in(path);
  std::string header, line, last;
  std::getline(in, header);
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  std::stringstream names(header), values(last);
  for (std::string name, value; std::getline(names, name, ',') && std::getline(values, value, ',');)
    if (name == column) return std::stod(value);
  throw std::runtime_error(path + ": no column '" + column + "' in '" + header + "'");
}

// The cells of a row of energy.csv or load_steps.csv as numbers, without the
// column run_id (the run's identifier, a text: docs/formats.md, "Run
// identifier"), where `header`, the file's first line, has one.
inline std::vector<double> csv_numbers(const std::string& header, const std::string& row) {
  std::stringstream names(header), values(row);
  std::vector<double> numbers;
  for (std::string name, value; std::getline(values, value, ',');) {
    if (!std::getline(names, name, ',')) name.clear();
    if (name != "run_id") numbers.push_back(std::stod(value));
  }
  return numbers;
}

}  // namespace pd::test_support
