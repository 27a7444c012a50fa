#include "tread_wear/ros/tread_wear_node.h"

#include <geometry_msgs/TransformStamped.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "tread_wear/io/params_io.h"
#include "tread_wear/ros/wear_markers.h"

namespace tread_wear {
namespace {

double steadyNow_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double wallNow_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

/// Longest tire id the loop copies without allocating (the message strings are reserved to this).
constexpr std::size_t kMaxTireIdLength = 63;

std::uint8_t toMsgStatus(WheelStatus s) {
  switch (s) {
    case WheelStatus::kOk: return tread_wear::WheelWear::STATUS_OK;
    case WheelStatus::kLowSpeed: return tread_wear::WheelWear::STATUS_LOW_SPEED;
    case WheelStatus::kNoInput: return tread_wear::WheelWear::STATUS_NO_INPUT;
    case WheelStatus::kStaleInput: return tread_wear::WheelWear::STATUS_STALE_INPUT;
    case WheelStatus::kInvalidInput: return tread_wear::WheelWear::STATUS_INVALID_INPUT;
    case WheelStatus::kTimeJump: return tread_wear::WheelWear::STATUS_TIME_JUMP;
  }
  return tread_wear::WheelWear::STATUS_INVALID_INPUT;
}

void atomicMax(std::atomic<double>& a, double v) {
  double cur = a.load(std::memory_order_relaxed);
  while (v > cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}

/// Pre-sizes a wheel message's strings so that the loop's assignments never allocate.
void reserveStrings(tread_wear::WheelWear* m) {
  m->header.frame_id.reserve(128);
  m->wheel.reserve(128);
  m->tire_id.reserve(kMaxTireIdLength + 1);
  m->preset.reserve(16);
}

}  // namespace

TreadWearNode::TreadWearNode(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh), pnh_(pnh) {}

TreadWearNode::~TreadWearNode() { shutdown(); }

bool TreadWearNode::loadWheel(const WheelConfig& config, Wheel* wheel) {
  wheel->config = config;
  try {
    const TireParams tire = loadTireParams(config.tire_params);
    WearModelOptions options;
    options.preset = config_.preset;
    options.orientation = config_.orientation;
    options.min_speed_mps = config_.min_speed_mps;
    wheel->model = std::make_unique<WearModel>(tire, options);
    wheel->planner_model = std::make_unique<WearModel>(tire, options);
    wheel->marker_model = std::make_unique<WearModel>(tire, options);
    wheel->estimator = std::make_unique<WheelEstimator>(config_.estimator, tire.material);
  } catch (const std::exception& e) {
    ROS_FATAL("wheel %s: cannot load tire parameters '%s': %s", config.name.c_str(), config.tire_params.c_str(),
              e.what());
    return false;
  }
  if (config.tire_id.size() > kMaxTireIdLength) {
    ROS_FATAL("wheel %s: tire_id '%s' is longer than %zu characters", config.name.c_str(), config.tire_id.c_str(),
              kMaxTireIdLength);
    return false;
  }
  wheel->inputs = WheelInputs(config_.estimator.limits);
  wheel->loop_inputs = wheel->inputs;
  wheel->last_step_inputs = wheel->inputs;
  wheel->tire_id = config.tire_id;
  wheel->active_preset = static_cast<int>(config_.preset);
  return true;
}

bool TreadWearNode::initialize() {
  std::string error;
  if (!NodeConfig::load(pnh_, &config_, &error)) {
    ROS_FATAL("tread_wear_node: invalid configuration: %s", error.c_str());
    return false;
  }
  ROS_INFO_STREAM("tread_wear_node parameters:\n" << config_.describe());
  for (const WheelConfig& wc : config_.wheels) {
    auto wheel = std::make_unique<Wheel>();
    if (!loadWheel(wc, wheel.get())) return false;
    wheels_.push_back(std::move(wheel));
  }
  period_s_ = 1.0 / config_.update_rate_hz;
  budget_us_ = config_.budget_us;
  configured_preset_ = static_cast<int>(config_.preset);

  if (!config_.state_file.empty()) {
    store_ = std::make_unique<StateStore>(config_.state_file);
    restoreState();
  }

  // Outputs, with every message preallocated for the loop.
  vehicle_publisher_ = std::make_unique<RealtimePublisher<tread_wear::VehicleWear>>(nh_, "wear", 10);
  vehicle_publisher_->msg().header.frame_id = config_.base_frame;
  vehicle_publisher_->msg().wheels.resize(wheels_.size());
  for (auto& m : vehicle_publisher_->msg().wheels) reserveStrings(&m);
  for (auto& w : wheels_) {
    w->publisher = std::make_unique<RealtimePublisher<tread_wear::WheelWear>>(nh_, w->config.wear_topic, 10);
    reserveStrings(&w->publisher->msg());
  }

  // Inputs: validated and counted on arrival, stamped with the node's clock (sim time under replay).
  for (auto& wp : wheels_) {
    Wheel* w = wp.get();
    const std::string& name = w->config.name;
    auto warn = [name](InputKind kind, InputFault fault) {
      if (fault != InputFault::kNone)
        ROS_WARN_THROTTLE(5.0, "wheel %s: rejected %s input (%s); the wheel is not evaluated until a valid one arrives",
                          name.c_str(), inputKindName(kind), inputFaultName(fault));
    };
    w->load_sub = nh_.subscribe<tread_wear::WheelLoad>(
        w->config.load_topic, 10, [w, warn](const tread_wear::WheelLoad::ConstPtr& m) {
          InputFault f;
          {
            std::lock_guard<std::mutex> lock(w->input_mutex);
            f = w->inputs.setLoad(ros::Time::now().toSec(), m->load_n);
          }
          warn(InputKind::kLoad, f);
        });
    w->slip_sub = nh_.subscribe<tread_wear::WheelSlip>(
        w->config.slip_topic, 10, [w, warn](const tread_wear::WheelSlip::ConstPtr& m) {
          InputFault f;
          {
            std::lock_guard<std::mutex> lock(w->input_mutex);
            f = w->inputs.setSlip(ros::Time::now().toSec(), m->slip_angle_rad, m->slip_ratio, m->path_curvature_per_m);
          }
          warn(InputKind::kSlip, f);
        });
    w->speed_sub = nh_.subscribe<tread_wear::WheelSpeed>(
        w->config.speed_topic, 10, [w, warn](const tread_wear::WheelSpeed::ConstPtr& m) {
          InputFault f;
          {
            std::lock_guard<std::mutex> lock(w->input_mutex);
            f = w->inputs.setSpeed(ros::Time::now().toSec(), m->speed_mps);
          }
          warn(InputKind::kSpeed, f);
        });
    w->temperature_sub = nh_.subscribe<tread_wear::TreadTemperature>(
        w->config.temperature_topic, 10, [w, warn](const tread_wear::TreadTemperature::ConstPtr& m) {
          InputFault f;
          {
            std::lock_guard<std::mutex> lock(w->input_mutex);
            f = w->inputs.setTemperature(ros::Time::now().toSec(), m->temperature_c);
          }
          warn(InputKind::kTemperature, f);
        });
  }

  evaluate_service_ = nh_.advertiseService("evaluate_wear", &TreadWearNode::evaluateWear, this);
  reset_service_ = nh_.advertiseService("reset_wheel", &TreadWearNode::resetWheel, this);

  updater_ = std::make_unique<diagnostic_updater::Updater>(nh_, pnh_);
  updater_->setHardwareID("tread_wear");
  updater_->add("update loop", this, &TreadWearNode::diagnoseLoop);
  updater_->add("persistence", this, &TreadWearNode::diagnosePersistence);
  for (auto& wp : wheels_) {
    Wheel* w = wp.get();
    updater_->add("wheel " + w->config.name,
                  [this, w](diagnostic_updater::DiagnosticStatusWrapper& stat) { diagnoseWheel(*w, stat); });
  }
  // force_update on a wall timer: Updater::update() follows ROS time and would stall after a backward
  // sim-time jump (a looping bag) until the clock caught up again.
  diagnostics_timer_ = nh_.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) {
    updater_->force_update();
  });

