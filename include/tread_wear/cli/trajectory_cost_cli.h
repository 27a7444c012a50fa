#pragma once
/// @file trajectory_cost_cli.h
/// The tread_wear_trajectory_cost tool as a function over streams (the main stays one line, tests run it
/// in-process): a planner's wear cost of candidate trajectories (planning/trajectory_cost.h), directly or from the
/// wear map (planning/wear_map.h). Exit codes: 0 every trajectory evaluated, 1 bad data (file, row, or a trajectory
/// that could not be evaluated: its row says why), 2 bad usage.

#include <istream>
#include <ostream>
#include <string>
#include <vector>

#include "tread_wear/planning/trajectory_cost.h"

namespace tread_wear {

/// One candidate trajectory of a trajectory CSV.
struct CandidateTrajectory {
  std::string id;
  std::vector<TrajectorySample> samples;
};

/// Reads a trajectory CSV: a header with the columns trajectory_id, time_s, speed_mps, accel_mps2,
/// curvature_per_m and optionally grade_rad (any order, other columns are errors), one sample per row; the rows of a
/// trajectory keep their file order, trajectories the order of their first row. false with *error naming the line
/// and the column for a malformed cell (numbers must be finite) or an unknown column.
bool readTrajectoryCsv(std::istream& in, std::vector<CandidateTrajectory>* trajectories, std::string* error);

/// tread_wear_trajectory_cost --vehicle FILE (--tire FILE | --wheels FILE) [--preset NAME] [--temperature C]
///                            [--map [--threads N] | --compare] TRAJECTORIES.csv|-
/// tread_wear_trajectory_cost --generate N [--seed S]   (writes N seeded candidates as a trajectory CSV)
int runTrajectoryCostCli(int argc, const char* const argv[], std::istream& in, std::ostream& out, std::ostream& err);

}  // namespace tread_wear
