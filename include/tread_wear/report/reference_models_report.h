#pragma once
/// @file reference_models_report.h
/// Table 5 of the paper as tread_wear_reference_models writes it: DIR/table5.json (machine-readable) and
/// DIR/table5.md (the table for a person, also printed), both from the same rows.

#include <string>
#include <vector>

namespace tread_wear {

/// One row of Table 5: a model's parameters and errors from one source. NaN: not available (null in JSON, "-" in
/// Markdown).
struct Table5Row {
  std::string model;   ///< Opt (the brush model), M_P, M_EP, M_PT, M_EPT (Eq 26)
  std::string source;  ///< "paper Table 5", "paper parameters on these runs" or "fitted here"
  double w1 = 0.0;     ///< [-]
  double w2 = 0.0;     ///< [-]
  double w3 = 0.0;     ///< Opt: [1e-2 mg/(s mm^2)], reference models: [1e-2 mg/s]
  double w4 = 0.0;     ///< as w3
  double rmse = 0.0;   ///< wear rate RMSE [1e-2 g/km]
  double rmser = 0.0;  ///< RMSER of the wear rate [-]
  double eri = 0.0;    ///< RMSER / RMSER(Opt) of the same row kind [-]
  double cv_rmser = 0.0;  ///< leave-one-condition-out RMSER [-]
  double cv_eri = 0.0;    ///< leave-one-condition-out ERI [-]
};

/// Table 5 of one run table.
struct Table5 {
  std::string orientation;              ///< slip angle orientation of the Opt fit (literal, flipped)
  bool temperatures_available = false;  ///< every run has a tread temperature: M_PT and M_EPT are fitted
  std::vector<Table5Row> rows;          ///< in table order
};

/// table5.json: orientation, side_force_input, temperatures_available and rows {model, source, w1, w2, w3_1e-2,
/// w4_1e-2, rmse_1e-2_g_per_km, rmser, eri, cv_rmser, cv_eri}; indented, ends with a newline.
std::string table5Json(const Table5& table);

/// table5.md: the Markdown table and its notes (units, ERI, LOO, why temperature models are missing).
std::string table5Markdown(const Table5& table);

}  // namespace tread_wear
