#include "tread_wear/ros/wheel_pipeline.h"

namespace tread_wear {
namespace {

// One status enumeration for the live and the planner message: both carry WheelStatus's values.
constexpr int code(WheelStatus s) { return static_cast<int>(s); }
static_assert(tread_wear::WheelWear::STATUS_OK == code(WheelStatus::kOk) &&
                  tread_wear::WheelWear::STATUS_LOW_SPEED == code(WheelStatus::kLowSpeed) &&
                  tread_wear::WheelWear::STATUS_NO_INPUT == code(WheelStatus::kNoInput) &&
                  tread_wear::WheelWear::STATUS_STALE_INPUT == code(WheelStatus::kStaleInput) &&
                  tread_wear::WheelWear::STATUS_INVALID_INPUT == code(WheelStatus::kInvalidInput) &&
                  tread_wear::WheelWear::STATUS_TIME_JUMP == code(WheelStatus::kTimeJump),
              "WheelWear.STATUS_* must be WheelStatus's values");
static_assert(tread_wear::WheelWearRate::STATUS_OK == code(WheelStatus::kOk) &&
                  tread_wear::WheelWearRate::STATUS_LOW_SPEED == code(WheelStatus::kLowSpeed) &&
                  tread_wear::WheelWearRate::STATUS_INVALID_INPUT == code(WheelStatus::kInvalidInput),
              "WheelWearRate.STATUS_* must be WheelStatus's values");

}  // namespace

std::uint8_t statusCode(WheelStatus status) { return static_cast<std::uint8_t>(status); }

void reserveStrings(tread_wear::WheelWear* m) {
  m->header.frame_id.reserve(128);
  m->wheel.reserve(128);
  m->tire_id.reserve(kMaxTireIdLength + 1);
  m->preset.reserve(16);
}

void fillMessage(const WheelPipeline& wheel, const ros::Time& stamp, Preset configured, tread_wear::WheelWear* m) {
  wheel.readLastStep([&](const WheelPipeline::LastStep& last) {
    const WheelOutput& out = last.output;
    // In input time the estimate is as of the last step's input time, which the node clock need not have reached.
    m->header.stamp = last.input_time && last.stepped ? ros::Time(last.step_time_s) : stamp;
    if (m->wheel != wheel.config().name) {  // first message only (capacity reserved by the caller)
      m->header.frame_id = wheel.config().frame_id;
      m->wheel = wheel.config().name;
    }
    m->tire_id = last.tire_id;
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
    m->degraded = out.preset < configured;
    m->status = statusCode(out.status);
    m->unaccounted_time_s = last.unaccounted_time_s;
  });
}

}  // namespace tread_wear
