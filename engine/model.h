// The immutable description of a DEM problem: block shapes, mass properties, materials,
// contact-law parameters and global settings. Built once by ModelBuilder (which validates
// every block), then only read by the step pipeline. SI units throughout.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/math.h"

namespace ishibashi {

// Any problem with the user's model or run settings; the message names the block,
// material or setting and says what would be right.
struct ModelError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The most candidate pairs (bounding boxes or spheres that overlap) an assembly of `blocks`
// may have: 100 a block, at least a million. Masonry has about 10 a block; blocks far
// thinner than they are long, side by side, have thousands, and their pair lists would
// exhaust the memory. Validation (its boxes) and the broadphase (its spheres) refuse more.
constexpr int kMaxPairsPerBlock = 100;
inline long long max_candidate_pairs(long long blocks) { return std::max(kMaxPairsPerBlock * blocks, 1'000'000LL); }

// What a block is in the structure it belongs to; carried to the output, never used by
// the mechanics. Part numbers are the generator's (geometry/bridge.h names them).
struct BlockTag {
  int part = 0;
  int course = 0;
};

enum class Motion : std::uint8_t {
  free,        // moves under forces (Newton-Euler)
  fixed,       // never moves
  prescribed,  // moves with the velocity the driver sets in State each step
};

struct Material {
  std::string name;
  double density_kg_m3 = 2500.0;
  double young_pa = 1e10;
  double poisson = 0.25;
  double friction_deg = 30.0;
  double tensile_pa = 0.0;   // bond tensile strength f_t of joints originally in contact
  double cohesion_pa = 0.0;  // bond cohesion c of joints originally in contact
  // Fracture energies of the bond, J/m^2: 0 (MODEL.md as written) makes it brittle, its
  // strength gone in the step a point reaches it; > 0 makes it soften as Lourenco's
  // interface model does (exponentially, dissipating G_f per unit area before it is gone).
  double tension_fracture_j_m2 = 0.0;  // G_f^I, mode I (opening)
  double shear_fracture_j_m2 = 0.0;    // G_f^II, mode II (sliding)
  double damping_normal = 0.0;  // h_n, fraction of critical
  double damping_shear = 0.0;   // h_s, fraction of critical
};

// Contact-law parameters of one material pair (MODEL.md section 3).
struct PairLaw {
  double tan_friction = 0.0;
  double tensile_pa = 0.0;
  double cohesion_pa = 0.0;
  double tension_fracture_j_m2 = 0.0;
  double shear_fracture_j_m2 = 0.0;
  double damping_normal = 0.0;
  double damping_shear = 0.0;
  // Its joints originally in contact carry a bond (mortar).
  bool carries_bond() const { return tensile_pa > 0 || cohesion_pa > 0; }
  // Its bond softens (fracture energies given) rather than breaking at once.
  bool bond_softens() const { return tension_fracture_j_m2 > 0; }
};

// Finest contact subdivision (ModelOptions::subdivision): 16^2 points per fan triangle.
constexpr int kMaxSubdivision = 16;

// Most corners of one face of a block (the narrowphase clips faces on the stack).
constexpr int kMaxFaceCorners = 60;

// Capped dashpots keep dt within this share of each block's stability limit.
constexpr double kDampingCapMargin = 0.8;

struct ContactSettings {
  // A sub-contact exists while its gap is below tolerance_ratio * (size of the smaller
  // block), size = cbrt(volume). Forces depend on the gap, not on this tolerance.
  double tolerance_ratio = 1e-3;
  // Broadphase margin as a fraction of the mean block size; the pair list is rebuilt when
  // a block has moved more than half of it.
  double margin_ratio = 0.1;
  // Area given to a corner or edge contact (vertex-face, edge-face, edge-edge), as a
  // fraction of size^2 of the smaller block, so that K_n stays finite and sensible.
  double point_area_ratio = 0.01;
};

// Where a face-to-face joint's sub-contacts sit and what area each carries (subdivision 1).
enum class JointRule : std::uint8_t {
  // One point per corner of the contact polygon with its tributary area: the right area
  // and resultant, like the study's corner-against-face contacts (its Fig. 2), but three
  // times a uniform spring bed's rocking stiffness on a rectangle (K a^2/4, not K a^2/12).
  corners,
  // The corners, the centroid and the centroid of each fan triangle (centroid, corner i,
  // corner i+1), weighted a twelfth of each fan triangle's area at its three vertices and
  // three quarters at its centroid: a quadrature exact for every quadratic, so the points
  // carry the polygon's area, centroid and second moments (a uniform bed's stiffness in
  // rocking and twist, for any convex polygon), and the corners keep points, so a joint
  // opening at an edge rocks about that edge.
  moments,
};
// The names of an option's values, in the enum's order: its name and parse functions and
// the scenario reader's list of choices all read this one list.
inline constexpr std::array<const char*, 2> kJointRuleNames{"corners", "moments"};
inline const auto& choice_names(JointRule) { return kJointRuleNames; }
inline const char* joint_rule_name(JointRule rule) { return kJointRuleNames[static_cast<int>(rule)]; }
JointRule parse_joint_rule(const std::string& name);  // throws ModelError listing the choices

// The shear spring of a joint (MODEL.md section 3; the study's own formula is lost from our
// copy, so this is a choice it leaves open).
enum class ShearSpring : std::uint8_t {
  // K_s = S / (l_A/G_A + l_B/G_B), G = E / (2 (1 + nu)): the series formula with the shear
  // modulus, K_s = 0.39 K_n for the Nishida stone.
  shear_modulus = 0,
  // K_s = K_n, as many DEM codes take it for want of a better value.
  normal = 1,
};
inline constexpr std::array<const char*, 2> kShearSpringNames{"shear_modulus", "normal"};
inline const auto& choice_names(ShearSpring) { return kShearSpringNames; }
inline const char* shear_spring_name(ShearSpring spring) { return kShearSpringNames[static_cast<int>(spring)]; }
ShearSpring parse_shear_spring(const std::string& name);

// How the dashpots of MODEL.md section 3 enter the step.
enum class Damping : std::uint8_t {
  // Explicit, every dashpot as the materials' h specify: dt must stay below the limit the
  // dashpots set (h = 1 on a block held by many joints: a tenth of the springs' or less).
  study = 0,
  // Explicit, but where a free block's dashpots would make the step unstable they are
  // scaled down just enough (stability.cpp), so the springs alone limit dt; every joint
  // the step resolves keeps its h. Quick exploration, not verdicts.
  capped = 1,
  // Every dashpot as specified, integrated implicitly (implicit_damping.cpp): the springs
  // alone limit dt, and each step solves for the dashpots over the whole structure.
  implicit = 2,
};
inline constexpr std::array<const char*, 3> kDampingNames{"study", "capped", "implicit"};
inline const auto& choice_names(Damping) { return kDampingNames; }
inline const char* damping_name(Damping damping) { return kDampingNames[static_cast<int>(damping)]; }
Damping parse_damping(const std::string& name);

// The value of enum E named `name` (choice_names(E{})), or -1.
template <class E>
int choice_index(const std::string& name) {
  const auto& names = choice_names(E{});
  for (std::size_t i = 0; i < names.size(); ++i)
    if (name == names[i]) return static_cast<int>(i);
  return -1;
}
// "\"a\", \"b\" or \"c\"", for messages.
template <class E>
std::string choice_list() {
  const auto& names = choice_names(E{});
  std::string list;
  for (std::size_t i = 0; i < names.size(); ++i)
    list += std::string(i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + "\"" + names[i] + "\"";
  return list;
}

// ModelOptions::damping_solve_tolerance unless a run sets it.
constexpr double kDampingSolveTolerance = 1e-3;

// What an analysis asks of a model beyond its blocks and materials. Applied and checked
// once, by ModelBuilder::build; a built Model is never edited (the same blocks with other
// options are built again from the same builder).
struct ModelOptions {
  // 1: one sub-contact per vertex of the contact polygon. n > 1 (at most 16): the polygon
  // is split into triangles from its centroid and each into n*n sub-triangles, one
  // sub-contact at each centroid, so the joint's rotational stiffness approaches a uniform
  // spring bed.
  int subdivision = 1;
  JointRule joint_rule = JointRule::corners;  // at subdivision 1; n > 1 refines either the same way
  ShearSpring shear_spring = ShearSpring::shear_modulus;
  Damping damping = Damping::study;
  // Damping::implicit: the conjugate gradients stop when the residual is this share of the
  // dashpots' impulse (implicit_damping.cpp).
  double damping_solve_tolerance = kDampingSolveTolerance;
  // Fixed blocks become prescribed: a driver sets their velocity each step (the ground of
  // a seismic run or an impulse response).
  bool drive_fixed_blocks = false;
  // The impulse analysis (MODEL.md section 6.1): every joint originally in contact bonded
  // with a strength it can never reach, no contact damping, no gravity; fixed blocks driven.
  bool linear_joints = false;
  // Mortar that sets in the settled pose: the joints originally in contact are found
  // without a bond, and World::form_bonds gives them theirs once the structure stands
  // under its weight (a seismic run, after settling), as mortar laid wet hardens under
  // the dead load and carries none of the tension of gravity switched on at once.
  // false: bonded from the first step.
  bool bonds_when_settled = false;
};

// A tie rod: a steel bar through the masonry, anchored by plates at two points fixed in
// two blocks. It carries tension only (a slack rod, or one pushed, carries nothing),
// elastic up to its yield force, then perfectly plastic: it lengthens for good.
struct Tie {
  int block_a = -1, block_b = -1;
  Vec3 anchor_a_local = Vec3::Zero(), anchor_b_local = Vec3::Zero();  // the anchor points in each block's principal frame, m
  double rest_length_m = 0.0;           // the anchors' distance as built, less pretension / stiffness
  double stiffness_n_m = 0.0;           // E A / L
  double yield_force_n = 0.0;           // f_y A
  double pretension_n = 0.0;            // its tension as built (a post-tensioned rod), N
};

struct Model {
  // ---- blocks (nb) ----
  int block_count = 0;
  std::vector<std::string> block_name;   // for messages (nb)
  std::vector<BlockTag> block_tag;       // part and course, for output (nb)
  std::vector<double> mass_kg;           // (nb)
  std::vector<Vec3> inertia_kg_m2;       // principal moments (nb)
  std::vector<double> volume_m3;         // (nb)
  std::vector<double> size_m;            // cbrt(volume) (nb)
  std::vector<double> radius_m;          // bounding radius about the centroid (nb)
  std::vector<int> material;             // index into materials (nb)
  std::vector<Motion> motion;            // (nb)
  std::vector<Vec3> initial_position;    // centroid, world frame (nb)
  std::vector<Quat> initial_orientation; // principal frame -> world (nb)

  // ---- shapes: flat tables in each block's principal frame (origin at the centroid) ----
  std::vector<int> vertex_begin{0};         // block b owns vertices [vertex_begin[b], vertex_begin[b+1]) (nb+1)
  std::vector<Vec3> vertex_local;        // (nv)
  std::vector<int> face_begin{0};           // block b owns faces [face_begin[b], face_begin[b+1]) (nb+1)
  std::vector<int> face_vertex_begin{0};    // face f has corners face_vertex[face_vertex_begin[f] ..] (nf+1)
  std::vector<int> face_vertex;          // global vertex index, counter-clockwise seen from outside
  std::vector<Vec3> face_normal_local;   // outward unit normal (nf)
  std::vector<double> face_offset_local; // n . x on the face plane, m (nf)
  std::vector<int> edge_begin{0};           // (nb+1)
  std::vector<std::array<int, 2>> edge_vertex;  // global vertex indices (ne)
  std::vector<int> edge_direction;       // index into direction_local of the edge's direction (ne)
  std::vector<int> direction_begin{0};      // (nb+1)
  std::vector<Vec3> direction_local;     // distinct edge directions of a block, unit (nd)

  // ---- materials and contact laws ----
  std::vector<Material> materials;
  std::vector<PairLaw> pair_law;         // (nmat x nmat), row-major
  const PairLaw& law(int material_a, int material_b) const {
    return pair_law[material_a * materials.size() + material_b];
  }

  Vec3 gravity_m_s2{0.0, 0.0, -9.81};
  // Depth along gravity (g_hat . x, m) below which a free block's centroid has left the
  // model: the lowest point of the fixed and prescribed blocks plus the largest block
  // size. Such a block fell past the ground; it is frozen there (State::left_model)
  // instead of falling for ever. Infinite when the model has no immobile block or no
  // gravity.
  double leave_depth_m = INFINITY;
  ContactSettings contact;
  ModelOptions options;
  double margin_m = 0.0;  // broadphase margin, from contact.margin_ratio * mean block size
  // Apart pairs are left unvisited while a clock of every block's step motions stays below
  // their slack (separating_axis.cpp); a block's turn counts there at this lever (m), so a
  // pair whose own lever (its centres' distance plus its limit, plus b's diameter) is longer
  // is visited every step: 6 free radii and 4 margins, more than any two free blocks within
  // the broadphase's reach have.
  double apart_lever_bound_m = 0.0;

  // Gap below which a sub-contact between blocks a and b exists, m.
  double contact_tolerance_m(int a, int b) const {
    return contact.tolerance_ratio * std::min(size_m[a], size_m[b]);
  }
  // Area of a corner or edge contact between blocks a and b, m^2.
  double point_contact_area_m2(int a, int b) const {
    const double size = std::min(size_m[a], size_m[b]);
    return contact.point_area_ratio * size * size;
  }

  // ---- ties (nt): steel rods anchored in two free blocks (a retrofit), ties.cpp ----
  std::vector<Tie> ties;
  std::vector<int> block_tie_begin;      // (nb+1) block b's tie sides are block_tie[block_tie_begin[b] ..]
  std::vector<int> block_tie;            // side 2 t: block_a of tie t, 2 t + 1: its block_b (2 nt)

  int face_count(int b) const { return face_begin[b + 1] - face_begin[b]; }
  std::string block_label(int b) const;  // "block 12 'ring-3'" for messages
};

// ties.cpp: Model::block_tie_begin and block_tie from Model::ties (ModelBuilder::build).
void index_ties(Model& model);
// ties.cpp: each tie's rest length set so that it carries its pretension in the model's
// initial pose (a model whose blocks were moved after it was built: an ensemble member's),
// its stiffness E A / L kept.
void make_ties_snug(Model& model);

// Collects materials and blocks, validates each block and computes its mass properties.
class ModelBuilder {
 public:
  int add_material(const Material& material);

  // A convex polyhedron given by its vertices (world frame, m) and faces (indices into
  // `vertices`, counter-clockwise seen from outside). Throws ModelError naming the block
  // when it is open, non-convex, degenerate or inside out.
  int add_block(const std::vector<Vec3>& vertices, const std::vector<std::vector<int>>& faces,
                int material, Motion motion = Motion::free, std::string name = {}, BlockTag tag = {});

  // A tie rod between two points (world frame, m), each strictly inside one free block (an
  // anchor plate on a wall's outer face: a point just inside it), of cross-section area_m2,
  // Young's modulus young_pa and yield stress yield_pa, tightened to pretension_n as built
  // (0: snug). Throws ModelError saying which point lies in no block, or on a joint between
  // two, or in a block that cannot move, or that the pretension is not below the yield force.
  int add_tie(const Vec3& from, const Vec3& to, double area_m2, double young_pa, double yield_pa, double pretension_n = 0);

  void set_gravity(const Vec3& g) { gravity_ = g; }
  ContactSettings& contact_settings() { return contact_; }
  // The Model of the blocks added so far with `options`; throws ModelError naming the
  // setting that is out of range. May be called again with other options.
  Model build(const ModelOptions& options = {}) const;

 private:
  Model model_;
  Vec3 gravity_{0.0, 0.0, -9.81};
  ContactSettings contact_;
};

// The default law of a material pair: friction of the weaker (smaller angle) side, as
// MODEL.md asks for stone-soil; bond strengths of the weaker side; mean damping ratios.
PairLaw default_pair_law(const Material& a, const Material& b);

}  // namespace ishibashi
