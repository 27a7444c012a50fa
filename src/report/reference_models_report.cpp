#include "tread_wear/report/reference_models_report.h"

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

namespace tread_wear {

std::string table5Json(const Table5& table) {
  using nlohmann::json;
  auto num = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  json j;
  j["orientation"] = table.orientation;
  j["side_force_input"] = "measured mean side force per run (one Eq 23 bin; the paper bins recorded samples)";
  j["temperatures_available"] = table.temperatures_available;
  for (const Table5Row& r : table.rows)
    j["rows"].push_back({{"model", r.model}, {"source", r.source}, {"w1", num(r.w1)}, {"w2", num(r.w2)},
                         {"w3_1e-2", num(r.w3)}, {"w4_1e-2", num(r.w4)}, {"rmse_1e-2_g_per_km", num(r.rmse)},
                         {"rmser", num(r.rmser)}, {"eri", num(r.eri)}, {"cv_rmser", num(r.cv_rmser)},
                         {"cv_eri", num(r.cv_eri)}});
  return j.dump(2) + "\n";
}

std::string table5Markdown(const Table5& table) {
  auto f = [](double v, const char* fmt) {
    if (!std::isfinite(v)) return std::string("-");
    char b[64];
    std::snprintf(b, sizeof b, fmt, v);
    return std::string(b);
  };
  std::string md =
      "| model | source | w1 | w2 | w3 [1e-2 mg/s] | w4 [1e-2 mg/s] | RMSE [1e-2 g/km] | RMSER | ERI | "
      "LOO RMSER | LOO ERI |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Table5Row& r : table.rows) {
    char line[512];
    std::snprintf(line, sizeof line, "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", r.model.c_str(),
                  r.source.c_str(), f(r.w1, "%.3f").c_str(), f(r.w2, "%.3f").c_str(), f(r.w3, "%.4g").c_str(),
                  f(r.w4, "%.4g").c_str(), f(r.rmse, "%.2f").c_str(), f(100 * r.rmser, "%.2f%%").c_str(),
                  f(r.eri, "%.2f").c_str(), f(100 * r.cv_rmser, "%.2f%%").c_str(), f(r.cv_eri, "%.2f").c_str());
    md += line;
  }
  if (!table.temperatures_available)
    md += "\nOpt_T, M_PT and M_EPT are not fitted: the run table has no tread temperatures (Table 3 has none and "
          "the paper's Fig 12 temperatures are not tabulated).\n";
  md += "\nERI = RMSER / RMSER(Opt) of the same row kind (paper rows: the paper's ERI; its RMSER column is ERI x "
        "8.32%). LOO = leave-one-condition-out. Opt w3, w4 are per contact area (mg/(s mm^2)); the reference "
        "models' are global (mg/s). Reference models use the measured mean side force per run.\n";
  return md;
}

}  // namespace tread_wear
