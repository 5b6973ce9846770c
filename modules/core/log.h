// volts::core — logging: sections, a stopwatch per phase, progress for long loops.
// Logs go to stderr so that stdout stays free for summaries a script may parse.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace volts::core {

/// Verbosity of log output; set once by the executable (library code never reads config).
enum class LogLevel { quiet = 0, normal = 1, verbose = 2 };
void set_log_level(LogLevel level);
LogLevel log_level();

/// Prints "[tool] message" at normal verbosity.
void log(const std::string& message);
/// Prints at verbose level only.
void log_verbose(const std::string& message);
/// Prints "[tool] warning: message" always (unless quiet).
void log_warning(const std::string& message);
/// Sets the tool name shown in front of every line.
void set_log_tool(const std::string& tool);

/// While alive, the log lines of the thread that made it (log, log_verbose, log_warning,
/// sections) are kept instead of printed; release() hands them over, else the destructor prints
/// them. For work run concurrently whose log should read as if it had run in turn
/// (core::parallel_tasks). Captures nest: an inner one's lines go to the outer one.
class LogCapture {
 public:
  LogCapture();
  ~LogCapture();
  LogCapture(const LogCapture&) = delete;
  LogCapture& operator=(const LogCapture&) = delete;
  /// Stops capturing and returns the lines kept, each ending in a newline.
  std::string release();

 private:
  std::string lines_;
  std::string* outer_;  // the capture this one is nested in (its lines go there)
  bool released_ = false;
};

/// Prints lines a LogCapture released, as they are.
void log_lines(const std::string& lines);

/// Wall-clock stopwatch.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

/// CPU time of this process so far, all threads (seconds).
double process_cpu_seconds();

/// A named phase: logs "== name" on entry and "== name: 0.123 s (CPU 0.240 s)" on exit: wall time,
/// and the process' CPU time over all threads (how parallel the phase ran; other threads' work
/// in the same span counts too).
class LogSection {
 public:
  explicit LogSection(std::string name);
  ~LogSection();
  LogSection(const LogSection&) = delete;
  LogSection& operator=(const LogSection&) = delete;
  double seconds() const { return watch_.seconds(); }

 private:
  std::string name_;
  Stopwatch watch_;
  double cpu_start_;
};

/// Progress of a long loop, printed at most every ~2 s and at 100 %.
class Progress {
 public:
  Progress(std::string what, std::size_t total);
  void step(std::size_t done);
  void finish();

 private:
  std::string what_;
  std::size_t total_;
  Stopwatch watch_;
  double last_ = 0.0;
  bool finished_ = false;
};

}  // namespace volts::core
