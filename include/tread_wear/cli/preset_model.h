#pragma once
/// @file preset_model.h
/// The model behind the --preset and --grid options of tread_wear_eval and tread_wear_compare.

#include <memory>

#include "tread_wear/fitting/run_comparison.h"
#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/wear_model.h"
#include "tread_wear/reference/reference_solver.h"

namespace tread_wear {

/// The model of a preset: the marcher (WearModel) for fast, standard and fine; for reference the independent CVODE
/// solver (reference_solver.h) at its default tolerances; for a custom grid (--grid) the marcher at that grid.
/// All with WearModel's low-speed convention (lowSpeedPoint, wear_model.h: speed and rolling-speed floors).
class PresetModel {
 public:
  /// With a grid, the marcher at that grid and the reference preset's other options (the --grid option).
  PresetModel(const TireParams& params, const WearModelOptions& options, const GridSpec* grid = nullptr);

  /// Evaluates op like WearModel::evaluate: kInvalidInput, kLowSpeed (floors applied) or kOk.
  EvalStatus evaluate(const OperatingPoint& op, WearResult* result);

  /// This model as a PointModel, which throws std::invalid_argument for an invalid operating point. The
  /// PresetModel must outlive it.
  PointModel point();

 private:
  WearModel marcher_;
  std::unique_ptr<ReferenceBrushSolver> reference_;
  std::unique_ptr<BrushWearModel> custom_;
};

}  // namespace tread_wear
