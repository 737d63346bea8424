#include "analysis/run/how_it_fails.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <nlohmann/json.hpp>

#include "analysis/run/checkpoint.h"
#include "geometry/bridge.h"

namespace ishibashi {
namespace {

constexpr int kPartCount = static_cast<int>(Part::imported) + 1;
constexpr std::array<const char*, 4> kTowardNames{"+x", "-x", "+y", "-y"};  // FallDirection 1-4
constexpr std::array<const char*, 3> kSideNames{"-y", "middle", "+y"};

// The bridge's middle across (y) and half its width, from the blocks other than the ground.
struct Across {
  double middle_m = 0, half_width_m = 0;
};
Across across_of(const Model& m) {
  double lo = INFINITY, hi = -INFINITY;
  for (int b = 0; b < m.block_count; ++b) {
    if (m.block_tag[b].part == static_cast<int>(Part::ground)) continue;
    lo = std::min(lo, m.initial_position[b].y());
    hi = std::max(hi, m.initial_position[b].y());
  }
  if (lo > hi) return {};
  return {0.5 * (lo + hi), 0.5 * (hi - lo)};
}

// 0: the -y side, 1: the middle (within a tenth of the half width, or a millimetre: a ring
// stone as wide as the ring), 2: the +y side.
int side_of(const Across& a, double y) {
  const double off = y - a.middle_m;
  if (std::abs(off) <= std::max(0.1 * a.half_width_m, 1e-3)) return 1;
  return off < 0 ? 0 : 2;
}

std::string part_stones(const std::string& part) { return part == "soil" ? "soil elements" : part + " stones"; }

std::string seconds(double shaking_s) {
  if (shaking_s < 0) return "while settling";
  char text[48];
  std::snprintf(text, sizeof text, "from %.2f s of shaking", shaking_s);
  return text;
}

}  // namespace

void FallRecord::check_read(std::size_t blocks) const {
  if (fell_at_s_.size() != blocks || toward_.size() != blocks)
    throw CheckpointError("its record of fallen stones holds " + std::to_string(fell_at_s_.size()) + " and " +
                          std::to_string(toward_.size()) + " blocks of the model's " + std::to_string(blocks));
  for (FallDirection d : toward_)
    if (d > FallDirection::minus_y) throw CheckpointError("a fall direction of " + std::to_string(static_cast<int>(d)) + " where 0 to 4 belong");
}

void FallRecord::note(const Model& m, const State& s, const Vec3& ground_displacement_m) {
  for (int b = 0; b < m.block_count; ++b) {
    if (fell_at_s_[b] >= 0 || !is_fallen(m, s, b)) continue;
    fell_at_s_[b] = s.time_s;
    const Vec3 d = s.position[b] - m.initial_position[b] - ground_displacement_m;
    if (std::abs(d.x()) >= std::abs(d.y()))
      toward_[b] = d.x() >= 0 ? FallDirection::plus_x : FallDirection::minus_x;
    else
      toward_[b] = d.y() >= 0 ? FallDirection::plus_y : FallDirection::minus_y;
  }
}

nlohmann::ordered_json FallRecord::summary(const Model& m, double settle_time_s) const {
  struct PartFalls {
    int fallen = 0;
    double first_s = INFINITY;
    std::array<int, 3> sides{};
  };
  std::array<PartFalls, kPartCount> parts{};
  std::array<int, 4> toward{};
  const Across across = across_of(m);
  for (int b = 0; b < m.block_count; ++b) {
    if (fell_at_s_[b] < 0) continue;
    const int part = std::clamp(m.block_tag[b].part, 0, kPartCount - 1);
    PartFalls& p = parts[part];
    ++p.fallen;
    p.first_s = std::min(p.first_s, fell_at_s_[b] - settle_time_s);
    ++p.sides[side_of(across, m.initial_position[b].y())];
    const int way = static_cast<int>(toward_[b]);
    if (way >= 1 && way <= 4) ++toward[way - 1];
  }
  std::array<int, kPartCount> order{};
  for (int k = 0; k < kPartCount; ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](int i, int j) { return parts[i].first_s < parts[j].first_s; });
  nlohmann::ordered_json how;
  how["parts"] = nlohmann::ordered_json::array();
  for (int k : order) {
    const PartFalls& p = parts[k];
    if (p.fallen == 0) continue;
    nlohmann::ordered_json part{{"part", part_name(static_cast<Part>(k))}, {"fallen", p.fallen}, {"first_fall_s", p.first_s}};
    for (int side = 0; side < 3; ++side) part["sides"][kSideNames[side]] = p.sides[side];
    how["parts"].push_back(part);
  }
  for (int way = 0; way < 4; ++way) how["toward"][kTowardNames[way]] = toward[way];
  return how;
}

