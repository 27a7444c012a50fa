#include "tread_wear/ros/bag/replay_cli.h"

#include <ros/time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <thread>
#include <utility>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/io/replay_summary_json.h"
#include "tread_wear/ros/bag/drive_bag_reader.h"
#include "tread_wear/ros/bag/replay_config.h"
#include "tread_wear/ros/bag/wear_bag_writer.h"

namespace tread_wear {
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

/// The options of one replay, checked.
struct ReplayOptions {
  std::string in, wheels_path;                     ///< input bag, node configuration
  std::string out, summary_path, timeseries_path;  ///< outputs; empty: not written
  double rate_hz = 0.0;                            ///< 0: the configuration's update rate [Hz]
  double out_rate_hz = 0.0;                        ///< 0: a wear message every update [Hz]
  double timeseries_rate_hz = 1.0;                 ///< [Hz]
  double max_span_s = ReplaySettings().max_span_s;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  bool has_preset = false;  ///< the preset overrides the configuration's
  Preset preset = Preset::kStandard;
  bool quiet = false;
};

/// The options of a parsed command line; false with *error (a usage error) when one is malformed or missing.
bool replayOptions(const CommandLine& args, const std::string& share_dir, ReplayOptions* o, std::string* error) {
  if (!args.number("rate-hz", &o->rate_hz, error) || !args.number("out-rate-hz", &o->out_rate_hz, error) ||
      !args.number("timeseries-rate-hz", &o->timeseries_rate_hz, error) ||
      !args.integer("threads", &o->threads, error) || !args.number("max-span-s", &o->max_span_s, error))
    return false;
  if (args.positional().empty()) return (*error = "the input bag is required", false);
  const std::pair<const char*, double> positive[] = {{"rate-hz", o->rate_hz},
                                                     {"out-rate-hz", o->out_rate_hz},
                                                     {"timeseries-rate-hz", o->timeseries_rate_hz},
                                                     {"max-span-s", o->max_span_s}};
  for (const auto& [name, value] : positive)
    if (args.has(name) && !(value > 0.0)) return (*error = std::string("--") + name + " must be > 0", false);
  if (o->threads < 1) return (*error = "--threads must be >= 1", false);
  o->has_preset = args.has("preset");
  if (o->has_preset && !parsePreset(args.get("preset"), &o->preset))
    return (*error = std::string("--preset must be ") + kPresetChoices + ", not '" + args.get("preset") + "'", false);
  o->in = args.positional()[0];
  o->out = args.get("out");
  o->summary_path = args.get("summary");
  o->timeseries_path = args.get("timeseries");
  o->wheels_path = args.get("wheels", share_dir + "/config/vehicle_wheels.yaml");
  o->quiet = args.has("quiet");
  return true;
}

/// Writes the summary through a temporary file, so that a reader never sees half a summary; nothing without a path.
void writeSummary(const std::string& path, const std::string& summary) {
  if (path.empty()) return;
  std::ofstream out(path + ".tmp");
  out << summary;
  out.close();
  if (!out || std::rename((path + ".tmp").c_str(), path.c_str()) != 0)
    throw std::runtime_error(path + ": cannot write the summary");
}

/// Per-window means for plots: speed, wear rate (loss difference over the window), loss, slide fraction.
void writeTimeseries(const std::string& path, const DriveReplay& replay, std::uint64_t window, double time_offset_s) {
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

/// Progress bar on err while the replay runs (a line per quarter when err is not a terminal).
void showProgress(const std::atomic<std::uint64_t>& done, std::uint64_t total, const std::atomic<bool>& finished,
                  std::ostream& err, bool err_is_terminal) {
  int last_quarter = 0;
  const auto start = std::chrono::steady_clock::now();
  while (!finished.load()) {
    const double f = total > 0 ? static_cast<double>(done.load()) / static_cast<double>(total) : 1.0;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (err_is_terminal) {
      const int width = 40, filled = static_cast<int>(f * width);
      err << formatted("\rreplay [%s%s] %5.1f%% %6.1f s", std::string(static_cast<std::size_t>(filled), '#').c_str(),
                       std::string(static_cast<std::size_t>(width - filled), ' ').c_str(), 100.0 * f, elapsed)
          << std::flush;
    } else if (static_cast<int>(f * 4) > last_quarter) {
      last_quarter = static_cast<int>(f * 4);
      err << formatted("replay %3d%% %6.1f s\n", 25 * last_quarter, elapsed) << std::flush;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  if (err_is_terminal) err << formatted("\rreplay [%s] 100.0%%\n", std::string(40, '#').c_str()) << std::flush;
}

/// Runs the replay, with the progress bar on err unless quiet.
void runWithProgress(DriveReplay* replay, bool quiet, std::ostream& err, bool err_is_terminal) {
  std::atomic<std::uint64_t> done{0};
  std::atomic<bool> finished{false};
  // The progress thread ends and is joined however run() ends (a joinable std::thread must not be destroyed).
  struct ProgressBar {
    std::atomic<bool>& finished;
    std::thread thread;
    ~ProgressBar() {
      finished = true;
      if (thread.joinable()) thread.join();
    }
  } bar{finished, {}};
  if (!quiet)
    bar.thread = std::thread(showProgress, std::cref(done), replay->steps() * replay->wheelCount(), std::cref(finished),
                             std::ref(err), err_is_terminal);
  replay->run(&done);
}

/// The replay of o.in with every output; returns 0 or kExitIncompleteReplay. @throw std::exception on bad data
int replay(const ReplayOptions& o, std::ostream& out, std::ostream& err, bool err_is_terminal) {
  writeSummary(o.summary_path, incompleteReplaySummary(o.in, "replay did not finish"));
  ros::Time::init();
  ReplayConfig config = loadReplayConfig(o.wheels_path);
  if (o.rate_hz > 0.0) config.settings.update_rate_hz = o.rate_hz;
  if (o.has_preset) config.settings.model.preset = o.preset;
  config.settings.threads = o.threads;
  config.settings.max_span_s = o.max_span_s;
  DriveReplay replay(config.settings, config.wheels);
  const auto read_start = std::chrono::steady_clock::now();
  const DriveInfo info = readDriveBag(o.in, config, &replay);
  const double read_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();
  const std::clock_t cpu_start = std::clock();
  runWithProgress(&replay, o.quiet, err, err_is_terminal);
  const double cpu_s = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;

  const ReplaySummary summary = replay.summarize(info.phases, info.time_offset_s);
  if (!o.out.empty()) {
    const double rate = config.settings.update_rate_hz;
    const auto decimation =
        o.out_rate_hz > 0.0 ? static_cast<std::uint64_t>(std::llround(std::max(1.0, rate / o.out_rate_hz))) : 1;
    writeWearBag(o.out, replay, config, decimation);
  }
  if (!o.timeseries_path.empty()) {
    const auto window =
        static_cast<std::uint64_t>(std::llround(std::max(1.0, config.settings.update_rate_hz / o.timeseries_rate_hz)));
    writeTimeseries(o.timeseries_path, replay, window, info.time_offset_s);
  }
  writeSummary(o.summary_path, replaySummaryDocument(summary, config.settings, {o.in, read_s, cpu_s, info.text}));
  const double span_s = summary.end_s - summary.start_s;
  out << formatted("%s: %.0f s replayed in %.2f s (%.0fx real time, preset %s, %g Hz, %zu wheels)%s\n", o.in.c_str(),
                   span_s, summary.wall_time_s, summary.wall_time_s > 0 ? span_s / summary.wall_time_s : 0.0,
                   presetName(config.settings.model.preset), config.settings.update_rate_hz, summary.wheels.size(),
                   summary.complete ? "" : " INCOMPLETE");
  out << formatted("  bag read %.2f s; compute %.2f s wall, %.2f s CPU (%.0fx real time per CPU second)\n", read_s,
                   summary.wall_time_s, cpu_s, cpu_s > 0 ? span_s / cpu_s : 0.0);
  for (const WheelSummary& w : summary.wheels)
    out << formatted("  %-12s %9.3f mg  %8.1f m  %8.2f mg/km  slide %.4f\n", w.name.c_str(), w.mass_loss_kg * 1e6,
                     w.distance_m, w.mg_per_km, w.slide_fraction_mean);
  if (!summary.complete) {
    err << "tread_wear_replay: incomplete replay: " << summary.incomplete_reason << "\n";
    return kExitIncompleteReplay;
  }
  return 0;
}

}  // namespace

int runReplayCli(int argc, const char* const argv[], const std::string& share_dir, std::ostream& out, std::ostream& err,
                 bool err_is_terminal) {
  CommandLine args;
  std::string error;
  ReplayOptions options;
  if (!args.parse(argc, argv,
                  {"out", "summary", "timeseries", "preset", "wheels", "rate-hz", "out-rate-hz", "timeseries-rate-hz",
                   "threads", "max-span-s"},
                  {"quiet"}, &error, 1))
    return usageError(err, "tread_wear_replay", error, kUsage);
  if (args.help()) {
    out << kUsage;
    return 0;
  }
  if (!replayOptions(args, share_dir, &options, &error)) return usageError(err, "tread_wear_replay", error, kUsage);
  try {
    return replay(options, out, err, err_is_terminal);
  } catch (const std::exception& e) {
    err << "tread_wear_replay: " << e.what() << "\n";
    try {
      writeSummary(options.summary_path, incompleteReplaySummary(options.in, e.what()));
    } catch (const std::exception&) {  // the error above is what the user must see; exit code says it failed
    }
    return kExitData;
  }
}

}  // namespace tread_wear
