#include "bezier/bspline_volume.h"

#include <cmath>
#include <string>

#include "bezier/bspline.h"
#include "core/errors.h"

namespace volts::bezier {

namespace {

[[noreturn]] void bad_weight() { throw core::InvalidInputError("TensorBSplineVolume: a weight is not finite and positive"); }

// Everything but the weights' signs: O(knots), cheap enough for every evaluate().
void check_shape(const TensorBSplineVolume& volume) {
  static const char* names[3] = {"TensorBSplineVolume: U", "TensorBSplineVolume: V", "TensorBSplineVolume: W"};
  for (int d = 0; d < 3; ++d) {
    if (volume.degree[d] < 1)
      throw core::InvalidInputError(std::string(names[d]) + " degree must be >= 1");
    check_knot_vector(volume.knots[d], volume.degree[d], names[d]);
  }
  const auto n = volume.num_points();
  const std::size_t count = static_cast<std::size_t>(n[0]) * n[1] * n[2];
  if (volume.points.size() != count)
    throw core::InvalidInputError("TensorBSplineVolume: " + std::to_string(volume.points.size()) +
                                  " control points, the knot vectors need " + std::to_string(count));
  if (!volume.weights.empty() && volume.weights.size() != count)
    throw core::InvalidInputError("TensorBSplineVolume: " + std::to_string(volume.weights.size()) +
                                  " weights for " + std::to_string(count) + " control points");
}

}  // namespace

void check(const TensorBSplineVolume& volume) {
  check_shape(volume);
  for (double w : volume.weights)
    if (!(w > 0.0) || !std::isfinite(w)) bad_weight();
}

Eigen::Vector3d evaluate(const TensorBSplineVolume& volume, const Eigen::Vector3d& uvw) {
  check_shape(volume);  // the weights used are checked below
  const auto n = volume.num_points();
  const auto& P = volume.degree;
  std::array<BasisValues, 3> b;
  for (int d = 0; d < 3; ++d) b[d] = basis_functions(volume.knots[d], P[d], uvw[d]);
  Eigen::Vector3d A = Eigen::Vector3d::Zero();
  double W = 0.0;
  for (int c = 0; c <= P[2]; ++c)
    for (int bb = 0; bb <= P[1]; ++bb)
      for (int a = 0; a <= P[0]; ++a) {
        const int i = b[0].span - P[0] + a, j = b[1].span - P[1] + bb, k = b[2].span - P[2] + c;
        const int idx = i + n[0] * (j + n[1] * k);
        const double wi = volume.weights.empty() ? 1.0 : volume.weights[idx];
        if (!(wi > 0.0) || !std::isfinite(wi)) bad_weight();
        const double w = wi * b[0].values[a] * b[1].values[bb] * b[2].values[c];
        A += w * volume.points[idx];
        W += w;
      }
  return A / W;
}

std::vector<BezierHex> extract_bezier_hexes(const TensorBSplineVolume& volume) {
  check(volume);
  const auto n = volume.num_points();
  const auto& P = volume.degree;
  std::array<std::vector<int>, 3> spans;
  std::array<std::vector<Eigen::MatrixXd>, 3> ops;
  for (int d = 0; d < 3; ++d) {
    spans[d] = element_spans(volume.knots[d], P[d]);
    ops[d] = extraction_operators(volume.knots[d], P[d]);
  }
  std::vector<BezierHex> hexes;
  hexes.reserve(spans[0].size() * spans[1].size() * spans[2].size());
  for (std::size_t ec = 0; ec < spans[2].size(); ++ec)
    for (std::size_t eb = 0; eb < spans[1].size(); ++eb)
      for (std::size_t ea = 0; ea < spans[0].size(); ++ea) {
        // The element's B-spline control points as a container of the same shape; the Bézier
        // points are then (Cu ⊗ Cv ⊗ Cw)ᵀ applied to them.
        BezierHex local;
        local.degree = P;
        local.points.resize(local.num_points());
        if (!volume.weights.empty()) local.weights.resize(local.num_points());
        for (int c = 0; c <= P[2]; ++c)
          for (int b = 0; b <= P[1]; ++b)
            for (int a = 0; a <= P[0]; ++a) {
              const int i = spans[0][ea] - P[0] + a, j = spans[1][eb] - P[1] + b, k = spans[2][ec] - P[2] + c;
              const int idx = i + n[0] * (j + n[1] * k);
              local.points[local.index(a, b, c)] = volume.points[idx];
              if (!volume.weights.empty()) local.weights[local.index(a, b, c)] = volume.weights[idx];
            }
        hexes.push_back(map_coefficients(
            local, {ops[0][ea].transpose(), ops[1][eb].transpose(), ops[2][ec].transpose()}));
      }
  return hexes;
}

}  // namespace volts::bezier