  if (config_.marker_rate_hz > 0.0) {
    marker_publisher_ = nh_.advertise<visualization_msgs::MarkerArray>("wear_markers", 2);
    marker_timer_ = nh_.createTimer(ros::Duration(1.0 / config_.marker_rate_hz), &TreadWearNode::publishMarkers, this);
  }
  if (store_) {
    save_timer_ = nh_.createWallTimer(ros::WallDuration(config_.save_interval_s),
                                      [this](const ros::WallTimerEvent&) { saveState("periodic"); });
  }
  broadcastWheelFrames();

  // The update loop on its own queue and thread.
  ros::NodeHandle loop_nh(nh_);
  loop_nh.setCallbackQueue(&loop_queue_);
  loop_timer_ = loop_nh.createTimer(ros::Duration(period_s_.load()), &TreadWearNode::loop, this);
  loop_running_ = true;
  loop_thread_ = std::thread([this] {
    while (loop_running_ && ros::ok()) loop_queue_.callAvailable(ros::WallDuration(0.05));
  });

  // Last: the server calls reconfigure() at once with the parameter server's values.
  reconfigure_server_ =
      std::make_unique<dynamic_reconfigure::Server<tread_wear::TreadWearConfig>>(reconfigure_mutex_, pnh_);
  reconfigure_server_->setCallback(
      [this](tread_wear::TreadWearConfig& c, uint32_t level) { reconfigure(c, level); });
  ROS_INFO("tread_wear_node: %zu wheel(s), running at %.1f Hz", wheels_.size(), config_.update_rate_hz);
  return true;
}

