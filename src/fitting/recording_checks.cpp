#include "tread_wear/fitting/recording_checks.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "tread_wear/model/wear_model.h"

namespace tread_wear {

std::vector<std::string> screenSideForceSigns(const TireParams& params, TurnSlipOrientation orientation,
                                              RunTable* table) {
  const BrushWearModel model(params, presetOptions(Preset::kFast, orientation));
  struct Opposite {
    std::size_t run;
    double predicted_n;
  };
  std::vector<Opposite> opposite;
  int checked = 0;
  for (std::size_t i = 0; i < table->runs.size(); ++i) {
    const RunRecord& run = table->runs[i];
    // Zero has no sign (the tools reject it as a measurement themselves); invalid conditions are reported there too.
    if (!std::isfinite(run.measured_side_force_n) || run.measured_side_force_n == 0.0 || !run.op.validate(nullptr))
      continue;
    WearResult predicted;
    double fy_n = 0.0;
    if (run.drive_points.empty()) {
      model.evaluate(run.op, &predicted);
      fy_n = predicted.fy_n;
    } else {
      // A drive segment's mean side force over its points (signed slips are in the points, not in the means).
      for (const WeightedOperatingPoint& p : run.drive_points) {
        model.evaluate(p.op, &predicted);
        fy_n += predicted.fy_n * p.time_s / run.drive_time_s;
      }
    }
    if (!(std::fabs(fy_n) >= kSideForceSignCheckShareOfLoad * run.op.load_n)) continue;
    ++checked;
    if ((run.measured_side_force_n > 0.0) != (fy_n > 0.0)) opposite.push_back({i, fy_n});
  }
  auto describe = [&](const Opposite& o) {
    std::ostringstream s;
    s.precision(4);
    s << "run " << o.run + 1 << " (condition '" << table->runs[o.run].condition_id << "'): measured side force "
      << table->runs[o.run].measured_side_force_n << " N has the opposite sign of the model's " << o.predicted_n
      << " N";
    return s.str();
  };
  if (2 * static_cast<int>(opposite.size()) > checked)
    throw RunTableError("measured side forces have the opposite sign of the model's on " +
                        std::to_string(opposite.size()) + " of " + std::to_string(checked) + " runs (first: " +
                        describe(opposite.front()) + "). The recordings are probably in another axis convention: " +
                        "tread_wear expects ISO 8855 (Fy > 0 for a negative slip angle; docs/run_table.md)");
  std::vector<std::string> warnings;
  for (const Opposite& o : opposite) {
    warnings.push_back(describe(o) + "; left out of the fit");
    table->runs[o.run].measured_side_force_n = std::numeric_limits<double>::quiet_NaN();
  }
  return warnings;
}

}  // namespace tread_wear
