#include "bezier/transfinite_tet.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"

namespace volts::bezier {

namespace {

// Face f (F1..F4 = 0..3) lies on λ_zero = 0 and takes s = λ_s, t = λ_t (barycentric λ of the tet,
// λ0 = 1-u-v-w, λ1 = u, λ2 = v, λ3 = w), as in (3).
struct FaceMap {
  int zero, s, t;
};
constexpr FaceMap kFaces[4] = {{3, 2, 1}, {2, 1, 3}, {0, 2, 3}, {1, 3, 2}};
const char* const kVertex[4] = {"(0,0,0)", "(1,0,0)", "(0,1,0)", "(0,0,1)"};

int face_on(int zero) {
  for (int f = 0; f < 4; ++f)
    if (kFaces[f].zero == zero) return f;
  return -1;
}

// Triangle barycentric (1-s-t, s, t) of the tet point λ (which lies on the face's plane).
Eigen::Vector4d triangle_coords(int f, const Eigen::Vector4d& l) {
  const double s = l[kFaces[f].s], t = l[kFaces[f].t];
  return {1 - s - t, s, t, 0};
}

Eigen::Vector3d face_value(const BezierTriangle& F, double s, double t) { return evaluate(F, Eigen::Vector2d(s, t)); }

std::string face_call(int f, int v, int w) {
  // F(s,t) along the edge λ_v = 1-μ, λ_w = μ, as text.
  const auto arg = [&](int idx) { return idx == v ? std::string("1-μ") : idx == w ? std::string("μ") : std::string("0"); };
  return "F" + std::to_string(f + 1) + "(" + arg(kFaces[f].s) + "," + arg(kFaces[f].t) + ")";
}

// F_f ∘ (λ ↦ Mλ) as a degree-n tet net, by blossoming: c_β = P(F)(τ(M e_0)^β0, .., τ(M e_3)^β3).
std::vector<Eigen::Vector3d> compose(const BezierTriangle& F, int f, const Eigen::Matrix4d& M) {
  const int n = F.degree;
  std::vector<Eigen::Vector4d> net(F.points.size());
  for (std::size_t i = 0; i < net.size(); ++i) net[i] << F.points[i], 1.0;
  std::array<Eigen::Vector4d, 4> tau;
  for (int m = 0; m < 4; ++m) tau[m] = triangle_coords(f, M.col(m));
  std::vector<Eigen::Vector3d> out;
  for (const auto& b : simplex_multi_indices(3, n)) {
    std::vector<Eigen::Vector4d> args;
    for (int m = 0; m < 4; ++m) args.insert(args.end(), b[m], tau[m]);
    out.push_back(blossom(2, n, net, args).head<3>());
  }
  return out;
}

}  // namespace

void check_compatibility(const std::array<BezierTriangle, 4>& faces, const TransfiniteParams& params) {
  Eigen::AlignedBox3d box;
  int n = 1;
  for (int f = 0; f < 4; ++f) {
    try {
      check(faces[f]);
    } catch (const core::InvalidInputError& e) {
      throw core::InvalidInputError("transfinite_tet: F" + std::to_string(f + 1) + ": " + e.what());
    }
    if (faces[f].is_rational())
      throw core::InvalidInputError("transfinite_tet: F" + std::to_string(f + 1) + " is rational; only polynomial faces are supported");
    for (const auto& p : faces[f].points) box.extend(p);
    n = std::max(n, faces[f].degree);
  }
  const double tol = params.tolerance_rel * std::max(box.diagonal().norm(), 1e-300);
  // Corner conditions: the three faces through each vertex agree there.
  for (int v = 0; v < 4; ++v) {
    std::vector<int> fs;
    for (int f = 0; f < 4; ++f)
      if (kFaces[f].zero != v) fs.push_back(f);
    const Eigen::Vector4d l = Eigen::Vector4d::Unit(v);
    std::ostringstream cond;
    for (std::size_t a = 0; a < fs.size(); ++a)
      cond << (a ? " = " : "") << "F" << fs[a] + 1 << "(" << l[kFaces[fs[a]].s] << "," << l[kFaces[fs[a]].t] << ")";
    for (std::size_t a = 1; a < fs.size(); ++a) {
      const double d = (face_value(faces[fs[0]], l[kFaces[fs[0]].s], l[kFaces[fs[0]].t]) -
                        face_value(faces[fs[a]], l[kFaces[fs[a]].s], l[kFaces[fs[a]].t])).norm();
      if (d > tol)
        throw core::InvalidInputError("transfinite_tet: corner " + std::string(kVertex[v]) + ": " + cond.str() +
                                      " fails by " + std::to_string(d));
    }
  }
  // Edge conditions: the two faces through each edge agree along it (at n+1 points: degree <= n).
  for (int v = 0; v < 4; ++v)
    for (int w = v + 1; w < 4; ++w) {
      std::vector<int> fs;
      for (int f = 0; f < 4; ++f)
        if (kFaces[f].zero != v && kFaces[f].zero != w) fs.push_back(f);
      for (int k = 0; k <= n; ++k) {
        const double mu = double(k) / n;
        Eigen::Vector4d l = Eigen::Vector4d::Zero();
        l[v] = 1 - mu;
        l[w] = mu;
        const double d = (face_value(faces[fs[0]], l[kFaces[fs[0]].s], l[kFaces[fs[0]].t]) -
                          face_value(faces[fs[1]], l[kFaces[fs[1]].s], l[kFaces[fs[1]].t])).norm();
        if (d > tol)
          throw core::InvalidInputError("transfinite_tet: edge " + std::string(kVertex[v]) + "-" + kVertex[w] + ": " +
                                        face_call(fs[0], v, w) + " = " + face_call(fs[1], v, w) + " fails at μ = " +
                                        std::to_string(mu) + " by " + std::to_string(d));
      }
    }
}

BezierTet transfinite_tet(const std::array<BezierTriangle, 4>& faces_in, const TransfiniteParams& params) {
  check_compatibility(faces_in, params);
  int n = 1;
  for (const auto& F : faces_in) n = std::max(n, F.degree);
  std::array<BezierTriangle, 4> faces;
  for (int f = 0; f < 4; ++f) faces[f] = elevate_degree(faces_in[f], n);

  const int size = simplex_size(3, n);
  const auto idx = simplex_multi_indices(3, n + 1);
  std::vector<Eigen::Vector3d> X(idx.size(), Eigen::Vector3d::Zero());
  for (int i = 0; i < 4; ++i) {
    // T_i = Σ_j X(P_j λ) − Σ_{j<k} X(P_j P_k λ) + X(e_i), j, k != i: P_j moves the mass λ_j to λ_i.
    std::vector<Eigen::Vector3d> T(size, Eigen::Vector3d::Zero());
    const auto add = [&](const std::vector<int>& js, double sign) {
      Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
      for (int j : js) {
        M(j, j) = 0;
        M(i, j) = 1;
      }
      const int f = face_on(js[0]);
      const std::vector<Eigen::Vector3d> c = compose(faces[f], f, M);
      for (int m = 0; m < size; ++m) T[m] += sign * c[m];
    };
    std::vector<int> others;
    for (int j = 0; j < 4; ++j)
      if (j != i) others.push_back(j);
    for (int j : others) add({j}, 1.0);
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b) add({others[a], others[b]}, -1.0);
    add(others, 1.0);  // P_j P_k P_l λ = e_i: the vertex
    // p_i T_i with p_i = λ_i: coefficient γ of degree n+1 is γ_i/(n+1) · T_{γ-e_i}.
    for (std::size_t g = 0; g < idx.size(); ++g) {
      std::array<int, 4> a = idx[g];
      if (a[i] == 0) continue;
      const double c = double(a[i]) / (n + 1);
      --a[i];
      X[g] += c * T[simplex_index(3, n, a[1], a[2], a[3])];
    }
  }
  BezierTet tet;
  tet.degree = n + 1;
  tet.points = std::move(X);
  return tet;
}

}  // namespace volts::bezier
