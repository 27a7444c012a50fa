// tread_wear_replay: runs a recorded drive through the node's estimator offline (no ROS master), writes the wear
// topics to a bag, a per-wheel summary JSON and a time series for plots. Usage and formats: docs/drive.md.
#include <ros/time.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <exception>
#include <iostream>
#include <fstream>
#include <string>
#include <thread>
#include <utility>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/io/replay_summary_json.h"
#include "tread_wear/ros/bag/bag_io.h"

namespace {

const char* const kUsage =
    "usage: tread_wear_replay IN.bag [--out OUT.bag] [--summary FILE.json] [--timeseries FILE.csv]\n"
    "                         [--preset fast|standard|fine|reference] [--wheels CONFIG.yaml] [--rate-hz HZ]\n"
    "                         [--out-rate-hz HZ] [--timeseries-rate-hz 1] [--threads N] [--max-span-s 21600]\n"
    "                         [--quiet]\n"
    "  --wheels   node configuration (wheels, tires, topics, update rate, preset) [default: "
    "config/vehicle_wheels.yaml]\n"
    "  --rate-hz  update rate, overrides the configuration's update_rate_hz [Hz]\n"
    "  --out-rate-hz  rate of the written wear messages [Hz] [default: every update]\n"
    "  --max-span-s   longest bag time span replayed [s] (a longer one is refused as a likely corrupt time stamp)\n";

void writeSummary(const std::string& path, const nlohmann::json& summary) {
  if (path.empty()) return;
  std::ofstream out(path + ".tmp");
  out << summary.dump(2) << "\n";
  out.close();
  if (!out || std::rename((path + ".tmp").c_str(), path.c_str()) != 0)
    throw std::runtime_error(path + ": cannot write the summary");
}

/// Per-window means for plots: speed, wear rate (loss difference over the window), loss, slide fraction.
void writeTimeseries(const std::string& path, const tread_wear::DriveReplay& replay, std::uint64_t window,
                     double time_offset_s) {
  std::ofstream out(path);
  out << "time_s,speed_kmh";
  for (int w = 0; w < replay.wheelCount(); ++w) {
    const std::string& n = replay.wheel(w).name;
    out << "," << n << "_wear_rate_mg_per_s," << n << "_loss_mg," << n << "_slide_fraction";
  }
  out << "\n";
  const std::uint64_t steps = replay.steps();
  for (std::uint64_t k0 = 0; k0 + window <= steps; k0 += window) {
    const std::uint64_t k1 = k0 + window - 1;
    double speed = 0.0;
    for (int w = 0; w < replay.wheelCount(); ++w)
      for (std::uint64_t k = k0; k <= k1; ++k) speed += replay.records(w)[k].speed_mps;
    speed /= static_cast<double>(window * replay.wheelCount());
    out << replay.stepTime(k1) - time_offset_s << "," << speed * 3.6;
    for (int w = 0; w < replay.wheelCount(); ++w) {
      const auto& rec = replay.records(w);
      const double before = k0 > 0 ? rec[k0 - 1].accumulated_loss_kg : 0.0;
      const double dt = static_cast<double>(window) / replay.settings().update_rate_hz;
      double slide = 0.0;
      for (std::uint64_t k = k0; k <= k1; ++k) slide += rec[k].slide_fraction;
      out << "," << (rec[k1].accumulated_loss_kg - before) * 1e6 / dt << "," << rec[k1].accumulated_loss_kg * 1e6 << ","
          << slide / static_cast<double>(window);
    }
    out << "\n";
  }
  if (!out) throw std::runtime_error(path + ": cannot write the time series");
}

/// Progress bar on stderr while the replay runs (a line per quarter when stderr is not a terminal).
void showProgress(const std::atomic<std::uint64_t>& done, std::uint64_t total, const std::atomic<bool>& finished) {
  const bool tty = isatty(STDERR_FILENO) != 0;
  int last_quarter = 0;
  const auto start = std::chrono::steady_clock::now();
  while (!finished.load()) {
    const double f = total > 0 ? static_cast<double>(done.load()) / static_cast<double>(total) : 1.0;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (tty) {
      const int width = 40, filled = static_cast<int>(f * width);
      std::fprintf(stderr, "\rreplay [%s%s] %5.1f%% %6.1f s",
                   std::string(static_cast<std::size_t>(filled), '#').c_str(),
                   std::string(static_cast<std::size_t>(width - filled), ' ').c_str(), 100.0 * f, elapsed);
    } else if (static_cast<int>(f * 4) > last_quarter) {
      last_quarter = static_cast<int>(f * 4);
      std::fprintf(stderr, "replay %3d%% %6.1f s\n", 25 * last_quarter, elapsed);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  if (tty) std::fprintf(stderr, "\rreplay [%s] 100.0%%\n", std::string(40, '#').c_str());
}

}  // namespace

int main(int argc, char** argv) {
  auto usage_error = [](const std::string& message) {
    return tread_wear::usageError(std::cerr, "tread_wear_replay", message, kUsage);
  };
  tread_wear::CommandLine args;
  std::string error;
  if (!args.parse(argc, argv,
                  {"out", "summary", "timeseries", "preset", "wheels", "rate-hz", "out-rate-hz", "timeseries-rate-hz",
                   "threads", "max-span-s"},
                  {"quiet"}, &error, 1))
    return usage_error(error);
  if (args.help()) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  double rate_hz = 0.0, out_rate_hz = 0.0, timeseries_rate_hz = 1.0;  // 0 = the configuration's / every update
  double max_span_s = tread_wear::ReplaySettings().max_span_s;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (!args.number("rate-hz", &rate_hz, &error) || !args.number("out-rate-hz", &out_rate_hz, &error) ||
      !args.number("timeseries-rate-hz", &timeseries_rate_hz, &error) || !args.integer("threads", &threads, &error) ||
      !args.number("max-span-s", &max_span_s, &error))
    return usage_error(error);
  if (args.positional().empty()) return usage_error("the input bag is required");
  const std::pair<const char*, double> positive[] = {
      {"rate-hz", rate_hz}, {"out-rate-hz", out_rate_hz}, {"timeseries-rate-hz", timeseries_rate_hz},
      {"max-span-s", max_span_s}};
  for (const auto& [name, value] : positive)
    if (args.has(name) && !(value > 0.0)) return usage_error(std::string("--") + name + " must be > 0");
  if (threads < 1) return usage_error("--threads must be >= 1");
  tread_wear::Preset preset = tread_wear::Preset::kStandard;
  if (args.has("preset") && !tread_wear::parsePreset(args.get("preset"), &preset))
    return usage_error(std::string("--preset must be ") + tread_wear::kPresetChoices + ", not '" + args.get("preset") +
                       "'");
  const std::string in = args.positional()[0], out = args.get("out"), summary_path = args.get("summary");
  const std::string timeseries_path = args.get("timeseries");
  const std::string wheels_path = args.get("wheels", std::string(TREAD_WEAR_SHARE_DIR) + "/config/vehicle_wheels.yaml");
  try {
    // A failed run must never leave an earlier summary that looks complete.
    writeSummary(summary_path, {{"format", "tread_wear_replay_summary"}, {"version", 1}, {"complete", false},
                                {"incomplete_reason", "replay did not finish"}, {"input", in}});
    ros::Time::init();
    tread_wear::ReplayConfig config = tread_wear::loadReplayConfig(wheels_path);
    if (rate_hz > 0.0) config.settings.update_rate_hz = rate_hz;
    if (args.has("preset")) config.settings.model.preset = preset;
    config.settings.threads = threads;
    config.settings.max_span_s = max_span_s;
    tread_wear::DriveReplay replay(config.settings, config.wheels);
    const auto read_start = std::chrono::steady_clock::now();
    const tread_wear::DriveInfo info = tread_wear::readDriveBag(in, config, &replay);
    const double read_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();
    const std::clock_t cpu_start = std::clock();

    std::atomic<std::uint64_t> done{0};
    std::atomic<bool> finished{false};
    {
      // The progress thread ends and is joined however run() ends (a joinable std::thread must not be destroyed).
      struct ProgressBar {
        std::atomic<bool>& finished;
        std::thread thread;
        ~ProgressBar() {
          finished = true;
          if (thread.joinable()) thread.join();
        }
      } bar{finished, {}};
      if (!args.has("quiet"))
        bar.thread =
            std::thread(showProgress, std::cref(done), replay.steps() * replay.wheelCount(), std::cref(finished));
      replay.run(&done);
    }
    const double cpu_s = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;

    const tread_wear::ReplaySummary summary = replay.summarize(info.phases, info.time_offset_s);
    nlohmann::json json = tread_wear::replaySummaryToJson(summary, config.settings);
    json["input"] = in;
    json["bag_read_s"] = read_s;
    json["compute_cpu_s"] = cpu_s;  // CPU time of all replay threads: load-independent cost measure
    if (info.present) json["drive"] = info.json;
    if (!out.empty()) {
      const double rate = config.settings.update_rate_hz;
      const auto decimation =
          out_rate_hz > 0.0 ? static_cast<std::uint64_t>(std::llround(std::max(1.0, rate / out_rate_hz))) : 1;
      tread_wear::writeWearBag(out, replay, config, decimation);
    }
    if (!timeseries_path.empty()) {
      const auto window = static_cast<std::uint64_t>(
          std::llround(std::max(1.0, config.settings.update_rate_hz / timeseries_rate_hz)));
      writeTimeseries(timeseries_path, replay, window, info.time_offset_s);
    }
    writeSummary(summary_path, json);
    std::printf("%s: %.0f s replayed in %.2f s (%.0fx real time, preset %s, %g Hz, %zu wheels)%s\n", in.c_str(),
                summary.end_s - summary.start_s, summary.wall_time_s,
                summary.wall_time_s > 0 ? (summary.end_s - summary.start_s) / summary.wall_time_s : 0.0,
                tread_wear::presetName(config.settings.model.preset), config.settings.update_rate_hz,
                summary.wheels.size(), summary.complete ? "" : " INCOMPLETE");
    std::printf("  bag read %.2f s; compute %.2f s wall, %.2f s CPU (%.0fx real time per CPU second)\n", read_s,
                summary.wall_time_s, cpu_s, cpu_s > 0 ? (summary.end_s - summary.start_s) / cpu_s : 0.0);
    for (const tread_wear::WheelSummary& w : summary.wheels)
      std::printf("  %-12s %9.3f mg  %8.1f m  %8.2f mg/km  slide %.4f\n", w.name.c_str(), w.mass_loss_kg * 1e6,
                  w.distance_m, w.mg_per_km, w.slide_fraction_mean);
    if (!summary.complete) {
      std::fprintf(stderr, "tread_wear_replay: incomplete replay: %s\n", summary.incomplete_reason.c_str());
      return 3;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tread_wear_replay: %s\n", e.what());
    try {
      writeSummary(summary_path, {{"format", "tread_wear_replay_summary"}, {"version", 1}, {"complete", false},
                                  {"incomplete_reason", e.what()}, {"input", in}});
    } catch (const std::exception&) {  // the error above is what the user must see; exit code says it failed
    }
    return 1;
  }
  return 0;
}
