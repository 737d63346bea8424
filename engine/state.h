// Everything that changes during a run: block kinematics, the contact history that the
// incremental springs need, and the reusable work buffers of the step pipeline.
// Structure of arrays; buffers are sized once and keep their capacity from step to step.
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "engine/math.h"
#include "engine/model.h"
#include "engine/profile.h"

namespace ishibashi {

struct SpringConstants {
  double kn, ks;  // N/m
  double cn, cs;  // N s/m
};

// Bits of SubContacts::flags.
enum SubContactFlag : std::uint8_t {
  bonded = 1,    // carries tension and cohesion (mortar), not yet failed
  broken = 2,    // had a bond and lost it (tension or shear failure)
  sliding = 4,   // shear force at the friction limit this step
  open = 8,      // gap >= 0 and no bond: carries no force
  pulling = 16,  // a softening bond held at its tensile strength this step: no normal dashpot
  original = 32, // part of a joint in contact at the start (may carry a bond)
};

// Every array of SubContacts, listed once: X(type, name, comment). The struct's members,
// resize, copy_range, the checkpoint and the field-by-field tests are all made from this
// list, so a new field cannot be left out of any of them (a field left out of a regroup
// or a checkpoint would lose contact history silently).
#define ISHIBASHI_SUB_CONTACT_FIELDS(X)                                                                   \
  X(int, block_a, "the pair's blocks; the normal points from a to b")                                   \
  X(int, block_b, "")                                                                                   \
  X(std::uint64_t, key, "stable feature key within the pair")                                          \
  X(Vec3, point, "m, world, on the common plane")                                                        \
  X(Vec3, normal, "unit, a -> b")                                                                        \
  X(double, gap_m, "signed normal gap, > 0 open, < 0 overlap")                                           \
  X(double, gap_change_m, "gap_m minus last step's gap of the same sub-contact")                         \
  X(double, area_m2, "share S_i of the contact area")                                                    \
  /* Spring and dashpot constants (spring_constants() of the area and of the centroids'              */ \
  /* distances to the contact plane when the sub-contact was built; they hold while it is carried    */ \
  /* over, as its area does).                                                                          */ \
  X(double, normal_stiffness_n_m, "K_n")                                                                 \
  X(double, shear_stiffness_n_m, "K_s")                                                                  \
  X(double, normal_damping_n_s_m, "C_n")                                                                 \
  X(double, shear_damping_n_s_m, "C_s")                                                                  \
  /* Spring stretches: normal spring force e_n = K_n u_n (tension positive), shear spring force on b  */ \
  /* e_s = K_s u_s (in the contact plane).                                                             */ \
  X(double, normal_stretch_m, "u_n")                                                                     \
  X(Vec3, shear_stretch_m, "u_s")                                                                        \
  X(Vec3, damping_force_n, "dashpot part of the force on b, a re-clip's power carried (for the energy balance)") \
  X(double, slip_m, "accumulated sliding (plastic shear displacement)")                                  \
  X(double, bond_damage, "softening bond: share of its strength lost, 0-1 (fracture work / G_f S_i)")   \
  X(Vec3, incident_local, "face contacts: the point on the incident face, in the incident block's frame") \
  X(std::uint8_t, flags, "SubContactFlag bits")

// Sub-contacts, grouped by pair (Pair::sub_begin, sub_count; State::contacts). The normal
// points from block_a to block_b and the force is the one that block_a exerts on block_b
// (block_b exerts -force on block_a). Structure of arrays, one per field of the list above.
struct SubContacts {
#define ISHIBASHI_DECLARE_FIELD(type, name, comment) std::vector<type> name;
  ISHIBASHI_SUB_CONTACT_FIELDS(ISHIBASHI_DECLARE_FIELD)
#undef ISHIBASHI_DECLARE_FIELD

