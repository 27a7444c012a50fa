#include "tread_wear/ros/tread_wear_node.h"

#include <visualization_msgs/MarkerArray.h>

#include <cstdint>

#include <std_srvs/SetBool.h>

#include "tread_wear/InputProgress.h"
#include "tread_wear/TreadTemperature.h"
#include "tread_wear/WheelLoad.h"
#include "tread_wear/WheelSlip.h"
#include "tread_wear/WheelSpeed.h"
#include "tread_wear/pipeline/loop_clock.h"
#include "tread_wear/ros/node_config.h"
#include "tread_wear/ros/node_services.h"
#include "tread_wear/ros/ros_log.h"

namespace tread_wear {

TreadWearNode::TreadWearNode(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh), pnh_(pnh) {}

TreadWearNode::~TreadWearNode() { shutdown(); }

bool TreadWearNode::initialize() {
  std::string error;
  if (!loadNodeConfig(pnh_, &config_, &error)) {
    ROS_FATAL("tread_wear_node: invalid configuration: %s", error.c_str());
    return false;
  }
  ROS_INFO_STREAM("tread_wear_node parameters:\n" << config_.describe());
  try {
    for (const WheelConfig& wc : config_.wheels) wheels_.push_back(WheelPipeline::load(wc, config_));
  } catch (const std::exception& e) {
    ROS_FATAL("tread_wear_node: %s", e.what());
    return false;
  }
  persistence_ = std::make_unique<NodePersistence>(config_.state_file, rosconsoleSink());
  persistence_->restore(wheels_);
  reconfigure_ = std::make_unique<NodeReconfigure>(config_, &loop_status_);

  // Outputs, with every message preallocated for the loop.
  vehicle_publisher_ = std::make_unique<RealtimePublisher<tread_wear::VehicleWear>>(
      nh_.advertise<tread_wear::VehicleWear>("wear", 10));
  vehicle_publisher_->msg().header.frame_id = config_.base_frame;
  vehicle_publisher_->msg().wheels.resize(wheels_.size());
  for (auto& m : vehicle_publisher_->msg().wheels) reserveStrings(&m);
  for (auto& w : wheels_) {
    wheel_publishers_.push_back(std::make_unique<RealtimePublisher<tread_wear::WheelWear>>(
        nh_.advertise<tread_wear::WheelWear>(w->config().wear_topic, 10)));
    reserveStrings(&wheel_publishers_.back()->msg());
  }
  for (auto& w : wheels_) subscribeInputs(w.get());

  evaluate_service_ = nh_.advertiseService<tread_wear::EvaluateWear::Request, tread_wear::EvaluateWear::Response>(
      "evaluate_wear", [this](tread_wear::EvaluateWear::Request& req, tread_wear::EvaluateWear::Response& res) {
        evaluateWear(wheels_, loop_status_.configuredPreset(), req, &res);
        return true;
      });
  reset_service_ = nh_.advertiseService<tread_wear::ResetWheel::Request, tread_wear::ResetWheel::Response>(
      "reset_wheel", [this](tread_wear::ResetWheel::Request& req, tread_wear::ResetWheel::Response& res) {
        if (resetWheel(wheels_, wallNow_s(), req, &res)) {
          ROS_WARN("%s", res.message.c_str());  // a tire change is an event worth seeing in every log
          persistence_->save(wheels_, "tire change");
        }
        return true;
      });

  startPlanner();
  diagnostics_ = std::make_unique<NodeDiagnostics>(wheels_, loop_status_, *persistence_, *reconfigure_);
  updater_ = std::make_unique<diagnostic_updater::Updater>(nh_, pnh_);
  diagnostics_->addTo(updater_.get());
  // force_update on a wall timer: Updater::update() follows ROS time and would stall after a backward
  // sim-time jump (a looping bag) until the clock caught up again.
  diagnostics_timer_ =
      nh_.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { updater_->force_update(); });

  if (config_.marker_rate_hz > 0.0) {
    markers_ = std::make_unique<WearMarkers>(wheels_);
    marker_publisher_ = nh_.advertise<visualization_msgs::MarkerArray>("wear_markers", 2);
    marker_timer_ = nh_.createTimer(ros::Duration(1.0 / config_.marker_rate_hz), &TreadWearNode::publishMarkers, this);
  }
  if (persistence_->status().saving)
    save_timer_ = nh_.createWallTimer(ros::WallDuration(config_.save_interval_s),
                                      [this](const ros::WallTimerEvent&) { persistence_->save(wheels_, "periodic"); });
  broadcastWheelFrames();

