#include "tread_wear/estimation/drive_replay.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace tread_wear {

namespace {

/// Share of the replayed time that may stay unintegrated (start-up, gaps) in a complete replay [-].
constexpr double kMaxUnaccountedShare = 0.01;
/// Wheel-steps between progress counter updates (keeps the shared counter out of the inner loop) [-].
constexpr std::uint64_t kProgressBatch = 256;

/// |Fx| |kappa V_x| + |Fy| |V sin(alpha)| [W]: the brush forces on the rigid slip velocities (operating_point.h).
double frictionPower(const WearResult& result, const WheelInputs& inputs) {
  const double v = inputs.speed_mps(), alpha = inputs.slipAngle_rad();
  return std::fabs(result.fx_n * inputs.slipRatio() * v * std::cos(alpha)) +
         std::fabs(result.fy_n * v * std::sin(alpha));
}

}  // namespace

struct DriveReplay::WheelRun {
  std::vector<InputSample> samples;
  std::vector<StepRecord> records;
  std::unique_ptr<WearModel> model;
  std::unique_ptr<WheelEstimator> estimator;
  WheelInputs inputs;
};

bool ReplaySettings::validate(std::string* error) const {
  std::ostringstream os;
  if (!(update_rate_hz > 0.0) || !std::isfinite(update_rate_hz)) {
    os << "update_rate_hz = " << update_rate_hz << ": must be finite and > 0";
  } else if (threads < 1) {
    os << "threads = " << threads << ": must be >= 1";
  } else if (!(max_span_s > 0.0) || !std::isfinite(max_span_s)) {
    os << "max_span_s = " << max_span_s << ": must be finite and > 0";
  } else {
    std::string sub;
    if (!model.validate(&sub))
      os << "model." << sub;
    else if (!estimator.validate(&sub))
      os << "estimator." << sub;
  }
  if (os.str().empty()) return true;
  if (error != nullptr) *error = os.str();
  return false;
}

DriveReplay::DriveReplay(const ReplaySettings& settings, std::vector<ReplayWheel> wheels)
    : settings_(settings), wheels_(std::move(wheels)) {
  std::string error;
  if (!settings_.validate(&error)) throw std::invalid_argument("invalid replay settings: " + error);
  if (wheels_.empty()) throw std::invalid_argument("replay needs at least one wheel");
  for (const ReplayWheel& w : wheels_) {
    auto run = std::make_unique<WheelRun>();
    run->model = std::make_unique<WearModel>(w.tire, settings_.model);
    run->estimator = std::make_unique<WheelEstimator>(settings_.estimator, w.tire.material);
    run->inputs = WheelInputs(settings_.estimator.limits);
    runs_.push_back(std::move(run));
  }
}

DriveReplay::~DriveReplay() = default;

void DriveReplay::addSample(int wheel, const InputSample& sample) {
  std::vector<InputSample>& samples = runs_.at(static_cast<std::size_t>(wheel))->samples;
  if (!samples.empty() && sample.t_s < samples.back().t_s)
    throw std::invalid_argument("replay: samples of wheel '" + wheels_[static_cast<std::size_t>(wheel)].name +
                                "' out of time order");
  bool first = true;
  for (const auto& r : runs_) first = first && r->samples.empty();
  t0_ = first ? sample.t_s : std::min(t0_, sample.t_s);
  t_end_ = first ? sample.t_s : std::max(t_end_, sample.t_s);
  samples.push_back(sample);
}

std::size_t DriveReplay::sampleCount(int wheel) const {
  return runs_.at(static_cast<std::size_t>(wheel))->samples.size();
}

const std::vector<StepRecord>& DriveReplay::records(int wheel) const {
  return runs_.at(static_cast<std::size_t>(wheel))->records;
}

std::uint64_t DriveReplay::steps() const {
  bool any = false;
  for (const auto& r : runs_) any = any || !r->samples.empty();
  if (!any) return 0;
  return static_cast<std::uint64_t>(std::floor((t_end_ - t0_) * settings_.update_rate_hz + 1e-9)) + 1;
}

