// Proves that an evaluation allocates nothing: a counting global operator new/delete wraps the heap,
// and the counter must not move across evaluate() of every preset, with and without local fields,
// with turn slip and straight, and through the WearModel facade (budget, low speed).
#include <gtest/gtest.h>


#include "common/allocation_counter.h"
#include "tread_wear/model/units.h"
#include "tread_wear/model/wear_model.h"


namespace tread_wear {
namespace {

std::vector<OperatingPoint> points() {
  std::vector<OperatingPoint> out;
  OperatingPoint rig;  // Table 3 benchmark condition on the rig (turn slip)
  rig.speed_mps = 2.0;
  rig.slip_angle_rad = -10.0 * units::kDegree;
  rig.load_n = 75.0;
  rig.path_curvature_per_m = 1.0 / 0.060;
  out.push_back(rig);
  OperatingPoint road;  // straight, combined slip (mirror-symmetric path)
  road.speed_mps = 20.0;
  road.slip_angle_rad = 6.0 * units::kDegree;
  road.slip_ratio = -0.1;
  road.load_n = 100.0;
  out.push_back(road);
  OperatingPoint slow = road;  // low-speed and rolling-speed conventions
  slow.speed_mps = 0.0;
  out.push_back(slow);
  slow.speed_mps = 1.0;
  slow.slip_ratio = -0.999999;
  out.push_back(slow);
  return out;
}

TEST(NoAllocation, BrushWearModelEvaluateAllocatesNothing) {
  const TireParams params;
  for (Preset preset : kAllPresets) {
    const BrushWearModel model(params, presetOptions(preset));
    PatchFields fields;
    fields.resize(model.nodesX(), model.strips());
    for (const OperatingPoint& op : points()) {
      if (op.speed_mps <= 0.0) continue;  // BrushWearModel needs V > 0 (WearModel handles standstill)
      WearResult r;
      const long before = t_allocations;
      model.evaluate(op, &r);
      model.evaluate(op, &r, &fields);
      EXPECT_EQ(t_allocations - before, 0) << presetName(preset);
      EXPECT_TRUE(std::isfinite(r.fy_n));
    }
  }
}

TEST(NoAllocation, WearModelEvaluateAllocatesNothingUnderBudget) {
  WearModelOptions options;
  options.time_budget_s = 1e-6;  // forces degrading and probing paths
  options.budget_probe_interval = 2;
  const WearModel model(TireParams(), options);
  WearResult r;
  const auto pts = points();
  const long before = t_allocations;
  for (int k = 0; k < 12; ++k) model.evaluate(pts[k % pts.size()], &r);
  EXPECT_EQ(t_allocations - before, 0);
  EXPECT_GT(model.degradedCount(), 0);  // the budget path really ran
}

}  // namespace
}  // namespace tread_wear