  // The update loop on its own queue and thread. Live, it steps every wheel on the node clock. Under simulated time
  // the wheels step on their inputs' stamps (WheelPipeline::receive) and the loop only publishes, at the update rate
  // of wall time: its load does not grow with the play rate, and the last steps are published after the bag (and
  // with it the clock) has stopped.
  ros::NodeHandle loop_nh(nh_);
  loop_nh.setCallbackQueue(&loop_queue_);
  if (ros::Time::isSimTime()) {
    loop_wall_timer_ = loop_nh.createWallTimer(ros::WallDuration(loop_status_.period_s.load()),
                                               [this](const ros::WallTimerEvent&) { loop(); });
    progress_publisher_ = nh_.advertise<tread_wear::InputProgress>("input_progress", 10);
    pnh_.param<std::string>("replay_resume_service", resume_service_, "");
    ROS_INFO("simulated time: wheels step on their inputs' stamps; replay_resume_service: %s",
             resume_service_.empty() ? "(none)" : resume_service_.c_str());
    progress_start_ = connected_since_ = ros::WallTime::now();
    start_timer_ = nh_.createWallTimer(ros::WallDuration(0.05), [this](const ros::WallTimerEvent&) { startReplay(); });
    progress_timer_ = loop_nh.createWallTimer(ros::WallDuration(kProgressPeriod_s),
                                              [this](const ros::WallTimerEvent&) { publishProgress(); });
  } else {
    loop_timer_ = loop_nh.createTimer(ros::Duration(loop_status_.period_s.load()),
                                      [this](const ros::TimerEvent&) { loop(); });
  }
  loop_running_ = true;
  loop_thread_ = std::thread([this] {
    while (loop_running_ && ros::ok()) loop_queue_.callAvailable(ros::WallDuration(0.05));
  });

  // Last, since the server calls reconfigure() at once. It starts from the node's configuration: its own start
  // reads the parameter server and the .cfg defaults, which need not be the configuration's.
  reconfigure_server_ =
      std::make_unique<dynamic_reconfigure::Server<tread_wear::TreadWearConfig>>(reconfigure_mutex_, pnh_);
  reconfigure_server_->updateConfig(reconfigure_->current());
  reconfigure_server_->setCallback([this](tread_wear::TreadWearConfig& c, uint32_t) { reconfigure(c); });
  ROS_INFO("tread_wear_node: %zu wheel(s), running at %.6g Hz", wheels_.size(), config_.update_rate_hz);
  return true;
}

void TreadWearNode::startPlanner() {
  NodePlannerConfig planner_config;
  std::string error;
  if (!loadNodePlannerConfig(pnh_, config_.config_dir, &planner_config, &error)) {
    ROS_ERROR("tread_wear_node: planner off: %s", error.c_str());  // the wear estimation runs on without it
    planner_config.vehicle_params.clear();
  }
  map_publisher_ = nh_.advertise<tread_wear::PlannerWearMap>("wear_map", 1, /*latch=*/true);
  planner_ = std::make_unique<NodePlanner>(
      planner_config, wheels_, config_.model, [this](tread_wear::PlannerWearMap& msg) {
        msg.header.stamp = ros::Time::now();  // on the map builder's thread, never the update loop's
        msg.header.frame_id = config_.base_frame;
        map_publisher_.publish(msg);
        ROS_INFO("tread_wear_node: wear map %s (version %u, preset %s) built in %.3g s", msg.fingerprint.c_str(),
                 msg.version, msg.preset.c_str(), msg.build_time_s);
      });
  if (!planner_->available())
    ROS_WARN("tread_wear_node: evaluate_trajectories unavailable: %s", planner_->reason().c_str());
  trajectories_service_ =
      nh_.advertiseService<tread_wear::EvaluateTrajectories::Request, tread_wear::EvaluateTrajectories::Response>(
          "evaluate_trajectories",
          [this](tread_wear::EvaluateTrajectories::Request& req, tread_wear::EvaluateTrajectories::Response& res) {
            planner_->evaluate(req, loop_status_.configuredPreset(), ros::Time::now().toSec(), &res);
            return true;
          });
  // Preset (dynamic_reconfigure) and tread temperatures are checked once a second; a change rebuilds the map.
  planner_->refresh(loop_status_.configuredPreset(), ros::Time::now().toSec());
  planner_timer_ = nh_.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) {
    planner_->refresh(loop_status_.configuredPreset(), ros::Time::now().toSec());
  });
}