void TreadWearNode::restoreState() {
  const LoadResult r = store_->load();
  std::ostringstream report;
  switch (r.status) {
    case LoadStatus::kLoaded: ROS_INFO("%s", r.message.c_str()); break;
    case LoadStatus::kMissing: ROS_INFO("%s", r.message.c_str()); break;
    case LoadStatus::kCorrupt:
    case LoadStatus::kIncompatible: {
      ROS_ERROR("%s. Accumulated loss starts from zero; recover the old values from the moved file by hand.",
                r.message.c_str());
      std::lock_guard<std::mutex> lock(save_mutex_);
      persistence_problem_ = r.message;
      break;
    }
    case LoadStatus::kIoError: {
      // The file is still there and may be good: never overwrite it with zeros.
      ROS_ERROR("%s. Saving is disabled so the file is not overwritten.", r.message.c_str());
      std::lock_guard<std::mutex> lock(save_mutex_);
      persistence_problem_ = r.message + " (saving disabled)";
      store_.reset();
      break;
    }
  }
  report << loadStatusName(r.status);
  saved_state_ = r.state;
  for (auto& w : wheels_) {
    const WheelRecord* rec = saved_state_.find(w->config.name);
    if (rec == nullptr) continue;
    w->estimator->restore({rec->accumulated_loss_kg, rec->distance_m});
    if (rec->tire_id != w->config.tire_id)
      ROS_INFO("wheel %s: saved tire_id '%s' replaces the configured '%s'", w->config.name.c_str(),
               rec->tire_id.c_str(), w->config.tire_id.c_str());
    w->tire_id = rec->tire_id.substr(0, kMaxTireIdLength);
    w->reset_unix_s = rec->reset_unix_s;
    ROS_INFO("wheel %s: restored accumulated loss %.9g kg over %.6g m (tire %s)", w->config.name.c_str(),
             rec->accumulated_loss_kg, rec->distance_m, rec->tire_id.c_str());
  }
  for (const WheelRecord& rec : saved_state_.wheels) {
    bool configured = false;
    for (auto& w : wheels_) configured = configured || w->config.name == rec.name;
    if (!configured)
      ROS_WARN("state file has wheel '%s' which is not configured: kept in the file, not estimated",
               rec.name.c_str());
  }
  restore_report_ = report.str();
}

