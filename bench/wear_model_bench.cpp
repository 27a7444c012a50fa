/// Time per wheel evaluation of the wear-model presets (docs/performance.md), Google Benchmark.
///   tread_wear_bench [--benchmark_repetitions=N ...]
/// Each benchmark evaluates every condition of a grid once per iteration and reports, per evaluation:
/// median, p99 and max over all (condition, iteration) samples, timed one by one with a steady clock
/// (counters median_us, p99_us, max_us) and with the thread's CPU clock (cpu_median_us, ...), and the
/// maximum error against the marcher's reference preset
/// (counters err_F_pct = max over Fx, Fy, Mz; err_W_pct; err_frac = max over stick and exact-stick
/// fractions), measured once per benchmark. Grids and error scales: bench_conditions.h.
/// BM_ReferenceSolver times the CVODE ReferenceBrushSolver (default options) on the same grids: the
/// reference for the speed-up ratio and the "naive" general-purpose stiff integrator per element path
/// (BDF with a dense Jacobian and event location at every stick/slide switch, no return mapping).
/// Conditions where it throws are skipped and counted (counter failures).
#include <benchmark/benchmark.h>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <vector>

#include "bench_conditions.h"
#include "tread_wear/model/wear_model.h"
#include "tread_wear/reference/reference_solver.h"

using namespace tread_wear;

namespace {

/// CPU time of this thread [s]: excludes time the thread waits while other processes run (the
/// machine is shared), so its percentiles are those of the work itself.
double threadCpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/// Writes median, p99 and max [us] of samples [s] as counters prefix_median_us, ...
void percentiles(benchmark::State& state, const std::string& prefix, std::vector<double> samples) {
  std::sort(samples.begin(), samples.end());
  auto pct = [&](double q) {
    return samples.empty() ? 0.0 : samples[std::min(samples.size() - 1, size_t(q * samples.size()))];
  };
  state.counters[prefix + "median_us"] = pct(0.5) * 1e6;
  state.counters[prefix + "p99_us"] = pct(0.99) * 1e6;
  state.counters[prefix + "max_us"] = samples.empty() ? 0.0 : samples.back() * 1e6;
}

const std::vector<bench::Condition>& grid(int which) {
  static const std::vector<bench::Condition> rig = bench::rigConditions();
  static const std::vector<bench::Condition> road = bench::roadConditions(100.0);
  return which == 0 ? rig : road;
}

std::vector<WearResult> evaluateGrid(const BrushWearModel& lit, const BrushWearModel& flip,
                                     const std::vector<bench::Condition>& conds) {
  std::vector<WearResult> out(conds.size());
  for (size_t k = 0; k < conds.size(); ++k)
    (conds[k].orientation == TurnSlipOrientation::kLiteral ? lit : flip).evaluate(conds[k].op, &out[k]);
  return out;
}

const std::vector<WearResult>& reference(int which) {
  static std::map<int, std::vector<WearResult>> cache;
  auto it = cache.find(which);
  if (it != cache.end()) return it->second;
  const TireParams params;
  const BrushWearModel lit(params, presetOptions(Preset::kReference, TurnSlipOrientation::kLiteral));
  const BrushWearModel flip(params, presetOptions(Preset::kReference, TurnSlipOrientation::kFlipped));
  return cache[which] = evaluateGrid(lit, flip, grid(which));
}

void BM_Evaluate(benchmark::State& state) {
  const Preset preset = static_cast<Preset>(state.range(0));
  const int which = static_cast<int>(state.range(1));
  const auto& conds = grid(which);
  const TireParams params;
  const BrushWearModel lit(params, presetOptions(preset, TurnSlipOrientation::kLiteral));
  const BrushWearModel flip(params, presetOptions(preset, TurnSlipOrientation::kFlipped));
  std::vector<double> wall, cpu;
  wall.reserve(conds.size() * 64);
  cpu.reserve(conds.size() * 64);
  WearResult r;
  for (auto _ : state) {
    for (const auto& c : conds) {
      const BrushWearModel& m = c.orientation == TurnSlipOrientation::kLiteral ? lit : flip;
      const double c0 = threadCpuSeconds();
      const auto t0 = std::chrono::steady_clock::now();
      m.evaluate(c.op, &r);
      const auto t1 = std::chrono::steady_clock::now();
      const double c1 = threadCpuSeconds();
      benchmark::DoNotOptimize(r);
      if (wall.size() < wall.capacity()) {
        wall.push_back(std::chrono::duration<double>(t1 - t0).count());
        cpu.push_back(c1 - c0);
      }
    }
  }
  percentiles(state, "", wall);
  percentiles(state, "cpu_", cpu);
  state.counters["evals"] = benchmark::Counter(double(conds.size()), benchmark::Counter::kIsIterationInvariantRate,
                                               benchmark::Counter::OneK::kIs1000);
  if (preset != Preset::kReference) {
    const auto res = evaluateGrid(lit, flip, conds);
    const auto& ref = reference(which);
    SolverErrors worst;
    for (size_t k = 0; k < conds.size(); ++k) worst.maxWith(solverErrors(ref[k], res[k], conds[k].op.load_n));
    state.counters["err_F_pct"] = 100.0 * std::max({worst.fx, worst.fy, worst.mz});
    state.counters["err_W_pct"] = 100.0 * worst.wear;
    state.counters["err_frac"] = std::max(worst.stick, worst.exact_stick);
  }
  state.SetLabel(std::string(presetName(preset)) + (which == 0 ? " rig(Table 3)" : " road grid"));
}

void BM_ReferenceSolver(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const auto& conds = grid(which);
  const TireParams params;
  ReferenceSolverOptions o_lit, o_flip;
  o_flip.orientation = TurnSlipOrientation::kFlipped;
  ReferenceBrushSolver lit(params, o_lit), flip(params, o_flip);
  std::vector<double> wall, cpu;
  int failures = 0;
  WearResult r;
  for (auto _ : state) {
    failures = 0;
    for (const auto& c : conds) {
      ReferenceBrushSolver& m = c.orientation == TurnSlipOrientation::kLiteral ? lit : flip;
      const double c0 = threadCpuSeconds();
      const auto t0 = std::chrono::steady_clock::now();
      try {
        m.evaluate(c.op, &r);
      } catch (const std::exception&) {
        ++failures;
        continue;
      }
      wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      cpu.push_back(threadCpuSeconds() - c0);
    }
  }
  percentiles(state, "", wall);
  percentiles(state, "cpu_", cpu);
  state.counters["failures"] = failures;
  state.SetLabel(std::string("CVODE reference") + (which == 0 ? " rig(Table 3)" : " road grid"));
}

}  // namespace

BENCHMARK(BM_ReferenceSolver)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1);

BENCHMARK(BM_Evaluate)
    ->ArgsProduct({{0, 1, 2, 3}, {0, 1}})
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(0.5);

BENCHMARK_MAIN();
