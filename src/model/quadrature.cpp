#include "tread_wear/model/quadrature.h"

#include <cmath>

#include "tread_wear/model/units.h"

namespace tread_wear {

void gaussLegendre(int n, std::vector<double>* nodes, std::vector<double>* weights) {
  nodes->assign(n, 0.0);
  weights->assign(n, 0.0);
  for (int k = 0; k < (n + 1) / 2; ++k) {
    double x = std::cos(units::kPi * (k + 0.75) / (n + 0.5));
    double dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int l = 2; l <= n; ++l) {
        const double p2 = ((2.0 * l - 1.0) * x * p1 - (l - 1.0) * p0) / l;
        p0 = p1;
        p1 = p2;
      }
      if (n == 1) p0 = 1.0;
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::fabs(dx) < 1e-16) break;
    }
    const double w = 2.0 / ((1.0 - x * x) * dp * dp);
    (*nodes)[k] = -x;
    (*nodes)[n - 1 - k] = x;
    (*weights)[k] = (*weights)[n - 1 - k] = w;
  }
  if (n % 2 == 1) (*nodes)[n / 2] = 0.0;
}

}  // namespace tread_wear
