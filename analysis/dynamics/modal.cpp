#include "analysis/dynamics/modal.h"

#include <Eigen/Sparse>
#include <Spectra/MatOp/SparseSymShiftSolve.h>
#include <Spectra/SymEigsShiftSolver.h>

#include <algorithm>
#include <cmath>

#include "engine/pipeline.h"

namespace ishibashi {

int ModalResult::dominant_direction(int mode) const {
  const Vec3& r = effective_mass_ratio[mode];
  int d = 0;
  for (int k = 1; k < 3; ++k)
    if (r[k] > r[d]) d = k;
  return d;
}

// Assembly, eigen-solution and mass normalisation in one place: each step's arrays (the
// free-block index, K, M) are the next step's input, and apart they would only be passed on.
ModalResult modal_analysis(const Model& m, const State& s, int modes) {
  ModalResult out;
  std::vector<int> dof_of(m.block_count, -1);
  for (int b = 0; b < m.block_count; ++b)
    if (m.motion[b] == Motion::free) {
      dof_of[b] = 6 * static_cast<int>(out.free_blocks.size());
      out.free_blocks.push_back(b);
    }
  const int n = 6 * static_cast<int>(out.free_blocks.size());
  if (n == 0) throw ModelError("modal analysis: the model has no free block");
  modes = std::max(modes, 1);

  // Mass^(-1/2) per block: 1/sqrt(m) for translations, R D^(-1/2) R^T for rotations.
  std::vector<Mat3> rot_inv_sqrt(out.free_blocks.size());
  std::vector<double> mass(out.free_blocks.size());
  for (std::size_t k = 0; k < out.free_blocks.size(); ++k) {
    const int b = out.free_blocks[k];
    const Mat3 r = s.orientation[b].toRotationMatrix();
    rot_inv_sqrt[k] = r * m.inertia_kg_m2[b].cwiseSqrt().cwiseInverse().asDiagonal() * r.transpose();
    mass[k] = m.mass_kg[b];
    out.total_mass_kg += mass[k];
  }
  // Scaled constraint rows: for direction d at point p, the relative displacement is
  // d . (u_b + theta_b x r_b) - d . (u_a + theta_a x r_a), theta x r . d = theta . (r x d).
  // Each row is multiplied by M^(-1/2), so K' = M^(-1/2) K M^(-1/2) = sum k j j^T.
  std::vector<Eigen::Triplet<double>> triplets;
  // A spring of `stiffness` along d between point[0] of block[0] and point[1] of block[1].
  auto add_spring = [&](const Vec3& d, double stiffness, const int (&block)[2], const Vec3 (&point)[2]) {
    int index[12];
    double value[12];
    int count = 0;
    for (int side = 0; side < 2; ++side) {
      const int b = block[side];
      if (dof_of[b] < 0) continue;
      const int g = dof_of[b] / 6;
      const double sign = side == 0 ? -1.0 : 1.0;
      const Vec3 lin = sign * d / std::sqrt(mass[g]);
      const Vec3 ang = sign * rot_inv_sqrt[g] * (point[side] - s.position[b]).cross(d);
      for (int q = 0; q < 3; ++q) {
        index[count] = dof_of[b] + q, value[count++] = lin[q];
        index[count] = dof_of[b] + 3 + q, value[count++] = ang[q];
      }
    }
    for (int p = 0; p < count; ++p)
      for (int q = 0; q < count; ++q) triplets.emplace_back(index[p], index[q], stiffness * value[p] * value[q]);
  };
  const SubContacts& c = s.contacts;
  for_each_sub_contact(s, [&](int i) {
    const SpringConstants k = c.constants(i);
    const Vec3& n_dir = c.normal[i];
    const Vec3 t1 = n_dir.unitOrthogonal(), t2 = n_dir.cross(t1);
    const int block[2] = {c.block_a[i], c.block_b[i]};
    const Vec3 point[2] = {c.point[i], c.point[i]};
    for (const auto& [d, stiffness] : {std::pair{n_dir, k.kn}, {t1, k.ks}, {t2, k.ks}}) add_spring(d, stiffness, block, point);
  });
  // Tie rods held linear, as the joints are: a snug rod stiffens the bridge in tension and
  // pushes in compression here, where in a run it would go slack.
  for (const Tie& tie : m.ties) {
    const int block[2] = {tie.block_a, tie.block_b};
    const Vec3 point[2] = {s.position[tie.block_a] + s.orientation[tie.block_a] * tie.anchor_a_local,
                           s.position[tie.block_b] + s.orientation[tie.block_b] * tie.anchor_b_local};
    if ((point[1] - point[0]).norm() > 0) add_spring((point[1] - point[0]).normalized(), tie.stiffness_n_m, block, point);
  }
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(triplets.begin(), triplets.end());

  // Lowest eigenvalues. Small systems: dense, all modes. Large ones: shift-invert about
  // a small negative shift (a free rigid-body mode, if any, has eigenvalue 0 and must not
  // make the shifted matrix singular).
  Eigen::VectorXd lambda;
  Eigen::MatrixXd y;
  if (n <= 240) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> dense{Eigen::MatrixXd(a)};
    modes = std::min(modes, n);
    lambda = dense.eigenvalues().head(modes);
    y = dense.eigenvectors().leftCols(modes);
  } else {
    modes = std::min(modes, n - 2);
    double scale = 0;
    for (int j = 0; j < n; ++j) scale = std::max(scale, a.coeff(j, j));
    Spectra::SparseSymShiftSolve<double> op(a);
    const int ncv = std::min(n, std::max(2 * modes + 1, modes + 20));
    Spectra::SymEigsShiftSolver<Spectra::SparseSymShiftSolve<double>> solver(op, modes, ncv, -1e-9 * scale);
    solver.init();
    solver.compute(Spectra::SortRule::LargestMagn, 1000, 1e-10, Spectra::SortRule::SmallestAlge);
    if (solver.info() != Spectra::CompInfo::Successful)
      throw ModelError("modal analysis: the eigensolver did not converge (" + std::to_string(n) + " degrees of freedom)");
    lambda = solver.eigenvalues();
    y = solver.eigenvectors();
  }

  out.shapes.resize(n, lambda.size());
  for (int mode = 0; mode < lambda.size(); ++mode) {
    out.frequency_hz.push_back(std::sqrt(std::max(0.0, lambda[mode])) / (2 * M_PI));
    // phi = M^(-1/2) y; participation in direction e: phi^T M r_e = y^T M^(1/2) r_e.
    Vec3 participation = Vec3::Zero();
    for (std::size_t g = 0; g < out.free_blocks.size(); ++g) {
      const Vec3 yl = y.col(mode).segment<3>(6 * g), ya = y.col(mode).segment<3>(6 * g + 3);
      out.shapes.col(mode).segment<3>(6 * g) = yl / std::sqrt(mass[g]);
      out.shapes.col(mode).segment<3>(6 * g + 3) = rot_inv_sqrt[g] * ya;
      participation += std::sqrt(mass[g]) * yl;
    }
    out.effective_mass_ratio.push_back(participation.cwiseAbs2() / out.total_mass_kg);
  }
  return out;
}

}  // namespace ishibashi
