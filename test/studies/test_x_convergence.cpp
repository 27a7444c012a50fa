// Order of the marcher's x discretisation (variable-step BDF2 along the element path, trapezoid rule in x):
// with the lateral grid fixed, the error against a fine x grid falls as h^2 once the grid resolves the
// element's natural period 2 pi sqrt(m/k_x). A first-order piece anywhere in the step (an unlocated
// stick/slide switch that the state carried, a BDF1 step per node) would show as order 1. Also the
// tread_wear_convergence --point options on bad input. Background: docs/performance.md, "Where the error is".
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "tread_wear/model/units.h"
#include "tread_wear/cli/convergence_cli.h"
#include "tread_wear/studies/convergence_study.h"

namespace tread_wear {
namespace {

OperatingPoint point(double load_n, double alpha_deg, double kappa, double speed_mps, double curvature_per_m) {
  OperatingPoint op;
  op.load_n = load_n;
  op.slip_angle_rad = alpha_deg * units::kDegree;
  op.slip_ratio = kappa;
  op.speed_mps = speed_mps;
  op.path_curvature_per_m = curvature_per_m;
  return op;
}

// Observed order log2(e(n) / e(2n)) on the rungs 240 -> 480 -> 960 (10-60 steps per natural period here).
void expectSecondOrder(const OperatingPoint& op, double SolverErrors::*output, const char* name) {
  const auto rows = xConvergence(TireParams(), xConvergenceOptions(), op, {240, 480, 960}, 6400);
  for (size_t k = 1; k < rows.size(); ++k) {
    const double order = std::log2(rows[k - 1].errors.*output / (rows[k].errors.*output));
    EXPECT_GT(order, 1.6) << name << " from " << rows[k - 1].n_x_steps << " to " << rows[k].n_x_steps << " x steps";
    EXPECT_LT(order, 2.6) << name << " from " << rows[k - 1].n_x_steps << " to " << rows[k].n_x_steps << " x steps";
  }
}

// Partial sliding at 5 m/s (transit about one natural period): side force, aligning moment and wear.
TEST(XConvergence, SecondOrderWithPartialSliding) {
  const OperatingPoint op = point(50, 6, 0, 5, 0);
  expectSecondOrder(op, &SolverErrors::fy, "Fy");
  expectSecondOrder(op, &SolverErrors::mz, "Mz");
  expectSecondOrder(op, &SolverErrors::wear, "W_r");
}

// Pure turn slip at 5 m/s: the aligning moment of the leading-edge transient.
TEST(XConvergence, SecondOrderUnderPureTurnSlip) {
  expectSecondOrder(point(100, 0, 0, 5, 0.2), &SolverErrors::mz, "Mz");
}

// Driving at 0.5 m/s: the elements break away at mid-patch and oscillate at their natural period, which
// a fine grid resolves (the wear of that oscillation is what the 60-step grid of `standard` misses).
TEST(XConvergence, SecondOrderForTheWearOfTheBreakawayOscillation) {
  expectSecondOrder(point(150, 0, 0.2, 0.5, 0), &SolverErrors::wear, "W_r");
}

TEST(XConvergence, CliRejectsBadPoints) {
  for (const std::vector<const char*>& args :
       {std::vector<const char*>{"tread_wear_convergence", "--point", "50,6,0,5"},
        {"tread_wear_convergence", "--point", "50,6,0,5,x"},
        {"tread_wear_convergence", "--point", "50,6,0,0,0"},
        {"tread_wear_convergence", "--point", "-50,6,0,5,0"},
        {"tread_wear_convergence", "--point", "50,6,0,5,0", "--strips", "0"},
        {"tread_wear_convergence", "--point", "50,6,0,5,0", "--grading", "1"},
        {"tread_wear_convergence", "--point", "50,6,0,5,0", "--quick"},
        {"tread_wear_convergence", "--strips", "12"}}) {
    std::ostringstream out, err;
    EXPECT_EQ(runConvergenceCli(static_cast<int>(args.size()), args.data(), out, err), 2) << args[2];
    EXPECT_TRUE(out.str().empty()) << args[2];
    EXPECT_FALSE(err.str().empty()) << args[2];
  }
}

TEST(XConvergence, CliPrintsTheLadder) {
  const char* args[] = {"tread_wear_convergence", "--point", "50,6,0,5,0", "--strips", "12"};
  std::ostringstream out, err;
  ASSERT_EQ(runConvergenceCli(5, args, out, err), 0) << err.str();
  EXPECT_NE(out.str().find("| 1920 |"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("12 shoulder-panel strips"), std::string::npos) << out.str();
}

}  // namespace
}  // namespace tread_wear
