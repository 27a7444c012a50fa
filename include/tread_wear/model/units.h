#pragma once
/// @file units.h
/// Unit conversion factors to SI. The core works in SI only (REP-103); the paper's tables use
/// mm, MPa, mg, g/km and degrees. Each factor converts a value in the named unit to SI:
/// value_SI = value_in_unit * kFactor. Conversions happen once, where data enter the core
/// (parameter files, CSV tables), never inside the model.

namespace tread_wear {
namespace units {

constexpr double kPi = 3.14159265358979323846;

constexpr double kMillimetre = 1e-3;              ///< mm -> m
constexpr double kMegapascal = 1e6;               ///< MPa -> Pa
constexpr double kMilligram = 1e-6;               ///< mg -> kg
constexpr double kGramPerKilometre = 1e-6;        ///< g/km -> kg/m
constexpr double kMilligramPerKilometre = 1e-9;   ///< mg/km -> kg/m
constexpr double kMillimetrePerSecond = 1e-3;     ///< mm/s -> m/s
constexpr double kKilometrePerHour = 1.0 / 3.6;   ///< km/h -> m/s
constexpr double kDegree = kPi / 180.0;           ///< deg -> rad

/// Stiffness per unit area: MPa/mm -> Pa/m.
constexpr double kMegapascalPerMillimetre = kMegapascal / kMillimetre;
/// Load-dependent stiffness per unit area (Table 4 k_y1, "1/mm^3" = MPa/(mm N)) -> Pa/(m N).
constexpr double kMegapascalPerMillimetreNewton = kMegapascal / kMillimetre;
/// Damping per unit area: MPa/(mm/s) -> Pa s/m.
constexpr double kMegapascalSecondPerMillimetre = kMegapascal / kMillimetre;
/// Mass per unit area (Table 4 "MPa/(mm/s^2)") -> Pa s^2/m = kg/m^2.
constexpr double kMegapascalSecondSquaredPerMillimetre = kMegapascal / kMillimetre;
/// Local wear-rate coefficient per unit area: mg/(s mm^2) -> kg/(s m^2) (model spec: w3, w4).
constexpr double kMilligramPerSecondSquareMillimetre = kMilligram / (kMillimetre * kMillimetre);
/// Global wear-rate coefficient (Eq 26 reference models): mg/s -> kg/s.
constexpr double kMilligramPerSecond = kMilligram;
/// Abrasion per friction work (adhesion_wear.h; the friction-work models' unit): mg/kJ -> kg/J.
constexpr double kMilligramPerKilojoule = kMilligram / 1e3;

}  // namespace units
}  // namespace tread_wear
