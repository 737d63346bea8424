#include "geometry/bridge.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "geometry/block_order.h"
#include "geometry/bridge_fill.h"
#include "geometry/bridge_outline.h"
#include "geometry/materials.h"

namespace ishibashi {

const char* part_name(Part p) {
  switch (p) {
    case Part::ground: return "ground";
    case Part::ring: return "ring";
    case Part::wall: return "wall";
    case Part::fill: return "fill";
    case Part::soil: return "soil";
    case Part::side_wall: return "side wall";
    case Part::imported: return "imported";
  }
  return "?";
}

namespace {
constexpr Part kMortarParts[] = {Part::ring, Part::wall, Part::fill, Part::side_wall, Part::ground};
}  // namespace

const char* mortar_part_name(Part part) {
  for (std::size_t i = 0; i < kMortarPartNames.size(); ++i)
    if (part == kMortarParts[i]) return kMortarPartNames[i];
  return part_name(part);
}

std::vector<std::string> mortar_part_names(const BridgeSpec& spec) {
  if (spec.mortar_parts.empty()) return {kMortarPartNames.begin(), kMortarPartNames.end()};
  std::vector<std::string> names;
  for (Part p : spec.mortar_parts) names.push_back(mortar_part_name(p));
  return names;
}

std::string mortar_description(const BridgeSpec& spec) {
  if (!(spec.mortar_pa > 0)) return "";
  std::ostringstream text;
  text << "f_t = c = " << std::setprecision(4) << spec.mortar_pa << " Pa at ";
  if (spec.mortar_parts.empty()) return text.str() + "every stone joint in contact";
  text << "the stone joints in contact within ";
  const std::vector<std::string> names = mortar_part_names(spec);
  for (std::size_t i = 0; i < names.size(); ++i) text << (i ? ", " : "") << names[i];
  return text.str();
}

Part parse_mortar_part(const std::string& name) {
  for (std::size_t i = 0; i < kMortarPartNames.size(); ++i)
    if (name == kMortarPartNames[i]) return kMortarParts[i];
  std::string list;
  for (const char* n : kMortarPartNames) list += std::string(list.empty() ? "" : ", ") + n;
  throw ModelError("mortar part '" + name + "' is none of " + list);
}

// x of each span's centre: springers a pier width apart, the whole centred on x = 0.
static std::vector<double> span_centres(const BridgeSpec& s, const RingGeometry& g) {
  const double pitch = 2.0 * g.springer_half_width + s.pier_width_m;
  std::vector<double> c;
  for (int k = 0; k < s.spans; ++k) c.push_back((k - 0.5 * (s.spans - 1)) * pitch);
  return c;
}

std::vector<BridgeBlock> generate_bridge(const BridgeSpec& s) {
  const RingGeometry g = ring_geometry(s.ring);  // validates the ring parameters
  // No stone thinner than 0.3 stone (height; bridge_fill.cpp keeps every course to that):
  // small blocks would set a small stable time step.
  const double stone = s.ring.stone_m, sliver = 0.3 * stone;
  require_spec(s.spans >= 1, "spans must be at least 1");
  // Above a pier narrower than a sliver the fill is cut into slivers (a 1 mm pier: a 1 kg
  // stone and a step of 6e-8 s); at no pier at all the cut crashed.
  if (s.spans > 1 && s.pier_width_m < sliver) {
    std::ostringstream msg;
    msg << "pier_width_m (" << s.pier_width_m << ") must be at least 0.3 stone_m (" << sliver
        << " m) between spans: the fill above a narrower pier would be cut into slivers";
    require_spec(false, msg.str());
  }
  require_spec(s.fill_height_m >= 0 && s.length_m >= 0, "fill_height_m and length_m must be >= 0");
  require_spec(s.side_wall_width_m >= 0 && s.ground_thickness_m >= 0 && s.ground_margin_m >= 0,
               "side_wall_width_m, ground_thickness_m and ground_margin_m must be >= 0");
  // A stone size in the wrong unit (millimetres for metres) would cut the bridge into
  // billions of blocks and exhaust the memory before any message: the ring's stones are
  // counted, the fill's and walls' bounded by their box over a stone's cube.
  const double ring_stones = static_cast<double>(g.along) * g.across * s.spans;
  const double fill_stones = s.length_m * s.fill_height_m * (s.ring.width_m + 2 * s.side_wall_width_m) / (stone * stone * stone);
  if (ring_stones + fill_stones > kMaxGeneratedBlocks) {
    std::ostringstream msg;
    msg << "stone_m = " << stone << " m cuts the bridge into about " << std::setprecision(2) << ring_stones + fill_stones
        << " blocks (" << g.across << " across the ring's width); the generator makes at most " << kMaxGeneratedBlocks
        << " (is stone_m in metres?)";
    require_spec(false, msg.str());
  }
  const std::vector<double> centres = span_centres(s, g);
  const double bridge_half = centres.back() + g.springer_half_width;
  const bool filled = s.fill_height_m > 0;
  const double crown_top = g.centre_z + g.outer_radius;
  if (filled) {
    require_spec(s.fill_height_m >= crown_top + sliver,
                 "fill_height_m (" + std::to_string(s.fill_height_m) + ") must reach at least " +
                     std::to_string(crown_top + sliver) + " m, 0.3 stone above the crown's extrados");
    require_spec(s.length_m >= 2 * bridge_half + 2 * sliver,
                 "length_m (" + std::to_string(s.length_m) + ") must exceed the rings' extent " +
                     std::to_string(2 * bridge_half + 2 * sliver) + " m");
  }
  if (s.backfill == Backfill::soil) require_spec(g.across >= 3, "soil backfill needs at least 3 stones across the width");

  std::vector<BridgeBlock> blocks;
  // ---- rings: voussoirs, squared-off fixed springers ----
  for (double centre_x : centres)
    for (const Voussoir& v : make_arch_ring_at(s.ring, centre_x, /*square_springers=*/true))
      blocks.push_back(BridgeBlock{v.shape, Part::ring, v.ring_index, v.fixed});

  if (filled) add_fill(s, g, centres, blocks);

  // ---- fixed side walls and ground ----
  const double half_length = filled ? 0.5 * s.length_m : bridge_half;
  const double height = filled ? s.fill_height_m : crown_top;
  if (s.side_wall_width_m > 0)
    for (double side : {-1.0, 1.0}) {
      const double x = side * (half_length + 0.5 * s.side_wall_width_m);
      blocks.push_back(BridgeBlock{make_box(Vec3(x, 0, 0.5 * height), Vec3(s.side_wall_width_m, s.ring.width_m, height)),
                                   Part::side_wall, 0, true});
    }
  if (s.ground_thickness_m > 0) {
    // By default wide enough to catch what falls: four times the bridge's height H beyond it
    // on every side. A wall toppling out of plane brings its top down at up to sqrt(3 g H) and
    // throws stones about sqrt(6) H = 2.4 H, then they hop and roll (model B with mortar threw
    // four past 2 H). What leaves it anyway is frozen below it (Model::leave_depth_m).
    const double margin = s.ground_margin_m > 0 ? s.ground_margin_m : std::max(2 * stone, 4 * height);
    const double length = 2 * (half_length + s.side_wall_width_m + margin);
    blocks.push_back(BridgeBlock{make_box(Vec3(0, 0, -0.5 * s.ground_thickness_m),
                                          Vec3(length, s.ring.width_m + 2 * margin, s.ground_thickness_m)),
                                 Part::ground, 0, true});
  }
  order_blocks_for_locality(blocks);
  return blocks;
}

double design_volume_m3(const BridgeSpec& s) {
  const RingGeometry g = ring_geometry(s.ring);
  const std::vector<double> centres = span_centres(s, g);
  const double w = s.ring.width_m;
  double area = 0;
  if (s.fill_height_m > 0) {
    // Outline: the fill's rectangle less the openings under the intrados chords.
    area = s.length_m * s.fill_height_m;
    for (double c : centres) area -= area_xz(ring_outline(g, c).intrados);  // the opening
  } else {
    // The ring alone: each span's outline less its opening.
    for (double c : centres) {
      const Ring2 r = ring_outline(g, c);
      std::vector<Vec3> outline = to_xz(r.outline);
      area += area_xz(outline) - area_xz(r.intrados);
    }
  }
  double volume = area * w;
  if (s.side_wall_width_m > 0) {
    const double height = s.fill_height_m > 0 ? s.fill_height_m : g.centre_z + g.outer_radius;
    volume += 2 * s.side_wall_width_m * w * height;
  }
  return volume;
}

ModelBuilder bridge_builder(const BridgeSpec& s, const std::vector<BridgeBlock>& blocks) {
  ModelBuilder builder;
  Material stone = s.stone.name.empty() ? nishida_stone() : s.stone;
  stone.tensile_pa = stone.cohesion_pa = s.mortar_pa;
  stone.tension_fracture_j_m2 = s.mortar_tension_fracture_j_m2;
  stone.shear_fracture_j_m2 = s.mortar_shear_fracture_j_m2;
  const int stone_id = builder.add_material(stone);
  Material soil = s.soil.name.empty() ? nishida_soil() : s.soil;
  soil.tensile_pa = soil.cohesion_pa = 0.0;  // soil joints are never reinforced
  const int soil_id = builder.add_material(soil);
  auto of_soil = [&](const BridgeBlock& b) {
    return b.part == Part::soil || (b.part == Part::ground && s.ground == GroundMaterial::soil);
  };
  // Stone outside the mortar's parts: a material of its own without the bond, so that the
  // pair law of a joint (the weaker side's bond) carries mortar only between two listed parts.
  auto mortared = [&](Part p) {
    return s.mortar_parts.empty() || std::find(s.mortar_parts.begin(), s.mortar_parts.end(), p) != s.mortar_parts.end();
  };
  int dry_stone_id = stone_id;
  if (s.mortar_pa > 0) {
    for (Part p : s.mortar_parts)
      if (std::none_of(blocks.begin(), blocks.end(), [&](const BridgeBlock& b) { return b.part == p && !of_soil(b); }))
        throw ModelError(std::string("mortar_parts (the model's [bridge] or the scenario's [model]) lists \"") +
                         mortar_part_name(p) + "\", but the bridge has no stone block of that part (the ground of soil and "
                         "soil backfill never carry mortar; a ring alone has no wall, fill or side wall; imported blocks "
                         "have no parts: leave mortar_parts out)");
    if (std::any_of(blocks.begin(), blocks.end(), [&](const BridgeBlock& b) { return !of_soil(b) && !mortared(b.part); })) {
      Material dry = stone;
      dry.name = stone.name + " (dry joints)";
      dry.tensile_pa = dry.cohesion_pa = dry.tension_fracture_j_m2 = dry.shear_fracture_j_m2 = 0.0;
      dry_stone_id = builder.add_material(dry);
    }
  }
  int index = 0;
  for (const BridgeBlock& b : blocks) {
    const int material = of_soil(b) ? soil_id : mortared(b.part) ? stone_id : dry_stone_id;
    builder.add_block(b.shape.vertices, b.shape.faces, material, b.fixed ? Motion::fixed : Motion::free,
                      std::string(part_name(b.part)) + "-" + std::to_string(index++),
                      BlockTag{static_cast<int>(b.part), b.course});
  }
  return builder;
}

}  // namespace ishibashi