RingHinges::RingHinges(const Model& m, const Joints& joints) {
  const int ring = static_cast<int>(Part::ring);
  int along = 0;  // voussoirs along the arc, springers included
  for (int b = 0; b < m.block_count; ++b)
    if (m.block_tag[b].part == ring) along = std::max(along, m.block_tag[b].course + 1);
  // A radial joint: two ring stones at neighbouring positions, over an area (three points or
  // more, not stones of neighbouring courses across the width touching along an edge). Its
  // section is its position (the joint's number along the arc) in its span: the spans'
  // sections at one position lie a span apart along x.
  struct Radial {
    int position;
    double x_m;
    int joint;
  };
  std::vector<Radial> radial;
  for (int j = 0; j < joints.size(); ++j) {
    const int a = joints.block_a[j], b = joints.block_b[j];
    if (m.block_tag[a].part != ring || m.block_tag[b].part != ring) continue;
    if (std::abs(m.block_tag[a].course - m.block_tag[b].course) != 1) continue;  // between courses across the width
    if (joints.point_begin[j + 1] - joints.point_begin[j] < 3) continue;
    const Vec3 centre = m.initial_position[a] + m.initial_orientation[a] * joints.centre_on_a[j];
    radial.push_back({std::max(m.block_tag[a].course, m.block_tag[b].course), centre.x(), j});
  }
  std::sort(radial.begin(), radial.end(),
            [](const Radial& p, const Radial& q) { return p.position != q.position ? p.position < q.position : p.x_m < q.x_m; });
  for (std::size_t k = 0; k < radial.size(); ++k) {
    const Radial& r = radial[k];
    const bool same_position = k > 0 && r.position == radial[k - 1].position;
    if (!same_position || r.x_m - radial[k - 1].x_m > 0.1) {
      const int a = joints.block_a[r.joint];
      // A radial joint's normal is the arc's tangent, (cos a, 0, -sin a) at angle a from the
      // crown: |a| from its x, the side from its position (joints before the middle one lie
      // toward -x, geometry/arch_ring.h's RingGeometry::joint); its depth runs across the
      // normal in the x-z plane.
      const Vec3 n = m.initial_orientation[a] * joints.normal_on_a[r.joint];
      const double in_plane = std::max(std::hypot(n.x(), n.z()), 1e-300);
      Section section;
      section.span = same_position ? sections_.back().span + 1 : 0;
      section.position = r.position;
      section.angle_deg = ((2 * r.position > along) - (2 * r.position < along)) *
                          std::acos(std::min(1.0, std::abs(n.x()) / in_plane)) * 180 / std::numbers::pi;
      const Vec3 across = m.initial_orientation[a].inverse() * Vec3(-n.z() / in_plane, 0, n.x() / in_plane);
      double lo = INFINITY, hi = -INFINITY;
      for (int q = joints.point_begin[r.joint]; q < joints.point_begin[r.joint + 1]; ++q) {
        lo = std::min(lo, joints.point_on_a[q].dot(across));
        hi = std::max(hi, joints.point_on_a[q].dot(across));
      }
      section.depth_m = hi - lo;
      sections_.push_back(section);
    }
    sections_.back().joints.push_back(r.joint);
  }
  // Along each span's arc, so that a section's neighbours come before and after it.
  std::stable_sort(sections_.begin(), sections_.end(),
                   [](const Section& p, const Section& q) { return p.span != q.span ? p.span < q.span : p.position < q.position; });
}

int RingHinges::note(const Joints& joints, double time_s, bool ring_stone_fell) {
  const std::size_t n = sections_.size();
  std::vector<double> opening(n);  // (sections) the median over the width, m
  std::vector<double> of_joints;
  for (std::size_t k = 0; k < n; ++k) {
    of_joints.clear();
    for (int j : sections_[k].joints) of_joints.push_back(joints.opening_m[j]);
    std::nth_element(of_joints.begin(), of_joints.begin() + of_joints.size() / 2, of_joints.end());
    opening[k] = of_joints[of_joints.size() / 2];
  }
  auto neighbours = [&](std::size_t k, std::size_t l) {
    return sections_[k].span == sections_[l].span && std::abs(sections_[k].position - sections_[l].position) == 1;
  };
  std::vector<double> angles;
  for (std::size_t k = 0; k < n; ++k) {
    if (opening[k] < kHingeRotationRad * sections_[k].depth_m) continue;
    if (k > 0 && neighbours(k, k - 1) && opening[k - 1] >= opening[k]) continue;  // ties: the first along the arc
    if (k + 1 < n && neighbours(k, k + 1) && opening[k + 1] > opening[k]) continue;
    angles.push_back(sections_[k].angle_deg);
  }
  const int hinged = static_cast<int>(angles.size());
  if (ring_stone_fell || hinged == 0) return hinged;
  if (first_s_ < 0) first_s_ = time_s;
  if (hinged > most_) most_ = hinged, most_at_s_ = time_s, most_angles_deg_ = angles;
  return hinged;
}

