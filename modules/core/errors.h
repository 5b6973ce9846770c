// volts::core — typed errors shared by every module and executable.
//
// Every failure a user can meet is one of these. Executables catch them at the top, print
// `volts-STAGE: error: <message>` and exit with exit_code(); see docs/errors.md.
#pragma once

#include <stdexcept>
#include <string>

namespace volts::core {

/// Exit codes of every volts executable (documented in docs/errors.md).
enum class ExitCode : int {
  ok = 0,
  internal = 1,       ///< a bug: an unexpected exception
  usage = 2,          ///< wrong command line
  config = 3,         ///< config file: unknown key, wrong type, out of range
  invalid_input = 4,  ///< an input file is unreadable, malformed or not a valid surface
  topology = 5,       ///< valid input the algorithm cannot handle (e.g. not box-like)
  io = 6,             ///< an output could not be written
  numerical = 7,      ///< a solver failed or a result is invalid
  not_certified = 8,  ///< volts-check: some element is invalid or undecided (not an error: a verdict)
};

/// Base of all volts errors.
class Error : public std::runtime_error {
 public:
  Error(const std::string& what, ExitCode code) : std::runtime_error(what), code_(code) {}
  ExitCode code() const { return code_; }
  int exit_code() const { return static_cast<int>(code_); }

 private:
  ExitCode code_;
};

/// Bad command line.
struct UsageError : Error {
  explicit UsageError(const std::string& w) : Error(w, ExitCode::usage) {}
};
/// Bad configuration: unknown key, wrong type, out-of-range value. Message names the key path.
struct ConfigError : Error {
  explicit ConfigError(const std::string& w) : Error(w, ExitCode::config) {}
};
/// An input file is missing, malformed, truncated, of a wrong version, or not a valid closed surface.
/// Message names the file, the problem and where.
struct InvalidInputError : Error {
  explicit InvalidInputError(const std::string& w) : Error(w, ExitCode::invalid_input) {}
};
/// The input is valid but its topology is one the algorithm cannot (yet) handle.
struct TopologyError : Error {
  explicit TopologyError(const std::string& w) : Error(w, ExitCode::topology) {}
};
/// An output file could not be written.
struct IoError : Error {
  explicit IoError(const std::string& w) : Error(w, ExitCode::io) {}
};
/// A numerical method failed (solver did not converge, singular system, invalid result).
struct NumericalError : Error {
  explicit NumericalError(const std::string& w) : Error(w, ExitCode::numerical) {}
};

}  // namespace volts::core
