#include "tread_wear/model/tire_params.h"

#include <cmath>
#include <sstream>

#include "tread_wear/model/units.h"

namespace tread_wear {
namespace {

/// Records the first broken constraint as "<field> = <value>: must be <constraint>".
class Checker {
 public:
  Checker(std::string prefix, std::string* error) : prefix_(std::move(prefix)), error_(error) {}

  Checker& require(bool ok, const char* field, double value, const char* constraint) {
    if (ok_ && !(ok && std::isfinite(value))) {
      ok_ = false;
      if (error_ != nullptr) {
        std::ostringstream msg;
        msg.precision(10);
        msg << prefix_ << field << " = " << value << ": must be " << (std::isfinite(value) ? constraint : "finite");
        *error_ = msg.str();
      }
    }
    return *this;
  }
  Checker& positive(const char* field, double value) { return require(value > 0.0, field, value, "> 0"); }
  Checker& nonNegative(const char* field, double value) { return require(value >= 0.0, field, value, ">= 0"); }
  bool ok() const { return ok_; }

 private:
  std::string prefix_;
  std::string* error_;
  bool ok_ = true;
};

}  // namespace

bool FootprintParams::validate(std::string* error) const {
  Checker c("footprint.", error);
  c.nonNegative("a1", a1_m).require(a2 > 0.0 && a2 < 3.0, "a2", a2, "in (0, 3)").nonNegative("a3", a3_m);
  c.require(a1_m + a3_m > 0.0, "a1 + a3", a1_m + a3_m, "> 0 (a contact length at 1 N)");
  c.positive("b", b_m).positive("n_x", n_x).positive("n_y", n_y);
  c.require(lambda_x > -1.0, "lambda_x", lambda_x, "> -1 (pressure stays positive inside the patch)");
  c.require(lambda_y > -1.0, "lambda_y", lambda_y, "> -1 (pressure stays positive inside the patch)");
  c.require(std::fabs(y_e_m) < b_m, "y_e", y_e_m, "inside the contact width, |y_e| < b");
  return c.ok();
}

double FootprintParams::halfLength(double load_n) const { return a1_m * std::pow(load_n, a2) + a3_m; }

bool FrictionParams::validate(std::string* error) const {
  Checker c("friction.", error);
  c.positive("mu_0", mu_0).require(mu_m >= mu_0, "mu_m", mu_m, ">= mu_0 (Savkoor peak above static)");
  c.positive("v_m", v_m_mps).positive("h", h).positive("p_0", p_0_pa).positive("p_ref", p_ref_pa);
  c.require(q >= 0.0 && q < 1.0, "q", q, "in [0, 1) (friction force must grow with pressure)");
  return c.ok();
}

bool TreadParams::validate(std::string* error) const {
  Checker c("tread.", error);
  c.positive("k_y0", k_y0_pa_per_m).nonNegative("k_y1", k_y1_pa_per_m_n).positive("phi", phi);
  c.positive("c_x", c_x_pa_s_per_m).positive("c_y", c_y_pa_s_per_m);
  // Model spec: with c = m = 0 the velocity-weakening branch of Eq 10 makes the model ill-posed.
  c.positive("m", m_kg_per_m2);
  return c.ok();
}

bool WearLawParams::validate(std::string* error) const {
  Checker c("wear.", error);
  c.nonNegative("w1", w1).nonNegative("w2", w2).nonNegative("w3", w3_kg_per_s_m2).nonNegative("w4", w4_kg_per_s_m2);
  c.nonNegative("adhesion", adhesion_kg_per_j);
  if (temperature_enabled) {
    c.require(std::isfinite(t0_c), "T0", t0_c, "finite").require(sigma_t_c != 0.0, "sigma_T", sigma_t_c, "!= 0");
  }
  return c.ok();
}

double WearLawParams::temperatureFactor(double tread_temperature_c) const {
  if (!temperature_enabled || !std::isfinite(tread_temperature_c)) return 1.0;
  const double d = tread_temperature_c - t0_c;
  // Eq 25 as printed: w3 grows away from the optimum temperature T0 (positive exponent).
  return std::exp(d * d / (2.0 * sigma_t_c * sigma_t_c));
}

bool MaterialParams::validate(std::string* error) const {
  Checker c("material.", error);
  c.positive("rubber_density", rubber_density_kg_per_m3).positive("tread_depth", tread_depth_m);
  c.positive("tread_width", tread_width_m).positive("rolling_radius", rolling_radius_m);
  c.require(tread_depth_m < rolling_radius_m, "tread_depth", tread_depth_m, "< rolling_radius");
  return c.ok();
}

double MaterialParams::massPerDepth_kg_per_m() const {
  return rubber_density_kg_per_m3 * tread_width_m * 2.0 * units::kPi * rolling_radius_m;
}

bool TireParams::validate(std::string* error) const {
  return footprint.validate(error) && friction.validate(error) && tread.validate(error) && wear.validate(error) &&
         material.validate(error);
}

}  // namespace tread_wear
