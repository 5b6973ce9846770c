// volts::bezier — Gauss–Legendre quadrature on [0,1], hand-written (Newton on the Legendre
// three-term recurrence, Chebyshev initial guesses). Exact for polynomials of degree <= 2n-1.
//
// Throws core::InvalidInputError if n < 1 (or n > 1000, where the Newton iteration is untested).
#pragma once

#include <vector>

namespace volts::bezier {

/// The n Gauss–Legendre points on [0,1], increasing.
std::vector<double> gauss_legendre_points(int n);

/// The matching n weights; they sum to 1.
std::vector<double> gauss_legendre_weights(int n);

}  // namespace volts::bezier
