// Gauss-Legendre rule against closed forms: exact for x^k up to k = 2n - 1, the known nodes of small n.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tread_wear/model/quadrature.h"

namespace tread_wear {
namespace {

TEST(GaussLegendre, IntegratesPolynomialsUpToDegree2nMinus1Exactly) {
  for (int n : {1, 2, 3, 6, 8, 12, 24, 64}) {
    std::vector<double> x, w;
    gaussLegendre(n, &x, &w);
    ASSERT_EQ(static_cast<int>(x.size()), n);
    for (int k = 0; k <= 2 * n - 1 && k <= 40; ++k) {
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum += w[i] * std::pow(x[i], k);
      const double exact = k % 2 == 1 ? 0.0 : 2.0 / (k + 1);  // integral of x^k over [-1, 1]
      EXPECT_NEAR(sum, exact, 1e-13) << "n = " << n << ", k = " << k;
    }
    for (int i = 1; i < n; ++i) EXPECT_LT(x[i - 1], x[i]) << "ascending, n = " << n;
  }
}

TEST(GaussLegendre, KnownNodes) {
  std::vector<double> x, w;
  gaussLegendre(2, &x, &w);
  EXPECT_NEAR(x[1], 1.0 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(w[0], 1.0, 1e-15);
  gaussLegendre(3, &x, &w);
  EXPECT_EQ(x[1], 0.0);
  EXPECT_NEAR(x[2], std::sqrt(0.6), 1e-15);
  EXPECT_NEAR(w[1], 8.0 / 9.0, 1e-15);
  EXPECT_NEAR(w[2], 5.0 / 9.0, 1e-15);
}

}  // namespace
}  // namespace tread_wear
