#include "geometry/bridge.h"

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>

#include <algorithm>
#include <cmath>
#include <list>

#include "geometry/materials.h"

namespace ishibashi {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Point2 = K::Point_2;  // (x, z)
using Polygon2 = CGAL::Polygon_2<K>;
using PolygonWithHoles2 = CGAL::Polygon_with_holes_2<K>;

void require(bool ok, const std::string& what) {
  if (!ok) throw ModelError("bridge: " + what);
}

Polygon2 rectangle(double x0, double x1, double z0, double z1) {
  Polygon2 p;
  p.push_back(Point2(x0, z0));
  p.push_back(Point2(x1, z0));
  p.push_back(Point2(x1, z1));
  p.push_back(Point2(x0, z1));
  return p;
}

std::vector<Vec3> to_xz(const Polygon2& p) {
  std::vector<Vec3> out;
  Polygon2 q = p;
  if (q.orientation() == CGAL::CLOCKWISE) q.reverse_orientation();
  for (auto v = q.vertices_begin(); v != q.vertices_end(); ++v)
    out.emplace_back(CGAL::to_double(v->x()), 0.0, CGAL::to_double(v->y()));
  return out;
}

double area_xz(const std::vector<Vec3>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3& u = p[i];
    const Vec3& w = p[(i + 1) % p.size()];
    a += u.x() * w.z() - w.x() * u.z();
  }
  return 0.5 * std::abs(a);
}

// One span's ring in the x-z plane: intrados and extrados points at the joint angles.
struct Ring2 {
  double centre_x;
  std::vector<Vec3> intrados, extrados;  // (x, 0, z), index 0 at the x < 0 springing
  Polygon2 outline;                      // ring + springers + opening: what fill avoids
};

Ring2 ring_outline(const RingGeometry& g, double centre_x) {
  Ring2 r;
  r.centre_x = centre_x;
  for (int i = 0; i <= g.along; ++i) {
    const double a = g.joint(i);
    r.intrados.emplace_back(centre_x + g.radius * std::sin(a), 0.0, g.centre_z + g.radius * std::cos(a));
    r.extrados.emplace_back(centre_x + g.outer_radius * std::sin(a), 0.0, g.centre_z + g.outer_radius * std::cos(a));
  }
  // Springers are squared off: vertical outer face, flat top at the next joint's height.
  const int n = g.along;
  const Vec3& e0 = r.extrados[0];
  const Vec3& en = r.extrados[n];
  r.outline.push_back(Point2(e0.x(), 0.0));
  r.outline.push_back(Point2(en.x(), 0.0));
  r.outline.push_back(Point2(en.x(), r.extrados[n - 1].z()));
  for (int i = n - 1; i >= 1; --i) r.outline.push_back(Point2(r.extrados[i].x(), r.extrados[i].z()));
  r.outline.push_back(Point2(e0.x(), r.extrados[1].z()));
  return r;
}

// The part of rectangle `cell` outside every ring outline: one convex polygon by
// construction of the courses (each cell meets at most one chord of a ring).
bool cut_cell(const Polygon2& cell, const std::vector<Ring2>& rings, std::vector<Vec3>& out) {
  std::list<PolygonWithHoles2> pieces{PolygonWithHoles2(cell)};
  for (const Ring2& r : rings) {
    std::list<PolygonWithHoles2> next;
    for (const auto& p : pieces) CGAL::difference(p, r.outline, std::back_inserter(next));
    pieces.swap(next);
  }
  if (pieces.empty()) return false;
  // Drop vertices that lie on the line of their neighbours (exact predicate).
  Polygon2 boundary;
  if (pieces.size() == 1 && !pieces.front().has_holes()) {
    const Polygon2& raw = pieces.front().outer_boundary();
    const std::size_t m = raw.size();
    for (std::size_t i = 0; i < m; ++i)
      if (!CGAL::collinear(raw[(i + m - 1) % m], raw[i], raw[(i + 1) % m])) boundary.push_back(raw[i]);
  }
  if (boundary.size() < 3 || !boundary.is_convex()) {
    const auto box = cell.bbox();
    throw ModelError("bridge: internal error, the fill cell at x = " + std::to_string(box.xmin()) + " .. " +
                     std::to_string(box.xmax()) + ", z = " + std::to_string(box.ymin()) + " .. " +
                     std::to_string(box.ymax()) + " is not convex after cutting; please report the parameters");
  }
  out = to_xz(boundary);
  return area_xz(out) > 1e-12;
}

}  // namespace

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

