// volts::volmap — the regularized foldover-free energy of one tet (Garanzha, Kaporin, Kudryavtseva,
// Protais, Ray & Sokolov 2021, "Foldover-free maps in 50 lines of code", theta = 1/2), which the
// volume map's joint untangling and its smoothing minimize (Liu et al. 2013 §4.3: the map must be
// one-to-one). Internal to volmap; public for its test.
#pragma once

#include <Eigen/Dense>

namespace volts::volmap {

/// Energy of a tet whose map (physical reference shape → parameter image) has Jacobian J,
/// regularized by eps ≥ 0: ½ |J|²_F / (3 χ^{2/3}) + ½ (D² + 1) / (2 χ), D = det J,
/// χ = (D + √(eps² + D²)) / 2. Writes D to `det` and, if `dJ` is not null, the energy's
/// derivative in J. With eps = 0 and D ≤ 0 the energy is not finite (a barrier).
double tet_energy(const Eigen::Matrix3d& J, double eps, double* det, Eigen::Matrix3d* dJ);

/// The same energy as a function of one vertex's position p, where J = A + p gᵀ (g: the vertex's
/// row of the tet's shape functions' gradients): its value, its gradient in p and, if `hess` is
/// not null, its Hessian in p, in closed form (det J is affine in p by the matrix determinant
/// lemma). Replaces a Hessian by differences of three gradients in the smoothing's Newton steps.
double vertex_energy(const Eigen::Matrix3d& J, const Eigen::Vector3d& g, double eps, double* det, Eigen::Vector3d* grad,
                     Eigen::Matrix3d* hess);

}  // namespace volts::volmap
