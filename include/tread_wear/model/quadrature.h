#pragma once
/// @file quadrature.h
/// Gauss-Legendre quadrature on [-1, 1], shared by the lateral strips of the marcher (brush_wear_model.h) and
/// of the CVODE reference solver (reference_solver.h). Exact for polynomials up to degree 2n - 1.

#include <vector>

namespace tread_wear {

/// The n nodes (ascending, symmetric about 0) and their weights, by Newton iteration on the Legendre
/// recurrence; n >= 1.
void gaussLegendre(int n, std::vector<double>* nodes, std::vector<double>* weights);

}  // namespace tread_wear
