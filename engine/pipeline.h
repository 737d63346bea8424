// The stages of one time step, in the order World::step calls them. Each stage reads the
// Model and updates part of the State; each lives in its own .cpp file.
#pragma once
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "engine/model.h"
#include "engine/parallel.h"
#include "engine/state.h"

namespace ishibashi {

// pose.cpp: every block's rotation matrix and world-frame face planes (the narrowphase
// makes the vertices and edge directions of the pairs it searches: narrowphase.h).
// Returns whether the pair list must be rebuilt: there is none, or a block has moved more
// than half the margin since it was built (update_pairs' check, made in the same pass).
// A step's integrate pass poses the blocks once it has moved them (State::posed_ahead), so
// this runs only where no step has: a new or restored state.
bool update_pose(const Model& model, State& state);
// The same pose, block by block, for a pass over the blocks in stage chunks: each chunk
// keeps its part of the check in a PoseChunk, and finish_pose combines them.
struct PoseChunk {
  bool moved = false;  // a block of the chunk moved half the margin
  // The spread of the blocks' step shifts along each axis (m) and their largest step turn
  // (rad), for the apart pairs' clock.
  Vec3 shift_lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 shift_hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
  double turn = 0.0;
};
// `add`: the blocks' step motions add to those no narrowphase has read yet (begin_pose).
bool begin_pose(State& state);
void pose_block(const Model& model, State& state, std::ptrdiff_t b, bool add, PoseChunk& chunk);
// Returns whether the pair list must be rebuilt, as update_pose; advances the apart clock.
bool finish_pose(const Model& model, State& state, const PoseChunk* chunks, int chunk_count);

// broadphase.cpp: rebuilds the sorted candidate pair list when a block has moved more
// than half the margin since the last rebuild; keeps each surviving pair's memory.
// Returns true when it rebuilt. The second form takes the check from update_pose.
bool update_pairs(const Model& model, State& state);
bool update_pairs(const Model& model, State& state, bool moved);
// Block b has moved more than half the margin since the pair list was built: the
// inflated spheres of the list may no longer hold all its contacts.
inline bool moved_half_margin(const Model& model, const State& state, int b) {
  return (state.position[b] - state.position_at_rebuild[b]).squaredNorm() > 0.25 * model.margin_m * model.margin_m;
}
// Throws ModelError, naming the most crowded block, when the broadphase's pairs at the current
// poses exceed max_candidate_pairs (model.h): a ring cut into 1-mm slices would exhaust the
// memory before any message. Counts without storing the pairs, and stops past the limit.
void refuse_crowded_spheres(const Model& model, State& state);
// The margin-inflated bounding spheres of blocks a and b overlap (the broadphase's test).
bool spheres_overlap(const Model& model, const State& state, int a, int b);
// Brute-force oracle of the broadphase: all pairs a < b whose inflated spheres overlap.
std::vector<Pair> brute_force_pairs(const Model& model, const State& state);

class ContactLaw;

// narrowphase.cpp: sub-contacts of every candidate pair, with the history (springs, bond)
// of each key that already existed. `first_detection` marks the joints originally in
// contact, the only ones that may carry a bond. dt_s: the step that led to the current
// pose (s), for how far re-clipped points moved.
// With `law`, each chunk of pairs runs its contact law right after its narrowphase, in
// the same loop (one end-of-loop wait a step fewer), or, where a pair of the chunk changed
// its count, once the layout is mended: every chunk's law runs once.
void update_contacts(const Model& model, State& state, bool first_detection, double dt_s,
                     ContactLaw* law = nullptr);
// The sub-contact arrays laid out densely in pair order, without dead entries (the
// narrowphase does it itself when they pile up; what it moves changes no result).
void compact_contacts(const Model& model, State& state);
// World::form_bonds (contact_history.cpp).
int form_bonds(const Model& model, State& state);

// contact_law.cpp: spring and dashpot constants (MODEL.md section 3) of a sub-contact
// of area S_i between blocks a and b, whose centroids lie l_A, l_B from the contact plane:
// K_n = S_i / (l_A/E_A + l_B/E_B), K_s likewise with G, C = 2 h sqrt(m_eq K),
// m_eq = (rho_A l_A + rho_B l_B) S_i. The narrowphase stores them with each sub-contact
// (SubContacts::constants).
SpringConstants spring_constants(const Model& model, int a, int b, double lever_a_m, double lever_b_m, double area_m2);

// contact_law.cpp: spring, dashpot and failure update of every sub-contact over dt, then
// the tie rods (apply_ties); accumulates dissipated energy and returns the elastic energy
// now stored in both (J).
double apply_contact_law(const Model& model, State& state, double dt_s);
// The same law chunk by chunk of the pair loops (State::pair_chunk_begin), so that the
// narrowphase can run each chunk's law in its own pass (update_contacts): made once the
// pair list is final for the step, then every chunk run once, on any thread, then
// finish(). The same numbers either way: the chunks' energies are added in chunk order.
struct LawEnergy {
  double elastic_j = 0, damping_j = 0, friction_j = 0, bond_j = 0;
};
class ContactLaw {
 public:
  // Sizes the per-pair outputs. `clocked`: each chunk and finish() time themselves (two
  // clock reads a chunk, for the profile's split of a pass shared with the narrowphase).
  ContactLaw(const Model& model, State& state, double dt_s, bool clocked = false);
  void run_chunk(int k);
  // Adds the dissipated energies to State::energy, then the tie rods (ties.cpp); returns
  // the elastic energy stored in the sub-contacts and ties (J).
  double finish();
  // Clocked: the thread-seconds its chunks and finish() took.
  double seconds() const;

