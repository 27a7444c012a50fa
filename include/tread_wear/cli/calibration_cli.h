#pragma once
/// @file calibration_cli.h
/// The calibration tools together (tread_wear_calibrate, tread_wear_reference_models,
/// tread_wear_wear_characteristics), for the tests that run them in-process; each tool has its own header.

#include "tread_wear/cli/calibrate_cli.h"
#include "tread_wear/cli/reference_models_cli.h"
#include "tread_wear/cli/wear_characteristics_cli.h"
