#pragma once
/// @file csv.h
/// Small CSV helpers shared by the run-table and evaluator readers: one record per line, comma separated,
/// RFC 4180 double quotes ("" inside quotes is a quote; no line breaks inside cells), unquoted cells trimmed.

#include <string>
#include <vector>

namespace tread_wear {
namespace csv {

/// Splits one line into cells (a trailing '\r' is dropped). False with *error set on an unterminated quote,
/// text after a closing quote or a control character other than tab (a binary or corrupt file).
bool splitLine(const std::string& line, std::vector<std::string>* cells, std::string* error);
/// True when the whole cell is a finite decimal number; "nan", "inf", empty and text are rejected.
bool parseFiniteDouble(const std::string& cell, double* value);
/// True when the whole cell is a decimal integer that fits an int.
bool parseInt(const std::string& cell, int* value);
/// The cell as written to CSV: quoted when it contains a comma, a quote or leading/trailing spaces.
std::string quote(const std::string& text);
/// Shortest text that reads back as the same double (round-trip precision).
std::string formatDouble(double value);
/// Index of name in header, or -1.
int findColumn(const std::vector<std::string>& header, const std::string& name);

}  // namespace csv
}  // namespace tread_wear
