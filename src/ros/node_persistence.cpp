#include "tread_wear/ros/node_persistence.h"

#include <ros/console.h>

#include <chrono>

namespace tread_wear {
namespace {

double wallNow_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

constexpr const char* kSaveFailed = "save failed: ";

}  // namespace

NodePersistence::NodePersistence(const std::string& state_file) : state_file_(state_file) {
  if (!state_file_.empty()) store_ = std::make_unique<StateStore>(state_file_);
}

void NodePersistence::restore(const std::vector<std::unique_ptr<WheelPipeline>>& wheels) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!store_) return;
  const LoadResult r = store_->load();
  switch (r.status) {
    case LoadStatus::kLoaded:
    case LoadStatus::kMissing: ROS_INFO("%s", r.message.c_str()); break;
    case LoadStatus::kCorrupt:
    case LoadStatus::kIncompatible:
      ROS_ERROR("%s. Accumulated loss starts from zero; recover the old values from the moved file by hand.",
                r.message.c_str());
      problem_ = r.message;
      break;
    case LoadStatus::kIoError:
      // The file is still there and may be good: never overwrite it with zeros.
      ROS_ERROR("%s. Saving is disabled so the file is not overwritten.", r.message.c_str());
      problem_ = r.message + " (saving disabled)";
      store_.reset();
      break;
  }
  restore_report_ = loadStatusName(r.status);
  saved_ = r.state;
  for (const auto& w : wheels) {
    const WheelRecord* rec = saved_.find(w->config().name);
    if (rec == nullptr) continue;
    w->restore(*rec);
    if (rec->tire_id != w->config().tire_id)
      ROS_INFO("wheel %s: saved tire_id '%s' replaces the configured '%s'", w->config().name.c_str(),
               rec->tire_id.c_str(), w->config().tire_id.c_str());
    ROS_INFO("wheel %s: restored accumulated loss %.9g kg over %.6g m (tire %s)", w->config().name.c_str(),
             rec->accumulated_loss_kg, rec->distance_m, rec->tire_id.c_str());
  }
  for (const WheelRecord& rec : saved_.wheels)
    if (findWheel(wheels, rec.name) == nullptr)
      ROS_WARN("state file has wheel '%s' which is not configured: kept in the file, not estimated",
               rec.name.c_str());
}

void NodePersistence::save(const std::vector<std::unique_ptr<WheelPipeline>>& wheels, const char* reason) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!store_) return;
  StateFile state = saved_;
  for (const auto& w : wheels) {
    const WheelRecord rec = w->record();
    if (WheelRecord* existing = state.find(rec.name))
      *existing = rec;
    else
      state.wheels.push_back(rec);
  }
  std::string error;
  if (store_->save(state, &error)) {
    saved_ = state;
    last_save_unix_s_ = wallNow_s();
    if (problem_.rfind(kSaveFailed, 0) == 0) problem_.clear();  // a failed save is over; a restore problem stays
    ROS_DEBUG("state saved (%s) to %s", reason, store_->path().c_str());
  } else {
    problem_ = kSaveFailed + error;
    ROS_ERROR_THROTTLE(30.0, "cannot save the wear state (%s): %s", reason, error.c_str());
  }
}

NodePersistence::Status NodePersistence::status() const {
  std::lock_guard<std::mutex> lock(mutex_);
  Status s;
  s.saving = store_ != nullptr;
  s.state_file = state_file_;
  s.restore = restore_report_;
  s.problem = problem_;
  s.seconds_since_save = last_save_unix_s_ > 0.0 ? wallNow_s() - last_save_unix_s_ : -1.0;
  return s;
}

}  // namespace tread_wear
