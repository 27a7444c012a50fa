#include "tread_wear/ros/node_planner.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cmath>
#include <condition_variable>
#include <limits>
#include <mutex>
#include <thread>

#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/model/validation.h"
#include "tread_wear/planning/trajectory_cost.h"
#include "tread_wear/planning/wear_map.h"

namespace tread_wear {

static_assert(NodePlannerConfig::kPlaces == kWheelCount, "a place per vehicle wheel");

namespace {

bool sameTemperature(double a, double b, double step_c) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::fabs(a - b) <= step_c;
}

}  // namespace

bool NodePlannerConfig::validate(std::string* error) const {
  if (!(std::isfinite(map_temperature_step_c) && map_temperature_step_c > 0.0))
    return failValidation(error, "planner/map_temperature_step_c", map_temperature_step_c, "finite and > 0 [K]");
  if (!(std::isfinite(max_path_curvature_per_m) && max_path_curvature_per_m > 0.0))
    return failValidation(error, "planner/max_path_curvature_per_m", max_path_curvature_per_m, "finite and > 0 [1/m]");
  if (map_threads < 1) return failValidation(error, "planner/map_threads", map_threads, ">= 1");
  return true;
}

bool loadNodePlannerConfig(const ros::NodeHandle& pnh, const std::string& config_dir, NodePlannerConfig* config,
                           std::string* error) {
  NodePlannerConfig c;
  pnh.param<std::string>("planner/vehicle_params", c.vehicle_params, c.vehicle_params);
  if (!c.vehicle_params.empty() && c.vehicle_params[0] != '/' && !config_dir.empty())
    c.vehicle_params = config_dir + "/" + c.vehicle_params;
  std::vector<std::string> names;
  if (pnh.getParam("planner/wheel_names", names)) {
    if (names.size() != kWheelCount) {
      if (error != nullptr)
        *error = "planner/wheel_names: " + std::to_string(names.size()) +
                 " names: must be 4 (front_left, front_right, rear_left, rear_right)";
      return false;
    }
    for (std::size_t i = 0; i < kWheelCount; ++i) c.wheel_names[i] = names[i];
  }
  pnh.param("planner/build_map", c.build_map, c.build_map);
  pnh.param("planner/map_temperature_step_c", c.map_temperature_step_c, c.map_temperature_step_c);
  pnh.param("planner/max_path_curvature_per_m", c.max_path_curvature_per_m, c.max_path_curvature_per_m);
  pnh.param("planner/map_threads", c.map_threads, c.map_threads);
  if (!c.validate(error)) return false;
  *config = c;
  return true;
}

struct NodePlanner::State {
  NodePlannerConfig config;
  WearMapParams map_params;
  std::vector<WheelPipeline*> vehicle_wheels;  ///< the node's wheel at each vehicle place
  bool available = false;
  std::string reason;
  VehicleWearSetup base;  ///< vehicle, tires, limits, model options (preset and temperatures set per use)
  MapCallback on_map;

  std::mutex direct_mutex;
  std::unique_ptr<TrajectoryCostEvaluator> direct;  ///< guarded by direct_mutex

  std::shared_ptr<const WearMap> map;  ///< std::atomic_load / std::atomic_store only
  std::atomic<std::uint32_t> map_version{0};

  mutable std::mutex build_mutex;
  std::condition_variable build_wanted;
  bool has_pending = false;      ///< guarded by build_mutex
  VehicleWearSetup pending;      ///< guarded by build_mutex
  bool has_requested = false;    ///< guarded by build_mutex: a setup was handed to the builder
  VehicleWearSetup requested;    ///< guarded by build_mutex: the last setup handed to the builder
  std::string build_error;       ///< guarded by build_mutex
  std::atomic<bool> cancel_build{false};
  bool stopping = false;         ///< guarded by build_mutex
  std::thread builder;

  /// The setup at the preset with the wheels' live temperatures at now_s.
  VehicleWearSetup currentSetup(Preset preset, double now_s) const;
  void builderLoop();
};

