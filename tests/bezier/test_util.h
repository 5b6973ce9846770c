// Shared helpers of the volts::bezier tests: seeded random knot vectors.
#pragma once

#include <algorithm>
#include <random>
#include <vector>

namespace volts::bezier::testing {

/// A random valid knot vector of degree p: random interior knots with multiplicities 1..p+1 (so
/// C^0 lines and discontinuities occur), clamped ends or (if !clamped) distinct random knots outside the domain.
inline std::vector<double> random_knots(std::mt19937& rng, int p, bool clamped) {
  std::uniform_int_distribution<int> count(0, 5), mult(1, p + 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> interior;
  const int distinct = count(rng);
  for (int i = 0; i < distinct; ++i) interior.push_back(0.05 + 0.9 * unit(rng));
  std::sort(interior.begin(), interior.end());
  std::vector<double> knots;
  if (clamped) {
    knots.assign(p + 1, 0.0);
  } else {
    for (int i = 0; i <= p; ++i) knots.push_back(-0.3 * (p + 1 - i) / (p + 1) * (1.0 + 0.5 * unit(rng)));
    std::sort(knots.begin(), knots.end());
    knots.back() = 0.0;  // knots[p] = domain start
  }
  for (double x : interior) knots.insert(knots.end(), mult(rng), x);
  if (clamped) {
    knots.insert(knots.end(), p + 1, 1.0);
  } else {
    std::vector<double> tail{1.0};
    for (int i = 1; i <= p; ++i) tail.push_back(1.0 + 0.3 * i / (p + 1) * (1.0 + 0.5 * unit(rng)));
    std::sort(tail.begin(), tail.end());
    knots.insert(knots.end(), tail.begin(), tail.end());
  }
  return knots;
}

}  // namespace volts::bezier::testing
