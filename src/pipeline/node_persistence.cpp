#include "tread_wear/pipeline/node_persistence.h"

#include <cstdio>
#include <utility>

#include "tread_wear/pipeline/loop_clock.h"

namespace tread_wear {
namespace {

constexpr const char* kSaveFailed = "save failed: ";
/// A failed save is logged at most this often [s].
constexpr double kFailureLogPeriod_s = 30.0;

}  // namespace

NodePersistence::NodePersistence(const std::string& state_file, LogSink log)
    : state_file_(state_file), log_(std::move(log)) {
  if (!log_) log_ = [](LogLevel, const std::string&) {};
  if (!state_file_.empty()) store_ = std::make_unique<StateStore>(state_file_);
}

void NodePersistence::restore(const std::vector<std::unique_ptr<WheelPipeline>>& wheels) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!store_) return;
  const LoadResult r = store_->load();
  switch (r.status) {
    case LoadStatus::kLoaded:
    case LoadStatus::kMissing: log_(LogLevel::kInfo, r.message); break;
    case LoadStatus::kCorrupt:
    case LoadStatus::kIncompatible:
      log_(LogLevel::kError,
           r.message + ". Accumulated loss starts from zero; recover the old values from the moved file by hand.");
      problem_ = r.message;
      break;
    case LoadStatus::kIoError:
      // The file is still there and may be good: never overwrite it with zeros.
      log_(LogLevel::kError, r.message + ". Saving is disabled so the file is not overwritten.");
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
      log_(LogLevel::kInfo, "wheel " + w->config().name + ": saved tire_id '" + rec->tire_id +
                                "' replaces the configured '" + w->config().tire_id + "'");
    char text[160];
    std::snprintf(text, sizeof(text), "restored accumulated loss %.9g kg over %.6g m", rec->accumulated_loss_kg,
                  rec->distance_m);
    log_(LogLevel::kInfo, "wheel " + w->config().name + ": " + text + " (tire " + rec->tire_id + ")");
  }
  for (const WheelRecord& rec : saved_.wheels)
    if (findWheel(wheels, rec.name) == nullptr)
      log_(LogLevel::kWarn,
           "state file has wheel '" + rec.name + "' which is not configured: kept in the file, not estimated");
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
    log_(LogLevel::kDebug, std::string("state saved (") + reason + ") to " + store_->path());
  } else {
    problem_ = kSaveFailed + error;
    const double now_s = wallNow_s();
    if (now_s - last_failure_log_unix_s_ >= kFailureLogPeriod_s) {
      last_failure_log_unix_s_ = now_s;
      log_(LogLevel::kError, std::string("cannot save the wear state (") + reason + "): " + error);
    }
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
