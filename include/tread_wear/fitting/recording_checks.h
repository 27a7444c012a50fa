#pragma once
/// @file recording_checks.h
/// Checks of measured recordings against the model before anything is fitted to them (calibration, diagnosis).
///
/// Side-force sign: the calibrated levels (w3, mu) and every diagnosis term scale the side force or shift it by a
/// few per cent; none flips its sign where the slip angle dominates. A measured side force of the opposite sign
/// of the model's is therefore a broken run, not physics, and a table where that is the case for most runs is in
/// another axis convention than ISO 8855 (SAE's y axis points the other way). Fitted as they are, such runs pull
/// the friction level to its bound (calibration) or get "explained" by a sensor term (diagnosis).

#include <string>
#include <vector>

#include "tread_wear/io/run_table.h"
#include "tread_wear/model/brush_wear_model.h"

namespace tread_wear {

/// Runs whose predicted side force is below this share of the load [-] are not checked: there turn slip or the
/// model's own error can flip the sign.
constexpr double kSideForceSignCheckShareOfLoad = 0.1;

/// Compares each measured side force with the `fast`-preset brush model's at the run's conditions (a drive
/// segment: the time-weighted mean over its points; parameter file
/// as given, orientation as given). A run of the opposite sign has its side force set to not measured (NaN; its
/// wear stays) and gets a warning, "run i (condition 'c'): why; left out of the fit", returned in run order.
/// @throw RunTableError when more than half of the checked runs have the opposite sign (another axis convention).
std::vector<std::string> screenSideForceSigns(const TireParams& params, TurnSlipOrientation orientation,
                                              RunTable* table);

}  // namespace tread_wear