void TreadWearNode::subscribeInputs(WheelPipeline* w) {
  const std::string& name = w->config().name;
  // Inputs are validated and counted on arrival, stamped with the node's clock; under simulated time with their own
  // header stamp (when set), which the wheel's steps then follow (WheelPipeline::setInputTime, docs/node.md).
  w->setInputTime(ros::Time::isSimTime());
  // Live, a backlog would be stamped late: keep only the newest few. Stamped samples of a fast replay arrive in
  // bursts and may wait behind other topics' callbacks: keep them (10,000 per input: 2 s of wall time for a 50 Hz
  // input at rate 100), since a dropped second of one input is a gap the wheel cannot integrate.
  const std::uint32_t queue_size = ros::Time::isSimTime() ? 10000 : 10;
  // Each sample goes to the wheel (in input time it steps there), with a throttled warning when it was rejected.
  auto receive = [this, w, name](const std_msgs::Header& header, InputKind kind, double v0, double v1 = 0.0,
                                 double v2 = 0.0) {
    InputSample sample;
    sample.t_s = ros::Time::isSimTime() && !header.stamp.isZero() ? header.stamp.toSec() : ros::Time::now().toSec();
    sample.kind = kind;
    sample.value[0] = v0;
    sample.value[1] = v1;
    sample.value[2] = v2;
    const InputFault fault = w->receive(sample, steadyNow_s(), stepSettings());
    last_input_stamp_s_.store(sample.t_s, std::memory_order_relaxed);
    if (fault != InputFault::kNone)
      ROS_WARN_THROTTLE(5.0, "wheel %s: rejected %s input (%s); the wheel is not evaluated until a valid one arrives",
                        name.c_str(), inputKindName(kind), inputFaultName(fault));
  };
  input_subscribers_.push_back(nh_.subscribe<tread_wear::WheelLoad>(
      w->config().load_topic, queue_size,
      [receive](const tread_wear::WheelLoad::ConstPtr& m) { receive(m->header, InputKind::kLoad, m->load_n); }));
  input_subscribers_.push_back(nh_.subscribe<tread_wear::WheelSlip>(
      w->config().slip_topic, queue_size, [receive](const tread_wear::WheelSlip::ConstPtr& m) {
        receive(m->header, InputKind::kSlip, m->slip_angle_rad, m->slip_ratio, m->path_curvature_per_m);
      }));
  input_subscribers_.push_back(nh_.subscribe<tread_wear::WheelSpeed>(
      w->config().speed_topic, queue_size,
      [receive](const tread_wear::WheelSpeed::ConstPtr& m) { receive(m->header, InputKind::kSpeed, m->speed_mps); }));
  required_subscribers_.insert(required_subscribers_.end(), input_subscribers_.end() - 3, input_subscribers_.end());
  input_subscribers_.push_back(nh_.subscribe<tread_wear::TreadTemperature>(
      w->config().temperature_topic, queue_size, [receive](const tread_wear::TreadTemperature::ConstPtr& m) {
        receive(m->header, InputKind::kTemperature, m->temperature_c);
      }));
}

void TreadWearNode::broadcastWheelFrames() {
  const std::vector<geometry_msgs::TransformStamped> transforms = wheelFrameTransforms(config_, ros::Time::now());
  if (transforms.empty()) return;
  tf_broadcaster_ = std::make_unique<tf2_ros::StaticTransformBroadcaster>();
  tf_broadcaster_->sendTransform(transforms);
}

void TreadWearNode::reconfigure(tread_wear::TreadWearConfig& c) {
  const double period_s = loop_status_.period_s.load();
  if (reconfigure_->apply(&c) && loop_status_.period_s.load() != period_s) {
    if (loop_wall_timer_.isValid()) loop_wall_timer_.setPeriod(ros::WallDuration(loop_status_.period_s.load()));
    if (loop_timer_.isValid()) loop_timer_.setPeriod(ros::Duration(loop_status_.period_s.load()));
  }
}

double TreadWearNode::evaluationDeadline_us() const {
  const double budget_us = loop_status_.budget_us.load(std::memory_order_relaxed);
  // The budget when set, else the wheel's share of the update period.
  const double period_s = loop_status_.period_s.load(std::memory_order_relaxed);
  return budget_us > 0.0 ? budget_us : 1e6 * period_s / static_cast<double>(wheels_.size());
}

WheelPipeline::StepSettings TreadWearNode::stepSettings() const {
  WheelPipeline::StepSettings settings;
  settings.preset = loop_status_.configuredPreset();
  settings.budget_s = 1e-6 * loop_status_.budget_us.load(std::memory_order_relaxed);
  settings.deadline_us = evaluationDeadline_us();
  settings.period_s = loop_status_.period_s.load(std::memory_order_relaxed);
  return settings;
}