NodePlanner::NodePlanner(const NodePlannerConfig& config, const std::vector<std::unique_ptr<WheelPipeline>>& wheels,
                         const WearModelOptions& model, MapCallback on_map)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.config = config;
  s.on_map = std::move(on_map);
  s.map_params.build_threads = config.map_threads;
  if (!config.map_speed_mps.empty()) s.map_params.speed_mps = config.map_speed_mps;
  if (!config.map_accel_x_mps2.empty()) s.map_params.accel_x_mps2 = config.map_accel_x_mps2;
  if (!config.map_lateral_share.empty()) s.map_params.lateral_share = config.map_lateral_share;
  if (config.vehicle_params.empty()) {
    s.reason = "no vehicle parameters (set planner/vehicle_params, e.g. vehicle_passenger_car.yaml)";
    return;
  }
  if (!config.validate(&s.reason) || !s.map_params.validate(&s.reason)) return;
  std::vector<std::string> names;
  for (const auto& w : wheels) names.push_back(w->config().name);
  std::array<std::size_t, kWheelCount> index{};
  if (!matchVehicleWheels(names, config.wheel_names, &index, &s.reason)) return;
  try {
    s.base.vehicle = loadVehicleParams(config.vehicle_params);
    for (std::size_t i = 0; i < kWheelCount; ++i) {
      s.vehicle_wheels.push_back(wheels[index[i]].get());
      s.base.tires[i] = wheels[index[i]]->tire();
    }
    s.base.model = model;
    s.base.model.time_budget_s = 0.0;  // the planner's cost is exact at its preset; the budget is the loop's
    s.base.limits = wheels[index[0]]->estimatorParams().limits;
    s.base.max_path_curvature_per_m = config.max_path_curvature_per_m;
    s.direct = std::make_unique<TrajectoryCostEvaluator>(s.base);
  } catch (const std::exception& e) {
    s.reason = e.what();
    s.vehicle_wheels.clear();
    return;
  }
  s.available = true;
  if (config.build_map) s.builder = std::thread([this] { state_->builderLoop(); });
}

NodePlanner::~NodePlanner() { stop(); }

bool NodePlanner::available() const { return state_->available; }
const std::string& NodePlanner::reason() const { return state_->reason; }
std::shared_ptr<const WearMap> NodePlanner::map() const { return std::atomic_load(&state_->map); }
std::uint32_t NodePlanner::mapVersion() const { return state_->map_version.load(); }

void NodePlanner::stop() {
  State& s = *state_;
  {
    const std::lock_guard<std::mutex> lock(s.build_mutex);
    s.stopping = true;
    s.cancel_build = true;
  }
  s.build_wanted.notify_all();
  if (s.builder.joinable()) s.builder.join();
}

std::string NodePlanner::buildError() const {
  const std::lock_guard<std::mutex> lock(state_->build_mutex);
  return state_->build_error;
}

VehicleWearSetup NodePlanner::State::currentSetup(Preset preset, double now_s) const {
  VehicleWearSetup setup = base;
  setup.model.preset = preset;
  for (std::size_t i = 0; i < kWheelCount; ++i) {
    const WheelPipeline& w = *vehicle_wheels[i];
    // The live temperature as the live evaluation sees it: operatingPoint() drops a stale or invalid one (NaN).
    setup.tread_temperature_c[i] =
        operatingPoint(w.snapshot().inputs, now_s, w.estimatorParams().stale_timeout_s).tread_temperature_c;
  }
  return setup;
}

bool NodePlanner::refresh(Preset configured, double now_s) {
  State& s = *state_;
  if (!s.available || !s.config.build_map) return false;
  const VehicleWearSetup now = s.currentSetup(configured, now_s);
  const std::lock_guard<std::mutex> lock(s.build_mutex);
  if (s.has_requested) {
    bool same = s.requested.model.preset == now.model.preset;
    for (int i = 0; i < kWheelCount && same; ++i)
      same = sameTemperature(s.requested.effectiveTemperature(i), now.effectiveTemperature(i),
                             s.config.map_temperature_step_c);
    if (same) return false;
  }
  s.pending = now;
  s.has_pending = true;
  s.requested = now;
  s.has_requested = true;
  s.cancel_build = true;  // a build for an older setup is no longer wanted
  s.build_wanted.notify_all();
  return true;
}