  // Calls fn(array) for every array, in the list's order (fn(name, array) with names).
  template <class Fn>
  void for_each_array(Fn&& fn) {
#define ISHIBASHI_VISIT_FIELD(type, name, comment) fn(name);
    ISHIBASHI_SUB_CONTACT_FIELDS(ISHIBASHI_VISIT_FIELD)
#undef ISHIBASHI_VISIT_FIELD
  }
  template <class Fn>
  void for_each_array(Fn&& fn) const {
    const_cast<SubContacts&>(*this).for_each_array([&](const auto& array) { fn(array); });
  }
  template <class Fn>
  void for_each_named_array(Fn&& fn) const {
#define ISHIBASHI_VISIT_NAMED_FIELD(type, name, comment) fn(#name, name);
    ISHIBASHI_SUB_CONTACT_FIELDS(ISHIBASHI_VISIT_NAMED_FIELD)
#undef ISHIBASHI_VISIT_NAMED_FIELD
  }

  std::size_t size() const { return key.size(); }
  double normal_spring(std::size_t i) const { return normal_stiffness_n_m[i] * normal_stretch_m[i]; }  // e_n, N
  Vec3 shear_spring(std::size_t i) const { return shear_stiffness_n_m[i] * shear_stretch_m[i]; }      // e_s, N
  Vec3 spring_force(std::size_t i) const { return -normal_spring(i) * normal[i] + shear_spring(i); }  // on b, N
  // Energy stored in the sub-contact's springs, J.
  double spring_energy(std::size_t i) const {
    return 0.5 * (normal_spring(i) * normal_stretch_m[i] + shear_spring(i).dot(shear_stretch_m[i]));
  }
  SpringConstants constants(std::size_t i) const {
    return {normal_stiffness_n_m[i], shear_stiffness_n_m[i], normal_damping_n_s_m[i], shear_damping_n_s_m[i]};
  }
  void clear() { resize(0); }
  void resize(std::size_t n) {
    for_each_array([n](auto& array) { array.resize(n); });
  }
  // Copies `count` sub-contacts of `src` from index `from` to this at index `to` (this
  // must be large enough).
  void copy_range(const SubContacts& src, std::size_t from, std::size_t count, std::size_t to);
};

// One broadphase candidate pair, a < b, with what the narrowphase remembers of it.
struct Pair {
  int a = 0, b = 0;
  // Last separating-axis choice, kept for hysteresis so the features (and keys) persist:
  // kind 0 = face of a, 1 = face of b, 2 = edge-edge, -1 = none yet.
  int axis_kind = -1;
  int axis_feature = -1;
  // An apart pair is not visited while State::apart_clock_m stays below this (m): the
  // clock's value at its last visit plus its slack, how far its stones may still move
  // toward each other unseen. -inf: visited each step (separating_axis.cpp, schedule_apart).
  // Beside axis_kind: a skipped pair is read in one cache line.
  double apart_until_clock_m = -std::numeric_limits<double>::infinity();
  // Separation found by the last full axis search (m) and the relative pose then: b's
  // centroid in a's principal frame (m) and the rotation from b's frame to a's. While b
  // cannot have closed the distance relative to a, or has barely moved relative to a,
  // the search is skipped (a bridge shaken as a whole keeps its contacts as they are).
  double separation_m = -1.0;
  Vec3 offset_at_search = Vec3::Zero();
  Quat relative_at_search = Quat::Identity();
  double centre_distance_at_search_m = 0.0;  // |offset_at_search|
  // An upper bound on how far any point of b has moved relative to a since the search
  // (the measure moved_at_least tests), summed from the blocks' step motions: while it
  // stays below the pair's limit the exact test is skipped, with the same answer. inf:
  // not known (a new pair), so the exact test runs (as after a restore, whose blocks'
  // step turns are not known).
  double moved_bound_m = std::numeric_limits<double>::infinity();
  // A face pair whose manifold came out empty is not clipped again while its stone is
  // clear of the face: how far (m) it may still move relative to the face, less each
  // step's bound on its motion; 0: clipped each step it is visited (separating_axis.cpp).
  double clear_for_m = 0.0;
  int sub_begin = 0, sub_count = 0;  // this pair's range in State::contacts
  // This step's narrowphase: -1 when the pair's sub-contacts were updated in place,
  // else the number of rebuilt ones, at `rebuilt_begin` in its chunk's buffer.
  int rebuilt_begin = 0, rebuilt_count = -1;
  // The line in the face's plane that held such a pair's stone beside the face at its
  // last clip (separating_axis.cpp, stone_against_face); -1: none.
  int beside_axis = -1;
};

struct Energy {
  double kinetic_j = 0.0;
  double gravitational_j = 0.0;  // -m g . x, zero at the origin
  double elastic_j = 0.0;        // stored in the contact springs
  double damping_j = 0.0;        // dissipated by dashpots so far
  double friction_j = 0.0;       // dissipated by sliding so far
  double bond_j = 0.0;           // spring energy released when bonds broke
  double tie_yield_j = 0.0;      // dissipated by tie rods yielding (ties.cpp)
  double prescribed_work_j = 0.0;  // work done on the system by prescribed blocks so far
  double left_model_j = 0.0;     // mechanical energy taken from blocks that left the model when frozen (integrate.cpp)
  double reclip_j = 0.0;         // made (< 0: taken) by re-clipped pairs' springs: the model's, first order in dt (contact_history.cpp)
  double initial_total_j = 0.0;  // mechanical energy at the first step

