#include "fit/net.h"

#include <string>

#include "bezier/bspline.h"
#include "core/errors.h"

namespace volts::fit {
namespace {

void check_points(const std::vector<Eigen::Vector3d>& points, size_t expected, const char* what) {
  if (points.size() != expected)
    throw core::InvalidInputError(std::string(what) + ": " + std::to_string(points.size()) +
                                  " control points, expected " + std::to_string(expected));
  for (size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite())
      throw core::InvalidInputError(std::string(what) + ": control point " + std::to_string(i) + " is not finite");
}

void check_direction(int size, int degree, const char* what, int d) {
  if (degree < 1)
    throw core::InvalidInputError(std::string(what) + ": degree " + std::to_string(degree) + " in direction " +
                                  std::to_string(d) + " (must be >= 1)");
  if (size < degree + 1)
    throw core::InvalidInputError(std::string(what) + ": " + std::to_string(size) + " control points in direction " +
                                  std::to_string(d) + ", degree " + std::to_string(degree) + " needs at least " +
                                  std::to_string(degree + 1));
}

}  // namespace

void check(const CurveNet& net) {
  check_direction(static_cast<int>(net.points.size()), net.degree, "curve net", 0);
  check_points(net.points, net.points.size(), "curve net");
}

void check(const SurfaceNet& net) {
  for (int d = 0; d < 2; ++d) check_direction(net.size[d], net.degree[d], "surface net", d);
  check_points(net.points, static_cast<size_t>(net.size[0]) * net.size[1], "surface net");
}

void check(const SolidNet& net) {
  for (int d = 0; d < 3; ++d) check_direction(net.size[d], net.degree[d], "solid net", d);
  check_points(net.points, static_cast<size_t>(net.size[0]) * net.size[1] * net.size[2], "solid net");
}

bezier::TensorBSplineVolume to_volume(const SolidNet& net) {
  check(net);
  bezier::TensorBSplineVolume v;
  for (int d = 0; d < 3; ++d) {
    v.degree[d] = net.degree[d];
    v.knots[d] = bezier::open_uniform_knots(net.size[d] - net.degree[d], net.degree[d]);
  }
  v.points = net.points;
  return v;
}

SolidNet solid_net(const bezier::TensorBSplineVolume& volume) {
  bezier::check(volume);
  if (!volume.weights.empty()) throw core::InvalidInputError("solid net: the volume is rational");
  SolidNet net;
  net.size = volume.num_points();
  net.degree = volume.degree;
  net.points = volume.points;
  check(net);
  return net;
}

}  // namespace volts::fit
