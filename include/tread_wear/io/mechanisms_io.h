#pragma once
/// @file mechanisms_io.h
/// Reads a file of user-defined candidate mechanisms for the mismatch diagnosis (docs/diagnosis.md, "User-defined
/// mechanisms") into plain records, each field with its 1-based line in the file. This module checks the document's
/// shape: known keys only, required fields present, identifiers, one-line statements, numbers finite, bounds
/// ordered and the no-effect and start values inside them. What needs the diagnosis (output names, collisions with
/// the built-in library, the expression and its variables) is checked where the mechanisms are compiled
/// (diagnosis/user_mechanisms.h), with the same lines.
///
///   mechanisms:
///     - name: humidity_wear              # identifier
///       statement: one line              # the physical statement
///       physical: true                   # optional (false: an instrument effect, as sensor_gain)
///       parameters:                      # the first is the size of the effect
///         - {name: k_h_per_percent, unit: 1/%, lower: -0.05, upper: 0.05, no_effect: 0, initial: 0}
///       affects: [wear]                  # outputs the expression modifies
///       covariates: [humidity_percent]   # optional: recorded run-table columns the expression reads
///       expression: output * exp(k_h_per_percent * (humidity_percent - 50))
///       test_magnitudes: [-0.005, -0.015]  # optional: the first parameter's small and large effect for the
///                                        # concealed-effect generator (the last is its default) and the harness

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace tread_wear {

/// A fitted parameter of a user mechanism.
struct MechanismParameterSpec {
  std::string name;
  std::string unit;                 ///< as written, e.g. "1/%" or "-"
  double lower = 0.0, upper = 0.0;  ///< bounds [unit], lower < upper
  double no_effect = 0.0;  ///< value at which the mechanism leaves the model unchanged [unit], in [lower, upper]
  double initial = std::numeric_limits<double>::quiet_NaN();  ///< start of a fit [unit]; NaN = no_effect
  int line = 0;                                               ///< of the parameter's entry
};

/// One mechanism as written in the file.
struct MechanismSpec {
  std::string name;
  std::string statement;
  bool physical = true;
  std::vector<MechanismParameterSpec> parameters;
  std::vector<std::string> affects;  ///< output names as written
  std::vector<int> affects_lines;
  std::vector<std::string> covariates;  ///< recorded columns the expression may read
  std::vector<int> covariates_lines;
  std::string expression;
  /// values of the first parameter for generated cases (1 or 2, inside its bounds, not its no-effect value)
  std::vector<double> test_magnitudes;
  int line = 0;  ///< of the entry
  int name_line = 0;
  int expression_line = 0;
};

struct MechanismFile {
  std::string path;
  std::vector<MechanismSpec> mechanisms;
};

/// "FILE:LINE: what is wrong" (LINE omitted for a file that cannot be read).
class MechanismFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads and checks a mechanisms file. @throw MechanismFileError
MechanismFile readMechanismFile(const std::string& path);
/// The same from the document's text; `source` names it in the errors. @throw MechanismFileError
MechanismFile parseMechanismFile(const std::string& text, const std::string& source);

}  // namespace tread_wear