  double mechanical_j() const { return kinetic_j + gravitational_j + elastic_j; }
  // Energy that crossed the system's boundary: the work put in and every dissipation, J.
  double exchanged_j() const {
    return std::abs(prescribed_work_j) + std::abs(damping_j) + std::abs(friction_j) + std::abs(bond_j) + std::abs(tie_yield_j);
  }
  // (mechanical + dissipated - work in - made by re-clips) - initial; zero for an exact integrator.
  double balance_error_j() const {
    return mechanical_j() + damping_j + friction_j + bond_j + tie_yield_j + left_model_j - prescribed_work_j - reclip_j - initial_total_j;
  }
};

// Implicit dashpots (implicit_damping.cpp).
// A symmetric 6x6 matrix as its lower triangle, row-major: (i, j), j <= i, at i (i + 1) / 2 + j.
struct Sym6 {
  double v[21];
};
// The same in single precision: how the solve stores a pair's matrix. Its passes stream
// every pair's matrix once an iteration (model F: 1.4 MB so, 2.7 in double), and float's
// relative rounding (6e-8) lies four orders below the solve's tolerance (1e-3).
struct Sym6f {
  float v[21];
};
// Work vectors, world frame.
struct ImplicitDamping {
  // Per pair (np), from the sub-contacts' dashpots as the contact law left them this step
  // (pair_damping.h, summed by the contact law); blocks {a, -1} where the pair has no
  // sub-contacts (the solve's passes skip it).
  std::vector<std::array<int, 2>> blocks;  // (np) the pair's blocks a, b (b = -1: no sub-contacts)
  std::vector<Sym6f> pair_matrix;      // (np) the pair's dashpots this step
  // Dashpot resultants of the last product: force (N) and moment about the block's
  // centroid (N m), on b per pair, and on each block summed over the pairs where it is a.
  std::vector<Vec6> on_b;              // (np)
  std::vector<Vec6> on_a;              // (nb)
  // The pairs with dashpots this step, block i's in a range of its own (its entries of
  // State::block_pair and a spare slot, from dashpot_lists_begin(i)): those where it is a, in
  // pair order, up to a_end[i]; then those where it is b, in block_pair's order, up to
  // b_end[i]. A block's lists need no other block's, so a step makes anew only those of the
  // blocks whose pairs' dashpots came or went.
  std::vector<int> dashpot_pairs;  // (2 np + nb)
  std::vector<int> a_end, b_end;   // (nb)
  // The pairs whose dashpots came or went (blocks[p][1] changed) since the lists were made,
  // per chunk of the contact law's pass, up to kChangedPerChunk each. Past that, or when the
  // pair list changed (lists_stale), every block's lists are made anew.
  static constexpr int kChangedPerChunk = 8;
  std::vector<std::array<int, kChangedPerChunk>> changed;  // (chunks)
  std::vector<int> changed_count;                          // (chunks)
  bool lists_stale = true;
  std::vector<std::uint8_t> relist;  // (nb) 1: block i's lists are to be made anew before they are read
  std::vector<Vec6> velocity;          // (nb) v* (without dashpots); prescribed: the driver's
  std::vector<Vec6> delta;             // (nb) v_new - v*; last step's is the solve's first guess
  std::vector<Vec6> residual, preconditioned, direction, product;  // (nb) conjugate gradients
  std::vector<Mat6> diagonal;          // (nb) each block's 6x6 block of M + dt C, inverted (the
                                       // preconditioner, refreshed every kPreconditionerRefreshSteps)
};

struct State {
  double time_s = 0.0;
  long step = 0;