void TreadWearNode::loop() {
  const double cycle_start = steadyNow_s();
  const ros::Time stamp = ros::Time::now();
  const double now_s = stamp.toSec();
  const WheelPipeline::StepSettings settings = stepSettings();
  const Preset preset = settings.preset;
  std::uint64_t skipped = 0;
  const bool vehicle_slot = vehicle_publisher_->trylock();
  if (!vehicle_slot) ++skipped;
  double total_rate_s = 0.0, total_rate_m = 0.0, total_loss = 0.0;
  for (std::size_t i = 0; i < wheels_.size(); ++i) {
    WheelPipeline& w = *wheels_[i];
    const WheelOutput out = w.inputTime() ? w.lastOutput() : w.step(now_s, settings);
    RealtimePublisher<tread_wear::WheelWear>& publisher = *wheel_publishers_[i];
    if (publisher.trylock()) {
      fillMessage(w, stamp, preset, &publisher.msg());
      publisher.unlockAndPublish();
    } else {
      ++skipped;
    }
    if (vehicle_slot) fillMessage(w, stamp, preset, &vehicle_publisher_->msg().wheels[i]);
    total_rate_s += out.result.wear_rate_kg_per_s;
    total_rate_m += out.result.wear_rate_kg_per_m;
    total_loss += out.accumulated_loss_kg;
  }
  if (vehicle_slot) {
    tread_wear::VehicleWear& v = vehicle_publisher_->msg();
    // As of the wheel that has stepped least far (live, they all carry `stamp`).
    v.header.stamp = v.wheels.empty() ? stamp : v.wheels.front().header.stamp;
    for (const tread_wear::WheelWear& wheel : v.wheels)
      if (wheel.header.stamp < v.header.stamp) v.header.stamp = wheel.header.stamp;
    v.total_wear_rate_kg_per_s = total_rate_s;
    v.total_wear_rate_kg_per_m = total_rate_m;
    v.total_accumulated_loss_kg = total_loss;
    vehicle_publisher_->unlockAndPublish();
  }
  const double cycle_us = 1e6 * (steadyNow_s() - cycle_start);
  loop_status_.last_cycle_us.store(cycle_us, std::memory_order_relaxed);
  atomicMax(loop_status_.max_cycle_us, cycle_us);
  loop_status_.cycles.fetch_add(1, std::memory_order_relaxed);
  if (skipped > 0) loop_status_.skipped_publications.fetch_add(skipped, std::memory_order_relaxed);
  if (cycle_us > 1e6 * settings.period_s) loop_status_.cycle_overruns.fetch_add(1, std::memory_order_relaxed);
}

void TreadWearNode::startReplay() {
  // Once every required input has been connected to a publisher for kConnectSettle_s (the publisher side registers a
  // link a moment after the subscriber side), or kConnectWait_s has passed (a bag without some wheel's topics):
  // input_progress starts and a paused player is resumed, so that no sample is published before the node can hear it.
  const ros::WallTime now = ros::WallTime::now();
  int connected = 0;
  for (const ros::Subscriber& sub : required_subscribers_) connected += sub.getNumPublishers() > 0;
  if (connected < static_cast<int>(required_subscribers_.size())) connected_since_ = now;
  const bool waited_out = now - progress_start_ >= ros::WallDuration(kConnectWait_s);
  if (now - connected_since_ < ros::WallDuration(kConnectSettle_s) && !waited_out) return;
  start_timer_.stop();
  inputs_connected_ = true;
  if (waited_out)
    ROS_WARN("replay: only %d of %zu required inputs have a publisher after %.0f s; starting without the others",
             connected, required_subscribers_.size(), kConnectWait_s);
  if (resume_service_.empty()) return;
  std_srvs::SetBool resume;
  resume.request.data = false;  // pause = false
  if (!ros::service::call(resume_service_, resume))
    ROS_ERROR("replay: cannot resume the player through %s; the bag stays paused", resume_service_.c_str());
}

void TreadWearNode::publishProgress() {
  if (!inputs_connected_.load()) return;
  // With nothing queued, every sample that has arrived is processed and the node is as far as the clock; else as far
  // as the last sample processed (subscribers are served in arrival order).
  double progress_s = ros::Time::now().toSec();
  if (!ros::getGlobalCallbackQueue()->isEmpty())
    progress_s = std::min(progress_s, last_input_stamp_s_.load(std::memory_order_relaxed));
  tread_wear::InputProgress msg;
  msg.header.stamp.fromSec(progress_s);
  progress_publisher_.publish(msg);
}

void TreadWearNode::publishMarkers(const ros::TimerEvent&) {
  if (marker_publisher_.getNumSubscribers() == 0) return;
  visualization_msgs::MarkerArray array;
  markers_->build(ros::Time::now(), &array);
  marker_publisher_.publish(array);
}

void TreadWearNode::shutdown() {
  if (shut_down_.exchange(true)) return;
  loop_running_ = false;
  loop_timer_.stop();
  loop_wall_timer_.stop();
  progress_timer_.stop();
  if (loop_thread_.joinable()) loop_thread_.join();
  save_timer_.stop();
  diagnostics_timer_.stop();
  marker_timer_.stop();
  planner_timer_.stop();
  if (planner_) planner_->stop();
  if (persistence_) persistence_->save(wheels_, "shutdown");
  if (vehicle_publisher_) vehicle_publisher_->stop();
  for (auto& p : wheel_publishers_) p->stop();
}

}  // namespace tread_wear
