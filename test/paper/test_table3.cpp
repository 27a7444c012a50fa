// The paper's Table 3 with the Table 4 parameters (config/tires/grosch_wheel.yaml), both orientations of the
// slip angle against the track curve, against the independent figures of the model spec
// (shared/notes/model-spec.md, "The paper's tables, reproduced independently"):
//   literal: Fy RMSER about 25 %, W_r RMSER about 41 %, both over-predicted, most at alpha = 5 deg and Fz = 100 N
//   flipped: Fy RMSER about 51 %, W_r RMSER about 8.3 %
// These are NOT the paper's claims (7.47 % / 8.32 %): the published set does not reproduce both columns at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "tread_wear/fitting/run_comparison.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/io/run_table.h"
#include "tread_wear/model/wear_model.h"

namespace tread_wear {
namespace {

// Tolerances in percentage points of RMSER. The spec gives 25, 41 and 51 to two significant digits (rounding
// +-0.5 pp) from an independent implementation whose documented modelling alternatives (leading-edge state)
// move single predictions by up to 1.4 %; +-2 pp covers both with margin and still fails for any sign,
// unit or orientation mistake (which move these figures by tens of points). 8.3 is given to 0.1 pp, but a small
// RMSER of a few error ratios of mixed sign is sensitive to 1 % shifts of single predictions: +-1 pp.
constexpr double kCoarseFigureTolPp = 2.0;
constexpr double kWearFlippedTolPp = 1.0;

RunComparison compare(TurnSlipOrientation orientation, const RunTable& table) {
  WearModelOptions options;
  options.preset = Preset::kReference;  // the converged grid of the spec (1600 x-steps, 64 strips); < 1 s here
  options.orientation = orientation;
  const WearModel model(loadTireParams(std::string(TREAD_WEAR_SOURCE_DIR) + "/config/tires/grosch_wheel.yaml"),
                        options);
  const RunComparison c = compareRuns(table, wearModelPoint(model));
  std::printf("%s orientation, Table 3 with Table 4 parameters (reference preset)\n",
              orientation == TurnSlipOrientation::kLiteral ? "literal" : "flipped");
  for (std::size_t i = 0; i < table.runs.size(); ++i)
    std::printf("  %-14s Fy %6.2f N meas %6.2f N (%+6.1f %%)  W_r %6.3f g/km meas %6.3f g/km (%+6.1f %%)\n",
                table.runs[i].condition_id.c_str(), c.runs[i].side_force_n, table.runs[i].measured_side_force_n,
                100 * c.runs[i].side_force_error_ratio, c.runs[i].wear_rate_kg_per_m * 1e6,
                table.runs[i].measured_wear_rate_kg_per_m * 1e6, 100 * c.runs[i].wear_error_ratio);
  std::printf("  RMSER Fy = %.2f %%, RMSER W_r = %.2f %%\n", 100 * c.rmser_side_force, 100 * c.rmser_wear);
  return c;
}

class Table3 : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    table_ = new RunTable(readRunTable(std::string(TREAD_WEAR_SOURCE_DIR) + "/data/paper/table3_runs.csv"));
  }
  static void TearDownTestSuite() { delete table_; }
  static RunTable* table_;
};
RunTable* Table3::table_ = nullptr;

TEST_F(Table3, LiteralOrientation) {
  const RunComparison c = compare(TurnSlipOrientation::kLiteral, *table_);
  ASSERT_EQ(c.n_side_force, 9);
  ASSERT_EQ(c.n_wear, 9);
  EXPECT_NEAR(100 * c.rmser_side_force, 25.0, kCoarseFigureTolPp);
  EXPECT_NEAR(100 * c.rmser_wear, 41.0, kCoarseFigureTolPp);
  // Both columns over-predicted at every condition.
  for (const RunPrediction& p : c.runs) {
    EXPECT_GT(p.side_force_error_ratio, 0.0);
    EXPECT_GT(p.wear_error_ratio, 0.0);
  }
  // Largest side-force errors at alpha = 5 deg (row 4) and Fz = 100 N (row 9); largest wear error at 5 deg.
  std::vector<std::pair<double, int>> fy_errors;
  for (int i = 0; i < 9; ++i) fy_errors.push_back({c.runs[i].side_force_error_ratio, i});
  std::sort(fy_errors.rbegin(), fy_errors.rend());
  EXPECT_EQ(table_->runs[fy_errors[0].second].condition_id, "v2_a5_fz75");
  EXPECT_EQ(table_->runs[fy_errors[1].second].condition_id, "v2_a10_fz100");
  int worst_wear = 0;
  for (int i = 1; i < 9; ++i)
    if (c.runs[i].wear_error_ratio > c.runs[worst_wear].wear_error_ratio) worst_wear = i;
  EXPECT_EQ(table_->runs[worst_wear].condition_id, "v2_a5_fz75");
}

TEST_F(Table3, FlippedOrientation) {
  const RunComparison c = compare(TurnSlipOrientation::kFlipped, *table_);
  EXPECT_NEAR(100 * c.rmser_side_force, 51.0, kCoarseFigureTolPp);
  EXPECT_NEAR(100 * c.rmser_wear, 8.3, kWearFlippedTolPp);
}

}  // namespace
}  // namespace tread_wear
