#pragma once
/// @file command_line.h
/// The one command-line parser of the tools (tread_wear_eval, _compare, _calibrate, _diagnose, _drive, ...):
/// "--name value" options, "--name" switches and positional arguments. Every tool rejects unknown options,
/// missing values, repeated options and malformed numbers the same way, with a message naming the argument.

#include <cstddef>
#include <map>
#include <ostream>
#include <set>
#include <string>
#include <vector>

namespace tread_wear {

class CommandLine {
 public:
  /// Names are given without the leading "--". "-h" and "--help" set help(). False with *error naming the
  /// argument for an unknown option, an option without its value, an option given twice, or more than
  /// max_positional positional arguments.
  bool parse(int argc, const char* const argv[], const std::vector<std::string>& value_options,
             const std::vector<std::string>& switches, std::string* error, std::size_t max_positional = 0);

  bool help() const { return help_; }
  /// True when the value option or switch `name` (without "--") was given.
  bool has(const std::string& name) const { return values_.count(name) > 0 || switches_.count(name) > 0; }
  /// The value of option `name`, or `fallback` when it was not given.
  std::string get(const std::string& name, const std::string& fallback = "") const;
  const std::vector<std::string>& positional() const { return positional_; }

  /// Option `name` as a finite number, or an integer: *value is left as it is when the option is absent;
  /// false with "--name must be a number, not 'text'" (or "an integer") when it is present but malformed.
  bool number(const std::string& name, double* value, std::string* error) const;
  bool integer(const std::string& name, int* value, std::string* error) const;

 private:
  std::map<std::string, std::string> values_;
  std::set<std::string> switches_;
  std::vector<std::string> positional_;
  bool help_ = false;
};

/// Exit status of the tools for bad data (a file, parameter or row that cannot be used, a failed fit).
constexpr int kExitData = 1;
/// Exit status of the tools for bad usage (unknown, missing or malformed options).
constexpr int kExitUsage = 2;

/// Writes "<prefix>: <message>" (no such line when message is empty), then the usage text, to err; returns
/// kExitUsage. The one usage-error path of the tools.
int usageError(std::ostream& err, const std::string& prefix, const std::string& message, const std::string& usage);

/// A grid size "NXxNS" or "NX,NS" (x steps, lateral strips) of the tools' --grid options; nothing else.
bool parseGridSize(const std::string& text, int* n_x_steps, int* n_strips);

/// The non-empty items of a separated list ("a,b,,c" -> a, b, c).
std::vector<std::string> splitList(const std::string& text, char separator = ',');

/// printf-style formatting into a string of any length, for report lines whose layout is a printf format.
std::string formatted(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace tread_wear
