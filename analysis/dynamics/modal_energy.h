// Where a mode's strain energy sits: for a mode shape of the modal analysis, the energy of
// every sub-contact spring (normal K_n, two shear K_s) summed by joint class, the parts of
// the two blocks it joins (ring / ring, fill / ring, side wall / wall, ...). Tells which
// joints make a mode as stiff as it is (issue 26: which joints a frequency depends on).
#pragma once
#include <string>
#include <vector>

#include "analysis/dynamics/modal.h"

namespace ishibashi {

struct JointEnergyShare {
  std::string joint;  // "fill / ring"; a block that does not move (other than the ground) is "<part> (fixed)"
  double normal = 0;  // share of the mode's strain energy in the normal springs of these joints
  double shear = 0;   // and in their shear springs
};

// Shares of mode `mode`'s strain energy (they sum to 1; the energy is lambda / 2 for the
// mass-normalised shape), largest first; none for a mode that strains no joint (a block
// touching nothing moves freely). `state` must be the one the modal analysis used.
std::vector<JointEnergyShare> modal_energy_shares(const Model& model, const State& state, const ModalResult& modal,
                                                  int mode);

}  // namespace ishibashi
