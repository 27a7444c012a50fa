#pragma once
/// @file drive_cli.h
/// The tread_wear_drive tool as a function over streams, so that the main stays a few lines and tests can run it
/// in-process. It is here and not in cli because it writes a bag.

#include <ostream>
#include <string>

namespace tread_wear {

/// tread_wear_drive [--profile SPEED.csv] [--vehicle VEHICLE.yaml] [--rate-hz HZ] [--lateral-accel-limit A]
///     [--seed N] [--sensors] [--manoeuvre cruise|circle|accel ...] [--style S] [--max-accel-mps2 A]
///     [--max-decel-mps2 D] [--max-lateral-accel-mps2 AY] [--mass-kg M] [--drive-layout L] --out DRIVE.bag
/// Generates a test drive (speed profile + route + vehicle model; docs/drive.md) as a bag of the node's inputs
/// (drive_bag_writer.h) and prints its statistics to out: the profile as it prescribes (default), a manoeuvre
/// (vehicle/manoeuvre.h) or the profile's route within a driving style's envelope (vehicle/driving_style.h), with
/// the vehicle file's mass and drive layout or the command line's. The default profile and vehicle are
/// `share_dir`/data/wltc_class3b.csv and `share_dir`/config/vehicle_passenger_car.yaml.
/// Returns 0, 1 for bad data (profile, vehicle, unwritable bag) or 2 for bad usage (message on err).
int runDriveCli(int argc, const char* const argv[], const std::string& share_dir, std::ostream& out, std::ostream& err);

}  // namespace tread_wear
