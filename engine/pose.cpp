#include <array>
#include <cmath>
#include <limits>

#include "engine/parallel.h"
#include "engine/pipeline.h"

namespace ishibashi {
namespace {

// An upper bound on the angle (rad) between two orientations whose unit quaternions lie
// `chord` apart (4-d distance, the same sign): the angle is 4 asin(chord / 2), and asin(h)
// <= h (1 + h^2) for h <= 1/4. The difference keeps a tiny turn's digits, which 1 - the
// dot product of the two would cancel.
double turn_bound_rad(double chord) {
  if (!(chord <= 0.5)) return std::numeric_limits<double>::infinity();
  return 2.0 * chord * (1.0 + 0.25 * chord * chord) * (1.0 + 1e-12);
}

// Block b's rotation matrix and world-frame face planes, and how it moved since the last
// pose: added to what it moved before when no narrowphase has read that yet (`add`).
void pose_only(const Model& m, State& s, std::ptrdiff_t b, bool add) {
  const Mat3 r = s.rotation[b] = s.orientation[b].toRotationMatrix();
  const Vec3& x = s.position[b];
  const Vec3 shift = x - s.position_at_pose[b];
  const double turn = turn_bound_rad((s.orientation[b].coeffs() - s.orientation_at_pose[b].coeffs()).norm());
  s.step_shift[b] = add ? s.step_shift[b] + shift : shift;
  s.step_turn[b] = add ? s.step_turn[b] + turn : turn;
  s.position_at_pose[b] = x;
  s.orientation_at_pose[b] = s.orientation[b];
  for (int f = m.face_begin[b]; f < m.face_begin[b + 1]; ++f) {
    s.face_normal_world[f] = r * m.face_normal_local[f];
    s.face_offset_world[f] = m.face_offset_local[f] + s.face_normal_world[f].dot(x);
  }
}

// The apart pairs' clock moves on by a bound on any pair's step motion: b's shift relative
// to a's, |shift_b - shift_a|_1, is at most the spread's sum over the axes, and the turns
// move b's points relative to a by at most turn (lever + 2 r_b) (separating_axis.cpp,
// moved_at_least), within Model::apart_lever_bound_m. Padded as each pair's own bound is.
void advance_apart_clock(const Model& m, State& s, const PoseChunk& spread) {
  const double step = (spread.shift_hi - spread.shift_lo).sum() + spread.turn * m.apart_lever_bound_m;
  s.apart_clock_valid = std::isfinite(step);
  if (!s.apart_clock_valid) return;  // a turn not known (the first pose, a restore): none skipped
  s.apart_clock_step_m = step * (1.0 + 1e-12) + 1e-13;
  s.apart_clock_m += s.apart_clock_step_m;
}

}  // namespace

bool begin_pose(State& s) {
  const bool add = !s.step_motion_read;
  s.step_motion_read = false;
  return add;
}

void pose_block(const Model& m, State& s, std::ptrdiff_t b, bool add, PoseChunk& chunk) {
  pose_only(m, s, b, add);
  if (!s.pairs_valid) return;  // no list to check against: it is built next
  chunk.moved = chunk.moved || moved_half_margin(m, s, static_cast<int>(b));
  chunk.shift_lo = chunk.shift_lo.cwiseMin(s.step_shift[b]);
  chunk.shift_hi = chunk.shift_hi.cwiseMax(s.step_shift[b]);
  chunk.turn = std::max(chunk.turn, s.step_turn[b]);
}

bool finish_pose(const Model& m, State& s, const PoseChunk* chunks, int chunk_count) {
  if (!s.pairs_valid) {
    s.apart_clock_valid = false;
    return true;
  }
  // Minima, maxima and "any": the same whichever thread ran which chunk.
  PoseChunk all;
  for (int k = 0; k < chunk_count; ++k) {
    all.moved = all.moved || chunks[k].moved;
    all.shift_lo = all.shift_lo.cwiseMin(chunks[k].shift_lo);
    all.shift_hi = all.shift_hi.cwiseMax(chunks[k].shift_hi);
    all.turn = std::max(all.turn, chunks[k].turn);
  }
  advance_apart_clock(m, s, all);
  return all.moved;
}

bool update_pose(const Model& m, State& s) {
  // The broadphase's check rides on this pass over the blocks: as a loop of its own it
  // cost more to post to a team than its 3 ns a block (model F on 16 threads: 9 us a
  // step, against 6.7 on one thread).
  const bool add = begin_pose(s);
  std::array<PoseChunk, kStageChunks> chunks;
  const int count = stage_chunks(m.block_count);
  parallel_chunks(m.block_count, count, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    PoseChunk chunk;  // written once: the chunks' records share cache lines
    for (std::ptrdiff_t b = begin; b < end; ++b) pose_block(m, s, b, add, chunk);
    chunks[k] = chunk;
  });
  return finish_pose(m, s, chunks.data(), count);
}

}  // namespace ishibashi
