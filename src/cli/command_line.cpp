#include "tread_wear/cli/command_line.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <sstream>

#include "tread_wear/io/csv.h"

namespace tread_wear {

bool CommandLine::parse(int argc, const char* const argv[], const std::vector<std::string>& value_options,
                        const std::vector<std::string>& switches, std::string* error, std::size_t max_positional) {
  auto known = [](const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
  };
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool is_option = arg.size() > 2 && arg.compare(0, 2, "--") == 0;
    const std::string name = is_option ? arg.substr(2) : "";
    if (arg == "-h" || arg == "--help") {
      help_ = true;
    } else if (!is_option) {
      if (positional_.size() == max_positional) return (*error = "unexpected argument '" + arg + "'", false);
      positional_.push_back(arg);
    } else if (known(switches, name)) {
      if (!switches_.insert(name).second) return (*error = "option '" + arg + "' given twice", false);
    } else if (known(value_options, name)) {
      if (i + 1 >= argc) return (*error = "option '" + arg + "' needs a value", false);
      if (!values_.emplace(name, argv[++i]).second) return (*error = "option '" + arg + "' given twice", false);
    } else {
      return (*error = "unknown option '" + arg + "'", false);
    }
  }
  return true;
}

std::string CommandLine::get(const std::string& name, const std::string& fallback) const {
  const auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

bool CommandLine::number(const std::string& name, double* value, std::string* error) const {
  if (!has(name) || csv::parseFiniteDouble(get(name), value)) return true;
  *error = "--" + name + " must be a number, not '" + get(name) + "'";
  return false;
}

bool CommandLine::integer(const std::string& name, int* value, std::string* error) const {
  if (!has(name) || csv::parseInt(get(name), value)) return true;
  *error = "--" + name + " must be an integer, not '" + get(name) + "'";
  return false;
}

bool parseGridSize(const std::string& text, int* n_x_steps, int* n_strips) {
  const std::size_t separator = text.find_first_of("x,");
  return separator != std::string::npos && csv::parseInt(text.substr(0, separator), n_x_steps) &&
         csv::parseInt(text.substr(separator + 1), n_strips);
}

std::vector<std::string> splitList(const std::string& text, char separator) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  for (std::string item; std::getline(stream, item, separator);)
    if (!item.empty()) items.push_back(item);
  return items;
}

std::string formatted(const char* format, ...) {
  std::va_list args, size_args;
  va_start(args, format);
  va_copy(size_args, args);
  const int size = std::vsnprintf(nullptr, 0, format, size_args);
  va_end(size_args);
  std::string text(size > 0 ? static_cast<std::size_t>(size) : 0, '\0');
  if (size > 0) std::vsnprintf(text.data(), text.size() + 1, format, args);
  va_end(args);
  return text;
}

int usageError(std::ostream& err, const std::string& prefix, const std::string& message, const std::string& usage) {
  if (!message.empty()) err << prefix << ": " << message << "\n";
  err << usage;
  return kExitUsage;
}

}  // namespace tread_wear
