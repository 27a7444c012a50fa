#pragma once
/// @file adhesion_wear.h
/// Wear in the adhesion zone: micro-slip of the tread on the road texture while the brush element "sticks", and the
/// tread-band shear of free rolling. Not in the paper; the road extension that the LEON-T per-wheel measurements
/// call for (docs/measured_road_wear.md), added to the brush model's sliding wear (Eqs 19-20).
///
/// Why: in the paper's brush (Eqs 12-18) a sticking element does not move on the road, so a tire that rolls freely
/// or transmits small forces wears nothing, and the rear tyres of a front-driven car barely wear on gentle roads;
/// measured, they wear a third to a half of the front ones (LEON-T Run-in and Rural). On a real road the rubber's
/// contact with the texture asperities is compliant: part of the deformation the brush puts into the element is
/// taken by micro-slip at the asperity contacts (Schallamach 1958; the friction-work wear models of Grosch 1997 and
/// of the LEON-T data's authors rest on it), and it dissipates friction work tau . d(delta) there.
///
/// Model, per unit area of the adhesion zone (the part of each lateral strip from the leading edge to the point
/// where the static limit is first reached; beyond it the brush's sliding wear takes over):
///   element deflection in adhesion (brush in stick, Eq 12 quasi-static, tip fixed on the road; the turn-slip terms
///   of Eq 14 included):
///     delta_x(x, y) = (v_rx0 + Omega y) (a - x) / V_r + delta_fr(x)
///     delta_y(x)    = (v_ry0 (a - x) - Omega (a^2 - x^2) / 2) / V_r
///   free-rolling tread-band shear (the carcass compressed radially under the wheel centre: the tread base moves
///   at omega r(x) = omega (r_l + x^2 / r_l) along the flat contact while the tip sticks; zero net force fixes the
///   effective rolling radius r_e = r_l + a^2 / (3 r_l) = r_0 - rho/3, the textbook value, with rho = r_0 - r_l the
///   deflection and r_l = r_0 - a^2 / (2 r_0) from the chord of the contact length):
///     delta_fr(x) = x (a^2 - x^2) / (3 r_l r_e)       (forward in the front half, backward in the rear half)
///   shear work turned over in the adhesion zone per distance rolled:
///     E_a = (V_r / V) integral over the adhesion zone of |k_x delta_x d(delta_x)/dx + k_y delta_y d(delta_y)/dx| dx dy
///   wear per distance: W_a = K_a E_a, with K_a = chi k_abr (WearLawParams::adhesion_kg_per_j: the share chi of that
///   work which micro-slip dissipates times the abrasion per friction work k_abr, one coefficient) and the tread
///   temperature factor of Eq 25 when it is enabled (one abrasivity of the compound for both terms).
/// Consequences, measurable (test_adhesion_wear): free rolling wears W_a,0 = K_a 2 b k_x delta_fr,max^2 (delta
/// varies 0 -> max -> 0 -> -max -> 0 along x: total variation of k delta^2 / 2 is 2 k delta_max^2 per strip width),
/// independent of speed; at small slip E_a -> k (sigma (2a))^2 / 2 per strip (the friction work F s of a linear
/// brush: F = 2 k a^2 (2b) sigma, s = sigma), so the adhesion term follows F^2 / C like the friction-work models.
/// Stick limit: |k delta| <= sat(p) mu_0 p (Eqs 10-11 at v_s = 0), checked per node; beyond it the strip slides.
/// Limits: quasi-static (no element inertia or damping in the adhesion zone), the rigid-carcass patch of the brush
/// otherwise; no camber; the free-rolling field uses the tire's outer radius r_0 = MaterialParams::rolling_radius_m.
/// Cost: (kNx + 1) x 2 kNy nodes of arithmetic and kNx + 2 kNy powers per evaluation, no allocation, thread-safe.

#include <string>

#include "tread_wear/model/contact_patch.h"
#include "tread_wear/model/operating_point.h"
#include "tread_wear/model/tire_params.h"

namespace tread_wear {

/// Nodes of the adhesion zone's quadrature. Along x the work is the total variation of the deflection energy between
/// equally spaced nodes (exact where it is monotone between nodes) with the release point interpolated; across the
/// width, midpoints of equal strips.
struct AdhesionGrid {
  static constexpr int kNx = 40;  ///< intervals along x [-]
  static constexpr int kNy = 4;   ///< strips per half width [-]
};

/// The adhesion zone's shear work and wear of one operating point.
struct AdhesionWearResult {
  double work_j_per_m = 0.0;          ///< E_a, shear work turned over in the adhesion zone per distance [J/m]
  double wear_kg_per_m = 0.0;         ///< W_a [kg/m]
  double free_rolling_shear_m = 0.0;  ///< delta_fr,max = 2 a^3 / (9 sqrt(3) r_l r_e) [m]
};

/// Evaluates the adhesion-zone term for a tire. Construct once; evaluate() allocates nothing.
class AdhesionWear {
 public:
  explicit AdhesionWear(const TireParams& params);
  /// @param patch the contact patch at op.load_n; @param kinematics op.tipKinematics(); @param rolling_speed V_r > 0
  AdhesionWearResult evaluate(const OperatingPoint& op, const ContactPatch& patch, const TipKinematics& kinematics,
                              double rolling_speed) const;
  /// True when the coefficient is 0 (the term is off and evaluate() returns zeros at once).
  bool off() const { return params_.wear.adhesion_kg_per_j == 0.0; }

 private:
  TireParams params_;
};

}  // namespace tread_wear