  // ---- blocks (nb), world frame ----
  std::vector<Vec3> position;            // centroid, m
  std::vector<Quat> orientation;         // principal frame -> world, unit
  std::vector<Vec3> velocity;            // m/s
  std::vector<Vec3> angular_velocity;    // rad/s, world frame
  // A driver sets a prescribed block's velocities for the next step above, between steps;
  // within a step those hold, for every block, the ones that moved it into its pose (the law's
  // shear increments and dashpots follow its gaps' moves), the driver's here (World::step).
  std::vector<Vec3> driven_velocity;          // (nb) m/s, prescribed blocks only
  std::vector<Vec3> driven_angular_velocity;  // (nb) rad/s
  std::vector<Vec3> applied_force;       // external loads set by the driver, N
  std::vector<Vec3> applied_torque;      // N m
  std::vector<Vec3> force, torque;       // resultant of contacts + applied loads (no gravity);
                                         // prescribed blocks: applied loads only (gather.cpp)
  std::vector<std::uint8_t> left_model;  // 1: a free block that fell below Model::leave_depth_m,
                                         // frozen since (its kinetic energy in Energy::left_model_j)

  // ---- world-frame geometry of the current pose ----
  std::vector<Mat3> rotation;            // (nb) principal frame -> world
  // How each block moved since the last narrowphase (pose.cpp), for its bound on a pair's
  // relative motion: the centroid's displacement (m), a bound on the angle turned (rad; inf
  // until a narrowphase after the first pose or a restore has read it: forget_step_motion).
  std::vector<Vec3> step_shift;          // (nb)
  std::vector<double> step_turn;         // (nb)
  std::vector<Vec3> position_at_pose;    // (nb) the pose they are measured from
  std::vector<Quat> orientation_at_pose; // (nb)
  bool step_motion_read = false;         // a narrowphase has read step_shift and step_turn: the
                                         // next pose starts them anew (else adds to them)
  // The last step's integrate pass posed the blocks it moved (pose.cpp): the next step skips
  // its pose stage and takes the broadphase's check from `moved_ahead`. Whoever moves a block
  // between steps calls forget_step_motion, which clears it (a restore does).
  bool posed_ahead = false;
  bool moved_ahead = false;
  // A bound on how far any point moved relative to any other within Model::apart_lever_bound_m,
  // summed over the poses (pose.cpp): the step shifts' spread plus the largest step turn times
  // the lever, m; apart pairs are scheduled against it. Invalid where step turns are unknown.
  double apart_clock_m = 0.0;
  double apart_clock_step_m = 0.0;       // the last pose's addition
  bool apart_clock_valid = false;
  std::vector<Vec3> face_normal_world;   // (nf)
  std::vector<double> face_offset_world; // (nf)

  // ---- contacts ----
  std::vector<Pair> pairs;               // sorted by (a, b)
  SubContacts contacts;                  // current sub-contacts, grouped by pair (range at
                                         // Pair::sub_begin), and contacts_dead entries in no
                                         // pair's range: read through for_each_sub_contact
  int contacts_dead = 0;                 // sub-contacts left behind by pairs whose new ones were
                                         // appended (narrowphase.cpp); 0: the arrays are dense,
                                         // in pair order
  SubContacts next_contacts;             // where the narrowphase lays them out densely anew
                                         // (the pair list changed, or dead entries piled up)
  std::vector<SubContacts> chunk_contacts;  // per chunk: its re-clipped pairs' sub-contacts
                                         // (the arrays only grow: their size is room, not content)
  std::vector<std::vector<int>> chunk_rebuilt;  // per chunk: the pairs whose count changed this
                                         // step, in pair order (Pair::rebuilt_begin, rebuilt_count)
  bool pairs_changed = true;             // the pair list changed since the last narrowphase
  std::vector<Vec3> pair_force_n;        // (np) resultant force of a pair's sub-contacts on b
  std::vector<Vec3> pair_moment_nm;      // (2 np) moment of the pair's forces on a about a's
                                         // centroid (2p), and on b about b's (2p + 1)
  // Indices that follow the pair list (update_pair_index, when it changed):
  std::vector<int> block_pair_begin;     // (nb+1) gather index: block b's entries are
  std::vector<int> block_pair;           // block_pair[block_pair_begin[b] ..]; entry 2 p is
  std::vector<int> block_pair_cursor;    // side a of pair p, 2 p + 1 side b
  std::vector<int> pair_chunk_begin;     // (stage_chunks + 1) the pair loops' chunk k: pairs
                                         // [k] .. [k + 1], those whose block a lies in the
                                         // block loops' chunk k
  std::vector<std::array<int, 2>> prescribed_entry;  // {entry (as in block_pair), its
  std::vector<int> prescribed_entry_begin;  // block} where that block is prescribed, in pair
                                         // order; chunk k's from prescribed_entry_begin[k]
  std::vector<std::array<int, 2>> prescribed_entry_next;  // scratch of update_pair_index
  std::vector<int> prescribed_block;     // the prescribed blocks, in order (make_initial_state)
  bool pair_index_valid = false;
  std::vector<double> damping_scale;     // (nb) factor on the dashpots of a block's sub-contacts
                                         // (a pair takes the smaller): 1 unless Damping::capped
  std::vector<Vec6> cap_stiffness, cap_damping;  // (nb) scratch of update_damping_caps
  ImplicitDamping implicit;              // Damping::implicit

