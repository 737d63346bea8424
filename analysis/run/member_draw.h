// An ensemble member's draws (analysis/batch/ensemble.h runs the ensembles): what a real
// bridge is uncertain about, drawn reproducibly from the scenario's [ensemble] seed and the
// member's index with a fully specified generator (SplitMix64): the stones' fit and
// placement within a construction tolerance, and as options the joints' friction angle
// and the record's amplitude.
#pragma once
#include <cstdint>

#include "engine/model.h"
#include "io/scenario_file.h"

namespace ishibashi {

// SplitMix64's finaliser: each bit of x moves about half the bits of the result.
inline std::uint64_t splitmix_mixed(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// SplitMix64 (Steele, Lea and Flood 2014): a fully specified generator, so that a member's
// draws are the same with every compiler and library (the standard's distributions are
// not specified to the bit). One stream per (seed, member, purpose).
class DrawStream {
 public:
  DrawStream(long seed, int member, std::uint64_t purpose)
      : state_(static_cast<std::uint64_t>(seed) * 0x9E3779B97F4A7C15ull ^ (static_cast<std::uint64_t>(member) + 1) * 0xD1B54A32D192ED03ull ^
               purpose * 0xBF58476D1CE4E5B9ull) {}
  std::uint64_t next() { return splitmix_mixed(state_ += 0x9E3779B97F4A7C15ull); }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double between(double lo, double hi) { return lo + (hi - lo) * uniform(); }

 private:
  std::uint64_t state_;
};
// The purposes of the streams (a member's draws, its stones' poses, a chaos probe's nudges).
constexpr std::uint64_t kMemberDraws = 1, kPoseDraws = 2, kProbeDraws = 3;

// What a member draws besides its stones' poses.
struct MemberDraw {
  int member = 0;
  double amplitude = 1;           // factor on the record
  double friction_angle_deg = 0;  // every joint's; 0: the materials' own
};
MemberDraw draw_member(const EnsembleSpec& spec, int member);

// Member `member`'s model, for a construction tolerance t (spec.position_tolerance_m): each
// free stone cut up to t smaller than drawn (scaled about its centroid so that its nearest
// face moves in by a drawn cut in [0, t]; mass and inertia kept), then placed up to t / 2
// off along each axis and turned about a random axis so that no point moves more than
// t / 2, as far as that overlaps no neighbour (an overlapping stone's shift and turn are
// halved, up to 8 times, then dropped): the joints open by up to about 2 t, and close
// under gravity as the bridge settles, each member's stones bearing on different corners.
// Every joint's friction angle is set to the draw's when the spec varies it. Fixed and
// driven blocks stay. The same (spec, member) gives the same model, bit for bit; t = 0
// the scenario's own. A stone's draws are keyed by where it stands (its centroid), not by
// its block number, so a model that lists its blocks in another order draws the same. Tie
// rods stay anchored where they were in their stones and are snug again (make_ties_snug).
void perturb_model(Model& model, const EnsembleSpec& spec, const MemberDraw& draw);

}  // namespace ishibashi
