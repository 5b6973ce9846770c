// volts::tmesh — the inner loop of the joint rounds (Liu et al. 2013 §5.2, optimization of the
// worst scaled Jacobian): an element's Bézier points from its block's control points (and the
// transpose), the Jacobians of a polynomial Bézier hex on tensor grids of samples by sum
// factorization, their scaled Jacobians, the weighted gradients of those, and the transpose of
// the Jacobians' step (the gradients pulled back to the Bézier points).
//
// Hand-written: Eigen's fixed 3×3 types do not vectorize across samples. The samples' matrices are
// stored as a structure of arrays (one array per matrix entry) so that the per-sample kernels run
// over long contiguous arrays; on x86-64 every kernel is also built for AVX2 and the loader picks
// the version (GCC/Clang target_clones). No FMA, and every sum adds its terms in the order of the
// scalar Eigen code they replace (bezier::scaled_jacobian, Eigen's 3×3 determinant, norms, dot and
// cross products): every version gives the same bits, so a run does not depend on the machine's
// instruction set (tests/tmesh/jacobian_kernels_test.cpp compares them bit for bit).
//
// Internal to volts::tmesh (optimize.cpp); no checks of arguments: sizes are the caller's.
#pragma once

#include <Eigen/Dense>
#include <cstddef>
#include <vector>

namespace volts::tmesh::kernels {

/// Bernstein values of one direction at the grid's abscissae: B[i * n + a] = B_a(t_i), dB likewise;
/// BT[a * m + i] = B_a(t_i) (m abscissae), dBT likewise.
struct GridAxis {
  int n = 0;              ///< Bernstein functions per direction: degree + 1
  std::vector<double> t;  ///< abscissae in [0, 1]
  std::vector<double> B, dB, BT, dBT;
};

GridAxis grid_axis(int degree, const std::vector<double>& t);

/// A tensor grid of samples t_i × t_j × t_k in the element's parameters (i fastest).
struct Grid3 {
  GridAxis u, v, w;
  std::size_t size() const { return u.t.size() * v.t.size() * w.t.size(); }
};

/// 3×3 matrices of n samples, one array per entry: entry (r, c) of sample s is
/// entry(r, c)[s] (the order of Eigen's column-major Matrix3d is 3c + r).
class SampleMatrices {
 public:
  std::size_t size() const { return n_; }
  /// n samples; the values are unspecified (reused storage).
  void resize(std::size_t n) {
    n_ = n;
    if (data_.size() < 9 * n) data_.resize(9 * n);
  }
  double* entry(int r, int c) { return data_.data() + static_cast<std::size_t>(3 * c + r) * n_; }
  const double* entry(int r, int c) const { return data_.data() + static_cast<std::size_t>(3 * c + r) * n_; }
  Eigen::Matrix3d matrix(std::size_t s) const;
  void set(std::size_t s, const Eigen::Matrix3d& m);

 private:
  std::size_t n_ = 0;
  std::vector<double> data_;
};

/// The Jacobians of the polynomial hex with Bézier points Q[a + n(b + nc)] (n = g.u.n) at the
/// samples of g, written to J's samples first, first + 1, ..., first + g.size() - 1.
void grid_jacobians(const Eigen::Vector3d* Q, const Grid3& g, SampleMatrices& J, std::size_t first);

/// The scaled Jacobian det J / (|J0||J1||J2|) of one matrix and its derivative G = ∂/∂J (0 where a
/// column vanishes): the scalar form of weighted_gradients, for single samples.
double scaled_jacobian_gradient(const Eigen::Matrix3d& J, Eigen::Matrix3d& G);

/// out[s] = bezier::scaled_jacobian of sample s, for every sample of J.
void scaled_jacobians(const SampleMatrices& J, double* out);

/// Replaces every sample J_s by weight[s] · ∂(scaled Jacobian)/∂J at J_s (the derivative is 0 where a
/// column vanishes), and by 0 where weight[s] == 0.
void weighted_gradients(SampleMatrices& J, const double* weight);

/// The transpose of grid_jacobians: adds Σ_s tr(G_sᵀ ∂J_s/∂Q) over the samples first, ...,
/// first + g.size() - 1 of G to dQ[a + n(b + nc)].
void grid_pull_back(const SampleMatrices& G, std::size_t first, const Grid3& g, Eigen::Vector3d* dQ);

/// The Bézier points of one element of a tensor-product B-spline block: Q = (Cu ⊗ Cv ⊗ Cw)ᵀ P for the
/// n³ block points P[a + n(b + nc)] over the element and the n × n extraction matrices of its three
/// directions (column-major: C(a, i) = C[a + n i]), one direction at a time (u, v, then w), every
/// sum over a in order from zero.
void tensor_extract(int n, const double* Cu, const double* Cv, const double* Cw, const Eigen::Vector3d* P, Eigen::Vector3d* Q);

/// The transpose of tensor_extract, in place: G ← (Cu ⊗ Cv ⊗ Cw) G (w, v, then u; every sum in the
/// order of the index it runs over, from zero).
void tensor_extract_transpose(int n, const double* Cu, const double* Cv, const double* Cw, Eigen::Vector3d* G);

}  // namespace volts::tmesh::kernels
