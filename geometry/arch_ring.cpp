#include "geometry/arch_ring.h"

#include <cmath>
#include <sstream>

#include "geometry/materials.h"

namespace ishibashi {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw ModelError("arch ring: " + what);
}

}  // namespace

RingGeometry ring_geometry(const ArchRingSpec& s) {
  require(s.span_m > 0, "span_m must be positive");
  require(s.rise_m > 0, "rise_m must be positive");
  require(s.rise_m <= 0.5 * s.span_m + 1e-12,
          "rise_m (" + std::to_string(s.rise_m) + ") must not exceed half the span (" + std::to_string(0.5 * s.span_m) +
              ") for a segmental or semicircular arch");
  require(s.thickness_m > 0, "thickness_m must be positive");
  require(s.width_m > 0, "width_m must be positive");
  require(s.stone_m > 0, "stone_m must be positive");
  require(s.stone_m <= s.width_m, "stone_m must not exceed the ring width");

  // Intrados circle through both springings (z = 0) and the crown (z = rise).
  RingGeometry g;
  const double half = 0.5 * s.span_m;
  g.radius = (half * half + s.rise_m * s.rise_m) / (2.0 * s.rise_m);
  g.outer_radius = g.radius + s.thickness_m;
  g.centre_z = s.rise_m - g.radius;
  g.half_angle = std::asin(std::min(1.0, half / g.radius));  // pi/2 for a semicircle
  const double mid = g.radius + 0.5 * s.thickness_m;
  require(2.0 * g.half_angle * mid >= 3 * s.stone_m, "stone_m is too large for the ring (fewer than 3 voussoirs)");
  require(s.voussoirs == 0 || s.voussoirs >= 3, "voussoirs must be 0 (from stone_m) or at least 3");
  g.along = s.voussoirs > 0 ? s.voussoirs : std::max(3, static_cast<int>(std::lround(2.0 * g.half_angle * mid / s.stone_m)));
  g.across = std::max(1, static_cast<int>(std::lround(s.width_m / s.stone_m)));
  // Voussoirs far thinner than the stones across the width are slivers: they set a tiny
  // stable step, and 100,000 of them made a validation that ran out of memory.
  const double voussoir_m = 2.0 * g.half_angle * g.radius / g.along;
  if (voussoir_m < 0.1 * s.stone_m) {
    std::ostringstream msg;
    msg.precision(3);
    msg << "voussoirs = " << g.along << " makes each " << voussoir_m << " m along the intrados, less than a tenth of stone_m ("
        << s.stone_m << " m); at most " << static_cast<int>(2.0 * g.half_angle * g.radius / (0.1 * s.stone_m)) << " voussoirs";
    require(false, msg.str());
  }
  g.springer_half_width = g.outer_radius * std::sin(g.half_angle);
  return g;
}

std::vector<Voussoir> make_arch_ring_at(const ArchRingSpec& s, double centre_x, bool square_springers) {
  const RingGeometry g = ring_geometry(s);
  const Vec3 centre(centre_x, 0, g.centre_z);
  auto at = [&](double r, int joint) {
    const double a = g.joint(joint);
    return Vec3(centre.x() + r * std::sin(a), 0.0, centre.z() + r * std::cos(a));
  };
  const double dy = s.width_m / g.across;
  std::vector<Voussoir> out;
  for (int i = 0; i < g.along; ++i) {
    const bool springer = i == 0 || i == g.along - 1;
    // Running bond: every other ring of voussoirs is shifted by half a stone across the
    // width, with half stones at both faces.
    std::vector<double> cuts{0.0};
    const bool shifted = s.bond == Bond::running && i % 2 == 1 && g.across > 1;
    for (int k = 1; k < g.across + (shifted ? 1 : 0); ++k) cuts.push_back((k - (shifted ? 0.5 : 0.0)) * dy);
    cuts.push_back(s.width_m);
    // Cross-section in the x-z plane: intrados and extrados chords between two joints,
    // or a springer squared off to the ground and the next joint's height.
    std::vector<Vec3> section{at(g.radius, i), at(g.radius, i + 1), at(g.outer_radius, i + 1), at(g.outer_radius, i)};
    if (square_springers && springer) {
      const int foot = i == 0 ? 0 : g.along;       // springing joint
      const int head = i == 0 ? 1 : g.along - 1;   // the other joint
      const Vec3 outer = at(g.outer_radius, foot), top = at(g.outer_radius, head);
      section = {at(g.radius, foot), Vec3(outer.x(), 0, 0), Vec3(outer.x(), 0, top.z()), top, at(g.radius, head)};
    }
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      const double y0 = cuts[k] - 0.5 * s.width_m, y1 = cuts[k + 1] - 0.5 * s.width_m;
      out.push_back(Voussoir{make_prism_xz(section, y0, y1), i, static_cast<int>(k), springer});
    }
  }
  return out;
}

}  // namespace ishibashi
