#include "tread_wear/diagnosis/data.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

#include "tread_wear/model/units.h"

namespace tread_wear {
namespace diagnosis {
namespace {

/// Columns that restate a measurement: a trend of the residual over them says nothing about the model.
const std::set<std::string> kMeasurementColumns = {"mass_loss_kg"};

int findColumn(const std::vector<std::string>& names, const std::string& name) {
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

bool varies(const std::vector<double>& v) {
  double lo = INFINITY, hi = -INFINITY;
  for (double x : v) {
    if (!std::isfinite(x)) continue;
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  return hi > lo;
}

void addNumeric(DiagnosisData* d, const std::string& name, const std::string& kind, std::vector<double> values) {
  if (!varies(values)) return;
  d->covariates.push_back({name, kind, false, std::move(values), {}});
}

void addCategorical(DiagnosisData* d, const std::string& name, const std::string& kind,
                    const std::vector<std::string>& labels) {
  Covariate c{name, kind, true, {}, {}};
  std::map<std::string, int> index;
  for (const std::string& l : labels) {
    auto it = index.find(l);
    if (it == index.end()) {
      it = index.emplace(l, static_cast<int>(c.levels.size())).first;
      c.levels.push_back(l);
    }
    c.values.push_back(it->second);
  }
  // One level says nothing; one level per run (labels) cannot be compared.
  if (c.levels.size() < 2 || c.levels.size() * 2 > labels.size()) return;
  d->covariates.push_back(std::move(c));
}

}  // namespace

const char* outputName(Output output) { return output == Output::kSideForce ? "side_force" : "wear"; }

namespace {

/// Run i of the table as a diagnosis record, its sliding distance (Eq 1, over its points for a drive segment) and
/// what it tells about the data (measured outputs, turn slip, load spread). @throw DiagnosisError for a run that
/// does not roll, a zero side force or a wear rate <= 0.
DiagnosisRun diagnosisRun(const RunTable& table, int i, DiagnosisData* d) {
  const RunRecord& rec = table.runs[i];
  const int col_distance = findColumn(table.covariate_names, "distance_m");
  const int col_duration = findColumn(table.covariate_names, "duration_s");
  DiagnosisRun run;
  run.op = rec.op;
  run.op.tread_temperature_c = std::numeric_limits<double>::quiet_NaN();
  run.tread_temperature_c = rec.op.tread_temperature_c;
  run.load_std_n = rec.load_std_n;
  run.measured[0] = rec.measured_side_force_n;
  run.measured[1] = rec.measured_wear_rate_kg_per_m;
  run.condition = rec.condition_id;
  run.cycle = rec.cycle_id;
  run.run_order = rec.run_order;
  run.drive_points = rec.drive_points;
  run.drive_time_s = rec.drive_time_s;
  run.drive_distance_m = rec.drive_distance_m;
  const std::string where = "run " + std::to_string(i + 1) + " (condition '" + rec.condition_id + "')";
  if (!(rec.op.speed_mps > 0.0))
    throw DiagnosisError(where + ": speed_mps = " + std::to_string(rec.op.speed_mps) +
                         " must be > 0 for the diagnosis (a run must roll)");
  if (std::isfinite(run.measured[0]) && run.measured[0] == 0.0)
    throw DiagnosisError(where + ": side_force_n = 0; relative errors (Eq 24) need a non-zero measurement");
  if (std::isfinite(run.measured[1]) && !(run.measured[1] > 0.0))
    throw DiagnosisError(where + ": measured wear rate must be > 0, got " + std::to_string(run.measured[1]));
  for (int o = 0; o < kNumOutputs; ++o)
    if (std::isfinite(run.measured[o])) ++d->measured_count[o];
  double distance = col_distance >= 0 ? rec.covariates[col_distance] : std::numeric_limits<double>::quiet_NaN();
  if (!std::isfinite(distance) && col_duration >= 0) distance = rec.op.speed_mps * rec.covariates[col_duration];
  run.sliding_distance_m = distance * std::abs(std::sin(rec.op.slip_angle_rad));
  if (run.isDrive()) {
    // Eq 1 summed over the drive's points: the mean slip angle of a drive says little (left and right turns).
    run.sliding_distance_m = 0.0;
    for (const WeightedOperatingPoint& p : run.drive_points) {
      run.sliding_distance_m += p.distance_m * std::abs(std::sin(p.op.slip_angle_rad));
      if (p.op.path_curvature_per_m != 0.0) d->has_turn_slip = true;
    }
    if (!(run.drive_distance_m > 0.0) || !(run.drive_time_s > 0.0))
      throw DiagnosisError(where + ": a drive segment without integrated distance or time");
  }
  // A drive segment's load spread is resolved in its points: Eq 23 over it would count it twice.
  if (std::isfinite(run.load_std_n) && run.load_std_n > 0.0 && !run.isDrive()) d->has_load_std = true;
  if (rec.op.path_curvature_per_m != 0.0) d->has_turn_slip = true;
  return run;
}

/// Cumulative sliding distance per cycle (surface renewed between cycles), in run order; sets has_sequence (NaN
/// everywhere without a complete sequence).
void cumulativeSliding(DiagnosisData* d) {
  const bool orders_known =
      std::all_of(d->runs.begin(), d->runs.end(), [](const DiagnosisRun& r) { return r.run_order >= 0; });
  const bool any_order =
      std::any_of(d->runs.begin(), d->runs.end(), [](const DiagnosisRun& r) { return r.run_order >= 0; });
  const bool any_cycle =
      std::any_of(d->runs.begin(), d->runs.end(), [](const DiagnosisRun& r) { return r.cycle >= 0; });
  bool all_sequence = !d->runs.empty();
  std::vector<int> order(d->runs.size());
  std::iota(order.begin(), order.end(), 0);
  if (orders_known)
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return d->runs[a].run_order < d->runs[b].run_order; });
  std::map<int, double> surface_distance;
  for (int i : order) {
    DiagnosisRun& r = d->runs[i];
    if (!std::isfinite(r.sliding_distance_m)) {
      all_sequence = false;
      continue;
    }
    double& used = surface_distance[r.cycle];
    r.cumulative_sliding_m = used + 0.5 * r.sliding_distance_m;
    used += r.sliding_distance_m;
  }
  // A sequence needs an order: known run orders, or cycles in row order.
  all_sequence = all_sequence && (any_order || any_cycle);
  if (!all_sequence)
    for (DiagnosisRun& r : d->runs) r.cumulative_sliding_m = std::numeric_limits<double>::quiet_NaN();
  d->has_sequence = all_sequence;
}

/// The covariates of the locating tests: the operating region, the sequence and the table's recorded columns.
void addCovariates(const RunTable& table, DiagnosisData* d) {
  const bool orders_known =
      std::all_of(d->runs.begin(), d->runs.end(), [](const DiagnosisRun& r) { return r.run_order >= 0; });
  const bool any_order =
      std::any_of(d->runs.begin(), d->runs.end(), [](const DiagnosisRun& r) { return r.run_order >= 0; });
  auto column = [&](auto f) {
    std::vector<double> v;
    for (const DiagnosisRun& r : d->runs) v.push_back(f(r));
    return v;
  };
  addNumeric(d, "load_n", "operating region", column([](const DiagnosisRun& r) { return r.op.load_n; }));
  addNumeric(d, "abs_slip_angle_deg", "operating region",
             column([](const DiagnosisRun& r) { return std::abs(r.op.slip_angle_rad) * 180.0 / M_PI; }));
  addNumeric(d, "speed_mps", "operating region", column([](const DiagnosisRun& r) { return r.op.speed_mps; }));
  addNumeric(d, "slip_ratio", "operating region", column([](const DiagnosisRun& r) { return r.op.slip_ratio; }));
  addNumeric(d, "path_curvature_per_m", "operating region",
             column([](const DiagnosisRun& r) { return r.op.path_curvature_per_m; }));
  if (d->has_temperature)
    addNumeric(d, "tread_temperature_c", "operating region",
               column([](const DiagnosisRun& r) { return r.tread_temperature_c; }));
  if (d->has_load_std)
    addNumeric(d, "load_std_n", "operating region",
               column([](const DiagnosisRun& r) { return std::isfinite(r.load_std_n) ? r.load_std_n : 0.0; }));
  if (any_order && orders_known)
    addNumeric(d, "run_order", "sequence", column([](const DiagnosisRun& r) { return double(r.run_order); }));
  if (d->has_sequence)
    addNumeric(d, "cumulative_sliding_m", "sequence",
               column([](const DiagnosisRun& r) { return r.cumulative_sliding_m; }));
  std::vector<std::string> cycles, conditions;
  for (const DiagnosisRun& r : d->runs) {
    cycles.push_back(r.cycle < 0 ? "unknown" : std::to_string(r.cycle));
    conditions.push_back(r.condition);
  }
  addCategorical(d, "cycle_id", "sequence", cycles);
  addCategorical(d, "condition_id", "operating region", conditions);
  for (std::size_t c = 0; c < table.covariate_names.size(); ++c) {
    const std::string& name = table.covariate_names[c];
    if (kMeasurementColumns.count(name)) continue;
    std::vector<double> v;
    bool complete = true;
    for (const RunRecord& rec : table.runs) {
      v.push_back(rec.covariates[c]);
      complete = complete && std::isfinite(rec.covariates[c]);
    }
    if (complete) addNumeric(d, name, "recorded", std::move(v));
  }
  for (std::size_t c = 0; c < table.text_covariate_names.size(); ++c) {
    std::vector<std::string> labels;
    for (const RunRecord& rec : table.runs) labels.push_back(rec.text_covariates[c]);
    addCategorical(d, table.text_covariate_names[c], "recorded", labels);
  }
}

/// Cross-validation groups: whole cycles when there are enough of them, else periods of drive segments, else
/// conditions, else runs.
void crossValidationGroups(DiagnosisData* d) {
  const bool orders_known =
      std::all_of(d->runs.begin(), d->runs.end(), [](const DiagnosisRun& r) { return r.run_order >= 0; });
  std::set<int> cycle_set;
  std::set<std::string> condition_set;
  for (const DiagnosisRun& r : d->runs) {
    if (r.cycle >= 0) cycle_set.insert(r.cycle);
    condition_set.insert(r.condition);
  }
  const bool all_cycles =
      std::all_of(d->runs.begin(), d->runs.end(), [](const DiagnosisRun& r) { return r.cycle >= 0; });
  // Drive segments of several wheels between the same checkpoints share a period (their run order): holding out a
  // period holds out what the other wheels saw then, and costs one fold per period, not per wheel and segment.
  std::set<int> periods;
  for (const DiagnosisRun& r : d->runs) periods.insert(r.run_order);
  const bool by_period = !all_cycles && periods.size() >= 4 && orders_known &&
                         std::all_of(d->runs.begin(), d->runs.end(), [](const DiagnosisRun& r) { return r.isDrive(); });
  for (const DiagnosisRun& r : d->runs) {
    if (all_cycles && cycle_set.size() >= 4)
      d->cv_groups.push_back("cycle " + std::to_string(r.cycle));
    else if (by_period)
      d->cv_groups.push_back("period " + std::to_string(r.run_order));
    else if (condition_set.size() >= 4)
      d->cv_groups.push_back(r.condition);
    else
      d->cv_groups.push_back(std::to_string(d->cv_groups.size()));
  }
  d->cv_scheme = (all_cycles && cycle_set.size() >= 4) ? "leave one cycle out"
                 : by_period                           ? "leave one period out"
                 : condition_set.size() >= 4           ? "leave one condition out"
                                                       : "leave one run out";
}

/// The categorical covariate `name` of the data. @throw DiagnosisError "<purpose>: 'name' is not a categorical
/// covariate of the recordings (those ...)" naming the ones there are.
const Covariate& categoricalCovariate(const DiagnosisData& data, const std::string& name, const std::string& purpose) {
  std::string known;
  for (const Covariate& c : data.covariates) {
    if (!c.categorical) continue;
    if (c.name == name) return c;
    known += (known.empty() ? "" : ", ") + c.name;
  }
  throw DiagnosisError(purpose + ": '" + name + "' is not a categorical covariate of the recordings (those with 2 to " +
                       "n/2 levels: " + (known.empty() ? "none" : known) + ")");
}

}  // namespace

DiagnosisData buildDiagnosisData(const RunTable& table) {
  DiagnosisData d;
  const int n = static_cast<int>(table.runs.size());
  int with_measurement = 0;
  bool all_temperature = n > 0;
  for (int i = 0; i < n; ++i) {
    DiagnosisRun run = diagnosisRun(table, i, &d);
    if (std::isfinite(run.measured[0]) || std::isfinite(run.measured[1])) ++with_measurement;
    all_temperature = all_temperature && std::isfinite(run.tread_temperature_c);
    d.runs.push_back(std::move(run));
  }
  if (with_measurement < 4)
    throw DiagnosisError("the recordings have " + std::to_string(with_measurement) +
                         " runs with a measured side force or wear rate; the diagnosis needs at least 4");
  cumulativeSliding(&d);
  d.has_temperature = all_temperature;
  addCovariates(table, &d);
  crossValidationGroups(&d);
  return d;
}

void holdOutGroups(DiagnosisData* data, const std::string& covariate) {
  const Covariate& c = categoricalCovariate(*data, covariate, "cross-validation groups");
  if (c.levels.size() < 2)
    throw DiagnosisError("cross-validation groups '" + covariate + "': one level, nothing to hold out");
  data->cv_groups.clear();
  for (double v : c.values) data->cv_groups.push_back(covariate + " " + c.levels[static_cast<std::size_t>(v)]);
  data->cv_scheme = "leave one " + covariate + " out";
}

void calibrateHeldOutGroupsOn(DiagnosisData* data, const std::string& covariate, const std::string& level) {
  const Covariate& c = categoricalCovariate(*data, covariate, "cross-validation calibration");
  const auto at = std::find(c.levels.begin(), c.levels.end(), level);
  if (at == c.levels.end())
    throw DiagnosisError("cross-validation calibration: '" + covariate + "' has no level '" + level + "'");
  const double index = static_cast<double>(at - c.levels.begin());
  data->cv_calibration_run.assign(data->runs.size(), 0);
  std::map<std::string, std::pair<int, int>> calibrating_and_predicted;
  for (std::size_t i = 0; i < data->runs.size(); ++i) {
    data->cv_calibration_run[i] = c.values[i] == index ? 1 : 0;
    auto& counts = calibrating_and_predicted[data->cv_groups[i]];
    ++(data->cv_calibration_run[i] ? counts.first : counts.second);
  }
  for (const auto& [group, counts] : calibrating_and_predicted)
    if (counts.first == 0 || counts.second == 0)
      throw DiagnosisError("cross-validation calibration: group '" + group + "' has " + std::to_string(counts.first) +
                           " runs at " + covariate + " '" + level + "' and " + std::to_string(counts.second) +
                           " others; it needs both");
  data->cv_scheme += ", each held-out group's wear scale calibrated on its " + covariate + " " + level;
}

}  // namespace diagnosis
}  // namespace tread_wear