// x of each span's centre: springers a pier width apart, the whole centred on x = 0.
static std::vector<double> span_centres(const BridgeSpec& s, const RingGeometry& g) {
  const double pitch = 2.0 * g.springer_half_width + s.pier_width_m;
  std::vector<double> c;
  for (int k = 0; k < s.spans; ++k) c.push_back((k - 0.5 * (s.spans - 1)) * pitch);
  return c;
}

std::vector<BridgeBlock> generate_bridge(const BridgeSpec& s) {
  const RingGeometry g = ring_geometry(s.ring);  // validates the ring parameters
  // No stone thinner than 0.3 stone (height) and none shorter than half a stone along a
  // course next to a ring: small blocks would set a small stable time step.
  const double stone = s.ring.stone_m, sliver = 0.3 * stone, clearance = 0.5 * stone;
  require(s.spans >= 1, "spans must be at least 1");
  require(s.spans == 1 || s.pier_width_m >= 0, "pier_width_m must be >= 0");
  require(s.fill_height_m >= 0 && s.length_m >= 0, "fill_height_m and length_m must be >= 0");
  require(s.side_wall_width_m >= 0 && s.ground_thickness_m >= 0 && s.ground_margin_m >= 0,
          "side_wall_width_m, ground_thickness_m and ground_margin_m must be >= 0");
  const std::vector<double> centres = span_centres(s, g);
  const double bridge_half = centres.back() + g.springer_half_width;
  const bool filled = s.fill_height_m > 0;
  const double crown_top = g.centre_z + g.outer_radius;
  if (filled) {
    require(s.fill_height_m >= crown_top + sliver,
            "fill_height_m (" + std::to_string(s.fill_height_m) + ") must reach at least " +
                std::to_string(crown_top + sliver) + " m, 0.3 stone above the crown's extrados");
    require(s.length_m >= 2 * bridge_half + 2 * sliver,
            "length_m (" + std::to_string(s.length_m) + ") must exceed the rings' extent " +
                std::to_string(2 * bridge_half + 2 * sliver) + " m");
  }
  if (s.backfill == Backfill::soil) require(g.across >= 3, "soil backfill needs at least 3 stones across the width");

  std::vector<BridgeBlock> blocks;
  std::vector<Ring2> rings;
  for (double c : centres) rings.push_back(ring_outline(g, c));

  // ---- rings: voussoirs, squared-off fixed springers ----
  for (const Ring2& r : rings)
    for (const Voussoir& v : make_arch_ring_at(s.ring, r.centre_x, /*square_springers=*/true))
      blocks.push_back(BridgeBlock{v.shape, Part::ring, v.ring_index, v.fixed});

  const double y_min = -0.5 * s.ring.width_m;
  const double dy = s.ring.width_m / g.across;
  auto add_prisms = [&](const std::vector<Vec3>& xz, int course) {
    const bool fixed = s.fixed_bottom_course && std::any_of(xz.begin(), xz.end(), [](const Vec3& p) { return p.z() < 1e-9; });
    for (int k = 0; k < g.across; ++k) {
      const bool face_wall = k == 0 || k == g.across - 1;
      const Part part = s.backfill == Backfill::soil ? (face_wall ? Part::wall : Part::soil)
                                                     : (face_wall ? Part::wall : Part::fill);
      blocks.push_back(BridgeBlock{make_prism_xz(xz, y_min + k * dy, y_min + (k + 1) * dy), part, course, fixed});
    }
  };

  if (filled) {
    // ---- course levels ----
    // Low courses follow the extrados: one course per steep chord (rising at least 0.45
    // stone), its joints at the chord's ends, so each course meets one chord of each
    // ring. Above, courses of one stone; the last one takes what is left (>= 0.3 stone).
    const int n = g.along;
    std::vector<double> levels{0.0};
    int steep_end = n - 1;  // right-side extrados index where the steep part ends
    levels.push_back(rings[0].extrados[n - 1].z());
    for (int i = n - 2; i > n / 2; --i) {
      const double rise = rings[0].extrados[i].z() - rings[0].extrados[i + 1].z();
      if (rise < 0.45 * stone) break;
      levels.push_back(rings[0].extrados[i].z());
      steep_end = i;
    }
    const int steep_levels = static_cast<int>(levels.size());
    const double z_steep = levels.back();
    for (double z = z_steep + stone; z < s.fill_height_m - sliver + 1e-9; z += stone) levels.push_back(z);
    levels.push_back(s.fill_height_m);
    // Shallow chords (near the crown) carry columns of cut stones up to `top`.
    double top = s.fill_height_m;
    for (double z : levels)
      if (z >= crown_top + sliver - 1e-9) {
        top = z;
        break;
      }

    // ---- side cells of every course, in running bond ----
    // Per ring and course, the x-range its outline (or its columns) takes on each side:
    // `near` is the boundary's extreme towards the ring's centre, `far` towards the fill.
    // Cells start at `near` (the cut removes what lies in the ring) and joints keep
    // half a stone clear of `far`, so no stone next to a ring is a sliver.
    const double x_end = 0.5 * s.length_m;
    for (std::size_t band = 0; band + 1 < levels.size(); ++band) {
      const double z0 = levels[band], z1 = levels[band + 1];
      struct Side {
        double near, far;
      };
      std::vector<Side> lefts, rights;
      for (const Ring2& r : rings) {
        if (z0 >= top - 1e-9) break;
        const std::vector<Vec3>& e = r.extrados;  // each side from its own vertices (exact)
        if (band + 1 < static_cast<std::size_t>(steep_levels)) {
          if (band == 0) {  // beside the springers' vertical faces
            lefts.push_back(Side{e[0].x(), e[0].x()});
            rights.push_back(Side{e[n].x(), e[n].x()});
          } else {  // one steep chord per side: from joint `band` (low, outer) to band + 1
            lefts.push_back(Side{e[band + 1].x(), e[band].x()});
            rights.push_back(Side{e[n - band - 1].x(), e[n - band].x()});
          }
        } else {  // beside the columns of cut stones
          lefts.push_back(Side{e[n - steep_end].x(), e[n - steep_end].x()});
          rights.push_back(Side{e[steep_end].x(), e[steep_end].x()});
        }
      }
      // Stretches: from the fill's start to the first ring, between rings, to the end.
      std::vector<Side> starts{Side{-x_end, -x_end}}, ends;
      for (std::size_t k = 0; k < lefts.size(); ++k) {
        ends.push_back(lefts[k]);
        starts.push_back(rights[k]);
      }
      ends.push_back(Side{x_end, x_end});
      const double offset = (band % 2) * 0.5 * stone;
      for (std::size_t k = 0; k < starts.size(); ++k) {
        std::vector<double> cuts{starts[k].near};
        for (double j = std::ceil((starts[k].far + clearance + x_end - offset) / stone);; ++j) {
          const double x = -x_end + offset + j * stone;
          if (x > ends[k].far - clearance) break;
          cuts.push_back(x);
        }
        cuts.push_back(ends[k].near);
        for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
          std::vector<Vec3> xz;
          if (cut_cell(rectangle(cuts[c], cuts[c + 1], z0, z1), rings, xz)) add_prisms(xz, static_cast<int>(band));
        }
      }
    }

    // ---- columns of cut stones over the shallow chords ----
    for (const Ring2& r : rings)
      for (int i = n - steep_end; i < steep_end; ++i) {
        const Vec3& p = r.extrados[i];
        const Vec3& q = r.extrados[i + 1];
        double bottom = std::min(p.z(), q.z());
        const double chord_top = std::max(p.z(), q.z());
        for (std::size_t band = 0; band < levels.size(); ++band) {
          const double z = levels[band];
          if (z <= bottom + 1e-9 || z < chord_top + sliver - 1e-9) continue;
          if (z > top + 1e-9) break;
          std::vector<Vec3> xz;
          if (cut_cell(rectangle(p.x(), q.x(), bottom, z), rings, xz)) add_prisms(xz, static_cast<int>(band) - 1);
          bottom = z;
        }
      }
  }

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
  int index = 0;
  for (const BridgeBlock& b : blocks) {
    const bool of_soil = b.part == Part::soil || (b.part == Part::ground && s.ground == GroundMaterial::soil);
    builder.add_block(b.shape.vertices, b.shape.faces, of_soil ? soil_id : stone_id, b.fixed ? Motion::fixed : Motion::free,
                      std::string(part_name(b.part)) + "-" + std::to_string(index++),
                      BlockTag{static_cast<int>(b.part), b.course});
  }
  return builder;
}

}  // namespace ishibashi