void NodePlanner::State::builderLoop() {
  // Lowest CPU priority for this thread and the build threads it starts (Linux: nice is per thread and inherited),
  // so that a map build yields to the update loop, the spinner and everything else on the machine.
  setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 19);
  for (;;) {
    VehicleWearSetup setup;
    {
      std::unique_lock<std::mutex> lock(build_mutex);
      build_wanted.wait(lock, [this] { return has_pending || stopping; });
      if (stopping) return;
      setup = pending;
      has_pending = false;
      cancel_build = false;
    }
    try {
      std::shared_ptr<const WearMap> built = WearMap::build(setup, map_params, &cancel_build);
      if (!built) continue;  // cancelled: a newer setup is pending, or the node stops
      std::atomic_store(&map, built);
      const std::uint32_t version = ++map_version;
      {
        const std::lock_guard<std::mutex> lock(build_mutex);
        build_error.clear();
      }
      if (on_map) {
        tread_wear::PlannerWearMap message;
        std::array<std::string, NodePlannerConfig::kPlaces> names;
        for (std::size_t i = 0; i < kWheelCount; ++i) names[i] = vehicle_wheels[i]->config().name;
        fillWearMapMessage(*built, version, names, &message);
        on_map(message);
      }
    } catch (const std::exception& e) {
      const std::lock_guard<std::mutex> lock(build_mutex);
      build_error = e.what();
    }
  }
}

namespace {

void fillCost(const std::string& id, const TrajectoryCost& c, tread_wear::TrajectoryWearCost* m) {
  m->id = id;
  m->status = static_cast<std::uint8_t>(c.status);
  m->message = c.message;
  m->duration_s = c.duration_s;
  m->distance_m = c.distance_m;
  m->total_wear_kg = c.total_wear_kg;
  m->wear_per_distance_kg_per_m = c.wear_per_distance_kg_per_m;
  for (std::size_t i = 0; i < kWheelCount; ++i) {
    m->wheel_wear_kg[i] = c.wheel_wear_kg[i];
    m->stick_fraction[i] = c.stick_fraction[i];
    m->slide_fraction[i] = c.slide_fraction[i];
  }
}

/// The samples of a trajectory message; false with *error when its arrays differ in length.
bool samplesOf(const tread_wear::Trajectory& t, std::vector<TrajectorySample>* samples, std::string* error) {
  const std::size_t n = t.time_s.size();
  const bool has_grade = !t.grade_rad.empty();
  if (t.speed_mps.size() != n || t.accel_mps2.size() != n || t.path_curvature_per_m.size() != n ||
      (has_grade && t.grade_rad.size() != n)) {
    *error = "arrays of unequal length: time_s " + std::to_string(n) + ", speed_mps " +
             std::to_string(t.speed_mps.size()) + ", accel_mps2 " + std::to_string(t.accel_mps2.size()) +
             ", path_curvature_per_m " + std::to_string(t.path_curvature_per_m.size()) + ", grade_rad " +
             std::to_string(t.grade_rad.size()) + " (0 = flat road)";
    return false;
  }
  samples->resize(n);
  for (std::size_t k = 0; k < n; ++k)
    (*samples)[k] = {t.time_s[k], t.speed_mps[k], t.accel_mps2[k], t.path_curvature_per_m[k],
                     has_grade ? t.grade_rad[k] : 0.0};
  return true;
}

}  // namespace

