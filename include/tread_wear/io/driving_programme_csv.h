#pragma once
/// @file driving_programme_csv.h
/// Reads a driving programme (vehicle/driving_programme.h) from the LEON-T tables (data/leon_t_idiada, EUPL-1.2):
///   sectors.csv        Track, Sector number, Sector name, Distance (m), Longitudinal slope (%), Latitudinal slope (%),
///                      Corner radius (m), Corner angle (degrees)
///   maneuvers.csv      Track, Test section, Sector number, Maneuver code (Acceleration | Deceleration | Constant),
///                      Maneuver repeats, Start speed (m/s), End speed (m/s), Acceleration constant (m.s^-2),
///                      Deceleration constant (m.s^-2)
///   test_sections.csv  Section name, Test section, AbrasionTest, Track, Number of laps, Total distance (km)
/// and the direction of every corner from a turn table, which the data do not state (the package's assumption,
/// data/leon_t_idiada/turns.csv): Track, Sector number, turn (left | right). Other columns are ignored; rows keep
/// the files' order.

#include <string>

#include "tread_wear/vehicle/driving_programme.h"

namespace tread_wear {

/// @param dir folder with sectors.csv, maneuvers.csv and test_sections.csv
/// @param turns_path the turn table
/// @throw std::runtime_error "<file>:<line>: <problem>" for a missing file or column, an unreadable number, a corner
///        without a turn, or a programme that DrivingProgramme::validate() refuses
DrivingProgramme readDrivingProgramme(const std::string& dir, const std::string& turns_path);

}  // namespace tread_wear
