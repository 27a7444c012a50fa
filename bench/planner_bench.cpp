/// The planner's wear cost (issue 24, part 3; docs/planner.md), Google Benchmark.
///   tread_wear_planner_bench [--benchmark_filter=...]   (config files: $TREAD_WEAR_CONFIG_DIR, else the source's)
/// The passenger car of config/vehicle_passenger_car.yaml on four config/tires/passenger_205_55_r16.yaml tires at the
/// node's default preset (standard; BM_*/fast for the fast preset), 100 seeded candidate trajectories of 100 samples
/// (planning/candidate_trajectories.h, seed 24: cruising, accelerating, braking to a stop, curves, lane changes).
///   BM_MapBuild     one build of the default map (counters: nodes, threads)
///   BM_MapBatch     the cost of all 100 candidates from the map, per batch (the target: <= 5 ms)
///   BM_DirectBatch  the same from the model at every sample and wheel (40 000 evaluations per batch)
///   BM_MapError     accuracy, measured once: relative error of each candidate's total wear, map against direct
///                   (counters traj_max_pct, traj_rms_pct; the target: <= 3 % each), and of each wheel's wear rate
///                   at random samples uniform over the map's reach (v in [0, 45] m/s, a_x in [-8, 5] m/s^2,
///                   lateral share in [-1, 1]) and within a road tire's grip (hypot(a_x, a_y) <= 8 m/s^2): counters
///                   sample_max_pct, sample_rms_pct, sample_p99_pct, over samples whose direct rate is at least
///                   1e-9 kg/s (below that a relative error means little); box_max_pct over the whole box, where
///                   beyond the grip a wheel can lift off (zero load) inside a cell
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "tread_wear/io/params_io.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/planning/candidate_trajectories.h"
#include "tread_wear/planning/wear_map.h"

using namespace tread_wear;

