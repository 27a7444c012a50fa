// Table 5 documents (report/reference_models_report.h): the JSON keys of every row, null for what a row does not
// have, and the Markdown table from the same rows.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "tread_wear/report/reference_models_report.h"

namespace tread_wear {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Table5 twoRows(bool temperatures) {
  Table5 t;
  t.orientation = "literal";
  t.temperatures_available = temperatures;
  t.rows.push_back({"Opt", "paper Table 5", 0.31, 2.20, 13.35, 0.0538, 4.38, 0.0832, 1.0, kNan, kNan});
  t.rows.push_back({"M_P", "fitted here", 1.5, 1.25, 2.5, 9.75, 6.5, 0.125, 1.5, 0.25, kInf});
  return t;
}

TEST(Table5Json, KeysOfDocumentAndRows) {
  const std::string text = table5Json(twoRows(false));
  EXPECT_EQ(text.back(), '\n');
  const nlohmann::json j = nlohmann::json::parse(text);
  EXPECT_EQ(j.at("orientation"), "literal");
  EXPECT_EQ(j.at("temperatures_available"), false);
  EXPECT_TRUE(j.at("side_force_input").is_string());
  ASSERT_EQ(j.at("rows").size(), 2u);
  const nlohmann::json& fitted = j["rows"][1];
  EXPECT_EQ(fitted.size(), 11u);
  EXPECT_EQ(fitted.at("model"), "M_P");
  EXPECT_EQ(fitted.at("source"), "fitted here");
  EXPECT_EQ(fitted.at("w1"), 1.5);
  EXPECT_EQ(fitted.at("w2"), 1.25);
  EXPECT_EQ(fitted.at("w3_1e-2"), 2.5);
  EXPECT_EQ(fitted.at("w4_1e-2"), 9.75);
  EXPECT_EQ(fitted.at("rmse_1e-2_g_per_km"), 6.5);
  EXPECT_EQ(fitted.at("rmser"), 0.125);
  EXPECT_EQ(fitted.at("eri"), 1.5);
  EXPECT_EQ(fitted.at("cv_rmser"), 0.25);
}

TEST(Table5Json, NonFiniteValuesAreNull) {
  const nlohmann::json j = nlohmann::json::parse(table5Json(twoRows(false)));
  EXPECT_TRUE(j["rows"][0].at("cv_rmser").is_null());
  EXPECT_TRUE(j["rows"][0].at("cv_eri").is_null());
  EXPECT_TRUE(j["rows"][1].at("cv_eri").is_null());  // infinity too: JSON has no such number
  EXPECT_EQ(j["rows"][0].at("eri"), 1.0);
}

TEST(Table5Markdown, RowsDashesAndTemperatureNote) {
  const std::string md = table5Markdown(twoRows(false));
  EXPECT_NE(md.find("| Opt | paper Table 5 | 0.310 | 2.200 | 13.35 | 0.0538 | 4.38 | 8.32% | 1.00 | - | - |\n"),
            std::string::npos);
  EXPECT_NE(md.find("| M_P | fitted here | 1.500 | 1.250 | 2.5 | 9.75 | 6.50 | 12.50% | 1.50 | 25.00% | - |\n"),
            std::string::npos);
  EXPECT_NE(md.find("M_PT and M_EPT are not fitted"), std::string::npos);
  EXPECT_EQ(table5Markdown(twoRows(true)).find("are not fitted"), std::string::npos);
}

}  // namespace
}  // namespace tread_wear
