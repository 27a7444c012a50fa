#pragma once
/// @file user_mechanisms.h
/// User-defined candidate mechanisms (issue 26): a file of mechanisms (io/mechanisms_io.h) compiled with muparser
/// into terms of the library (extensions.h), numbered after the built-in ones, so that the selection, the detection
/// limits, the concealed-effect generator and the report treat them exactly as the built-in terms.
///
/// A mechanism's expression gives the modified value of each output it affects, evaluated once per run and output
/// after the model and its built-in terms:
///   output           the model's value of the output being modified (side force [N] or wear [kg/m])
///   side_force_n, wear_kg_per_m   the model's two outputs of the run
///   operating variables of the run (operatingVariables(): SI, tread temperature in degC; NaN when not recorded)
///   the declared recorded covariates (numeric run-table columns), and the mechanism's parameters.
/// At its parameters' no-effect values the expression must give `output` again (checked on the recordings,
/// checkNoEffect). Errors name the file and the line.

#include <memory>
#include <string>
#include <vector>

#include "tread_wear/diagnosis/data.h"
#include "tread_wear/diagnosis/extensions.h"
#include "tread_wear/io/mechanisms_io.h"

namespace tread_wear {
namespace diagnosis {

/// What a compiled user mechanism carries besides its TermInfo.
struct UserMechanism {
  std::string file;
  int line = 0;  ///< of the mechanism's entry
  int expression_line = 0;
  std::string expression;
  std::vector<std::string> covariates;  ///< declared recorded columns
  /// the first parameter's magnitudes for generated cases (proving/conceal.h: the last is the default;
  /// proving/harness.h: small and large); empty = none
  std::vector<double> test_magnitudes;
  /// operating variables and covariates the expression reads (its applicability needs them on every run)
  std::vector<std::string> data_variables;
  /// "FILE:LINE" of the entry, for messages
  std::string where() const { return file + ":" + std::to_string(line); }
};

/// Names of the per-run operating variables an expression may read.
const std::vector<std::string>& operatingVariables();

/// Compiles a file's mechanisms into library terms (their `term` still unset). @throw MechanismFileError naming
/// the file and line: an output that is not side_force or wear, a name or parameter name that collides with the
/// library, an output or a variable, an expression that does not parse (muparser's message), an unknown variable.
std::vector<TermInfo> compileMechanisms(const MechanismFile& file);

/// Reads a mechanisms file, compiles it and makes its mechanisms library terms while the object lives (the
/// previous user terms come back after); an empty path changes nothing. Not thread-safe: create it before any
/// diagnosis runs. @throw MechanismFileError
class MechanismsInUse {
 public:
  explicit MechanismsInUse(const std::string& path);
  ~MechanismsInUse();
  MechanismsInUse(const MechanismsInUse&) = delete;
  MechanismsInUse& operator=(const MechanismsInUse&) = delete;

 private:
  bool installed_ = false;
  std::vector<TermInfo> previous_;
};

/// Whether the data can show a user mechanism: every run has the variables its expression reads, and an output it
/// affects is measured; otherwise *why_not says what is missing.
bool userMechanismApplicable(const TermInfo& info, const DiagnosisData& data, std::string* why_not);

/// A user term's expression compiled once for one data set, its variables bound by pointer (muparser DefineVar).
/// Not thread-safe; ExtendedModel keeps one per active user term.
class MechanismEvaluator {
 public:
  /// @throw std::invalid_argument when `info` is not a user term or the data lack a variable it reads.
  MechanismEvaluator(const TermInfo& info, const DiagnosisData& data);
  ~MechanismEvaluator();
  MechanismEvaluator(const MechanismEvaluator&) = delete;
  MechanismEvaluator& operator=(const MechanismEvaluator&) = delete;
  /// Replaces run `run`'s outputs (side force [N], wear [kg/m]) by the mechanism's with its parameter values
  /// (in the order of info.parameters). Non-finite results are passed on.
  void apply(int run, const double* parameters, double* side_force_n, double* wear_kg_per_m);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Checks on every run that the user term at its no-effect values is finite and gives the model's outputs `model`
/// back (to 1e-9 relative). @throw DiagnosisError naming the file, the line and the first failing run.
void checkNoEffect(const TermInfo& info, const DiagnosisData& data, const Prediction& model);

}  // namespace diagnosis
}  // namespace tread_wear