namespace {

std::string configDir() {
  const char* dir = std::getenv("TREAD_WEAR_CONFIG_DIR");
  return dir != nullptr ? dir : TREAD_WEAR_SHARE_DIR "/config";
}

VehicleWearSetup passengerCar(Preset preset) {
  VehicleWearSetup setup;
  setup.vehicle = loadVehicleParams(configDir() + "/vehicle_passenger_car.yaml");
  setup.tires.fill(loadTireParams(configDir() + "/tires/passenger_205_55_r16.yaml"));
  setup.model.preset = preset;
  return setup;
}

int buildThreads() { return static_cast<int>(std::max(1u, std::thread::hardware_concurrency())); }

const std::vector<std::vector<TrajectorySample>>& candidates() {
  static const std::vector<std::vector<TrajectorySample>> set = generateCandidates(CandidateSetParams());
  return set;
}

/// One map per preset, built once for the benchmarks that query it.
const WearMap& mapFor(Preset preset) {
  static std::shared_ptr<const WearMap> maps[WearModel::kPresets];
  auto& map = maps[static_cast<int>(preset)];
  if (!map) {
    WearMapParams params;
    params.build_threads = buildThreads();
    map = WearMap::build(passengerCar(preset), params);
  }
  return *map;
}

Preset presetArg(const benchmark::State& state) { return static_cast<Preset>(state.range(0)); }

void BM_MapBuild(benchmark::State& state) {
  const VehicleWearSetup setup = passengerCar(presetArg(state));
  WearMapParams params;
  params.build_threads = buildThreads();
  std::size_t nodes = 0;
  for (auto _ : state) {
    const auto map = WearMap::build(setup, params);
    nodes = map->nodeCount();
  }
  state.counters["nodes"] = static_cast<double>(nodes);
  state.counters["threads"] = params.build_threads;
}

void BM_MapBatch(benchmark::State& state) {
  const WearMap& map = mapFor(presetArg(state));
  double total = 0.0;
  for (auto _ : state) {
    for (const auto& t : candidates()) total += map.evaluate(t.data(), t.size()).total_wear_kg;
    benchmark::DoNotOptimize(total);
  }
  state.counters["trajectories"] = static_cast<double>(candidates().size());
}

void BM_DirectBatch(benchmark::State& state) {
  const TrajectoryCostEvaluator direct(passengerCar(presetArg(state)));
  double total = 0.0;
  for (auto _ : state) {
    for (const auto& t : candidates()) total += direct.evaluate(t.data(), t.size()).total_wear_kg;
    benchmark::DoNotOptimize(total);
  }
}

double rms(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return v.empty() ? 0.0 : std::sqrt(s / static_cast<double>(v.size()));
}

void BM_MapError(benchmark::State& state) {
  const Preset preset = presetArg(state);
  const WearMap& map = mapFor(preset);
  const TrajectoryCostEvaluator direct(passengerCar(preset));
  std::vector<double> trajectory_errors, sample_errors;
  double box_max = 0.0;
  int failed = 0;
  for (auto _ : state) {
    trajectory_errors.clear();
    for (const auto& t : candidates()) {
      const TrajectoryCost d = direct.evaluate(t.data(), t.size()), m = map.evaluate(t.data(), t.size());
      if (!d.ok() || !m.ok() || !(d.total_wear_kg > 0.0)) {
        ++failed;
        continue;
      }
      trajectory_errors.push_back(std::fabs(m.total_wear_kg / d.total_wear_kg - 1.0));
    }
    sample_errors.clear();
    std::mt19937 random(7);
    std::uniform_real_distribution<double> speed(0.0, 45.0), accel(-8.0, 5.0), share(-1.0, 1.0);
    for (int k = 0; k < 2000; ++k) {
      const double v = speed(random), a_x = accel(random), eta = share(random);
      const double kappa = eta * map.maxLateralAccel_mps2(v) / std::max(v * v, 1e-12);
      const TrajectorySample sample{0.0, v, a_x, std::clamp(kappa, -0.25, 0.25)};
      WheelRates from_map, exact;
      std::string error;
      if (!map.rates(sample, &from_map, &error) || !direct.rates(sample, &exact, &error)) {
        ++failed;
        continue;
      }
      const bool within_grip = std::hypot(a_x, v * v * sample.path_curvature_per_m) <= 8.0;
      for (int w = 0; w < kWheelCount; ++w) {
        if (exact.wear_kg_per_s[w] < 1e-9) continue;
        const double e = std::fabs(from_map.wear_kg_per_s[w] / exact.wear_kg_per_s[w] - 1.0);
        box_max = std::max(box_max, e);
        if (within_grip) sample_errors.push_back(e);
      }
    }
  }
  std::sort(trajectory_errors.begin(), trajectory_errors.end());
  std::sort(sample_errors.begin(), sample_errors.end());
  state.counters["traj_max_pct"] = trajectory_errors.empty() ? 0.0 : 100.0 * trajectory_errors.back();
  state.counters["traj_rms_pct"] = 100.0 * rms(trajectory_errors);
  state.counters["sample_max_pct"] = sample_errors.empty() ? 0.0 : 100.0 * sample_errors.back();
  state.counters["sample_rms_pct"] = 100.0 * rms(sample_errors);
  state.counters["sample_p99_pct"] =
      sample_errors.empty() ? 0.0 : 100.0 * sample_errors[static_cast<std::size_t>(0.99 * (sample_errors.size() - 1))];
  state.counters["samples"] = static_cast<double>(sample_errors.size());
  state.counters["box_max_pct"] = 100.0 * box_max;
  state.counters["failed"] = failed;
}

void presets(benchmark::internal::Benchmark* b) {
  b->ArgName("preset")->Arg(static_cast<int>(Preset::kStandard))->Arg(static_cast<int>(Preset::kFast));
}

}  // namespace

BENCHMARK(BM_MapBuild)->Apply(presets)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK(BM_MapBatch)->Apply(presets)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DirectBatch)->Apply(presets)->Iterations(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MapError)->Apply(presets)->Iterations(1)->Unit(benchmark::kSecond);

BENCHMARK_MAIN();
