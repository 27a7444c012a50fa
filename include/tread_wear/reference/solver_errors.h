#pragma once
/// @file solver_errors.h
/// Errors of one brush-model result against a reference result of the same operating point: the
/// measures of the issue-4 accuracy targets (docs/performance.md), shared by the accuracy and benchmark
/// programs, the preset tests and the x-convergence study.
///  - Fx, Fy: |F - F_ref| / max(|F_ref|, 0.05 |(Fx, Fy)_ref|, 0.005 Fz): relative, with an absolute
///    floor for a component that is near zero while the other carries the force (and for F ~ 0).
///  - Mz: |Mz - Mz_ref| / max(|Mz_ref|, a floor_F), floor_F the force floor above and a the contact
///    half length (the natural lever arm; Mz changes sign past the force peak).
///  - W_r: relative (W_r >= w4 area / V > 0 always). Area fractions: absolute.

#include "tread_wear/model/brush_wear_model.h"

namespace tread_wear {

/// All fractions [-] (0.01 = 1%); the area fractions as differences.
struct SolverErrors {
  double fx = 0, fy = 0, mz = 0, wear = 0, stick = 0, slide = 0, exact_stick = 0;

  /// Component-wise maximum with e.
  void maxWith(const SolverErrors& e);
};

/// Errors of `result` against `reference`, both at the load `load_n` [N] (> 0).
SolverErrors solverErrors(const WearResult& reference, const WearResult& result, double load_n);

}  // namespace tread_wear