  // ---- tie rods (nt; ties.cpp) ----
  std::vector<double> tie_plastic_m;     // (nt) permanent elongation from yielding, m
  std::vector<double> tie_tension_n;     // (nt) this step's tension, N (0: slack)
  std::vector<double> tie_peak_tension_n;  // (nt) the largest tension so far, N (the demand on it)
  std::vector<Vec3> tie_force_n;         // (nt) its force on the tie's block_b (on block_a: -)
  std::vector<Vec3> tie_moment_nm;       // (2 nt) moment on block_a about its centroid (2 t), on block_b (2 t + 1)

  // ---- broadphase ----
  std::vector<Vec3> position_at_rebuild; // (nb)
  std::vector<Pair> pair_scratch;
  std::vector<std::vector<Pair>> chunk_pairs;     // per-chunk broadphase output
  std::vector<std::vector<int>> chunk_candidates; // per-chunk neighbour scratch
  std::vector<int> cell_start, cell_block, cell_cursor; // hashed cell list: blocks of bucket c are
                                           // cell_block[cell_start[c] .. cell_start[c+1])
  std::vector<int> large_block;            // immobile blocks too large for the grid's cells
  bool pairs_valid = false;

  // ---- bookkeeping ----
  Energy energy;
  // The ground's work over a step takes the mean of its contact forces at the pose before and
  // at this one (prescribed_power_of_chunk, gather.cpp). The pose before's: (prescribed_entry)
  // each listed pair side's force on its prescribed block (N) and moment about the block's
  // centroid (N m); (nb) per prescribed block, those of the sides listed before the pair list
  // last changed.
  std::vector<Vec3> prescribed_entry_force_before, prescribed_entry_moment_before;
  std::vector<Vec3> prescribed_force_carried, prescribed_moment_carried;
  double last_gravitational_j = 0.0;     // potentials of the previous step (see World::step)
  double last_elastic_j = 0.0;
  bool energy_started = false;
  Profile profile;
};

// A State at the model's initial pose, at rest, with no contacts yet.
State make_initial_state(const Model& model);

// The blocks' step motions unknown (a new or restored state): measured from the current
// pose on, with turns of inf, so that the next narrowphase runs every pair's exact test;
// and no pose made ahead, so that the next step poses the blocks where they are now.
void forget_step_motion(State& state);

// Calls fn(i) for every sub-contact i, pair by pair in pair order: the arrays' own order
// when they are dense, whatever dead entries they hold between two compactions.
template <class Fn>
void for_each_sub_contact(const State& state, Fn&& fn) {
  for (const Pair& pair : state.pairs)
    for (int i = pair.sub_begin; i < pair.sub_begin + pair.sub_count; ++i) fn(i);
}
// The number of sub-contacts (those in the pairs' ranges).
inline int sub_contact_count(const State& state) { return static_cast<int>(state.contacts.size()) - state.contacts_dead; }

// A free block has fallen when its centroid is lower than at the start by more than its
// size (cbrt of its volume).
bool is_fallen(const Model& model, const State& state, int block);

}  // namespace ishibashi
