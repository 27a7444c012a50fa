// The detectability reference (detectability.h) against independent references: the noncentral F power against
// the normal limit, Cohen's tables and a quadrature over the denominator's chi-square; the oracle's size on a
// no-effect case; the exact scaling of the noncentrality with the noise; and the oracle's Monte Carlo detection
// rate against the analytic power. The detection limits against a linear closed form and against the generator's
// recordings at the limit.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <stdexcept>

#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/diagnosis/statistics.h"
#include "tread_wear/proving/conceal.h"
#include "tread_wear/proving/detectability.h"

using namespace tread_wear;
using namespace tread_wear::diagnosis;

namespace {

double normalCdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

/// P(noncentral chi-square(1; lambda) > t): the square of N(sqrt(lambda), 1) beyond t.
double noncentralChiSquare1Tail(double lambda, double t) {
  return normalCdf(std::sqrt(lambda) - std::sqrt(t)) + normalCdf(-std::sqrt(lambda) - std::sqrt(t));
}

/// P(noncentral chi-square(2; lambda) > t) as a Poisson mixture of central chi-squares with 2 + 2j degrees of
/// freedom, whose tails are finite sums for even degrees of freedom.
double noncentralChiSquare2Tail(double lambda, double t) {
  double p = 0.0;
  for (int j = 0; j < 200; ++j) {
    const double weight = std::exp(-0.5 * lambda + j * std::log(0.5 * lambda) - std::lgamma(j + 1.0));
    double tail = 0.0;
    for (int i = 0; i <= j; ++i) tail += std::exp(-0.5 * t + i * std::log(0.5 * t) - std::lgamma(i + 1.0));
    p += weight * tail;
  }
  return p;
}

/// The critical value of F(df1, df2) at `level`, by bisection on the project's own F tail (statistics.h).
double fCriticalByBisection(double df1, double df2, double level) {
  double lo = 0.0, hi = 1e3;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (fDistributionUpperTail(mid, df1, df2) > level ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

ConcealSpec smallDesignCase(const std::string& effect, double magnitude) {
  ConcealSpec spec;
  spec.effect = effect;
  spec.magnitude = magnitude;
  spec.design = "small";
  spec.seed = 21;
  return spec;
}

/// The small design without an effect: its noise-free recordings and true levels (w3_scale, mu_scale).
struct NoEffectDesign {
  TireParams base;
  ConcealCase c = concealEffect(base, smallDesignCase("none", std::nan("")));
  DiagnosisData data = buildDiagnosisData(c.noise_free);
  double w3_scale() const { return c.answer.parameters.at("w3_scale"); }
  double mu_scale() const { return c.answer.parameters.at("mu_scale"); }
};

Detectability detectabilityOf(const ConcealSpec& spec, const DetectabilityOptions& options) {
  const TireParams base;
  const ConcealCase c = concealEffect(base, spec);
  return detectability(base, buildDiagnosisData(c.noise_free), spec.effect, options);
}

}  // namespace

TEST(DiagnosisDetectability, FTestPowerMatchesTheChiSquareLimitAndCohensTables) {
  // Denominator degrees of freedom -> infinity: df1 F -> chi-square(df1). 80% power at lambda = (z_(1-a/2) +
  // z_0.8)^2: 7.849 at 5%, 11.679 at 1%; for two degrees of freedom at 5%, 9.635 (Cohen 1988, Table 7.4.15 gives
  // 9.64).
  EXPECT_NEAR(fTestPower(7.849, 1, 1e8, 0.05), 0.80, 1e-3);
  EXPECT_NEAR(fTestPower(11.679, 1, 1e8, 0.01), 0.80, 1e-3);
  EXPECT_NEAR(fTestPower(9.635, 2, 1e8, 0.05), 0.80, 1e-3);
  for (double lambda : {0.5, 4.0, 15.0, 40.0}) {
    EXPECT_NEAR(fTestPower(lambda, 1, 1e8, 0.001), noncentralChiSquare1Tail(lambda, 10.827566170662733), 1e-4)
        << lambda;
    EXPECT_NEAR(fTestPower(lambda, 2, 1e8, 0.05), noncentralChiSquare2Tail(lambda, -2.0 * std::log(0.05)), 1e-4)
        << lambda;
  }
  EXPECT_DOUBLE_EQ(fTestPower(0.0, 1, 30, 0.01), 0.01);
  EXPECT_EQ(fTestPower(2e4, 1, 30, 0.01), 1.0);
  EXPECT_THROW(fTestPower(-1.0, 1, 30, 0.05), std::invalid_argument);
  EXPECT_THROW(fTestPower(1.0, 1, 30, 1.5), std::invalid_argument);
}

TEST(DiagnosisDetectability, FTestPowerWithFewDegreesOfFreedomMatchesAQuadrature) {
  // F'(1, 30; lambda) = chi'^2_1(lambda) / (chi^2_30 / 30): the power is the chi'^2_1 tail at F_crit x / 30,
  // averaged over the chi-square(30) density of x (trapezoid rule), with F_crit from the project's F tail.
  const double df2 = 30.0, level = 0.01 / 9.0;
  const double critical = fCriticalByBisection(1.0, df2, level);
  for (double lambda : {5.0, 15.0, 30.0}) {
    const int steps = 40000;
    const double x_max = 200.0, h = x_max / steps;
    double power = 0.0;
    for (int i = 1; i < steps; ++i) {
      const double x = i * h;
      const double density =
          std::exp((0.5 * df2 - 1.0) * std::log(x) - 0.5 * x - 0.5 * df2 * std::log(2.0) - std::lgamma(0.5 * df2));
      power += h * density * noncentralChiSquare1Tail(lambda, critical * x / df2);
    }
    EXPECT_NEAR(fTestPower(lambda, 1.0, df2, level), power, 1e-4) << lambda;
  }
}

TEST(DiagnosisDetectability, WithoutAnEffectTheOracleKeepsTheSizeOfItsTests) {
  // No hidden term: the noise-free recordings are the base model, the noncentrality is 0, and the verdict is
  // "none" unless one of the m tests at level alpha / m passes by chance: (1 - alpha / m)^m.
  DetectabilityOptions o;
  o.draws = 20000;
  const Detectability d = detectabilityOf(smallDesignCase("none", std::nan("")), o);
  EXPECT_LT(d.lambda, 1e-8);
  ASSERT_GT(d.terms_tried, 5);
  const double size = std::pow(1.0 - o.alpha_select / d.terms_tried, d.terms_tried);
  EXPECT_NEAR(d.expected_right, size, 4.0 * std::sqrt(size * (1.0 - size) / o.draws));
  EXPECT_EQ(d.verdicts.front().verdict, "none");
}

TEST(DiagnosisDetectability, NoncentralityScalesAsTheInverseSquareOfTheNoise) {
  // Halving both noise levels scales every weighted residual by 2 and leaves the best fit where it was.
  DetectabilityOptions o;
  o.draws = 100;
  const ConcealSpec spec = smallDesignCase("sensor_offset", 2.0);
  const Detectability rig = detectabilityOf(spec, o);
  o.wear_noise_rsd /= 2.0;
  o.side_force_noise_n /= 2.0;
  const Detectability quiet = detectabilityOf(spec, o);
  ASSERT_GT(rig.lambda, 1.0);
  EXPECT_NEAR(quiet.lambda / rig.lambda, 4.0, 4e-4);
  EXPECT_GT(quiet.power, rig.power);
}

TEST(DiagnosisDetectability, OracleDetectionRateMatchesTheNoncentralF) {
  // Only the hidden term tried: the oracle's Monte Carlo share of draws that accept it (linearised fits on noise
  // draws) and the analytic noncentral F power are two computations of one probability. Offset and compliance
  // sizes were picked for a power between 20% and 80% on the 18-run design at rig noise; compliance checks the
  // boundary version of the test (twice the level).
  for (const auto& [effect, magnitude] : {std::pair<std::string, double>{"sensor_offset", 1.6},
                                          std::pair<std::string, double>{"lateral_compliance", 1.2e-4}}) {
    DetectabilityOptions o;
    o.draws = 20000;
    Term t;
    ASSERT_TRUE(parseTerm(effect, &t));
    o.candidates = {t};
    const Detectability d = detectabilityOf(smallDesignCase(effect, magnitude), o);
    ASSERT_EQ(d.terms_tried, 1);
    EXPECT_GT(d.power, 0.2) << effect;
    EXPECT_LT(d.power, 0.8) << effect;
    // Monte Carlo error (4 standard errors) plus 0.01 for the linearisation.
    EXPECT_NEAR(d.expected_right, d.power, 4.0 * std::sqrt(0.25 / o.draws) + 0.01) << effect;
  }
}

TEST(DiagnosisDetectability, ReferenceStandardErrorIsTheSpreadOfNoisyFits) {
  // The offset's reference standard error against the spread of real (nonlinear) fits of base + offset, weighted by
  // the true noise, to 100 noisy copies of the case.
  const TireParams base;
  const ConcealSpec spec = smallDesignCase("sensor_offset", 2.0);
  const ConcealCase c = concealEffect(base, spec);
  const DiagnosisData truth = buildDiagnosisData(c.noise_free);
  DetectabilityOptions o;
  o.draws = 100;
  o.candidates = {Term::kSensorOffset};
  const Detectability d = detectability(base, truth, "sensor_offset", o);
  double reference_se = NAN;
  for (const ReferenceParameter& p : d.parameters)
    if (p.name == "side_force_offset_n") reference_se = p.std_error;
  ASSERT_TRUE(std::isfinite(reference_se));

  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  const int copies = 100;
  double sum = 0.0, sum_sq = 0.0;
  for (int k = 0; k < copies; ++k) {
    DiagnosisData noisy = truth;
    for (DiagnosisRun& r : noisy.runs) {
      r.measured[0] += o.side_force_noise_n * normal(rng);
      r.measured[1] *= 1.0 + o.wear_noise_rsd * normal(rng);
    }
    const ExtendedModel model(base, o.model, {Term::kSensorOffset}, noisy);
    LeastSquaresProblem problem;
    problem.parameters = model.parameters();
    problem.num_records = static_cast<int>(noisy.runs.size());
    problem.residuals_per_record = 2;
    problem.residuals = [&](const std::vector<double>& values, const std::vector<int>& records, double* res) {
      Prediction pred;
      if (!model.predict(values, &pred)) return false;
      for (std::size_t i = 0; i < records.size(); ++i) {
        const DiagnosisRun& r = noisy.runs[records[i]];
        res[2 * i] = (pred.side_force_n[records[i]] - r.measured[0]) / o.side_force_noise_n;
        res[2 * i + 1] = (pred.wear_kg_per_m[records[i]] / r.measured[1] - 1.0) / o.wear_noise_rsd;
      }
      return true;
    };
    const LeastSquaresSummary fit = solveLeastSquares(problem, LeastSquaresOptions{});
    ASSERT_TRUE(fit.usable);
    const double offset = fit.values()[model.parameterOffset(Term::kSensorOffset)];
    sum += offset;
    sum_sq += offset * offset;
  }
  const double mean = sum / copies, spread = std::sqrt((sum_sq - copies * mean * mean) / (copies - 1));
  // The sample standard deviation of 100 estimates is within about 7% of the true one (one standard error).
  EXPECT_NEAR(spread / reference_se, 1.0, 0.25) << "spread " << spread << " reference " << reference_se;
  EXPECT_NEAR(mean, 2.0, 4.0 * reference_se / std::sqrt(copies));
}

TEST(DiagnosisDetectability, InvalidOptionsAndTermsNameTheProblem) {
  const NoEffectDesign design;
  const TireParams& base = design.base;
  const DiagnosisData& data = design.data;
  DetectabilityOptions o;
  o.wear_noise_rsd = 0.0;
  try {
    detectability(base, data, "none", o);
    FAIL() << "zero wear noise accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("wear_noise_rsd = 0"), std::string::npos) << e.what();
  }
  o = DetectabilityOptions{};
  o.draws = 10;
  EXPECT_THROW(detectability(base, data, "none", o), std::invalid_argument);
  EXPECT_THROW(detectability(base, data, "tyre_pressure", DetectabilityOptions{}), std::invalid_argument);
  // Without tread temperatures no thermal term can be shown: never tested, never named.
  DiagnosisData no_temperatures = data;
  no_temperatures.has_temperature = false;
  o = DetectabilityOptions{};
  o.draws = 100;
  const Detectability thermal = detectability(base, no_temperatures, "thermal_wear", o);
  EXPECT_EQ(thermal.power, 0.0);
  EXPECT_EQ(thermal.expected_right, 0.0);
  // Too few measured values for the models: a clear error, not a negative degree of freedom.
  DiagnosisData two_runs = data;
  two_runs.runs.resize(2);
  two_runs.measured_count[0] = two_runs.measured_count[1] = 2;
  try {
    detectability(base, two_runs, "none", o);
    FAIL() << "two runs accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("too few"), std::string::npos) << e.what();
  }
}

namespace {

/// The noncentrality at which the first-step F test (1 numerator degree of freedom) reaches `power`, by bisection.
double lambdaForPower(double power, double df2, double level) {
  double lo = 0.0, hi = 200.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (fTestPower(mid, 1.0, df2, level) < power ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

int applicableTerms(const DiagnosisData& data) {
  int m = 0;
  for (const TermInfo& info : termLibrary()) m += termApplicable(info.term, data, nullptr) ? 1 : 0;
  return m;
}

const DetectionLimit& limitOf(const std::vector<DetectionLimit>& limits, const std::string& term) {
  for (const DetectionLimit& l : limits)
    if (l.term == term) return l;
  throw std::runtime_error("no limit for " + term);
}

}  // namespace

// An offset adds the same force to every run, so for a small offset the base model's best fit to base + offset is
// linear in it: lambda(o) = o^2 |(I - P_J) e|^2, e the offset's residual column and J the base levels' Jacobian
// (noise units). The limit is then sqrt(lambda* / |(I - P_J) e|^2) with lambda* where the F test reaches the power.
// A quiet transducer (0.1 N) keeps the limit small (0.3 N), where the mu_scale shift that absorbs part of it is
// linear to 0.3%; at 1 N the two sides differ by +-3% from the closed form, the second-order term.
TEST(DiagnosisDetectionLimits, OffsetLimitMatchesTheLinearClosedForm) {
  const NoEffectDesign design;
  const TireParams& base = design.base;
  const DiagnosisData& data = design.data;
  const double w3 = design.w3_scale(), mu = design.mu_scale();
  DetectabilityOptions o;
  o.side_force_noise_n = 0.1;
  o.wear_noise_rsd = 0.05;

  // Jacobian of the base model's residuals (noise units) in w3_scale and mu_scale, by central differences.
  const ExtendedModel model(base, o.model, {}, data);
  const int runs = static_cast<int>(data.runs.size()), n = 2 * runs;
  Prediction p0;
  ASSERT_TRUE(model.predict({w3, mu}, &p0));
  Eigen::MatrixXd jacobian(n, 2);
  for (int j = 0; j < 2; ++j) {
    std::vector<double> up{w3, mu}, down{w3, mu};
    const double h = 1e-5 * up[j];
    up[j] += h;
    down[j] -= h;
    Prediction pu, pd;
    ASSERT_TRUE(model.predict(up, &pu) && model.predict(down, &pd));
    for (int i = 0; i < runs; ++i) {
      jacobian(2 * i, j) = (pu.side_force_n[i] - pd.side_force_n[i]) / (2 * h) / o.side_force_noise_n;
      jacobian(2 * i + 1, j) = (pu.wear_kg_per_m[i] - pd.wear_kg_per_m[i]) / (2 * h) / p0.wear_kg_per_m[i] /
                               o.wear_noise_rsd;
    }
  }
  Eigen::VectorXd offset_column = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < runs; ++i) offset_column(2 * i) = 1.0 / o.side_force_noise_n;
  const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(jacobian).householderQ() *
                            Eigen::MatrixXd::Identity(n, 2);
  const double unabsorbed = offset_column.squaredNorm() - (q.transpose() * offset_column).squaredNorm();
  const double level = o.alpha_select / applicableTerms(data);
  const double expected = std::sqrt(lambdaForPower(0.8, n - 3, level) / unabsorbed);

  const std::vector<DetectionLimit> limits = detectionLimits(base, data, w3, mu, 0.8, o);
  const DetectionLimit& offset = limitOf(limits, "sensor_offset");
  EXPECT_EQ(offset.parameter, "side_force_offset_n");
  // The search ends within 0.1% of the limit; the rest is the model's curvature, second order in the offset (about
  // 0.3% at this noise, 3-4% at 1 N).
  EXPECT_NEAR(offset.above / expected, 1.0, 0.01) << "closed form " << expected << " N";
  EXPECT_NEAR(-offset.below / expected, 1.0, 0.01) << "closed form " << expected << " N";
}

// The generator's recordings of a term at its limit have the wanted power under the reference (detectability):
// the search and the truth it builds agree with the concealed-effect generator, for a two-sided term and for a
// one-sided one (the boundary test's doubled level).
TEST(DiagnosisDetectionLimits, RecordingsAtTheLimitHaveTheWantedPower) {
  const NoEffectDesign design;
  DetectabilityOptions o;
  o.draws = 100;
  const std::vector<DetectionLimit> limits =
      detectionLimits(design.base, design.data, design.w3_scale(), design.mu_scale(), 0.8, o);
  for (const char* term : {"sensor_gain", "lateral_compliance", "surface_polishing"}) {
    const DetectionLimit& limit = limitOf(limits, term);
    ASSERT_TRUE(std::isfinite(limit.above)) << term << ": " << limit.note;
    ConcealSpec spec = smallDesignCase(term, limit.above);
    spec.wear_noise_rsd = o.wear_noise_rsd;
    spec.side_force_noise_n = o.side_force_noise_n;
    const Detectability d = detectabilityOf(spec, o);
    // The search ends where sqrt(lambda) is within 0.1% of its value at power 0.8: lambda within 0.2%, which moves
    // the power by less than 0.002 (d power / d ln lambda < 1).
    EXPECT_NEAR(d.power, 0.8, 2e-3) << term << " at " << limit.above;
  }
  const DetectionLimit& gain = limitOf(limits, "sensor_gain");
  EXPECT_LT(gain.below, 1.0);
  EXPECT_GT(gain.above, 1.0);
}

TEST(DiagnosisDetectionLimits, OneSidedTermsSwitchesAndMissingCovariates) {
  const NoEffectDesign design;
  const TireParams& base = design.base;
  DiagnosisData data = design.data;
  data.has_temperature = false;
  DetectabilityOptions o;
  const std::vector<DetectionLimit> limits = detectionLimits(base, data, 1.0, 1.0, 0.8, o);
  ASSERT_EQ(limits.size(), termLibrary().size());
  for (const char* term : {"surface_polishing", "lateral_compliance", "load_fluctuation"}) {
    const DetectionLimit& l = limitOf(limits, term);
    EXPECT_EQ(l.neutral, 0.0) << term;
    EXPECT_TRUE(std::isnan(l.below)) << term << ": its effect goes one way only";
  }
  // The recorded load std (2-6% of the load) is far below what the 18 runs could show even at 6 times its size.
  EXPECT_TRUE(std::isnan(limitOf(limits, "load_fluctuation").above));
  EXPECT_NE(limitOf(limits, "load_fluctuation").note.find("above: power"), std::string::npos);
  const DetectionLimit& orientation = limitOf(limits, "turn_slip_orientation");
  EXPECT_GT(orientation.switch_power, 0.99) << "the rig's turn slip makes the orientation plain";
  for (const char* term : {"thermal_wear", "thermal_friction"}) {
    const DetectionLimit& l = limitOf(limits, term);
    EXPECT_TRUE(std::isnan(l.below) && std::isnan(l.above)) << term;
    EXPECT_EQ(l.note.rfind("not applicable: ", 0), 0u) << l.note;
  }
  EXPECT_EQ(limitOf(limits, "pressure_friction").neutral, base.friction.q);
}

TEST(DiagnosisDetectionLimits, BadInputNamesTheProblem) {
  const NoEffectDesign design;
  const TireParams& base = design.base;
  const DiagnosisData& data = design.data;
  DetectabilityOptions o;
  o.candidates = {Term::kSensorOffset};
  for (double power : {0.0, 1.0, std::nan("")}) {
    try {
      detectionLimits(base, data, 1.0, 1.0, power, o);
      FAIL() << "power " << power << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("power"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(detectionLimits(base, data, 0.0, 1.0, 0.8, o), std::invalid_argument);
  EXPECT_THROW(detectionLimits(base, data, 1.0, std::nan(""), 0.8, o), std::invalid_argument);
  o.side_force_noise_n = -1.0;
  EXPECT_THROW(detectionLimits(base, data, 1.0, 1.0, 0.8, o), std::invalid_argument);
  // Only the candidates asked for.
  o = DetectabilityOptions{};
  o.candidates = {Term::kSensorOffset};
  EXPECT_EQ(detectionLimits(base, data, 1.0, 1.0, 0.8, o).size(), 1u);
  // Too few values for a term's model: a note, not an error (the diagnosis itself may still have a verdict).
  DiagnosisData one_run = data;
  one_run.runs.resize(1);
  const std::vector<DetectionLimit> few = detectionLimits(base, one_run, 1.0, 1.0, 0.8, o);
  ASSERT_EQ(few.size(), 1u);
  EXPECT_NE(few[0].note.find("too few measured values (2) for its 3 parameters"), std::string::npos) << few[0].note;
  EXPECT_TRUE(std::isnan(few[0].below) && std::isnan(few[0].above));
}

// A small wear-only campaign through the whole diagnosis: the verdict stands, and every term gets a limit or says
// why not (no side force for the sensor terms; power not reached on five runs).
TEST(DiagnosisDetectionLimits, FiveWearOnlyRunsGiveNotesNotErrors) {
  const TireParams base;
  ConcealCase c = concealEffect(base, smallDesignCase("none", std::nan("")));
  c.table.runs.resize(5);
  for (RunRecord& r : c.table.runs) r.measured_side_force_n = std::nan("");
  DiagnosisOptions opt;
  opt.auto_preset = false;  // generated at fast: the machinery, generator = diagnoser
  opt.permutations = 99;
  const DiagnosisResult r = diagnose(base, buildDiagnosisData(c.table), opt);
  EXPECT_EQ(r.explanation, "none");
  EXPECT_TRUE(std::isnan(r.side_force_noise_n));
  EXPECT_GT(r.wear_noise_rsd, 0.0);
  ASSERT_EQ(r.detection_limits.size(), termLibrary().size());
  for (const DetectionLimit& l : r.detection_limits) {
    const bool limited = std::isfinite(l.below) || std::isfinite(l.above) || std::isfinite(l.switch_power);
    EXPECT_TRUE(limited || !l.note.empty()) << l.term;
    if (l.term == "sensor_gain" || l.term == "sensor_offset") {
      EXPECT_EQ(l.note, "not applicable: no side force measured");
    }
  }
}
