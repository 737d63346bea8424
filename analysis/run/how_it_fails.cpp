#include "analysis/run/how_it_fails.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

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
  how["text"] = how_it_fails_text(how);
  return how;
}

std::string how_it_fails_text(const nlohmann::ordered_json& how) {
  const nlohmann::ordered_json& parts = how["parts"];
  if (parts.empty()) return "no stone fell";
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
  if (across == all) return text + every + across_text;
  if (along == all) return text + every + along_text;
  text += "; of the " + std::to_string(all) + ", " + std::to_string(across) + " " + across_text + " and " +
          std::to_string(along) + " " + along_text;
  return text;
}

std::string failure_mode_of(const nlohmann::ordered_json& how) {
  if (how["parts"].empty()) return "no stone fell";
  const nlohmann::ordered_json& t = how["toward"];
  const int across = t["+y"].get<int>() + t["-y"].get<int>(), along = t["+x"].get<int>() + t["-x"].get<int>();
  const char* way = 3 * across >= 2 * (across + along) ? "across" : 3 * along >= 2 * (across + along) ? "along" : "both ways";
  return how["parts"][0]["part"].get<std::string>() + " first (" + way + ")";
}

}  // namespace ishibashi
