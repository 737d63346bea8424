#include "geometry/bridge_fill.h"

#include <algorithm>
#include <cmath>

#include "geometry/bridge_outline.h"
#include "geometry/shapes.h"

namespace ishibashi {
namespace {

// Where the courses are (m): `levels` from the ground to the fill's top, the first
// `steep_levels` of them at the first ring's steep chords (extrados indices up to
// `steep_end` on the right side), and `top`, the level the columns of cut stones reach.
struct Courses {
  std::vector<double> levels;
  int steep_levels = 0;
  int steep_end = 0;
  double top = 0;
};

// Low courses follow the extrados: one course per steep chord (rising at least 0.45
// stone), its joints at the chord's ends, so each course meets one chord of each ring.
// Above, courses of one stone; the last one takes what is left (>= 0.3 stone).
Courses course_levels(const BridgeSpec& s, const RingGeometry& g, const Ring2& ring) {
  const double stone = s.ring.stone_m, sliver = 0.3 * stone;
  const int n = g.along;
  Courses c;
  c.levels = {0.0};
  c.steep_end = n - 1;  // right-side extrados index where the steep part ends
  c.levels.push_back(ring.extrados[n - 1].z());
  for (int i = n - 2; i > n / 2; --i) {
    const double rise = ring.extrados[i].z() - ring.extrados[i + 1].z();
    if (rise < 0.45 * stone) break;
    c.levels.push_back(ring.extrados[i].z());
    c.steep_end = i;
  }
  c.steep_levels = static_cast<int>(c.levels.size());
  const double z_steep = c.levels.back();
  for (double z = z_steep + stone; z < s.fill_height_m - sliver + 1e-9; z += stone) c.levels.push_back(z);
  c.levels.push_back(s.fill_height_m);
  // Shallow chords (near the crown) carry columns of cut stones up to `top`.
  const double crown_top = g.centre_z + g.outer_radius;
  c.top = s.fill_height_m;
  for (double z : c.levels)
    if (z >= crown_top + sliver - 1e-9) {
      c.top = z;
      break;
    }
  return c;
}

// One cell of a course (its x-z outline) across the width: the face courses are the
// spandrel walls, the others fill or soil; fixed when on the ground and the bottom course
// is fixed.
void add_prisms(const BridgeSpec& s, const RingGeometry& g, const std::vector<Vec3>& xz, int course,
                std::vector<BridgeBlock>& blocks) {
  const double y_min = -0.5 * s.ring.width_m;
  const double dy = s.ring.width_m / g.across;
  const bool fixed = s.fixed_bottom_course && std::any_of(xz.begin(), xz.end(), [](const Vec3& p) { return p.z() < 1e-9; });
  for (int k = 0; k < g.across; ++k) {
    const bool face_wall = k == 0 || k == g.across - 1;
    const Part part = s.backfill == Backfill::soil ? (face_wall ? Part::wall : Part::soil)
                                                   : (face_wall ? Part::wall : Part::fill);
    blocks.push_back(BridgeBlock{make_prism_xz(xz, y_min + k * dy, y_min + (k + 1) * dy), part, course, fixed});
  }
}

// Side cells of every course, in running bond. Per ring and course, the x-range its
// outline (or its columns) takes on each side: `near` is the boundary's extreme towards
// the ring's centre, `far` towards the fill. Cells start at `near` (the cut removes what
// lies in the ring) and joints keep half a stone clear of `far`, so no stone next to a
// ring is a sliver.
void add_side_cells(const BridgeSpec& s, const RingGeometry& g, const std::vector<Ring2>& rings, const Courses& c,
                    std::vector<BridgeBlock>& blocks) {
  const double stone = s.ring.stone_m, clearance = 0.5 * stone;
  const int n = g.along;
  const double x_end = 0.5 * s.length_m;
  for (std::size_t band = 0; band + 1 < c.levels.size(); ++band) {
    const double z0 = c.levels[band], z1 = c.levels[band + 1];
    struct Side {
      double near, far;
    };
    std::vector<Side> lefts, rights;
    for (const Ring2& r : rings) {
      if (z0 >= c.top - 1e-9) break;
      const std::vector<Vec3>& e = r.extrados;  // each side from its own vertices (exact)
      if (band + 1 < static_cast<std::size_t>(c.steep_levels)) {
        if (band == 0) {  // beside the springers' vertical faces
          lefts.push_back(Side{e[0].x(), e[0].x()});
          rights.push_back(Side{e[n].x(), e[n].x()});
        } else {  // one steep chord per side: from joint `band` (low, outer) to band + 1
          lefts.push_back(Side{e[band + 1].x(), e[band].x()});
          rights.push_back(Side{e[n - band - 1].x(), e[n - band].x()});
        }
      } else {  // beside the columns of cut stones
        lefts.push_back(Side{e[n - c.steep_end].x(), e[n - c.steep_end].x()});
        rights.push_back(Side{e[c.steep_end].x(), e[c.steep_end].x()});
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
      for (std::size_t cell = 0; cell + 1 < cuts.size(); ++cell) {
        std::vector<Vec3> xz;
        if (cut_cell(rectangle(cuts[cell], cuts[cell + 1], z0, z1), rings, xz))
          add_prisms(s, g, xz, static_cast<int>(band), blocks);
      }
    }
  }
}

// Columns of cut stones over the shallow chords, course by course up to c.top.
void add_columns(const BridgeSpec& s, const RingGeometry& g, const std::vector<Ring2>& rings, const Courses& c,
                 std::vector<BridgeBlock>& blocks) {
  const double sliver = 0.3 * s.ring.stone_m;
  const int n = g.along;
  for (const Ring2& r : rings)
    for (int i = n - c.steep_end; i < c.steep_end; ++i) {
      const Vec3& p = r.extrados[i];
      const Vec3& q = r.extrados[i + 1];
      double bottom = std::min(p.z(), q.z());
      const double chord_top = std::max(p.z(), q.z());
      for (std::size_t band = 0; band < c.levels.size(); ++band) {
        const double z = c.levels[band];
        if (z <= bottom + 1e-9 || z < chord_top + sliver - 1e-9) continue;
        if (z > c.top + 1e-9) break;
        std::vector<Vec3> xz;
        if (cut_cell(rectangle(p.x(), q.x(), bottom, z), rings, xz)) add_prisms(s, g, xz, static_cast<int>(band) - 1, blocks);
        bottom = z;
      }
    }
}

}  // namespace

void add_fill(const BridgeSpec& s, const RingGeometry& g, const std::vector<double>& centres, std::vector<BridgeBlock>& blocks) {
  std::vector<Ring2> rings;
  for (double c : centres) rings.push_back(ring_outline(g, c));
  const Courses courses = course_levels(s, g, rings[0]);
  add_side_cells(s, g, rings, courses, blocks);
  add_columns(s, g, rings, courses, blocks);
}

}  // namespace ishibashi
