#pragma once
/// @file diagnosis_cli.h
/// The diagnosis tools together (tread_wear_diagnose, tread_wear_conceal, tread_wear_diagnosis_harness), for the
/// tests that run them in-process; each tool has its own header.

#include "tread_wear/cli/conceal_cli.h"
#include "tread_wear/cli/diagnose_cli.h"
#include "tread_wear/cli/diagnosis_harness_cli.h"
