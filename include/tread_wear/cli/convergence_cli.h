#pragma once
/// @file convergence_cli.h
/// The tread_wear_convergence tool (studies/convergence_study.h) as a function over streams.

#include <ostream>

namespace tread_wear {

/// tread_wear_convergence [--params FILE] [--orientation literal|flipped|both] [--quick] [--extended]
///                        [--point FZ_N,ALPHA_DEG,KAPPA,V_MPS,CURVATURE_PER_M [--strips N] [--grading G]]
/// Returns 0 on success, 2 on a usage error (message on err).
int runConvergenceCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err);

}  // namespace tread_wear