void TreadWearNode::broadcastWheelFrames() {
  std::vector<geometry_msgs::TransformStamped> transforms;
  for (auto& w : wheels_) {
    if (!w->config.has_position) continue;
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time::now();
    t.header.frame_id = config_.base_frame;
    t.child_frame_id = w->config.frame_id;
    t.transform.translation.x = w->config.position_m[0];
    t.transform.translation.y = w->config.position_m[1];
    t.transform.translation.z = w->config.position_m[2];
    t.transform.rotation.w = 1.0;
    transforms.push_back(t);
  }
  if (transforms.empty()) return;
  tf_broadcaster_ = std::make_unique<tf2_ros::StaticTransformBroadcaster>();
  tf_broadcaster_->sendTransform(transforms);
}

void TreadWearNode::reconfigure(tread_wear::TreadWearConfig& c, uint32_t) {
  Preset preset;
  if (!parsePreset(c.preset, &preset)) {
    ROS_WARN("dynamic_reconfigure: unknown preset '%s', keeping %s", c.preset.c_str(),
             presetName(static_cast<Preset>(configured_preset_.load())));
    c.preset = presetName(static_cast<Preset>(configured_preset_.load()));
    preset = static_cast<Preset>(configured_preset_.load());
  }
  configured_preset_ = static_cast<int>(preset);
  budget_us_ = c.budget_us;
  if (std::fabs(c.update_rate_hz - 1.0 / period_s_.load()) > 1e-9) {
    period_s_ = 1.0 / c.update_rate_hz;
    loop_timer_.setPeriod(ros::Duration(period_s_.load()));
  }
  ROS_INFO("dynamic_reconfigure: update_rate_hz %.3f [Hz], budget_us %.1f [us], preset %s", c.update_rate_hz,
           c.budget_us, c.preset.c_str());
}

void TreadWearNode::countOverrun(Wheel& wheel, double eval_us) {
  // Deadline of one evaluation: the budget when set, else the wheel's share of the update period.
  const double budget = budget_us_.load(std::memory_order_relaxed);
  const double limit_us = budget > 0.0 ? budget : 1e6 * period_s_.load() / static_cast<double>(wheels_.size());
  if (eval_us > limit_us) wheel.overruns.fetch_add(1, std::memory_order_relaxed);
}

void TreadWearNode::fillWheelMessage(Wheel& wheel, const WheelOutput& out, const ros::Time& stamp,
                                     tread_wear::WheelWear* m) {
  m->header.stamp = stamp;
  if (m->wheel != wheel.config.name) {  // first cycle only (capacity reserved at start-up)
    m->header.frame_id = wheel.config.frame_id;
    m->wheel = wheel.config.name;
  }
  m->tire_id = wheel.tire_id;
  m->wear_rate_kg_per_m = out.result.wear_rate_kg_per_m;
  m->wear_rate_kg_per_s = out.result.wear_rate_kg_per_s;
  m->accumulated_loss_kg = out.accumulated_loss_kg;
  m->tread_depth_loss_m = out.tread_depth_loss_m;
  m->remaining_tread_depth_m = out.remaining_tread_depth_m;
  m->distance_m = out.distance_m;
  m->stick_fraction = out.result.stick_fraction;
  m->slide_fraction = out.result.slide_fraction;
  m->exact_stick_fraction = out.result.exact_stick_fraction;
  m->fx_n = out.result.fx_n;
  m->fy_n = out.result.fy_n;
  m->mz_nm = out.result.mz_nm;
  m->preset = presetName(out.preset);
  m->degraded = static_cast<int>(out.preset) < configured_preset_.load(std::memory_order_relaxed);
  m->status = toMsgStatus(out.status);
  m->unaccounted_time_s = wheel.estimator->unaccountedTime_s();
}

