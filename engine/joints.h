// The joints of a structure as an engineer reads them: one joint per pair of blocks in
// contact at the start (two convex blocks meet on one plane), measured kinematically
// from the blocks' motion, so that neither re-keyed sub-contacts nor contacts that
// opened beyond the contact tolerance change what is counted.
//   opening: the largest separation normal to the joint over its corners, m (a hinge
//            opens at one edge first);
//   slip:    the relative displacement in the joint plane at its centre, m.
// A joint has cracked when it opened by more than `crack_opening_m` or its bond broke;
// it has slipped when the slip exceeds `slip_m`. Sliding is not cracking.
#pragma once
#include <cstdint>
#include <vector>

#include "engine/model.h"
#include "engine/state.h"

namespace ishibashi {

struct JointThresholds {
  double crack_opening_m = 1e-3;
  double slip_m = 1e-3;
};

struct Joints {
  // ---- geometry at the start (nj joints, nq points) ----
  std::vector<int> block_a, block_b;     // (nj) block_a < block_b
  std::vector<int> point_begin{0};       // (nj+1) joint j owns points [point_begin[j], point_begin[j+1])
  std::vector<Vec3> point_on_a, point_on_b;    // (nq) the same material point in a's and b's
                                               // principal frames (the original sub-contact points)
  std::vector<Vec3> centre_on_a, centre_on_b;  // (nj) the joint's centre, likewise
  std::vector<Vec3> normal_on_a;         // (nj) unit, a -> b, in a's principal frame
  // Separation of b's copy of each point from a's, in a's frame, at the reference pose
  // (zero at the start; set_joint_reference moves it, e.g. to the pose after settling).
  std::vector<Vec3> reference_on_a;      // (nq)
  std::vector<Vec3> centre_reference_on_a;  // (nj)

  // ---- measured by measure_joints ----
  std::vector<double> opening_m;         // (nj) now, >= 0
  std::vector<double> slip_m;            // (nj) now
  std::vector<int> broken_at_reference;  // (nj) its sub-contacts that had lost their bond then
  std::vector<std::uint8_t> bond_broken; // (nj) more of them lost their bond since (for good)
  std::vector<std::uint8_t> cracked;     // (nj) has cracked at some time (for good)

  int size() const { return static_cast<int>(block_a.size()); }
};

// The joints of the sub-contacts flagged original (in contact when the World was made),
// leaving out those of the blocks flagged in `leave_out` (nb; empty: none), e.g. a soil
// fill's elements, whose openings are no cracks of the masonry.
Joints find_original_joints(const State& state, const std::vector<std::uint8_t>& leave_out = {});

// Measures opening, slip and broken bonds from the current state on (a run's settled
// state): what cracked before counts no more. Returns the joints with a broken bond now.
int set_joint_reference(const State& state, Joints& joints);

struct JointCounts {
  int open = 0;      // open by more than the crack opening now
  int cracked = 0;   // cracked at some time (opened beyond it, or lost the bond)
  int slipped = 0;   // slip beyond the threshold now
  double largest_opening_m = 0, largest_slip_m = 0;
  int largest_slip_joint = -1;
};

// Updates the joints' openings, slips and crack flags from the current state.
JointCounts measure_joints(const State& state, const JointThresholds& thresholds, Joints& joints);

// How close sub-contact i's mortar is to cracking: the share of its strength it carries now,
// by the criterion that breaks a brittle bond (MODEL.md section 3, contact_law.cpp): the
// larger of tension sigma / f_t and shear (tau + sigma tan phi) / c, sigma tension positive;
// 0 in compression without shear, 1 at failure (a softening bond against its undamaged
// strength). -1 where it holds no bond (dry, or cracked).
double bond_utilisation(const Model& model, const State& state, int sub_contact);

// The largest bond_utilisation over the sub-contacts; -1: no bond left (a dry model).
double largest_bond_utilisation(const Model& model, const State& state);

}  // namespace ishibashi
