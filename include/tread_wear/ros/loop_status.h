#pragma once
/// @file loop_status.h
/// The update loop's live settings and counters, shared without locks: reconfigure writes the settings and the
/// loop reads them every cycle; the loop writes the counters and diagnostics reads them.

#include <atomic>
#include <cstdint>

#include "tread_wear/model/wear_model.h"

namespace tread_wear {

struct LoopStatus {
  // Settings (NodeReconfigure writes, the loop reads).
  std::atomic<double> period_s{0.01};                          ///< update period [s] = 1 / update_rate_hz
  std::atomic<double> budget_us{0.0};                          ///< time budget per wheel evaluation [us], 0 = none
  std::atomic<int> preset{static_cast<int>(Preset::kStandard)};  ///< configured (finest) preset

  // Counters (the loop writes, diagnostics reads).
  std::atomic<std::uint64_t> cycles{0};                ///< update cycles run [-]
  std::atomic<std::uint64_t> cycle_overruns{0};        ///< cycles longer than the period [-]
  std::atomic<std::uint64_t> skipped_publications{0};  ///< messages skipped: the publisher thread was busy [-]
  std::atomic<double> last_cycle_us{0.0};              ///< duration of the last cycle [us]
  std::atomic<double> max_cycle_us{0.0};               ///< longest cycle since start [us]

  Preset configuredPreset() const { return static_cast<Preset>(preset.load(std::memory_order_relaxed)); }
};

}  // namespace tread_wear
