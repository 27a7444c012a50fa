#pragma once
/// @file contact_patch.h
/// Rectangular footprint and 2D contact pressure, paper Section 3.1, Eqs 6-9.
///
///   a = a1 (Fz/1 N)^a2 + a3                                  (Eq 6, half length; b is load independent)
///   f_z(x) = Fz/(2a) g_x(x/a)                                (Eq 7, line load)
///   g(s) = A (1 - |s|^{2n}) (1 + lambda |s|^{2n}) (1 - B s)  (Eq 7; same form for g_y, Eq 8)
///   A = (2n+1)(4n+1) / (2n (4n+1+lambda))
///   B = -3 (2n+3)(4n+3)(4n+1+lambda) / ((2n+1)(4n+1)(4n+3+3 lambda)) * s_e   (s_e = x_e/a or y_e/b)
///   p(x, y) = f_z(x)/(2b) g_y(y/b)                           (Eq 8)
/// A and B make the pressure satisfy the three moment conditions of Eq 9 exactly:
/// integral p dA = Fz, integral p x dA = Fz x_e, integral p y dA = Fz y_e.
///
/// Assumptions and limits: flat cross-section, rectangular footprint (the Grosch wheel); |s|^{2n} is
/// used for non-integer n. If |B| > 1 the shape would go negative near one edge: the pressure is then
/// clipped at zero and PressureShape::clipped() says so (Eq 9 then no longer holds exactly).

#include "tread_wear/model/tire_params.h"

namespace tread_wear {

/// One-dimensional shape function g(s) on s in [-1, 1] with the normalisation of Eq 7.
class PressureShape {
 public:
  PressureShape() = default;
  /// @param n exponent n [-]; @param lambda shape factor [-]; @param centre_ratio s_e = x_e/a [-]
  PressureShape(double n, double lambda, double centre_ratio);
  /// g(s) [-]; zero outside [-1, 1].
  double operator()(double s) const;
  /// The even part A (1 - |s|^{2n})(1 + lambda |s|^{2n}); g(s) = even(s) (1 - B s).
  double even(double s) const;
  double A() const { return A_; }
  double B() const { return B_; }
  bool clipped() const { return B_ > 1.0 || B_ < -1.0; }

 private:
  double n_ = 1.0, lambda_ = 0.0, A_ = 1.0, B_ = 0.0;
};

/// Pressure field p(x, y) [Pa] of one tire at one vertical load.
class ContactPatch {
 public:
  ContactPatch() = default;
  /// @param load_n vertical load Fz [N], > 0
  ContactPatch(const FootprintParams& params, double load_n);

  double load() const { return load_n_; }            ///< Fz [N]
  double halfLength() const { return a_m_; }         ///< a [m]
  double halfWidth() const { return b_m_; }          ///< b [m]
  double area() const { return 4.0 * a_m_ * b_m_; }  ///< 4ab [m^2]
  /// Fz/(2a)/(2b) [Pa], the constant of Eqs 7-8: p(x, y) = pressureScale() g_x(x/a) g_y(y/b). For callers that
  /// evaluate the shapes themselves (the marcher keeps g_x's even part on its grid, see shapeX()).
  double pressureScale() const { return load_n_ / (2.0 * a_m_) / (2.0 * b_m_); }
  /// Line load f_z(x) [N/m] (Eq 7).
  double lineLoad(double x_m) const;
  /// Contact pressure p(x, y) [Pa] (Eq 8); zero outside the footprint.
  double pressure(double x_m, double y_m) const;
  const PressureShape& shapeX() const { return gx_; }
  const PressureShape& shapeY() const { return gy_; }

 private:
  double load_n_ = 0.0, a_m_ = 0.0, b_m_ = 0.0;
  PressureShape gx_, gy_;
};

}  // namespace tread_wear
