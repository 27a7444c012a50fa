// Pressure field (paper Eqs 6-9): the three moment conditions of Eq 9 hold to quadrature accuracy; the centre
// shift's factor of sat(p) (Eq 11) that the marcher sums as a series agrees with std::pow.
#include <gtest/gtest.h>

#include <cmath>

#include "tread_wear/model/contact_patch.h"
#include "tread_wear/model/friction.h"

namespace tread_wear {
namespace {

struct Moments {
  double f0, fx, fy;
};

// Composite Simpson in x and y, fine enough that its own error is far below the tolerances.
Moments integrate(const ContactPatch& patch, int n = 2000) {
  const double a = patch.halfLength(), b = patch.halfWidth();
  Moments m{0, 0, 0};
  for (int i = 0; i <= n; ++i) {
    const double x = -a + 2.0 * a * i / n;
    const double wi = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    for (int j = 0; j <= n; ++j) {
      const double y = -b + 2.0 * b * j / n;
      const double wj = (j == 0 || j == n) ? 1 : (j % 2 ? 4 : 2);
      const double w = wi * wj * (2.0 * a / n / 3.0) * (2.0 * b / n / 3.0);
      const double p = patch.pressure(x, y);
      m.f0 += w * p;
      m.fx += w * p * x;
      m.fy += w * p * y;
    }
  }
  return m;
}

TEST(ContactPatch, Eq6HalfLengthOfTheGroschWheel) {
  FootprintParams fp;  // Table 4: a = 0.05 mm * 75^0.82 + 1.37 mm at 75 N
  EXPECT_NEAR(fp.halfLength(75.0), (0.05 * std::pow(75.0, 0.82) + 1.37) * 1e-3, 1e-15);
  EXPECT_NEAR(fp.halfLength(75.0), 3.0947e-3, 1e-6);  // hand calculation
}

TEST(ContactPatch, Eq9MomentsHoldForTable4Shape) {
  FootprintParams fp;
  for (double load : {50.0, 75.0, 100.0}) {
    const ContactPatch patch(fp, load);
    const Moments m = integrate(patch);
    // |s|^(2n) with n = 2.06 has a weak singular derivative at s = 0: Simpson converges at ~1e-6 here.
    EXPECT_NEAR(m.f0 / load, 1.0, 1e-5) << "load " << load;
    EXPECT_NEAR(m.fx / (load * fp.x_e_m), 1.0, 1e-4) << "load " << load;
    EXPECT_NEAR(m.fy, 0.0, 1e-9 * load);
  }
}

TEST(ContactPatch, Eq9LateralCentreIsReproduced) {
  FootprintParams fp;
  fp.y_e_m = 0.5e-3;
  fp.x_e_m = -0.2e-3;
  const ContactPatch patch(fp, 80.0);
  const Moments m = integrate(patch);
  EXPECT_NEAR(m.f0 / 80.0, 1.0, 1e-5);
  EXPECT_NEAR(m.fx / (80.0 * fp.x_e_m), 1.0, 1e-4);
  EXPECT_NEAR(m.fy / (80.0 * fp.y_e_m), 1.0, 1e-4);
}

TEST(ContactPatch, PressureVanishesAtTheEdgesAndOutside) {
  const ContactPatch patch(FootprintParams{}, 75.0);
  const double a = patch.halfLength(), b = patch.halfWidth();
  EXPECT_DOUBLE_EQ(patch.pressure(a, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(patch.pressure(-a, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(patch.pressure(0.0, b), 0.0);
  EXPECT_DOUBLE_EQ(patch.pressure(1.01 * a, 0.0), 0.0);
  EXPECT_GT(patch.pressure(0.0, 0.0), 0.0);
}

TEST(ContactPatch, ValidationNamesTheField) {
  FootprintParams fp;
  fp.b_m = -1.0;
  std::string error;
  EXPECT_FALSE(fp.validate(&error));
  EXPECT_NE(error.find("footprint.b = -1"), std::string::npos) << error;
  EXPECT_NE(error.find("> 0"), std::string::npos) << error;
}

}  // namespace
}  // namespace tread_wear

namespace tread_wear {
namespace {

// The centre shift's factor of sat(p), (1 - u)^-q, by its binomial series agrees with std::pow to rounding
// over the range it serves, for exponents q across [0, 1); beyond kSeriesLimit it is std::pow itself.
TEST(ShiftSaturation, SeriesAgreesWithPow) {
  for (double q : {0.0, 0.14, 0.5, 0.99}) {
    const ShiftSaturation shift(q);
    for (double max_abs_u : {0.0, 1e-3, 0.07, 0.12, ShiftSaturation::kSeriesLimit}) {
      const int terms = shift.terms(max_abs_u);
      ASSERT_GE(terms, 1);
      ASSERT_LE(terms, ShiftSaturation::kMaxTerms);
      for (int k = -50; k <= 50; ++k) {
        const double u = max_abs_u * k / 50.0;
        EXPECT_NEAR(shift(u, terms) / std::pow(1.0 - u, -q), 1.0, 4e-16) << "q " << q << " u " << u;
      }
    }
    // The batch form gives the scalar form's values.
    double u[7] = {-0.25, -0.1, -1e-3, 0.0, 0.05, 0.2, 0.25}, out[7];
    for (int terms : {shift.terms(0.25), 0}) {
      shift(u, 7, terms, out);
      for (int m = 0; m < 7; ++m) EXPECT_EQ(out[m], shift(u[m], terms)) << "q " << q << " u " << u[m];
    }
    EXPECT_EQ(shift.terms(0.3), 0);
    EXPECT_EQ(shift(0.3, 0), std::pow(0.7, -q));
    EXPECT_EQ(shift(-0.6, 0), std::pow(1.6, -q));
  }
  // Fewer terms for a smaller shift: the series is cut where its remainder is below rounding.
  const ShiftSaturation shift(0.14);
  EXPECT_LT(shift.terms(0.07), shift.terms(0.12));
  EXPECT_LT(shift.terms(0.12), shift.terms(0.25));
}

}  // namespace
}  // namespace tread_wear