 private:
  const Model& m_;
  State& s_;
  double dt_s_;
  bool clocked_;
  std::array<LawEnergy, kStageChunks> parts_{};
  std::array<double, kStageChunks> chunk_s_{};
  double finish_s_ = 0;
};

// ties.cpp, at the contact law's end (ContactLaw::finish): each tie rod's tension at the
// current pose (tension only, yielding at its yield force: State::tie_plastic_m grows and
// Energy::tie_yield_j books the work), its force on b and moments for the gather. Returns
// the elastic energy of the ties (J).
double apply_ties(const Model& model, State& state);
// ties.cpp: adds each tie's axial stiffness to its blocks' diagonal stiffness (N/m, N m/rad in
// the principal frame; (nb)), for the stability limit.
void add_tie_stiffness(const Model& model, const State& state, std::vector<Vec6>& stiffness);

// stability.cpp: the largest stable dt of the free blocks on their current sub-contacts,
// per block and degree of freedom 2/omega (sqrt(1 + zeta^2) - zeta), omega^2 = K/M; with
// zeta = 0 unless with_damping. Sets *block to the limiting block.
double stability_limit_s(const Model& model, const State& state, bool with_damping, int* block);
// The same per block (nb): its own limit and the degree of freedom that sets it (0-2
// translations, 3-5 rotations about the principal axes); infinite for blocks that are not
// free or touch nothing.
struct BlockLimit {
  double dt_s = INFINITY;
  int dof = -1;
};
std::vector<BlockLimit> block_stability_limits(const Model& model, const State& state, bool with_damping);
// stability.cpp (Damping::capped): sets State::damping_scale so that every
// free block's damping ratio zeta in each degree of freedom keeps dt within
// kDampingCapMargin (model.h) of its limit; 1 where the materials' h already does.
void update_damping_caps(const Model& model, State& state, double dt_s);

// gather.cpp: the indices that follow the pair list (State::pair_index_valid): each
// block's pairs for the gather, and the pair loops' chunks (State::pair_chunk_begin).
// update_contacts rebuilds them when the pair list changed; the contact law, the gather
// and the implicit dashpots that follow it in a step read them.
void update_pair_index(const Model& model, State& state);

// gather.cpp: block b's resultant force and torque (State::force and torque), race-free
// (block -> contacts index). A pass over the blocks in stage chunks calls it for each of
// its blocks: integrate's with explicit dashpots, the implicit solve's first.
void gather_block(const Model& model, State& state, std::ptrdiff_t b);
// The ground's work over a step by the trapezoid rule: the mean of the prescribed blocks'
// contact forces at the pose before and at this one, times the velocities that moved them.
// (The force at this pose alone, a right Riemann sum, made the ground's work drift by
// dt m a^2 / 4 a second under a harmonic ground of amplitude a: as much as a stone riding
// it rigidly exchanges.) Over the sides of the pairs in chunk k of the pair loops
// (State::prescribed_entry_begin), on the thread whose contact law wrote their forces
// (a serial pass over every side on one thread cost model F 15 % of its two-thread step);
// each side's force at this pose is kept for the next step's mean.
double prescribed_power_of_chunk(State& state, int k);
// The same for the forces at the pose before of the sides no longer listed since the pair
// list changed (State::prescribed_force_carried); serial, over the prescribed blocks.
double carried_prescribed_power(State& state);

// implicit_damping.cpp (Damping::implicit), between the contact law and integrate: the
// dashpot forces at the end-of-step velocities (backward Euler), as the change delta
// (State::implicit) they make to the velocities. Its first pass over the blocks gathers
// their forces (gather_block). Conjugate gradients stop when the preconditioned residual
// is below ModelOptions::damping_solve_tolerance of the right-hand side's.
constexpr int kDampingSolveMaxIterations = 200;
constexpr long kPreconditionerRefreshSteps = 10;
struct DampingSolve {
  int iterations = 0;
  bool converged = true;
  double contact_power_w = 0.0;     // of the contacts on the prescribed blocks, as prescribed_power_of_chunk
  double prescribed_power_w = 0.0;  // power the prescribed blocks put in against the dashpots
  double prescribed_work_j = 0.0;   // the dashpots' work on the prescribed blocks' side over the step
};
DampingSolve solve_implicit_damping(const Model& model, State& state, double dt_s);
// Adds the solve's impulse on free block b, M delta, to its force and torque as M delta /
// dt; returns its work on b over the step (J, <= 0 up to the solve's tolerance), at the mean
// of the velocities before and after (the form in which the step balances kinetic energy).
// Called by integrate_with_dashpots just before the block moves.
double apply_dashpot_impulse(const Model& model, State& state, double dt_s, std::ptrdiff_t b);

// integrate.cpp: semi-implicit Euler with Euler's rotation equations in the principal frame,
// a pass over the blocks that reads State::rotation (the pose of this step) and then poses
// each block it moved, for the next step (State::posed_ahead, pose.cpp). The energy it
// returns: the kinetic and gravitational energy of the free blocks before the update (J),
// and the kinetic energy of blocks that left the model in this step and were frozen.
// Throws ModelError naming the block when its state becomes NaN or infinite.
struct BlockEnergy {
  double kinetic_j = 0.0;
  double gravitational_j = 0.0;  // -m g . x, zero at the origin
  double left_model_j = 0.0;     // energy taken from the blocks frozen in this step
};
struct ForcesAndMotion {
  BlockEnergy energy;
  double prescribed_power_w = 0.0;  // gather_and_integrate: as prescribed_power_of_chunk's, summed
  double dashpot_work_j = 0.0;      // integrate_with_dashpots: apply_dashpot_impulse's, summed
};
// Explicit dashpots: each block's forces gathered just before it moves (nothing comes
// between them).
ForcesAndMotion gather_and_integrate(const Model& model, State& state, double dt_s);
// Implicit dashpots: each free block's impulse from the solve added just before it moves.
ForcesAndMotion integrate_with_dashpots(const Model& model, State& state, double dt_s);

}  // namespace ishibashi
