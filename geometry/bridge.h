// Masonry arch bridges from a handful of parameters (MODEL.md section 5): arch rings of
// voussoirs on fixed springers, spandrel walls and backfill of stones (or soil between
// stone face walls) in horizontal courses, stones next to the extrados cut to fit the
// ring (CGAL Boolean operations), fixed side walls, several spans, a fixed ground base.
//
// Layout: x along the bridge (spans side by side, centred on x = 0), y across it
// (centred), z up from the ground at the springings.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "engine/model.h"
#include "geometry/arch_ring.h"
#include "geometry/materials.h"
#include "geometry/shapes.h"

namespace ishibashi {

enum class Part : int { ground = 0, ring = 1, wall = 2, fill = 3, soil = 4, side_wall = 5, imported = 6 };
const char* part_name(Part part);

// The parts whose stone joints mortar may bond, by the names model files give them.
inline constexpr std::array<const char*, 5> kMortarPartNames{"ring", "wall", "fill", "side_wall", "ground"};
Part parse_mortar_part(const std::string& name);  // one of kMortarPartNames
const char* mortar_part_name(Part part);          // its name there ("side_wall")

enum class Backfill { stone, soil };
enum class GroundMaterial { stone, soil };

struct BridgeSpec {
  ArchRingSpec ring;               // span, rise, thickness, width, stone size, ring bond
  int spans = 1;                   // identical spans side by side
  double pier_width_m = 2.0;       // clear distance between neighbouring springers
  double fill_height_m = 0.0;      // top of walls and backfill above the ground; 0: ring alone
  double length_m = 0.0;           // length of walls and backfill (centred); 0: ring alone
  Backfill backfill = Backfill::stone;  // soil: soil units between a front and a rear stone wall
  double side_wall_width_m = 0.0;  // fixed side walls (abutments) at both ends; 0: none
  double ground_thickness_m = 0.5; // fixed base under the whole bridge; 0: none
  double ground_margin_m = 0.0;    // ground beyond the bridge on every side; 0: 4 x its height
  // The ground's joints with the stones it carries take the soil's E, density and friction
  // angle and are never bonded by mortar, as the study gives them (MODEL.md section 4).
  GroundMaterial ground = GroundMaterial::soil;
  // Walls, fill and soil units of the lowest course, those standing on the ground, are
  // fixed like the springers (MODEL.md section 5: "bottom stones are fixed"); false: they
  // rest on the ground's joints and may slide and rock on it.
  bool fixed_bottom_course = false;
  Material stone;                  // empty name: the Nishida stone
  Material soil;                   // empty name: the Nishida soil (MODEL.md section 4)
  double mortar_pa = 0.0;          // f_t = c of stone joints originally in contact; 0: dry
  // The mortar's fracture energies G_f^I, G_f^II, J/m^2 (Material::tension_fracture_j_m2):
  // both 0, brittle (MODEL.md as written); both > 0, a softening bond.
  double mortar_tension_fracture_j_m2 = 0.0;
  double mortar_shear_fracture_j_m2 = 0.0;
  // Where the mortar lies: a joint carries it when both its blocks belong to a listed part
  // (a retrofit that grouts the ring alone, or repoints the walls and fill). Empty, the
  // default: every stone part, as the study's mortar runs have it. Soil never carries it.
  std::vector<Part> mortar_parts;
};

// The names of the parts whose joints the spec's mortar bonds (every one of
// kMortarPartNames when mortar_parts is empty), for summaries.
std::vector<std::string> mortar_part_names(const BridgeSpec& spec);
// "f_t = c = 2e+05 Pa at the stone joints in contact within ring, wall" ("at every stone
// joint in contact" without mortar_parts), or "" when dry.
std::string mortar_description(const BridgeSpec& spec);

struct BridgeBlock {
  Polyhedron shape;
  Part part;
  int course;   // horizontal course (fill) or position along the arc (ring)
  bool fixed;
};

// The most blocks generate_bridge makes: far above any masonry bridge (model F: 2,003;
// a million blocks' contacts take several GB), far below what a stone size in the wrong
// unit asks for.
constexpr int kMaxGeneratedBlocks = 1'000'000;

// Generates the blocks. Throws ModelError naming the parameter for impossible input.
std::vector<BridgeBlock> generate_bridge(const BridgeSpec& spec);

// Volume the blocks must fill: the bridge's outline less the openings under the
// intrados chords, plus the side walls (m^3). Independent of how blocks are cut.
double design_volume_m3(const BridgeSpec& spec);

// The blocks with their materials (stone, soil; mortar on the stone-stone joints within
// spec.mortar_parts), ready to build the engine Model with an analysis's options. Throws
// ModelError, when the bridge carries mortar, for a listed part of which it has no stone block.
ModelBuilder bridge_builder(const BridgeSpec& spec, const std::vector<BridgeBlock>& blocks);
inline Model compile_bridge(const BridgeSpec& spec, const std::vector<BridgeBlock>& blocks, const ModelOptions& options = {}) {
  return bridge_builder(spec, blocks).build(options);
}

// The unit on top of the arch crown, which the study monitors: the free ring block
// highest up, nearest the middle of the width (of equal ones, the one at the smaller x:
// found by position, whatever the numbering); -1 when the model has no free ring block.
int crown_unit(const Model& model);

// A unit off both symmetry planes of the bridge: the free ring block at the +y face next to
// the crown unit along the ring (the nearest one not at its x). A symmetric bridge's crown
// barely moves vertically in its horizontal modes; this unit does, so its vertical response
// to a horizontal step shows them (issue 26). -1 when there is none.
int face_unit_beside_crown(const Model& model);

}  // namespace ishibashi