void DriveReplay::run(std::atomic<std::uint64_t>* progress) {
  if (steps() > 0 && t_end_ - t0_ > settings_.max_span_s) {
    double gap = 0.0, gap_at = t0_;
    for (const auto& r : runs_)
      for (std::size_t i = 1; i < r->samples.size(); ++i)
        if (r->samples[i].t_s - r->samples[i - 1].t_s > gap) {
          gap = r->samples[i].t_s - r->samples[i - 1].t_s;
          gap_at = r->samples[i - 1].t_s;
        }
    std::ostringstream os;
    os << "replay: the samples span " << t_end_ - t0_ << " s of bag time (" << t0_ << " to " << t_end_
       << " s), more than max_span_s = " << settings_.max_span_s << " s; the largest gap between a wheel's samples is "
       << gap << " s after t = " << gap_at << " s (a corrupt time stamp?)";
    throw std::runtime_error(os.str());
  }
  const auto start = std::chrono::steady_clock::now();
  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto worker = [&]() {
    try {
      for (int w = next++; w < wheelCount(); w = next++) runWheel(w, progress);
    } catch (...) {
      next = wheelCount();  // the others stop after their current wheel
      const std::lock_guard<std::mutex> lock(failure_mutex);
      if (!failure) failure = std::current_exception();
    }
  };
  const int n_threads = std::min(settings_.threads, wheelCount());
  std::vector<std::thread> pool;
  for (int i = 1; i < n_threads; ++i) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
  wall_time_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void DriveReplay::runWheel(int wheel, std::atomic<std::uint64_t>* progress) {
  WheelRun& run = *runs_[static_cast<std::size_t>(wheel)];
  const std::uint64_t n_steps = steps();
  run.records.assign(n_steps, StepRecord{});
  std::size_t next_sample = 0;
  std::uint64_t unreported = 0;
  for (std::uint64_t k = 0; k < n_steps; ++k) {
    const double t = stepTime(k);
    while (next_sample < run.samples.size() && run.samples[next_sample].t_s <= t + kInputStampTolerance_s) {
      run.inputs.apply(run.samples[next_sample++]);
    }
    const WheelOutput& out = run.estimator->step(t, run.inputs, *run.model);
    StepRecord& r = run.records[k];
    r.wear_rate_kg_per_m = out.result.wear_rate_kg_per_m;
    r.wear_rate_kg_per_s = out.result.wear_rate_kg_per_s;
    r.accumulated_loss_kg = out.accumulated_loss_kg;
    r.tread_depth_loss_m = out.tread_depth_loss_m;
    r.remaining_tread_depth_m = out.remaining_tread_depth_m;
    r.distance_m = out.distance_m;
    r.stick_fraction = out.result.stick_fraction;
    r.slide_fraction = out.result.slide_fraction;
    r.exact_stick_fraction = out.result.exact_stick_fraction;
    r.fx_n = out.result.fx_n;
    r.fy_n = out.result.fy_n;
    r.mz_nm = out.result.mz_nm;
    r.unaccounted_time_s = run.estimator->unaccountedTime_s();
    r.speed_mps = out.evaluated ? run.inputs.speed_mps() : 0.0;
    r.friction_power_w = out.evaluated ? frictionPower(out.result, run.inputs) : 0.0;
    r.status = out.status;
    r.preset = out.preset;
    r.evaluated = out.evaluated;
    r.integrated = out.integrated;
    if (progress != nullptr && ++unreported == kProgressBatch) {
      progress->fetch_add(unreported);
      unreported = 0;
    }
  }
  if (progress != nullptr) progress->fetch_add(unreported);
}

ReplaySummary DriveReplay::summarize(const std::vector<ProfilePhase>& phases, double phase_time_offset_s) const {
  ReplaySummary s;
  s.start_s = t0_;
  s.end_s = t_end_;
  s.phase_time_offset_s = phase_time_offset_s;
  s.steps = steps();
  s.phases = phases;
  s.phase_distance_m.assign(phases.size(), 0.0);
  s.wall_time_s = wall_time_s_;
  s.complete = s.steps > 0;
  if (!s.complete) s.incomplete_reason = "no input samples";
  const double span = t_end_ - t0_;
  for (int w = 0; w < wheelCount(); ++w) {
    const WheelRun& run = *runs_[static_cast<std::size_t>(w)];
    WheelSummary ws;
    ws.name = wheels_[static_cast<std::size_t>(w)].name;
    ws.phase_loss_kg.assign(phases.size(), 0.0);
    double stick_sum = 0.0, slide_sum = 0.0;
    std::uint64_t evaluated = 0;
    const double dt = 1.0 / settings_.update_rate_hz;
    for (std::size_t k = 0; k < run.records.size(); ++k) {
      const StepRecord& r = run.records[k];
      if (r.evaluated) {
        stick_sum += r.stick_fraction;
        slide_sum += r.slide_fraction;
        ++evaluated;
      }
      if (k == 0) continue;
      if (r.integrated) ws.friction_work_j += 0.5 * (r.friction_power_w + run.records[k - 1].friction_power_w) * dt;
      const int phase = phaseIndexAt(phases, stepTime(k) - phase_time_offset_s);
      if (phase < 0) continue;
      ws.phase_loss_kg[static_cast<std::size_t>(phase)] +=
          r.accumulated_loss_kg - run.records[k - 1].accumulated_loss_kg;
      s.phase_distance_m[static_cast<std::size_t>(phase)] +=
          (r.distance_m - run.records[k - 1].distance_m) / wheelCount();
    }
    if (!run.records.empty()) {
      ws.mass_loss_kg = run.records.back().accumulated_loss_kg;
      ws.distance_m = run.records.back().distance_m;
    }
    ws.mg_per_km = ws.distance_m > 0.0 ? ws.mass_loss_kg / ws.distance_m * 1e9 : 0.0;
    ws.stick_fraction_mean = evaluated > 0 ? stick_sum / evaluated : 0.0;
    ws.slide_fraction_mean = evaluated > 0 ? slide_sum / evaluated : 0.0;
    ws.unaccounted_time_s = run.estimator->unaccountedTime_s();
    for (InputKind kind : {InputKind::kLoad, InputKind::kSlip, InputKind::kSpeed, InputKind::kTemperature})
      ws.samples_received += run.inputs.sample(kind).received;
    ws.samples_rejected = run.inputs.totalRejected();
    ws.evaluations = run.estimator->evaluations();
    ws.time_jumps = run.estimator->backwardJumps() + run.estimator->forwardJumps();
    if (s.complete) {
      for (InputKind kind : {InputKind::kLoad, InputKind::kSlip, InputKind::kSpeed}) {
        if (run.inputs.sample(kind).received == 0) {
          s.complete = false;
          s.incomplete_reason = "wheel '" + ws.name + "' has no " + inputKindName(kind) + " input";
        }
      }
    }
    if (s.complete && ws.unaccounted_time_s > kMaxUnaccountedShare * span) {
      s.complete = false;
      std::ostringstream os;
      os << "wheel '" << ws.name << "': " << ws.unaccounted_time_s << " s of " << span
         << " s not integrated (stale, invalid or missing inputs, time jumps)";
      s.incomplete_reason = os.str();
    }
    s.wheels.push_back(std::move(ws));
  }
  return s;
}

}  // namespace tread_wear