nlohmann::ordered_json RingHinges::summary(double settle_time_s) const {
  if (sections_.empty()) return nullptr;
  nlohmann::ordered_json h;
  h["sections"] = sections_.size();
  std::size_t radial = 0;
  for (const Section& section : sections_) radial += section.joints.size();
  h["joints"] = radial;
  h["rotation_rad"] = kHingeRotationRad;
  h["first_s"] = first_s_ < 0 ? nlohmann::ordered_json() : nlohmann::ordered_json(first_s_ - settle_time_s);
  h["most"] = most_;
  h["most_at_s"] = most_ == 0 ? nlohmann::ordered_json() : nlohmann::ordered_json(most_at_s_ - settle_time_s);
  h["angles_deg"] = most_angles_deg_;
  return h;
}

nlohmann::ordered_json how_it_fails(const Model& m, const FallRecord& falls, const RingHinges& hinges, double settle_time_s) {
  nlohmann::ordered_json how = falls.summary(m, settle_time_s);
  how["ring_hinges"] = hinges.summary(settle_time_s);
  how["text"] = how_it_fails_text(how);
  return how;
}

namespace {

// The ring hinges' clause of the sentence: "; ring hinges from ..." or "; no ring joint hinged";
// empty for a model without ring sections.
std::string ring_hinges_text(const nlohmann::ordered_json& how) {
  if (!how.contains("ring_hinges") || how["ring_hinges"].is_null()) return "";
  const nlohmann::ordered_json& h = how["ring_hinges"];
  const int most = h["most"].get<int>();
  if (most == 0) return "; no ring joint hinged";
  std::string angles;
  const auto& list = h["angles_deg"];
  for (std::size_t k = 0; k < list.size(); ++k) {
    angles += k == 0 ? "" : k + 1 == list.size() ? " and " : ", ";
    angles += std::to_string(std::lround(list[k].get<double>()));
  }
  bool ring_fell = false;
  for (const auto& p : how["parts"]) ring_fell |= p["part"] == "ring";
  std::string first = seconds(h["first_s"].get<double>()), at = seconds(h["most_at_s"].get<double>());
  if (at.rfind("from ", 0) == 0) at.erase(0, 5);  // "4.40 s of shaking"
  return "; ring hinges " + first + ", at most " + std::to_string(most) + " at once (at " + angles +
         " degrees from the crown, " + at + ")" + (ring_fell ? " before its first stone fell" : "");
}

}  // namespace

std::string how_it_fails_text(const nlohmann::ordered_json& how) {
  const nlohmann::ordered_json& parts = how["parts"];
  if (parts.empty()) return "no stone fell" + ring_hinges_text(how);
  std::string text;
  int all = 0;
  for (const auto& p : parts) {
    const int fallen = p["fallen"].get<int>();
    all += fallen;
    text += text.empty() ? "" : (&p == &parts.back() ? ", then " : ", ");
    text += part_stones(p["part"].get<std::string>()) + " " + seconds(p["first_fall_s"].get<double>()) + " (" +
            std::to_string(fallen);
    // A part that lost its stones mostly on one side of the bridge (one spandrel wall): say which.
    for (const char* side : {"-y", "+y"})
      if (const int n = p["sides"][side].get<int>(); fallen >= 2 && n >= 0.8 * fallen)
        text += ", " + std::to_string(n) + " of them on the " + side + " side";
    text += ")";
  }
  // Which way they went: across the bridge (+-y, out of plane) or along the span (+-x, in plane).
  const auto& t = how["toward"];
  auto way = [&](const char* plus, const char* minus, const char* where) {
    const int p = t[plus].get<int>(), n = t[minus].get<int>();
    return std::string("fell ") + where + ", " + std::to_string(std::max(p, n)) + " toward " + (p >= n ? plus : minus) + ")";
  };
  const int across = t["+y"].get<int>() + t["-y"].get<int>(), along = t["+x"].get<int>() + t["-x"].get<int>();
  const std::string across_text = way("+y", "-y", "across the bridge (out of plane");
  const std::string along_text = way("+x", "-x", "along the span (in plane");
  const std::string every = all == 1 ? "; it " : "; all " + std::to_string(all) + " ";
  if (across == all)
    text += every + across_text;
  else if (along == all)
    text += every + along_text;
  else
    text += "; of the " + std::to_string(all) + ", " + std::to_string(across) + " " + across_text + " and " +
            std::to_string(along) + " " + along_text;
  return text + ring_hinges_text(how);
}

std::string failure_mode_of(const nlohmann::ordered_json& how) {
  if (how["parts"].empty()) return "no stone fell";
  const nlohmann::ordered_json& t = how["toward"];
  const int across = t["+y"].get<int>() + t["-y"].get<int>(), along = t["+x"].get<int>() + t["-x"].get<int>();
  const char* way = 3 * across >= 2 * (across + along) ? "across" : 3 * along >= 2 * (across + along) ? "along" : "both ways";
  return how["parts"][0]["part"].get<std::string>() + " first (" + way + ")";
}

}  // namespace ishibashi
