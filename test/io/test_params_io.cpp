// Parameter files: the bundled Grosch wheel file against the paper's Table 4 converted by hand, unit
// variants, the error for each kind of bad input, and the SI round trip.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <string>

#include "common/temp_file.h"
#include "tread_wear/io/params_io.h"

namespace tread_wear {
namespace {

const std::string kGroschFile = std::string(TREAD_WEAR_SOURCE_DIR) + "/config/tires/grosch_wheel.yaml";

// Converting a paper value to SI multiplies by a power of ten once: one rounding, so equality to a few ulp.
constexpr double kConversionRelTol = 1e-14;

void expectSi(double expected, double actual, const char* what) {
  EXPECT_NEAR(actual, expected, std::fabs(expected) * kConversionRelTol) << what;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// The bundled file with one line replaced (the line must exist).
std::string groschWith(const std::string& old_line, const std::string& new_line) {
  std::string text = readFile(kGroschFile);
  const std::size_t pos = text.find(old_line);
  EXPECT_NE(pos, std::string::npos) << old_line;
  if (pos != std::string::npos) text.replace(pos, old_line.size(), new_line);
  return text;
}

/// Loads text expecting a ParamsError whose message contains every fragment.
void expectError(const std::string& text, const std::vector<std::string>& fragments) {
  TempFile file(text, ".yaml");
  try {
    loadTireParams(file.path());
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const ParamsError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(file.path()), std::string::npos) << "message must name the file: " << msg;
    for (const std::string& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
  }
}

TEST(ParamsIo, GroschFileIsTable4InSi) {
  const TireParams p = loadTireParams(kGroschFile);
  EXPECT_EQ(p.name, "grosch_wheel");
  // Table 4 values converted by hand: mm -> 1e-3 m, MPa -> 1e6 Pa, MPa/mm -> 1e9 Pa/m, mg/(s mm^2) -> kg/(s m^2).
  expectSi(0.05e-3, p.footprint.a1_m, "a1");
  expectSi(0.82, p.footprint.a2, "a2");
  expectSi(1.37e-3, p.footprint.a3_m, "a3");
  expectSi(9e-3, p.footprint.b_m, "b");
  expectSi(2.06, p.footprint.n_x, "n_x");
  expectSi(0.52, p.footprint.lambda_x, "lambda_x");
  expectSi(0.08e-3, p.footprint.x_e_m, "x_e");
  expectSi(4.0, p.footprint.n_y, "n_y");
  expectSi(1.84, p.footprint.lambda_y, "lambda_y");
  EXPECT_EQ(p.footprint.y_e_m, 0.0);
  expectSi(0.46, p.friction.mu_0, "mu_0");
  expectSi(1.15, p.friction.mu_m, "mu_m");
  expectSi(0.07009, p.friction.v_m_mps, "v_m");
  expectSi(0.42, p.friction.h, "h");
  expectSi(2e4, p.friction.p_0_pa, "p_0");
  expectSi(3e5, p.friction.p_ref_pa, "p_ref");
  expectSi(0.14, p.friction.q, "q");
  expectSi(0.92e9, p.tread.k_y0_pa_per_m, "k_y0");
  expectSi(5.42e6, p.tread.k_y1_pa_per_m_n, "k_y1");
  expectSi(0.43, p.tread.phi, "phi");
  expectSi(1.16e5, p.tread.c_x_pa_s_per_m, "c_x");
  expectSi(5.60e5, p.tread.c_y_pa_s_per_m, "c_y");
  expectSi(20.0, p.tread.m_kg_per_m2, "m");
  expectSi(0.31, p.wear.w1, "w1");
  expectSi(2.20, p.wear.w2, "w2");
  expectSi(0.1335, p.wear.w3_kg_per_s_m2, "w3");
  expectSi(5.38e-4, p.wear.w4_kg_per_s_m2, "w4");
  EXPECT_FALSE(p.wear.temperature_enabled);
  expectSi(47.17, p.wear.t0_c, "T0");
  expectSi(57.98, p.wear.sigma_t_c, "sigma_T");
  expectSi(1150.0, p.material.rubber_density_kg_per_m3, "density");
  expectSi(6e-3, p.material.tread_depth_m, "tread depth");
  expectSi(18e-3, p.material.tread_width_m, "tread width");
  expectSi(36e-3, p.material.rolling_radius_m, "rolling radius");

  const RigGeometry rig = loadRigGeometry(kGroschFile);
  expectSi(60e-3, rig.track_radius_m, "R_t");
  expectSi(36e-3, rig.wheel_radius_m, "wheel radius");
  expectSi(18e-3, rig.wheel_width_m, "wheel width");
  expectSi(30e-3, rig.rim_radius_m, "rim radius");
}

TEST(ParamsIo, GroschFileMatchesTheCompiledDefaults) {
  const TireParams file = loadTireParams(kGroschFile);
  const TireParams defaults;
  expectSi(defaults.tread.k_y0_pa_per_m, file.tread.k_y0_pa_per_m, "k_y0");
  expectSi(defaults.wear.w3_kg_per_s_m2, file.wear.w3_kg_per_s_m2, "w3");
  expectSi(defaults.footprint.a1_m, file.footprint.a1_m, "a1");
}

TEST(ParamsIo, SiSpellingsGiveTheSameValues) {
  const TireParams si = [] {
    TempFile f(groschWith("k_y0_MPa_per_mm: 0.92", "k_y0_Pa_per_m: 0.92e9"), ".yaml");
    return loadTireParams(f.path());
  }();
  expectSi(0.92e9, si.tread.k_y0_pa_per_m, "k_y0 in Pa/m");
  TempFile f(groschWith("v_m_mm_per_s: 70.09", "v_m_m_per_s: 0.07009"), ".yaml");
  expectSi(0.07009, loadTireParams(f.path()).friction.v_m_mps, "v_m in m/s");
}

TEST(ParamsIo, MaterialAndRigSectionsAreOptional) {
  std::string text = readFile(kGroschFile);
  text = text.substr(0, text.find("material:"));
  TempFile f(text, ".yaml");
  const TireParams p = loadTireParams(f.path());
  EXPECT_EQ(p.material.tread_depth_m, MaterialParams().tread_depth_m);
  EXPECT_EQ(loadRigGeometry(f.path()).track_radius_m, RigGeometry().track_radius_m);
}

TEST(ParamsIo, TemperatureSwitch) {
  TempFile f(groschWith("temperature_enabled: false", "temperature_enabled: true"), ".yaml");
  EXPECT_TRUE(loadTireParams(f.path()).wear.temperature_enabled);
  expectError(groschWith("temperature_enabled: false", "temperature_enabled: maybe"),
              {"wear.temperature_enabled", "maybe", "true or false"});
}

TEST(ParamsIo, UnknownKeyNamesItAndListsAcceptedKeys) {
  expectError(groschWith("k_y0_MPa_per_mm: 0.92", "k_y00_MPa_per_mm: 0.92"),
              {"unknown key 'tread.k_y00_MPa_per_mm'", "k_y0_MPa_per_mm", "k_y0_Pa_per_m"});
  expectError(readFile(kGroschFile) + "extras:\n  x: 1\n", {"unknown top-level key 'extras'"});
}

TEST(ParamsIo, MissingKeysAndSections) {
  expectError(groschWith("  b_mm: 9 ", "  "), {"missing required key 'footprint.b'", "b_mm or b_m"});
  expectError(groschWith("format_version: 1", ""), {"format_version"});
  expectError(groschWith("name: grosch_wheel", ""), {"missing required key 'name'"});
  std::string no_wear = readFile(kGroschFile);
  const std::size_t begin = no_wear.find("wear:");
  no_wear.erase(begin, no_wear.find("material:") - begin);
  expectError(no_wear, {"missing required section 'wear'"});
}

TEST(ParamsIo, BadValues) {
  expectError(groschWith("phi: 0.43", "phi: soft"), {"tread.phi", "'soft'", "finite number"});
  expectError(groschWith("phi: 0.43", "phi: .nan"), {"tread.phi", ".nan", "finite number"});
  expectError(groschWith("phi: 0.43", "phi: [1, 2]"), {"tread.phi", "single value"});
  expectError(groschWith("format_version: 1", "format_version: 2"), {"format_version", "'2'", "must be 1"});
  // Constraint violations found by TireParams::validate() name the field, its SI value and the constraint.
  expectError(groschWith("k_y0_MPa_per_mm: 0.92", "k_y0_MPa_per_mm: -0.92"), {"tread.k_y0", "-920000000", "> 0"});
  expectError(groschWith("mu_m: 1.15", "mu_m: 0.3"), {"friction.mu_m", "0.3", ">= mu_0"});
  expectError(groschWith("rim_radius_mm: 30", "rim_radius_mm: 40"), {"rig.rim_radius", "< wheel_radius"});
}

TEST(ParamsIo, TwoUnitsForOneFieldIsAnError) {
  expectError(groschWith("b_mm: 9 ", "b_mm: 9\n  b_m: 0.009 "), {"footprint.b", "b_mm", "b_m", "one unit"});
  expectError(groschWith("b_mm: 9 ", "b_mm: 9\n  b_mm: 9 "), {"b_mm", "twice"});
}

TEST(ParamsIo, UnreadableFiles) {
  EXPECT_THROW(loadTireParams("/nonexistent/dir/tire.yaml"), ParamsError);
  expectError("footprint: [unclosed\n  a: {", {"YAML"});
  expectError("- just\n- a list\n", {"mapping"});
  expectError("", {"mapping"});
}

TEST(ParamsIo, SaveLoadRoundTripIsExact) {
  TireParams p = loadTireParams(kGroschFile);
  p.name = "calibrated: wheel #2";
  p.tread.k_y0_pa_per_m = 1.234567890123e9;
  p.wear.w3_kg_per_s_m2 = 0.1 / 3.0;  // not representable in few digits
  p.wear.temperature_enabled = true;
  TempFile out("", ".yaml");
  saveTireParams(p, out.path(), "fit of Table 3\nsecond line");
  const std::string text = readFile(out.path());
  EXPECT_EQ(text.rfind("# fit of Table 3\n# second line\n", 0), 0u) << text;
  EXPECT_NE(text.find("k_y0_Pa_per_m"), std::string::npos) << "saved keys must be SI";
  const TireParams q = loadTireParams(out.path());
  EXPECT_EQ(q.name, p.name);
  EXPECT_EQ(q.tread.k_y0_pa_per_m, p.tread.k_y0_pa_per_m);
  EXPECT_EQ(q.wear.w3_kg_per_s_m2, p.wear.w3_kg_per_s_m2);
  EXPECT_EQ(q.wear.temperature_enabled, true);
  EXPECT_EQ(q.footprint.a1_m, p.footprint.a1_m);
  EXPECT_EQ(q.friction.v_m_mps, p.friction.v_m_mps);
  EXPECT_EQ(q.tread.m_kg_per_m2, p.tread.m_kg_per_m2);
  EXPECT_EQ(q.material.rubber_density_kg_per_m3, p.material.rubber_density_kg_per_m3);
  EXPECT_EQ(q.wear.sigma_t_c, p.wear.sigma_t_c);
}

}  // namespace
}  // namespace tread_wear
