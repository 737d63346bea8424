// Modal analysis of the block assembly with its joints held linear: the stiffness of
// every sub-contact spring (normal K_n, two shear K_s) linearised about the current
// pose, 6 degrees of freedom per free block (3 translations, 3 rotations), the full
// rotational inertia in the mass matrix, the lowest modes by a sparse shift-invert
// eigensolver (Spectra on Eigen).
#pragma once
#include <vector>

#include "engine/model.h"
#include "engine/state.h"

namespace ishibashi {

struct ModalResult {
  std::vector<int> free_blocks;            // block of each 6-dof group
  std::vector<double> frequency_hz;        // ascending (modes)
  Eigen::MatrixXd shapes;                  // (6 * free blocks) x modes, mass-normalised:
                                           // per block (ux, uy, uz, rx, ry, rz), world frame
  std::vector<Vec3> effective_mass_ratio;  // per mode: effective mass in x, y, z / total free mass
  double total_mass_kg = 0;
  int dominant_direction(int mode) const;  // 0 x, 1 y, 2 z
};

// Needs the State's sub-contacts (a World after construction has them). Throws
// ModelError when there is no free block or the eigensolver does not converge.
ModalResult modal_analysis(const Model& model, const State& state, int modes);

}  // namespace ishibashi
