#pragma once
// One Grosch-rig run for tests that need a run table: 2 m/s, slip angle -0.17 rad on the 60 mm track radius,
// 75 N, wear 6e-7 kg/m. The model predicts about +50 N side force there (ISO axes).
#include "tread_wear/io/run_table.h"

inline tread_wear::RunRecord rigRun(double side_force_n) {
  tread_wear::RunRecord r;
  r.op.speed_mps = 2.0;
  r.op.slip_angle_rad = -0.17;
  r.op.path_curvature_per_m = 1.0 / 0.06;
  r.op.load_n = 75.0;
  r.measured_side_force_n = side_force_n;
  r.measured_wear_rate_kg_per_m = 6e-7;
  r.condition_id = "bench";
  return r;
}
