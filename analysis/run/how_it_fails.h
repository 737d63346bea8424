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

#include "engine/joints.h"
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

  // The falls in summary.json's "how_it_fails" (how_it_fails below): {"parts": [{"part",
  // "fallen", "first_fall_s" (seconds of shaking; negative: while settling), "sides": {"-y",
  // "middle", "+y"}}, ...] in the order their first stones fell, "toward": {"+x", "-x", "+y", "-y"}}.
  nlohmann::ordered_json summary(const Model& m, double settle_time_s) const;

  template <class Archive>
  void visit(Archive& a) {
    const std::size_t blocks = fell_at_s_.size();
    a.field(fell_at_s_), a.field(toward_);
    if constexpr (Archive::reading) check_read(blocks);
  }

 private:
  void check_read(std::size_t blocks) const;  // throws CheckpointError unless read for as many blocks
  std::vector<double> fell_at_s_;      // (nb) simulated time of the frame that first found it fallen; -1: standing
  std::vector<FallDirection> toward_;  // (nb)
};

// The ring's hinges, noted at the output frames. A section between neighbouring voussoirs
// along the arc (ring stones whose positions along it, BlockTag::course, differ by one) opens
// by the median over its radial joints across the width (engine/joints.h's opening: at the
// edge a hinge opens at). It is a hinge when that opening is at least kHingeRotationRad of
// the joint's depth (a relative rotation of the two sides: 6.4 mm for the study's 0.64 m
// ring) and more than its neighbours' along the arc: a shaken ring opens most of its joints
// by a millimetre or two, and a hinge's rotation spread over two joints is one hinge. Four
// hinges make an arch a mechanism (Heyman); the study tells its model A's collapse by them
// ("the ring in five parts, like an M, then it falls"). Counted until the first ring stone
// fell: after that, open sections are the ring in pieces, no longer a mechanism forming.
constexpr double kHingeRotationRad = 0.01;

class RingHinges {
 public:
  // The ring's sections among the joints found at the start (find_original_joints).
  RingHinges(const Model& m, const Joints& joints);

  // The hinges now, from the joints as measure_joints left them at simulated time time_s;
  // the record takes them while no ring stone has fallen.
  int note(const Joints& joints, double time_s, bool ring_stone_fell);

  // summary.json's "how_it_fails" "ring_hinges": {"sections", "joints" (radial, across the
  // width of all sections), "rotation_rad" (kHingeRotationRad), "first_s" (seconds of shaking,
  // null: none hinged), "most" (at once), "most_at_s", "angles_deg" (of those, from the crown
  // of their span: negative toward -x)}; null for a model without ring sections.
  nlohmann::ordered_json summary(double settle_time_s) const;
  // The most hinges at once so far (the result's most_ring_hinges); -1 for a model without
  // ring sections.
  int most() const { return sections_.empty() ? -1 : most_; }

  template <class Archive>
  void visit(Archive& a) {
    a.field(first_s_), a.field(most_), a.field(most_at_s_), a.field(most_angles_deg_);
  }

 private:
  struct Section {
    int span = 0, position = 0;  // the span's number from -x; the joint's along the arc (1 .. voussoirs - 1)
    double angle_deg = 0;        // of its radial joints from the crown
    double depth_m = 0;          // of its joints, radially
    std::vector<int> joints;     // across the width
  };
  std::vector<Section> sections_;
  double first_s_ = -1;                  // the first frame with a hinge; -1: none yet
  int most_ = 0;                         // the most hinged at one frame
  double most_at_s_ = -1;                // the first frame with that many
  std::vector<double> most_angles_deg_;  // (most_) their angles then
};

// summary.json's "how_it_fails": the falls (FallRecord::summary), "ring_hinges"
// (RingHinges::summary) and "text", the two in a sentence (how_it_fails_text).
nlohmann::ordered_json how_it_fails(const Model& m, const FallRecord& falls, const RingHinges& hinges, double settle_time_s);

// The sentence of a summary's "how_it_fails" (its "parts", "toward" and "ring_hinges"): "no stone fell", or
// for instance "wall stones from 5.20 s of shaking (180, 150 of them on the -y side), then
// ring stones from 5.40 s of shaking (83); of the 263, 215 fell across the bridge (out of
// plane, 190 toward -y) and 48 fell along the span (in plane, 28 toward -x)"; then, for a
// model with a ring, "; ring hinges from 4.20 s of shaking, at most 5 at once (at -85, -55, 0,
// 55 and 85 degrees from the crown, 4.40 s of shaking) before its first stone fell" or
// "; no ring joint hinged". A part's side is named where four in five of its fallen stones
// or more (at least two) stood on it.
std::string how_it_fails_text(const nlohmann::ordered_json& how);

// A run's failure in a few words, from a summary's how_it_fails (its "parts" and "toward"):
// "no stone fell", or the part whose stones fell first and the way most fell, "wall first
// (across)" (two thirds or more across the bridge), "ring first (along)" (two thirds or more
// along the span) or "fill first (both ways)". The result's failure_mode (a column of
// summary.json, runs.csv, sweep.csv and ensemble.csv: no commas), what ensembles count.
std::string failure_mode_of(const nlohmann::ordered_json& how);

}  // namespace ishibashi