void NodePlanner::evaluate(const tread_wear::EvaluateTrajectories::Request& req, Preset configured, double now_s,
                           tread_wear::EvaluateTrajectories::Response* res) {
  State& st = *state_;
  res->success = false;
  if (!st.available) {
    res->message = "planner unavailable: " + st.reason;
    return;
  }
  for (std::size_t i = 0; i < kWheelCount; ++i) res->wheels[i] = st.vehicle_wheels[i]->config().name;
  const std::string mode = req.mode.empty() ? "map" : req.mode;
  if (mode != "map" && mode != "direct") {
    res->message = "unknown mode '" + req.mode + "' (map or direct)";
    return;
  }
  res->mode = mode;
  std::shared_ptr<const WearMap> map;
  Preset preset = configured;
  if (mode == "map") {
    if (!req.preset.empty()) {
      res->message = "preset applies to mode direct only (the map is built at the configured preset)";
      return;
    }
    map = this->map();
    if (!map) {
      const std::string error = buildError();
      res->message = st.config.build_map ? "the wear map is not built yet" +
                                             (error.empty() ? std::string(" (first build after start)")
                                                            : " (last build failed: " + error + ")") +
                                             "; use mode direct"
                                       : "the wear map is off (planner/build_map false); use mode direct";
      return;
    }
    preset = map->setup().model.preset;
    res->map_fingerprint = fingerprintText(map->fingerprint());
    if (preset != configured)
      res->message = std::string("note: the map is being rebuilt for preset ") + presetName(configured) +
                     "; these costs are from the current map";
  } else if (!req.preset.empty() && !parsePreset(req.preset, &preset)) {
    res->message = "unknown preset '" + req.preset + "' (" + std::string(kPresetChoices) + ")";
    return;
  }
  res->preset = presetName(preset);

  std::unique_lock<std::mutex> direct_lock(st.direct_mutex, std::defer_lock);
  if (!map) {
    const VehicleWearSetup setup = st.currentSetup(preset, now_s);
    direct_lock.lock();
    st.direct->setPreset(preset);
    for (int i = 0; i < kWheelCount; ++i) st.direct->setTemperature(i, setup.tread_temperature_c[static_cast<std::size_t>(i)]);
  }
  res->costs.resize(req.trajectories.size());
  std::vector<TrajectorySample> samples;
  for (std::size_t t = 0; t < req.trajectories.size(); ++t) {
    const tread_wear::Trajectory& trajectory = req.trajectories[t];
    TrajectoryCost cost;
    std::string error;
    if (!samplesOf(trajectory, &samples, &error)) {
      cost.status = CostStatus::kBadInput;
      cost.message = error;
    } else {
      cost = map ? map->evaluate(samples.data(), samples.size()) : st.direct->evaluate(samples.data(), samples.size());
    }
    fillCost(trajectory.id, cost, &res->costs[t]);
  }
  res->success = true;
}

void fillWearMapMessage(const WearMap& map, std::uint32_t version,
                        const std::array<std::string, NodePlannerConfig::kPlaces>& wheels,
                        tread_wear::PlannerWearMap* m) {
  const WearMapParams& p = map.params();
  const VehicleWearSetup& setup = map.setup();
  m->fingerprint = fingerprintText(map.fingerprint());
  m->version = version;
  m->preset = presetName(setup.model.preset);
  for (std::size_t i = 0; i < kWheelCount; ++i) {
    m->wheels[i] = wheels[i];
    m->tread_temperature_c[i] = setup.effectiveTemperature(static_cast<int>(i));
  }
  m->build_time_s = map.buildTime_s();
  m->max_path_curvature_per_m = setup.max_path_curvature_per_m;
  m->max_lateral_accel_mps2 = p.max_lateral_accel_mps2;
  m->wear_floor_kg_per_s = p.wear_floor_kg_per_s;
  m->speed_mps = p.speed_mps;
  m->accel_x_mps2 = p.accel_x_mps2;
  m->lateral_share = p.lateral_share;
  const std::size_t nodes = map.nodeCount();
  m->wear_rate_kg_per_s.resize(kWheelCount * nodes);
  m->stick_fraction.resize(kWheelCount * nodes);
  for (int w = 0; w < kWheelCount; ++w)
    for (std::size_t node = 0; node < nodes; ++node) {
      m->wear_rate_kg_per_s[static_cast<std::size_t>(w) * nodes + node] = map.nodeWearRate_kg_per_s(w, node);
      m->stick_fraction[static_cast<std::size_t>(w) * nodes + node] = map.nodeStickFraction(w, node);
    }
}

}  // namespace tread_wear