void TreadWearNode::loop(const ros::TimerEvent&) {
  const double cycle_start = steadyNow_s();
  const ros::Time stamp = ros::Time::now();
  const double now_s = stamp.toSec();
  const bool vehicle_slot = vehicle_publisher_->trylock();
  if (!vehicle_slot) vehicle_publisher_->countSkip();
  double total_rate_s = 0.0, total_rate_m = 0.0, total_loss = 0.0;
  for (std::size_t i = 0; i < wheels_.size(); ++i) {
    Wheel& w = *wheels_[i];
    {
      std::lock_guard<std::mutex> lock(w.input_mutex);
      w.loop_inputs = w.inputs;
    }
    // Apply live reconfiguration (plain stores in the model, no allocation). The model's time budget picks
    // the finest preset whose measured time fits (wear_model.h).
    const Preset wanted = static_cast<Preset>(configured_preset_.load(std::memory_order_relaxed));
    if (w.model->wantedPreset() != wanted) w.model->setPreset(wanted);
    const double budget_s = 1e-6 * budget_us_.load(std::memory_order_relaxed);
    if (w.model->timeBudget() != budget_s) w.model->setTimeBudget(budget_s);
    std::lock_guard<std::mutex> lock(w.state_mutex);
    const double t0 = steadyNow_s();
    const WheelOutput& out = w.estimator->step(now_s, w.loop_inputs, *w.model);
    const double eval_us = 1e6 * (steadyNow_s() - t0);
    w.last_step_inputs = w.loop_inputs;
    if (out.evaluated) {
      w.last_eval_us.store(eval_us, std::memory_order_relaxed);
      atomicMax(w.max_eval_us, eval_us);
      countOverrun(w, eval_us);
      w.active_preset.store(static_cast<int>(w.model->activePreset()), std::memory_order_relaxed);
      w.degraded_count.store(w.model->degradedCount(), std::memory_order_relaxed);
    }
    if (w.publisher->trylock()) {
      fillWheelMessage(w, out, stamp, &w.publisher->msg());
      w.publisher->unlockAndPublish();
    } else {
      w.publisher->countSkip();
    }
    if (vehicle_slot) fillWheelMessage(w, out, stamp, &vehicle_publisher_->msg().wheels[i]);
    total_rate_s += out.result.wear_rate_kg_per_s;
    total_rate_m += out.result.wear_rate_kg_per_m;
    total_loss += out.accumulated_loss_kg;
  }
  if (vehicle_slot) {
    tread_wear::VehicleWear& v = vehicle_publisher_->msg();
    v.header.stamp = stamp;
    v.total_wear_rate_kg_per_s = total_rate_s;
    v.total_wear_rate_kg_per_m = total_rate_m;
    v.total_accumulated_loss_kg = total_loss;
    vehicle_publisher_->unlockAndPublish();
  }
  const double cycle_us = 1e6 * (steadyNow_s() - cycle_start);
  last_cycle_us_.store(cycle_us, std::memory_order_relaxed);
  atomicMax(max_cycle_us_, cycle_us);
  cycles_.fetch_add(1, std::memory_order_relaxed);
  if (cycle_us > 1e6 * period_s_.load(std::memory_order_relaxed))
    cycle_overruns_.fetch_add(1, std::memory_order_relaxed);
}

bool TreadWearNode::evaluateWear(tread_wear::EvaluateWear::Request& req, tread_wear::EvaluateWear::Response& res) {
  Wheel* wheel = nullptr;
  for (auto& w : wheels_)
    if (w->config.name == req.wheel) wheel = w.get();
  if (wheel == nullptr) {
    res.success = false;
    res.message = "unknown wheel '" + req.wheel + "'";
    return true;
  }
  Preset preset = static_cast<Preset>(configured_preset_.load());
  if (!req.preset.empty() && !parsePreset(req.preset, &preset)) {
    res.success = false;
    res.message = "unknown preset '" + req.preset + "' (" + std::string(kPresetChoices) + ")";
    return true;
  }
  std::lock_guard<std::mutex> lock(wheel->planner_mutex);
  wheel->planner_model->setPreset(preset);
  res.preset = presetName(preset);
  res.results.resize(req.states.size());
  for (std::size_t k = 0; k < req.states.size(); ++k) {
    const tread_wear::WheelState& s = req.states[k];
    tread_wear::WheelWearRate& r = res.results[k];
    OperatingPoint op;
    op.load_n = s.load_n;
    op.speed_mps = s.speed_mps;
    op.slip_angle_rad = s.slip_angle_rad;
    op.slip_ratio = s.slip_ratio;
    op.path_curvature_per_m = s.path_curvature_per_m;
    op.tread_temperature_c = s.tread_temperature_c;
    WearResult result;
    std::string error;
    if (op.load_n == 0.0) {  // wheel off the ground: no force, no wear (as in the live estimator)
      op.load_n = 1.0;
      if (!op.validate(&error)) {
        r.status = r.STATUS_INVALID_INPUT;
        r.error = error;
        continue;
      }
      r.status = r.STATUS_OK;
      r.stick_fraction = 1.0;
      r.exact_stick_fraction = 1.0;
      continue;
    }
    if (!op.validate(&error)) {
      r.status = r.STATUS_INVALID_INPUT;
      r.error = error;
      continue;
    }
    const EvalStatus st = wheel->planner_model->evaluate(op, &result);
    r.status = st == EvalStatus::kLowSpeed ? r.STATUS_LOW_SPEED : r.STATUS_OK;
    r.wear_rate_kg_per_m = result.wear_rate_kg_per_m;
    r.wear_rate_kg_per_s = result.wear_rate_kg_per_s;
    r.fx_n = result.fx_n;
    r.fy_n = result.fy_n;
    r.mz_nm = result.mz_nm;
    r.stick_fraction = result.stick_fraction;
    r.slide_fraction = result.slide_fraction;
    r.exact_stick_fraction = result.exact_stick_fraction;
  }
  res.success = true;
  return true;
}

