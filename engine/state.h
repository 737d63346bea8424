// Everything that changes during a run: block kinematics, the contact history that the
// incremental springs need, and the reusable work buffers of the step pipeline.
// Structure of arrays; buffers are sized once and keep their capacity from step to step.
#pragma once
#include <cstdint>
#include <vector>

#include "engine/math.h"
#include "engine/model.h"

namespace ishibashi {

// Bits of SubContacts::flags.
enum SubContactFlag : std::uint8_t {
  bonded = 1,    // carries tension and cohesion (mortar), not yet failed
  broken = 2,    // had a bond and lost it (tension or shear failure)
  sliding = 4,   // shear force at the friction limit this step
  open = 8,      // gap >= 0 and no bond: carries no force
  fresh = 16,    // created this step: its springs start from the current overlap
  original = 32, // part of a joint in contact at the start (may carry a bond)
};

// Sub-contacts, sorted by (pair, key). The normal points from block_a to block_b and the
// force is the one that block_a exerts on block_b (block_b exerts -force on block_a).
struct SubContacts {
  std::vector<int> pair;                 // index into the pair list
  std::vector<int> block_a, block_b;
  std::vector<std::uint64_t> key;        // stable feature key within the pair
  std::vector<Vec3> point;               // m, world, on the common plane
  std::vector<Vec3> normal;              // unit, a -> b
  std::vector<double> gap_m;             // signed normal gap, > 0 open, < 0 overlap
  std::vector<double> gap_change_m;      // gap_m minus last step's gap of the same sub-contact
  std::vector<double> area_m2;           // share S_i of the contact area
  std::vector<double> lever_a_m, lever_b_m;  // l_A, l_B: centroid to contact plane
  std::vector<double> normal_spring_n;   // e_n, tension positive
  std::vector<Vec3> shear_spring_n;      // e_s, force on b, in the contact plane
  std::vector<Vec3> force_n;             // total force on b (springs + dashpots)
  std::vector<Vec3> damping_force_n;     // dashpot part of force_n (for the energy balance)
  std::vector<double> slip_m;            // accumulated sliding (plastic shear displacement)
  std::vector<Vec3> incident_local;      // face contacts: the point on the incident face, in
                                         // the incident block's principal frame (for reuse)
  std::vector<std::uint8_t> flags;       // SubContactFlag bits

  std::size_t size() const { return key.size(); }
  void clear();
  void resize(std::size_t n);
  // Copies all of `src` into this, starting at index `at` (this must be large enough).
  void copy_from(const SubContacts& src, std::size_t at);
};

// One broadphase candidate pair, a < b, with what the narrowphase remembers of it.
struct Pair {
  int a = 0, b = 0;
  // Last separating-axis choice, kept for hysteresis so the features (and keys) persist:
  // kind 0 = face of a, 1 = face of b, 2 = edge-edge, -1 = none yet.
  int axis_kind = -1;
  int axis_feature = -1;
  // Separation found by the last full axis search (m) and the blocks' travel then
  // (State::travel_m, turn_rad sums): while the blocks cannot have closed the distance,
  // or have barely moved, the search is skipped.
  double separation_m = -1.0;
  double travel_at_search_m = 0.0, turn_at_search_rad = 0.0;
  int sub_begin = 0, sub_count = 0;  // this pair's range in State::contacts
};

struct Energy {
  double kinetic_j = 0.0;
  double gravitational_j = 0.0;  // -m g . x, zero at the origin
  double elastic_j = 0.0;        // stored in the contact springs
  double damping_j = 0.0;        // dissipated by dashpots so far
  double friction_j = 0.0;       // dissipated by sliding so far
  double bond_j = 0.0;           // spring energy released when bonds broke
  double prescribed_work_j = 0.0;  // work done on the system by prescribed blocks so far
  double initial_total_j = 0.0;  // mechanical energy at the first step

  double mechanical_j() const { return kinetic_j + gravitational_j + elastic_j; }
  // (mechanical + dissipated - work in) - initial; zero for an exact integrator.
  double balance_error_j() const {
    return mechanical_j() + damping_j + friction_j + bond_j - prescribed_work_j - initial_total_j;
  }
};

struct Profile {  // seconds spent in each stage since the start
  double pose_s = 0, broadphase_s = 0, narrowphase_s = 0, contact_law_s = 0, gather_s = 0, integrate_s = 0;
  long broadphase_rebuilds = 0;
};

struct State {
  double time_s = 0.0;
  long step = 0;

  // ---- blocks (nb), world frame ----
  std::vector<Vec3> position;            // centroid, m
  std::vector<Quat> orientation;         // principal frame -> world, unit
  std::vector<Vec3> velocity;            // m/s
  std::vector<Vec3> angular_velocity;    // rad/s, world frame
  std::vector<Vec3> applied_force;       // external loads set by the driver, N
  std::vector<Vec3> applied_torque;      // N m
  std::vector<Vec3> force, torque;       // resultant of contacts + applied loads (no gravity)
  std::vector<double> travel_m;          // path length of the centroid since the start (nb)
  std::vector<double> turn_rad;          // accumulated rotation angle since the start (nb)

  // ---- world-frame geometry of the current pose ----
  std::vector<Vec3> vertex_world;        // (nv)
  std::vector<Vec3> face_normal_world;   // (nf)
  std::vector<double> face_offset_world; // (nf)
  std::vector<Vec3> direction_world;     // (nd)

  // ---- contacts ----
  std::vector<Pair> pairs;               // sorted by (a, b)
  SubContacts contacts;                  // current sub-contacts
  SubContacts previous_contacts;         // last step's, read while matching keys
  std::vector<SubContacts> chunk_contacts;  // per-chunk narrowphase output
  std::vector<int> block_contact_begin;  // (nb+1) gather index
  std::vector<int> block_contact;        // 2 i for side a of sub-contact i, 2 i + 1 for side b
  std::vector<int> block_contact_cursor;

  // ---- broadphase ----
  std::vector<Vec3> position_at_rebuild; // (nb)
  std::vector<Pair> pair_scratch;
  std::vector<std::vector<Pair>> chunk_pairs;     // per-chunk broadphase output
  std::vector<std::vector<int>> chunk_candidates; // per-chunk neighbour scratch
  std::vector<int> cell_start, cell_block, cell_cursor; // hashed cell list: blocks of bucket c are
                                           // cell_block[cell_start[c] .. cell_start[c+1])
  bool pairs_valid = false;

  // ---- bookkeeping ----
  Energy energy;
  double last_gravitational_j = 0.0;     // potentials of the previous step (see World::step)
  double last_elastic_j = 0.0;
  bool energy_started = false;
  Profile profile;
};

// A State at the model's initial pose, at rest, with no contacts yet.
State make_initial_state(const Model& model);

}  // namespace ishibashi
