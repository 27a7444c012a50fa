#pragma once
/// @file convergence_study.h
/// Convergence study of the two solvers of the brush wear model on the paper's Table 3 rig
/// conditions (7 unique conditions of Tables 2-3, Grosch wheel on the 60 mm track, alpha negative and
/// path curvature +1/R_t as in operating_point.h): the reference solver (reference_solver.h) at its
/// chosen settings and at coarser ones, and the marcher (brush_wear_model.h) on a ladder of grids,
/// all against the reference solver refined 4x in strips with its tolerance divided by 100.
/// Prints Markdown tables (docs/convergence.md). Not for the real-time path: a study takes ~1 min.
/// Also, at one operating point, the marcher's convergence in x alone (lateral grid fixed): the order of
/// the x discretisation (variable-step BDF2 along the element path, trapezoid rule in x) and how many x
/// steps a condition needs.

#include <ostream>
#include <vector>

#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/operating_point.h"
#include "tread_wear/reference/solver_errors.h"

namespace tread_wear {

/// The 7 unique Table 3 conditions (v0 [m/s], alpha [deg], Fz [N]) as operating points on the rig:
/// speed v0, slip angle -alpha, path curvature +1/0.060 m.
std::vector<OperatingPoint> table3RigConditions();

/// One rung of an x-convergence ladder: the marcher on n_x_steps against the finest x grid.
struct XConvergenceRow {
  int n_x_steps = 0;
  WearResult result;
  SolverErrors errors;  ///< against reference_n_x_steps, same lateral grid (solver_errors.h)
};

/// Options of the x study: 24 shoulder-panel strips, edge grading 0.9, 4 turn-slip passes, root tolerance
/// 1e-8, no substeps (the lateral grid fixed and fine, so that the x error is what is measured).
BrushOptions xConvergenceOptions();

/// The marcher at `op` on each x grid of `ladder` and on `reference_n_x_steps`, everything else as in
/// `options` (lateral grid, grading, passes, tolerance). @throw std::invalid_argument on invalid options.
std::vector<XConvergenceRow> xConvergence(const TireParams& params, BrushOptions options, const OperatingPoint& op,
                                          const std::vector<int>& ladder, int reference_n_x_steps);

/// The convergence study of both solvers on the Table 3 rig conditions, as Markdown tables (docs/convergence.md):
/// the reference solver at its defaults and coarser settings, and the marcher on a ladder of grids up to 1600x64
/// (`quick`: up to 400x32; `extended`: also 3200x256 and 6400x256), all against the refined reference solver.
void writeConvergenceStudy(const TireParams& params, TurnSlipOrientation orientation, bool quick, bool extended,
                           std::ostream& out);

/// The marcher's convergence in x alone at `op` (xConvergence on x steps 30 ... 1920 against 6400), as a Markdown
/// table with the observed order of each output.
void writeXConvergenceStudy(const TireParams& params, const BrushOptions& options, const OperatingPoint& op,
                            std::ostream& out);

}  // namespace tread_wear