bool TreadWearNode::resetWheel(tread_wear::ResetWheel::Request& req, tread_wear::ResetWheel::Response& res) {
  Wheel* wheel = nullptr;
  for (auto& w : wheels_)
    if (w->config.name == req.wheel) wheel = w.get();
  if (wheel == nullptr || req.tire_id.empty() || req.tire_id.size() > kMaxTireIdLength) {
    res.success = false;
    res.message = wheel == nullptr ? "unknown wheel '" + req.wheel + "'"
                                   : "tire_id must be 1 to " + std::to_string(kMaxTireIdLength) + " characters";
    return true;
  }
  std::string old_tire;
  {
    std::lock_guard<std::mutex> lock(wheel->state_mutex);
    const WheelAccumulators old = wheel->estimator->accumulators();
    res.previous_loss_kg = old.accumulated_loss_kg;
    res.previous_distance_m = old.distance_m;
    old_tire = wheel->tire_id;
    wheel->estimator->reset();
    wheel->tire_id = req.tire_id;
    wheel->reset_unix_s = wallNow_s();
  }
  std::ostringstream msg;
  msg.precision(9);
  msg << "wheel " << req.wheel << ": tire change " << old_tire << " -> " << req.tire_id
      << "; the removed tire lost " << res.previous_loss_kg << " kg over " << res.previous_distance_m << " m";
  res.message = msg.str();
  res.success = true;
  ROS_WARN("%s", res.message.c_str());  // a tire change is an event worth seeing in every log
  if (store_) saveState("tire change");
  return true;
}

void TreadWearNode::saveState(const char* reason) {
  if (!store_) return;
  std::lock_guard<std::mutex> save_lock(save_mutex_);
  StateFile state = saved_state_;
  for (auto& w : wheels_) {
    WheelRecord rec;
    {
      std::lock_guard<std::mutex> lock(w->state_mutex);
      const WheelAccumulators a = w->estimator->accumulators();
      rec = {w->config.name, w->tire_id, a.accumulated_loss_kg, a.distance_m, w->reset_unix_s};
    }
    if (WheelRecord* existing = state.find(rec.name)) {
      *existing = rec;
    } else {
      state.wheels.push_back(rec);
    }
  }
  std::string error;
  if (store_->save(state, &error)) {
    saved_state_ = state;
    last_save_wall_s_ = wallNow_s();
    if (!persistence_problem_.empty() && persistence_problem_.rfind("save failed", 0) == 0)
      persistence_problem_.clear();
    ROS_DEBUG("state saved (%s) to %s", reason, store_->path().c_str());
  } else {
    persistence_problem_ = "save failed: " + error;
    ROS_ERROR_THROTTLE(30.0, "cannot save the wear state (%s): %s", reason, error.c_str());
  }
}

