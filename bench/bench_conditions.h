#pragma once
/// @file bench_conditions.h
/// Condition grids shared by the wear-model benchmark and accuracy programs
/// (docs/performance.md). Header-only; used by bench/ only.
///
/// Grids:
///  - rig: the seven distinct conditions of the paper's Table 3 (v0, alpha, Fz) as the Grip and
///    Abrasion Test Stand runs them (slip_angle = -alpha, path radius +60 mm; table3RigConditions), in both
///    orientations.
///  - road: load x slip angle (past the force peak, which is near 15 deg for the Grosch wheel at 100 N)
///    x slip ratio in [-0.2, 0.2] x speed 0.5..40 m/s x path curvature (straight and R = 5 m).
///  - random road: n points drawn inside the road grid's envelope (between its nodes), for accuracy
///    claims that must not depend on where the grid's points happen to lie.
/// Error measures against a reference result: tread_wear/reference/solver_errors.h.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/units.h"
#include "tread_wear/reference/solver_errors.h"
#include "tread_wear/studies/convergence_study.h"

namespace tread_wear {
namespace bench {

struct Condition {
  OperatingPoint op;
  TurnSlipOrientation orientation = TurnSlipOrientation::kLiteral;
  std::string label;
};

inline std::vector<Condition> rigConditions() {
  std::vector<Condition> out;
  for (TurnSlipOrientation o : {TurnSlipOrientation::kLiteral, TurnSlipOrientation::kFlipped}) {
    for (const OperatingPoint& op : table3RigConditions()) {
      Condition c;
      c.op = op;
      c.orientation = o;
      // alpha back in whole degrees as the table gives it (the radians do not round-trip exactly).
      const double alpha_deg = std::round(-op.slip_angle_rad / units::kDegree * 1e9) / 1e9;
      c.label = std::string(o == TurnSlipOrientation::kLiteral ? "literal" : "flipped") + " v0=" +
                std::to_string(op.speed_mps).substr(0, 3) + " alpha=" + std::to_string(alpha_deg).substr(0, 4) +
                " Fz=" + std::to_string(op.load_n).substr(0, 5);
      out.push_back(c);
    }
  }
  return out;
}

/// Road-tire grid scaled to the tire: loads as fractions of nominal_load_n.
inline std::vector<Condition> roadConditions(double nominal_load_n, bool coarse = false) {
  std::vector<double> loads{0.5, 1.0, 1.5}, alphas{0, 1, 3, 6, 10, 15, 25}, kappas{-0.2, -0.05, 0, 0.05, 0.2},
      speeds{0.5, 5, 20, 40}, curvatures{0.0, 0.2};
  if (coarse) {
    loads = {0.5, 1.5};
    alphas = {0, 3, 10, 25};
    kappas = {-0.2, 0, 0.05};
    speeds = {0.5, 20};
  }
  std::vector<Condition> out;
  for (double l : loads)
    for (double al : alphas)
      for (double k : kappas)
        for (double v : speeds)
          for (double c : curvatures) {
            Condition cd;
            cd.op.load_n = l * nominal_load_n;
            cd.op.slip_angle_rad = al * units::kDegree;
            cd.op.slip_ratio = k;
            cd.op.speed_mps = v;
            cd.op.path_curvature_per_m = c;
            cd.label = "Fz=" + std::to_string(cd.op.load_n).substr(0, 6) + " alpha=" + std::to_string(al).substr(0, 4) +
                       " kappa=" + std::to_string(k).substr(0, 5) + " V=" + std::to_string(v).substr(0, 4) +
                       " curv=" + std::to_string(c).substr(0, 3);
            out.push_back(cd);
          }
  return out;
}

/// n road conditions drawn uniformly inside the road grid's envelope: load 0.5-1.5 nominal_load_n, slip angle
/// 0-25 deg, slip ratio -0.2..0.2, speed log-uniform 0.5-40 m/s, half of them straight and half on a path of
/// curvature 0-0.2 1/m. The same seed gives the same points on every machine (std::mt19937's sequence is fixed;
/// the draws go through the seed's raw 32-bit outputs, not a library distribution).
inline std::vector<Condition> randomRoadConditions(double nominal_load_n, int n, unsigned seed) {
  std::mt19937 rng(seed);
  auto uniform = [&rng] { return (rng() + 0.5) / 4294967296.0; };  // (0, 1), portable
  std::vector<Condition> out;
  for (int k = 0; k < n; ++k) {
    Condition c;
    c.op.load_n = nominal_load_n * (0.5 + uniform());
    c.op.slip_angle_rad = 25.0 * uniform() * units::kDegree;
    c.op.slip_ratio = -0.2 + 0.4 * uniform();
    c.op.speed_mps = 0.5 * std::pow(80.0, uniform());
    const bool turning = uniform() < 0.5;
    const double curvature = 0.2 * uniform();
    c.op.path_curvature_per_m = turning ? curvature : 0.0;
    char label[160];
    std::snprintf(label, sizeof(label), "Fz=%.1f alpha=%.2f kappa=%.3f V=%.2f curv=%.3f", c.op.load_n,
                  c.op.slip_angle_rad / units::kDegree, c.op.slip_ratio, c.op.speed_mps, c.op.path_curvature_per_m);
    c.label = label;
    out.push_back(c);
  }
  return out;
}

}  // namespace bench
}  // namespace tread_wear
