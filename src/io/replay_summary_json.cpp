#include "tread_wear/io/replay_summary_json.h"

#include <nlohmann/json.hpp>

namespace tread_wear {

namespace {

/// The summary without what only the tool knows (ReplayRun).
nlohmann::json replaySummaryToJson(const ReplaySummary& summary, const ReplaySettings& settings) {
  using nlohmann::json;
  json j;
  j["format"] = "tread_wear_replay_summary";
  j["version"] = 1;
  j["complete"] = summary.complete;
  if (!summary.complete) j["incomplete_reason"] = summary.incomplete_reason;
  j["preset"] = presetName(settings.model.preset);
  j["update_rate_hz"] = settings.update_rate_hz;
  j["start_s"] = summary.start_s;
  j["end_s"] = summary.end_s;
  j["duration_s"] = summary.end_s - summary.start_s;
  j["steps"] = summary.steps;
  j["wall_time_s"] = summary.wall_time_s;
  j["speedup"] = summary.wall_time_s > 0.0 ? (summary.end_s - summary.start_s) / summary.wall_time_s : 0.0;
  double total_loss = 0.0, mg_per_km_sum = 0.0;
  std::vector<double> phase_loss(summary.phases.size(), 0.0);
  json wheels = json::array();
  for (const WheelSummary& w : summary.wheels) {
    json jw;
    jw["name"] = w.name;
    jw["mass_loss_kg"] = w.mass_loss_kg;
    jw["distance_m"] = w.distance_m;
    jw["mg_per_km"] = w.mg_per_km;
    jw["stick_fraction_mean"] = w.stick_fraction_mean;
    jw["slide_fraction_mean"] = w.slide_fraction_mean;
    jw["friction_work_j"] = w.friction_work_j;
    jw["unaccounted_time_s"] = w.unaccounted_time_s;
    jw["samples_received"] = w.samples_received;
    jw["samples_rejected"] = w.samples_rejected;
    jw["evaluations"] = w.evaluations;
    jw["time_jumps"] = w.time_jumps;
    json jp = json::array();
    for (std::size_t i = 0; i < summary.phases.size(); ++i) {
      jp.push_back({{"name", summary.phases[i].name},
                    {"loss_kg", w.phase_loss_kg[i]},
                    {"share", w.mass_loss_kg > 0.0 ? w.phase_loss_kg[i] / w.mass_loss_kg : 0.0}});
      phase_loss[i] += w.phase_loss_kg[i];
    }
    jw["phases"] = jp;
    wheels.push_back(jw);
    total_loss += w.mass_loss_kg;
    mg_per_km_sum += w.mg_per_km;
  }
  j["wheels"] = wheels;
  j["total_mass_loss_kg"] = total_loss;
  j["mean_mg_per_km"] = summary.wheels.empty() ? 0.0 : mg_per_km_sum / summary.wheels.size();
  json phases = json::array();
  for (std::size_t i = 0; i < summary.phases.size(); ++i) {
    const double d = summary.phase_distance_m[i];
    phases.push_back({{"name", summary.phases[i].name},
                      {"start_s", summary.phases[i].start_s},
                      {"end_s", summary.phases[i].end_s},
                      {"distance_m", d},
                      {"loss_kg", phase_loss[i]},
                      {"share", total_loss > 0.0 ? phase_loss[i] / total_loss : 0.0},
                      {"mean_mg_per_km", d > 0.0 && !summary.wheels.empty()
                                             ? phase_loss[i] / summary.wheels.size() / d * 1e9 : 0.0}});
  }
  j["phases"] = phases;
  j["phase_time_offset_s"] = summary.phase_time_offset_s;
  return j;
}

}  // namespace

std::string replaySummaryDocument(const ReplaySummary& summary, const ReplaySettings& settings, const ReplayRun& run) {
  nlohmann::json j = replaySummaryToJson(summary, settings);
  j["input"] = run.input;
  j["bag_read_s"] = run.bag_read_s;
  j["compute_cpu_s"] = run.compute_cpu_s;
  if (!run.drive_info.empty()) j["drive"] = nlohmann::json::parse(run.drive_info);
  return j.dump(2) + "\n";
}

std::string incompleteReplaySummary(const std::string& input, const std::string& reason) {
  const nlohmann::json j = {{"format", "tread_wear_replay_summary"},
                            {"version", 1},
                            {"complete", false},
                            {"incomplete_reason", reason},
                            {"input", input}};
  return j.dump(2) + "\n";
}

}  // namespace tread_wear
