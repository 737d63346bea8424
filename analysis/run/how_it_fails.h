// How a run's bridge fails, told from its fallen stones: which parts lose stones and from
// when, on which side of the bridge, and which way they fall (across the bridge: out of
// plane; along the span: in plane). The study describes its bridges' collapses in these
// terms ("walls twist out of plane, stones of one side's wall fall from 5.2 s, no ring
// stone falls"), so a run's summary.json and its last lines give them beside the counts.
// Axes: x along the span, y across the bridge (geometry/bridge.h).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "engine/model.h"
#include "engine/state.h"

namespace ishibashi {

// Which way a fallen stone went: the larger horizontal component of its displacement
// relative to the ground at the frame that first found it fallen.
enum class FallDirection : std::uint8_t { none, plus_x, minus_x, plus_y, minus_y };

// Each stone's fall, noted at the output frames (the run's resolution of its first_fall).
class FallRecord {
 public:
  explicit FallRecord(int block_count) : fell_at_s_(block_count, -1.0), toward_(block_count, FallDirection::none) {}

  // Notes the stones found fallen (engine/state.h, is_fallen) for the first time at this
  // frame: the simulated time and which way they went relative to the ground, displaced gd.
  void note(const Model& m, const State& s, const Vec3& ground_displacement_m);

  // summary.json's "how_it_fails": {"parts": [{"part", "fallen", "first_fall_s" (seconds of
  // shaking; negative: while settling), "sides": {"-y", "middle", "+y"}}, ...] in the order
  // their first stones fell, "toward": {"+x", "-x", "+y", "-y"}, "text": the same in a sentence}.
  nlohmann::ordered_json summary(const Model& m, double settle_time_s) const;

  template <class Archive>
  void visit(Archive& a) {
    a.field(fell_at_s_), a.field(toward_);
  }

 private:
  std::vector<double> fell_at_s_;      // (nb) simulated time of the frame that first found it fallen; -1: standing
  std::vector<FallDirection> toward_;  // (nb)
};

// The sentence of a summary's "how_it_fails" (its "parts" and "toward"): "no stone fell", or
// for instance "wall stones from 5.20 s of shaking (180, 150 of them on the -y side), then
// ring stones from 5.40 s of shaking (83); of the 263, 215 fell across the bridge (out of
// plane, 190 toward -y) and 48 fell along the span (in plane, 28 toward -x)".
std::string how_it_fails_text(const nlohmann::ordered_json& how);

// A run's failure in a few words, from a summary's how_it_fails (its "parts" and "toward"):
// "no stone fell", or the part whose stones fell first and the way most fell, "wall first
// (across)" (two thirds or more across the bridge), "ring first (along)" (two thirds or more
// along the span) or "fill first (both ways)". The result's failure_mode (a column of
// summary.json, runs.csv, sweep.csv and ensemble.csv: no commas), what ensembles count.
std::string failure_mode_of(const nlohmann::ordered_json& how);

}  // namespace ishibashi
