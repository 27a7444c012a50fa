#include "tread_wear/io/csv.h"

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace tread_wear {
namespace csv {
namespace {

std::string trim(const std::string& s) {
  const std::size_t begin = s.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  return s.substr(begin, s.find_last_not_of(" \t") - begin + 1);
}

}  // namespace

bool splitLine(const std::string& raw, std::vector<std::string>* cells, std::string* error) {
  cells->clear();
  const std::string line = (!raw.empty() && raw.back() == '\r') ? raw.substr(0, raw.size() - 1) : raw;
  for (std::size_t k = 0; k < line.size(); ++k) {
    const unsigned char c = static_cast<unsigned char>(line[k]);
    if ((c < 0x20 && c != '\t') || c == 0x7f) {  // a binary or corrupt file: say so instead of echoing its bytes
      char code[8];
      std::snprintf(code, sizeof(code), "0x%02x", c);
      if (error) *error = std::string("control character ") + code + " at byte " + std::to_string(k + 1) +
                          ": not a text CSV file (binary or corrupt?)";
      return false;
    }
  }
  std::size_t i = 0;
  while (true) {
    std::size_t start = i;
    while (start < line.size() && (line[start] == ' ' || line[start] == '\t')) ++start;
    if (start < line.size() && line[start] == '"') {
      std::string cell;
      std::size_t j = start + 1;
      bool closed = false;
      while (j < line.size()) {
        if (line[j] == '"') {
          if (j + 1 < line.size() && line[j + 1] == '"') {
            cell += '"';
            j += 2;
            continue;
          }
          closed = true;
          ++j;
          break;
        }
        cell += line[j++];
      }
      if (!closed) {
        if (error) *error = "unterminated quote in cell " + std::to_string(cells->size() + 1);
        return false;
      }
      while (j < line.size() && (line[j] == ' ' || line[j] == '\t')) ++j;
      if (j < line.size() && line[j] != ',') {
        if (error) *error = "text after the closing quote in cell " + std::to_string(cells->size() + 1);
        return false;
      }
      cells->push_back(cell);
      if (j >= line.size()) return true;
      i = j + 1;
    } else {
      const std::size_t comma = line.find(',', i);
      cells->push_back(trim(line.substr(i, comma == std::string::npos ? std::string::npos : comma - i)));
      if (comma == std::string::npos) return true;
      i = comma + 1;
    }
  }
}

bool parseFiniteDouble(const std::string& cell, double* value) {
  if (cell.empty()) return false;
  // strtod also accepts "nan", "inf" and hex floats; a run table holds plain decimals only.
  for (char c : cell) {
    if (!((c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E')) return false;
  }
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  if (end != cell.c_str() + cell.size() || errno == ERANGE || !std::isfinite(v)) return false;
  *value = v;
  return true;
}

bool parseInt(const std::string& cell, int* value) {
  if (cell.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(cell.c_str(), &end, 10);
  if (end != cell.c_str() + cell.size() || errno == ERANGE || v < INT_MIN || v > INT_MAX) return false;
  *value = static_cast<int>(v);
  return true;
}

std::string quote(const std::string& text) {
  const bool needs = text.find_first_of(",\"") != std::string::npos ||
                     (!text.empty() && (text.front() == ' ' || text.back() == ' ' || text.front() == '\t' ||
                                        text.back() == '\t'));
  if (!needs) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string formatDouble(double value) {
  char buffer[32];
  for (int precision = 15; precision <= 17; ++precision) {
    std::snprintf(buffer, sizeof buffer, "%.*g", precision, value);
    if (std::strtod(buffer, nullptr) == value) break;
  }
  return buffer;
}

int findColumn(const std::vector<std::string>& header, const std::string& name) {
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return static_cast<int>(i);
  return -1;
}

}  // namespace csv
}  // namespace tread_wear
