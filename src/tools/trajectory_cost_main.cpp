// tread_wear_trajectory_cost: a planner's wear cost of candidate trajectories (usage: --help; logic in
// trajectory_cost_cli.h).
#include <iostream>

#include "tread_wear/cli/trajectory_cost_cli.h"

int main(int argc, char** argv) { return tread_wear::runTrajectoryCostCli(argc, argv, std::cin, std::cout, std::cerr); }