void TreadWearNode::publishMarkers(const ros::TimerEvent&) {
  if (marker_publisher_.getNumSubscribers() == 0) return;
  visualization_msgs::MarkerArray array;
  const ros::Time stamp = ros::Time::now();
  for (auto& w : wheels_) {
    WheelInputs inputs;
    WheelOutput out;
    {
      std::lock_guard<std::mutex> lock(w->state_mutex);
      inputs = w->last_step_inputs;
      out = w->estimator->output();
    }
    PatchFields fields;
    WearResult result = out.result;
    if (out.evaluated && inputs.load_n() > 0.0) {
      OperatingPoint op;
      op.load_n = inputs.load_n();
      op.speed_mps = inputs.speed_mps();
      op.slip_angle_rad = inputs.slipAngle_rad();
      op.slip_ratio = inputs.slipRatio();
      op.path_curvature_per_m = inputs.pathCurvature_per_m();
      w->marker_model->setPreset(out.preset);
      const BrushWearModel& solver = w->marker_model->solver(out.preset);
      fields.resize(solver.nodesX(), solver.strips());
      w->marker_model->evaluate(op, &result, &fields);
    }
    appendWheelMarkers(w->config.name, w->config.frame_id, stamp, fields, result, out, &array);
  }
  marker_publisher_.publish(array);
}

void TreadWearNode::diagnoseWheel(Wheel& w, diagnostic_updater::DiagnosticStatusWrapper& stat) {
  WheelInputs inputs;
  {
    std::lock_guard<std::mutex> lock(w.input_mutex);
    inputs = w.inputs;
  }
  WheelOutput out;
  std::uint64_t backward, forward, stale, evaluations;
  double unaccounted;
  std::string tire_id;
  {
    std::lock_guard<std::mutex> lock(w.state_mutex);
    out = w.estimator->output();
    backward = w.estimator->backwardJumps();
    forward = w.estimator->forwardJumps();
    stale = w.estimator->staleSteps();
    evaluations = w.estimator->evaluations();
    unaccounted = w.estimator->unaccountedTime_s();
    tire_id = w.tire_id;
  }
  const double wall = steadyNow_s();
  const double dt = w.last_diag_wall_s > 0.0 ? wall - w.last_diag_wall_s : 0.0;
  const double now_s = ros::Time::now().toSec();
  stat.add("tire_id", tire_id);
  stat.add("status", wheelStatusName(out.status));
  for (InputKind kind : {InputKind::kLoad, InputKind::kSlip, InputKind::kSpeed, InputKind::kTemperature}) {
    const WheelInputs::Sample& s = inputs.sample(kind);
    const int k = static_cast<int>(kind);
    const double rate = dt > 0.0 ? static_cast<double>(s.received - w.last_received[k]) / dt : 0.0;
    w.last_received[k] = s.received;
    stat.addf(std::string(inputKindName(kind)) + " rate [Hz]", "%.1f", rate);
    if (s.received > 0 && s.valid)
      stat.addf(std::string(inputKindName(kind)) + " age [s]", "%.3f", now_s - s.stamp_s);
    else
      stat.add(std::string(inputKindName(kind)) + " age [s]", s.received == 0 ? "never received" : "invalid");
    stat.add(std::string(inputKindName(kind)) + " rejected", s.rejected);
  }
  for (int f = 1; f < kInputFaultCount; ++f)
    if (inputs.faultCount(static_cast<InputFault>(f)) > 0)
      stat.add(std::string("invalid: ") + inputFaultName(static_cast<InputFault>(f)),
               inputs.faultCount(static_cast<InputFault>(f)));
  stat.add("stale steps", stale);
  stat.add("time jumps backward", backward);
  stat.add("time jumps forward", forward);
  stat.addf("unaccounted time [s]", "%.3f", unaccounted);
  stat.add("evaluations", evaluations);
  stat.addf("last evaluation [us]", "%.1f", w.last_eval_us.load());
  stat.addf("max evaluation [us]", "%.1f", w.max_eval_us.load());
  stat.add("deadline overruns", w.overruns.load());
  const Preset active = static_cast<Preset>(w.active_preset.load());
  const Preset configured = static_cast<Preset>(configured_preset_.load());
  stat.add("preset", presetName(active));
  stat.add("degraded", active < configured ? "true" : "false");
  stat.add("degraded evaluations", w.degraded_count.load());
  stat.addf("accumulated loss [kg]", "%.9g", out.accumulated_loss_kg);
  stat.addf("distance [m]", "%.6g", out.distance_m);
  stat.addf("remaining tread depth [m]", "%.6g", out.remaining_tread_depth_m);

  const std::uint64_t rejected = inputs.totalRejected();
  const bool new_rejects = rejected > w.last_rejected;
  const bool new_jump = backward > w.last_backward || forward > w.last_forward;
  if (new_jump)
    ROS_WARN_THROTTLE(5.0, "wheel %s: clock jumped (%llu backward, %llu forward so far); accumulated state kept, "
                      "integration restarted", w.config.name.c_str(), static_cast<unsigned long long>(backward),
                      static_cast<unsigned long long>(forward));
  w.last_rejected = rejected;
  w.last_backward = backward;
  w.last_forward = forward;
  w.last_diag_wall_s = wall;

  switch (out.status) {
    case WheelStatus::kOk:
    case WheelStatus::kLowSpeed:
      if (new_rejects)
        stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "invalid inputs rejected");
      else if (active < configured)
        stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "preset degraded by the time budget");
      else
        stat.summary(diagnostic_msgs::DiagnosticStatus::OK, out.status == WheelStatus::kOk ? "ok" : "low speed");
      break;
    case WheelStatus::kNoInput: stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "waiting for inputs"); break;
    case WheelStatus::kStaleInput:
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "stale input: not evaluated");
      ROS_WARN_THROTTLE(5.0, "wheel %s: inputs older than %.3f s; not evaluated, time not integrated",
                        w.config.name.c_str(), config_.estimator.stale_timeout_s);
      break;
    case WheelStatus::kInvalidInput:
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "invalid input: not evaluated");
      break;
    case WheelStatus::kTimeJump: stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "time jump"); break;
  }
}

