#include "core/log.h"

#include <cstdio>
#include <ctime>
#include <iostream>
#include <sstream>

namespace volts::core {
namespace {
LogLevel g_level = LogLevel::normal;
std::string g_tool = "volts";
thread_local std::string* t_capture = nullptr;  // this thread's LogCapture, if any

void emit(const std::string& line) {
  if (t_capture) *t_capture += line;
  else std::cerr << line;
}
}  // namespace

void set_log_level(LogLevel level) { g_level = level; }
LogLevel log_level() { return g_level; }
void set_log_tool(const std::string& tool) { g_tool = tool; }

void log(const std::string& message) {
  if (g_level >= LogLevel::normal) emit("[" + g_tool + "] " + message + "\n");
}
void log_verbose(const std::string& message) {
  if (g_level >= LogLevel::verbose) emit("[" + g_tool + "] " + message + "\n");
}
void log_warning(const std::string& message) {
  if (g_level > LogLevel::quiet) emit("[" + g_tool + "] warning: " + message + "\n");
}

LogCapture::LogCapture() : outer_(t_capture) { t_capture = &lines_; }
LogCapture::~LogCapture() {
  if (!released_) log_lines(release());
}
std::string LogCapture::release() {
  if (t_capture == &lines_) t_capture = outer_;
  released_ = true;
  return std::move(lines_);
}
void log_lines(const std::string& lines) { emit(lines); }

double process_cpu_seconds() {
  timespec t{};
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) != 0) return 0;
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

LogSection::LogSection(std::string name) : name_(std::move(name)), cpu_start_(process_cpu_seconds()) { log("== " + name_); }
LogSection::~LogSection() {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f s (CPU %.3f s)", watch_.seconds(), process_cpu_seconds() - cpu_start_);
  log("== " + name_ + ": " + buf);
}

Progress::Progress(std::string what, std::size_t total) : what_(std::move(what)), total_(total) {}
void Progress::step(std::size_t done) {
  const double t = watch_.seconds();
  if (t - last_ < 2.0 || total_ == 0) return;
  last_ = t;
  std::ostringstream s;
  s << what_ << ": " << done << "/" << total_ << " (" << (100 * done / total_) << " %)";
  log(s.str());
}
void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (watch_.seconds() >= 2.0) log(what_ + ": done");
}

}  // namespace volts::core
