#pragma once
/// @file tire_params.h
/// Parameters of the analytical tread wear model (Zhang, Unrau, Giessler, Gauterin: "Tire tread wear
/// characteristics: insights from indoor experiments and analytical modeling", Section 3, Table 4).
/// All members are SI; the defaults are the paper's Grosch wheel (Table 4, w3 from Table 5 "Opt"),
/// converted once. Every struct has validate(), which names the field, its value and the broken
/// constraint, in the style of Ceres' Solver::Options::IsValid.

#include <string>

namespace tread_wear {

/// Footprint size (Eq 6) and 2D pressure shape (Eqs 7-8).
struct FootprintParams {
  double a1_m = 0.05e-3;    ///< Eq 6 coefficient [m]: a = a1 (Fz/1 N)^a2 + a3
  double a2 = 0.82;         ///< Eq 6 exponent [-]
  double a3_m = 1.37e-3;    ///< Eq 6 offset [m]
  double b_m = 9e-3;        ///< half contact width b [m], independent of load
  double n_x = 2.06;        ///< longitudinal pressure shape exponent n_x [-] (Eq 7)
  double lambda_x = 0.52;   ///< longitudinal pressure shape factor lambda_x [-]
  double x_e_m = 0.08e-3;   ///< longitudinal pressure centre x_e [m] (Eq 9)
  double n_y = 4.0;         ///< lateral pressure shape exponent n_y [-] (Eq 8)
  double lambda_y = 1.84;   ///< lateral pressure shape factor lambda_y [-]
  double y_e_m = 0.0;       ///< lateral pressure centre y_e [m]

  bool validate(std::string* error) const;
  /// Contact half length a [m] at vertical load Fz [N] (Eq 6).
  double halfLength(double load_n) const;
};

/// Savkoor friction law with pressure saturation (Eqs 10-11).
struct FrictionParams {
  double mu_0 = 0.46;         ///< static coefficient of friction mu_0 [-]
  double mu_m = 1.15;         ///< maximum coefficient of friction mu_m [-]
  double v_m_mps = 0.07009;   ///< sliding speed at which mu_m is reached v_m [m/s]
  double h = 0.42;            ///< Savkoor shape factor h [-]
  double p_0_pa = 0.02e6;     ///< pressure floor p_0 of sat(p) [Pa]
  double p_ref_pa = 0.30e6;   ///< reference pressure p_ref [Pa]
  double q = 0.14;            ///< pressure exponent q [-]

  bool validate(std::string* error) const;
};

/// Massed Kelvin-Voigt tread elements per unit contact area (Eqs 12-13, 17).
struct TreadParams {
  double k_y0_pa_per_m = 0.92e9;     ///< lateral stiffness at zero load k_y0 [Pa/m]
  double k_y1_pa_per_m_n = 5.42e6;   ///< load sensitivity of the stiffness k_y1 [Pa/(m N)]
  double phi = 0.43;                 ///< anisotropy phi = k_x/k_y [-] (Eq 13)
  double c_x_pa_s_per_m = 1.16e5;    ///< longitudinal damping c_x [Pa s/m]
  double c_y_pa_s_per_m = 5.60e5;    ///< lateral damping c_y [Pa s/m]
  double m_kg_per_m2 = 20.0;         ///< element inertia per unit area m [kg/m^2] = [Pa s^2/m]

  bool validate(std::string* error) const;
  /// Lateral stiffness k_y = k_y0 + k_y1 Fz [Pa/m] at vertical load Fz [N] (Eq 13).
  double lateralStiffness(double load_n) const { return k_y0_pa_per_m + k_y1_pa_per_m_n * load_n; }
  /// Longitudinal stiffness k_x = phi k_y [Pa/m] at vertical load Fz [N] (Eq 13).
  double longitudinalStiffness(double load_n) const { return phi * lateralStiffness(load_n); }
};

/// Generalized-friction-power wear law (Eqs 19-20) with the optional temperature factor (Eq 25).
struct WearLawParams {
  double w1 = 0.31;                    ///< shear-stress exponent w1 [-]
  double w2 = 2.20;                    ///< sliding-speed exponent w2 [-]
  double w3_kg_per_s_m2 = 0.1335;      ///< abrasion coefficient w3 [kg/(s m^2)] (= 0.1335 mg/(s mm^2))
  double w4_kg_per_s_m2 = 5.38e-4;     ///< default (non-sliding) wear w4 [kg/(s m^2)]
  bool temperature_enabled = false;    ///< apply Eq 25 when a tread temperature is known
  double t0_c = 47.17;                 ///< Eq 25 reference temperature T_0 [degC] (Table 5, Opt_T)
  double sigma_t_c = 57.98;            ///< Eq 25 temperature width sigma_T [degC] (Table 5, Opt_T)
  /// K_a, wear per micro-slip work in the adhesion zone [kg/J], >= 0 (adhesion_wear.h; not in the paper: 0 = off)
  double adhesion_kg_per_j = 0.0;

  bool validate(std::string* error) const;
  /// Eq 25 factor on w3 for tread temperature T [degC]; 1 when disabled or T is not finite.
  double temperatureFactor(double tread_temperature_c) const;
  /// w3 at tread temperature T [degC]: w3 times the Eq 25 factor [kg/(s m^2)].
  double w3At(double tread_temperature_c) const { return w3_kg_per_s_m2 * temperatureFactor(tread_temperature_c); }
};

/// Rubber and tread geometry: converts mass loss into tread depth.
struct MaterialParams {
  double rubber_density_kg_per_m3 = 1150.0;  ///< tread rubber density [kg/m^3]
  double tread_depth_m = 6e-3;               ///< new tread depth [m] (Grosch wheel: 36 mm - 30 mm rim)
  double tread_width_m = 18e-3;              ///< worn tread width [m]
  double rolling_radius_m = 36e-3;           ///< outer radius of the tread [m]

  bool validate(std::string* error) const;
  /// Mass [kg] of a tread layer of depth d [m] over the whole circumference.
  double massPerDepth_kg_per_m() const;
};

/// Everything the brush wear model needs about one tire.
struct TireParams {
  std::string name = "grosch_wheel";
  FootprintParams footprint;
  FrictionParams friction;
  TreadParams tread;
  WearLawParams wear;
  MaterialParams material;

  bool validate(std::string* error) const;
};

}  // namespace tread_wear
