#include "tread_wear/proving/drive_fleet.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "tread_wear/estimation/drive_segments.h"
#include "tread_wear/vehicle/driving_style.h"
#include "tread_wear/vehicle/route.h"

namespace tread_wear {
namespace diagnosis {
namespace {

constexpr double kAmbientMeanC = 11.0;  ///< yearly mean ambient temperature [degC]
constexpr double kAmbientSwingC = 9.0;  ///< seasonal half swing [degC]
constexpr double kAmbientNoiseC = 1.5;  ///< weather around the season within a segment's mean [degC]
constexpr double kSegmentMonths = 2.0;  ///< months per segment (3000 km at 18000 km a year)
constexpr double kSpeedScaleMin = 0.92, kSpeedScaleMax = 1.05;  ///< the cycle's speeds as driven [-]
constexpr double kAccelScaleMin = 0.7, kAccelScaleMax = 1.4;    ///< the `normal` envelope as driven [-]
constexpr double kRoughShareMin = 0.05, kRoughShareMax = 0.65;  ///< share of coarse asphalt [-]
constexpr double kHeatingC_per_W = 0.015;      ///< steady tread temperature rise per watt of heat [degC/W]
constexpr double kThermalLag_s = 300.0;        ///< tread temperature time constant [s]
constexpr double kWheelOffsetC = 1.0;          ///< per wheel and segment temperature offset spread [degC]
constexpr double kMinMeasuredFraction = 0.05;  ///< floor of a measured wear rate, of the truth [-]

/// The cycle with its speeds scaled (same times, so the distance scales too).
SpeedProfile scaledProfile(const SpeedProfile& p, double scale) {
  std::vector<double> v = p.speeds_mps();
  for (double& x : v) x *= scale;
  return SpeedProfile(p.times_s(), std::move(v), p.phases(), p.name());
}

}  // namespace

PointCellParams fleetCells() {
  PointCellParams p;
  p.load = {100.0, 0.7};
  p.slip_angle = {1e-3, 2.5};
  p.slip_ratio = {1e-3, 2.5};
  p.speed = {1.0, 1.5};
  p.path_curvature = {1e-3, 3.0};
  p.temperature_bin_c = 10.0;
  return p;
}

bool DriveFleet::validate(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = "drive fleet: " + m;
    return false;
  };
  if (vehicles.empty()) return fail("vehicles is empty: at least one vehicle is needed");
  for (std::size_t i = 0; i < vehicles.size(); ++i) {
    std::string e;
    if (!vehicles[i].validate(&e)) return fail("vehicles[" + std::to_string(i) + "]: " + e);
  }
  if (!profile) return fail("profile is missing: the cycle to repeat is needed");
  if (checkpoints < 2) return fail("checkpoints = " + std::to_string(checkpoints) + " must be >= 2");
  if (!(segment_distance_m > 0.0) || !std::isfinite(segment_distance_m))
    return fail("segment_distance_m = " + std::to_string(segment_distance_m) + " must be finite and > 0");
  if (!(update_rate_hz >= 1.0 && update_rate_hz <= 100.0))
    return fail("update_rate_hz = " + std::to_string(update_rate_hz) + " must be in [1, 100]");
  if (!(payload_max_kg >= 0.0) || !std::isfinite(payload_max_kg))
    return fail("payload_max_kg = " + std::to_string(payload_max_kg) + " must be finite and >= 0");
  if (!(depth_gauge_sigma_m >= 0.0) || !std::isfinite(depth_gauge_sigma_m))
    return fail("depth_gauge_sigma_m = " + std::to_string(depth_gauge_sigma_m) + " must be finite and >= 0");
  std::string e;
  if (!cells.validate(&e)) return fail("cells: " + e);
  return true;
}

std::vector<DriveSegmentRuns> simulateDriveFleet(const DriveFleet& fleet, std::uint64_t seed, RunTable* table) {
  std::string error;
  if (!fleet.validate(&error)) throw std::invalid_argument(error);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  auto between = [&](double lo, double hi) { return lo + (hi - lo) * uniform(rng); };

  table->covariate_names = {"ambient_c", "rough_road_share", "payload_kg", "speed_scale", "accel_scale", "odometer_km"};
  table->text_covariate_names = {"vehicle", "wheel"};
  ReplaySettings settings;
  settings.update_rate_hz = fleet.update_rate_hz;
  std::vector<DriveSegmentRuns> out;
  const int segments = fleet.checkpoints - 1;
  for (std::size_t v = 0; v < fleet.vehicles.size(); ++v) {
    const double first_month = between(0.0, 12.0);
    RouteParams route_params;
    route_params.seed = static_cast<std::uint32_t>(20240601u + v);  // a vehicle drives its own roads
    double odometer_m = 0.0;
    for (int s = 0; s < segments; ++s) {
      const double month = first_month + kSegmentMonths * (s + 0.5);
      const double ambient =
          kAmbientMeanC - kAmbientSwingC * std::cos(2.0 * M_PI * month / 12.0) + kAmbientNoiseC * normal(rng);
      const double speed_scale = between(kSpeedScaleMin, kSpeedScaleMax);
      const double accel_scale = between(kAccelScaleMin, kAccelScaleMax);
      const double payload = between(0.0, fleet.payload_max_kg);
      const double rough_share = between(kRoughShareMin, kRoughShareMax);

      const SpeedProfile profile = scaledProfile(*fleet.profile, speed_scale);
      const Route route = buildRoute(profile, route_params);
      DrivingEnvelope envelope;
      envelope.max_accel_mps2 = std::min(kMaxEnvelopeAccel_mps2, envelope.max_accel_mps2 * accel_scale);
      envelope.max_decel_mps2 = std::min(kMaxEnvelopeAccel_mps2, envelope.max_decel_mps2 * accel_scale);
      envelope.max_lateral_accel_mps2 = std::min(kMaxEnvelopeAccel_mps2, envelope.max_lateral_accel_mps2 * accel_scale);
      const EnvelopeDrive drive = driveWithinEnvelope(profile, route, envelope);
      VehicleParams vp = fleet.vehicles[v];
      vp.mass_kg += payload;
      const VehicleModel vehicle(vp);

      DriveSegmentRuns seg;
      seg.vehicle = static_cast<int>(v);
      seg.segment = s;
      seg.cycle_distance_m = drive.trace.distance_m();
      seg.repetitions = std::max(1, static_cast<int>(std::lround(fleet.segment_distance_m / seg.cycle_distance_m)));

      const double duration = drive.trace.duration_s();
      const double dt = 1.0 / fleet.update_rate_hz;
      const std::size_t n = static_cast<std::size_t>(std::floor(duration * fleet.update_rate_hz + 1e-9)) + 1;
      std::vector<DriveSegmenter> segmenters;
      double temperature[kWheelCount], offset[kWheelCount];
      for (int w = 0; w < kWheelCount; ++w) {
        segmenters.emplace_back(settings, fleet.cells, std::vector<double>{0.0, (n - 1) * dt}, 0.0);
        offset[w] = kWheelOffsetC * normal(rng);
        temperature[w] = ambient + offset[w];
      }
      const double lag = 1.0 - std::exp(-dt / kThermalLag_s);
      VehicleState state;
      for (std::size_t k = 0; k < n; ++k) {
        const double t = k * dt;
        vehicle.evaluate(drive.trace.at(t), &state);
        for (int w = 0; w < kWheelCount; ++w) {
          const WheelState& ws = state.wheels[static_cast<std::size_t>(w)];
          const double heat_w = vp.rolling_resistance_coefficient * ws.load_n * ws.speed_mps +
                                std::abs(ws.fy_demand_n) * ws.speed_mps * std::abs(std::sin(ws.slip_angle_rad)) +
                                std::abs(ws.fx_demand_n) * ws.speed_mps * std::abs(ws.slip_ratio);
          const double steady = ambient + offset[w] + kHeatingC_per_W * heat_w;
          if (k > 0) temperature[w] += lag * (steady - temperature[w]);
          DriveSegmenter& sg = segmenters[static_cast<std::size_t>(w)];
          sg.addSample({t, InputKind::kLoad, {ws.load_n, 0.0, 0.0}});
          sg.addSample({t, InputKind::kSlip, {ws.slip_angle_rad, ws.slip_ratio, ws.path_curvature_per_m}});
          sg.addSample({t, InputKind::kSpeed, {ws.speed_mps, 0.0, 0.0}});
          sg.addSample({t, InputKind::kTemperature, {temperature[w], 0.0, 0.0}});
        }
      }
      const double reps = seg.repetitions;
      const double segment_m = reps * seg.cycle_distance_m;
      for (int w = 0; w < kWheelCount; ++w) {
        const DriveSegment ds = segmenters[static_cast<std::size_t>(w)].finish().front();
        RunRecord r = driveSegmentRecord(ds, reps);
        r.condition_id = fleet.vehicles[v].name + "/" + std::to_string(s + 1);
        r.covariates = {ambient, rough_share, payload, speed_scale, accel_scale, (odometer_m + 0.5 * segment_m) / 1e3};
        r.text_covariates = {fleet.vehicles[v].name, wheelName(w)};
        seg.runs.push_back(r);
        table->runs.push_back(r);
      }
      odometer_m += segment_m;
      out.push_back(std::move(seg));
    }
  }
  return out;
}

std::vector<double> measureDriveWear(const std::vector<DriveSegmentRuns>& segments,
                                     const std::vector<double>& true_wear_kg_per_m, double wear_noise_rsd,
                                     double depth_gauge_sigma_m, double mass_per_depth_kg_per_m, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> out;
  out.reserve(true_wear_kg_per_m.size());
  // The previous checkpoint's reading error of each (vehicle, wheel) [m]: neighbouring segments share a reading.
  std::vector<double> previous_error;
  std::size_t i = 0;
  for (const DriveSegmentRuns& seg : segments) {
    if (seg.segment == 0) {  // a new vehicle: the first reading of each wheel
      previous_error.clear();
      for (std::size_t w = 0; w < seg.runs.size(); ++w) previous_error.push_back(depth_gauge_sigma_m * normal(rng));
    }
    for (std::size_t w = 0; w < seg.runs.size(); ++w, ++i) {
      if (i >= true_wear_kg_per_m.size()) throw std::invalid_argument("measureDriveWear: fewer true rates than runs");
      const double truth = true_wear_kg_per_m[i];
      const double distance = seg.runs[w].drive_distance_m;
      double loss_kg = truth * distance * (1.0 + wear_noise_rsd * normal(rng));
      if (depth_gauge_sigma_m > 0.0) {
        const double error_m = depth_gauge_sigma_m * normal(rng);
        // loss = reading(start) - reading(end): the start reading's error adds, the end reading's subtracts.
        loss_kg += (previous_error[w] - error_m) * mass_per_depth_kg_per_m;
        previous_error[w] = error_m;
      }
      out.push_back(std::max(kMinMeasuredFraction * truth, loss_kg / distance));
    }
  }
  if (i != true_wear_kg_per_m.size()) throw std::invalid_argument("measureDriveWear: more true rates than runs");
  return out;
}

}  // namespace diagnosis
}  // namespace tread_wear