void TreadWearNode::diagnoseLoop(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const std::uint64_t overruns = cycle_overruns_.load();
  stat.add("cycles", cycles_.load());
  stat.addf("update rate [Hz]", "%.3f", 1.0 / period_s_.load());
  stat.addf("budget [us]", "%.1f", budget_us_.load());
  stat.addf("last cycle [us]", "%.1f", last_cycle_us_.load());
  stat.addf("max cycle [us]", "%.1f", max_cycle_us_.load());
  stat.add("cycle overruns", overruns);
  std::uint64_t skipped = vehicle_publisher_->skipped();
  for (auto& w : wheels_) skipped += w->publisher->skipped();
  stat.add("skipped publications", skipped);
  if (overruns > last_cycle_overruns_) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "update cycle exceeded its period");
    ROS_WARN_THROTTLE(10.0, "update loop: %llu cycle(s) longer than the period so far (max %.0f us)",
                      static_cast<unsigned long long>(overruns), max_cycle_us_.load());
  } else {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "ok");
  }
  last_cycle_overruns_ = overruns;
}

void TreadWearNode::diagnosePersistence(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(save_mutex_);
  stat.add("state_file", config_.state_file.empty() ? "(persistence off)" : config_.state_file);
  stat.add("restore", restore_report_);
  stat.addf("seconds since last save", "%.1f", last_save_wall_s_ > 0.0 ? wallNow_s() - last_save_wall_s_ : -1.0);
  if (!persistence_problem_.empty())
    stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, persistence_problem_);
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, store_ ? "ok" : "persistence off");
}

void TreadWearNode::shutdown() {
  if (shut_down_.exchange(true)) return;
  loop_running_ = false;
  loop_timer_.stop();
  if (loop_thread_.joinable()) loop_thread_.join();
  save_timer_.stop();
  diagnostics_timer_.stop();
  marker_timer_.stop();
  saveState("shutdown");
  if (vehicle_publisher_) vehicle_publisher_->stop();
  for (auto& w : wheels_)
    if (w->publisher) w->publisher->stop();
}

}  // namespace tread_wear
