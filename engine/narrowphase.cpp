// Narrowphase: the sub-contacts of every candidate pair for this step, in three stages
// (narrowphase.h): the separating-axis search, the manifold of each pair that touches, and
// the contact history passed on to it; then the arrays are regrouped when needed.
//
// Most pairs of a masonry structure barely move relative to each other from one step to
// the next: their sub-contacts are updated where they lie, and only pairs whose manifold
// is rebuilt go through per-chunk buffers. A pair that gains or loses sub-contacts gets a
// new range after the arrays' end, its old one left dead; the arrays are laid out densely
// anew only when the pair list changed or the dead entries reach 1/kDeadShare of the
// live ones. (A cracked bridge changes a handful of pairs' counts every other step: laying
// out every sub-contact anew each time, 8 MB read and written for model B, was a sixth
// of its step on one thread.)
#include <algorithm>
#include <array>
#include <cassert>
#include <cstdint>

#include "engine/narrowphase.h"
#include "engine/parallel.h"
#include "engine/pipeline.h"

namespace ishibashi {
namespace {

enum class Layout : std::uint8_t { unchanged = 0, regroup = 1 };

// Dense anew when the dead entries exceed this share of the live ones. A compaction
// copies every sub-contact; an appended pair costs the passes that walk the pairs a jump
// out of their stream (about twenty arrays). Model B cracked, one thread: 1/256 (a
// compaction of its 37,000 sub-contacts every few regroups) ran 3-10 % faster than 1/16.
constexpr int kDeadShare = 256;

// Every pair: searched, and its manifold rebuilt into its chunk's buffer (with history),
// or its sub-contacts updated in place. A rebuilt manifold with as many points as before
// goes straight on into the pair's own range (its history read from there first): as a
// loop of its own after this one, it ran in a third of model F's steps and in most of a
// cracked bridge's. The pairs whose counts changed are listed per chunk, their new
// sub-contacts from the buffer's start, in pair order. Returns how the layout changed.
Layout build_manifolds(const Model& m, State& s, bool first_detection, double dt_s, ContactLaw* law) {
  const int chunks = static_cast<int>(s.pair_chunk_begin.size()) - 1;
  s.chunk_contacts.resize(chunks);
  s.chunk_rebuilt.resize(chunks);
  std::array<double, kStageChunks> reclip_j{};  // J per chunk, added in chunk order: the same sum for any team
  parallel_ranges(s.pair_chunk_begin.data(), chunks, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    SubContacts& out = s.chunk_contacts[k];
    std::vector<int>& rebuilt = s.chunk_rebuilt[k];
    rebuilt.clear();
    int used = 0;  // out's entries in use; its arrays keep their size from step to step
                   // (resized for each pair, they took 3 % of a late step)
    double made_j = 0;  // by this chunk's re-clips
    thread_local Manifold manifold;  // one per thread, reused
    thread_local PairWorld world;
    for (std::ptrdiff_t pi = begin; pi < end; ++pi) {
      Pair& pair = s.pairs[pi];
      // An apart pair within its slack on the clock: its motion test would say no (its stones
      // could not have closed the gap). It has no sub-contacts, and its rebuilt_count is -1
      // since its last visit.
      if (pair.axis_kind == -1 && s.apart_clock_valid && s.apart_clock_m < pair.apart_until_clock_m) {
        assert(pair.sub_count == 0 && pair.rebuilt_count == -1 && apart_pair_unmoved(m, s, pair));
        continue;
      }
      pair.rebuilt_count = -1;
      if (!pair_manifold(m, s, pair, world, manifold)) {
        if (pair.sub_count > 0) update_in_place(s, pair);
        continue;
      }
      if (manifold.size() == pair.sub_count) {  // placed: its range is its own
        if (manifold.size() == 0) continue;
        made_j += append_rebuilt(m, s, pair, manifold, first_detection, dt_s, out, used);
        s.contacts.copy_range(out, used, manifold.size(), pair.sub_begin);
        continue;
      }
      pair.rebuilt_begin = used;
      pair.rebuilt_count = manifold.size();
      rebuilt.push_back(static_cast<int>(pi));
      made_j += append_rebuilt(m, s, pair, manifold, first_detection, dt_s, out, used);
      used += manifold.size();
    }
    reclip_j[k] = made_j;
    if (law && rebuilt.empty()) law->run_chunk(k);
  });
  for (int k = 0; k < chunks; ++k) s.energy.reclip_j += reclip_j[k];
  bool changed = s.pairs_changed;
  for (const std::vector<int>& rebuilt : s.chunk_rebuilt) changed |= !rebuilt.empty();
  s.pairs_changed = false;
  return changed ? Layout::regroup : Layout::unchanged;
}

// Rebuilt pairs (their counts changed: the others were placed) get new ranges after the
// arrays' end, each chunk's in pair order from its offset (the same layout for any team),
// and leave their old ranges dead.
void append_changed(State& s) {
  const int chunks = static_cast<int>(s.pair_chunk_begin.size()) - 1;
  std::array<int, kStageChunks + 1> chunk_at{};  // chunk k appends from chunk_at[k]
  std::array<int, kStageChunks> chunk_dead{};
  chunk_at[0] = static_cast<int>(s.contacts.size());
  for (int k = 0; k < chunks; ++k) {
    chunk_at[k + 1] = chunk_at[k];
    for (int pi : s.chunk_rebuilt[k]) chunk_at[k + 1] += s.pairs[pi].rebuilt_count;
  }
  s.contacts.resize(chunk_at[chunks]);
  parallel_ranges(s.pair_chunk_begin.data(), chunks, [&](std::ptrdiff_t, std::ptrdiff_t, int k) {
    int at = chunk_at[k], dead = 0;
    for (int pi : s.chunk_rebuilt[k]) {
      Pair& pair = s.pairs[pi];
      dead += pair.sub_count;
      pair.sub_begin = at;
      pair.sub_count = pair.rebuilt_count;
      at += pair.rebuilt_count;
      if (pair.rebuilt_count > 0) s.contacts.copy_range(s.chunk_contacts[k], pair.rebuilt_begin, pair.rebuilt_count, pair.sub_begin);
      pair.rebuilt_count = -1;  // placed: a compaction now keeps it where it is
    }
    chunk_dead[k] = dead;
  });
  for (int k = 0; k < chunks; ++k) s.contacts_dead += chunk_dead[k];
}

// The pair list changed, or the dead entries piled up: every pair's range is laid out anew
// in next_contacts, in pair order, rebuilt pairs from their chunk's buffer and the rest
// from the current arrays, which it then replaces. Each chunk counts its own pairs'
// sub-contacts, so only the chunks' offsets are summed by one thread.
void regroup(State& s) {
  const int chunks = static_cast<int>(s.pair_chunk_begin.size()) - 1;
  auto new_count = [](const Pair& pair) { return pair.rebuilt_count >= 0 ? pair.rebuilt_count : pair.sub_count; };
  std::array<int, kStageChunks + 1> chunk_begin{};  // chunk k's new range starts at chunk_begin[k]
  parallel_ranges(s.pair_chunk_begin.data(), chunks, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    int count = 0;
    for (std::ptrdiff_t pi = begin; pi < end; ++pi) count += new_count(s.pairs[pi]);
    chunk_begin[k + 1] = count;
  });
  for (int k = 0; k < chunks; ++k) chunk_begin[k + 1] += chunk_begin[k];
  s.next_contacts.resize(chunk_begin[chunks]);
  parallel_ranges(s.pair_chunk_begin.data(), chunks, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    // Runs of pairs that kept their sub-contacts and lie one after the other: one copy
    // per run, not one per pair.
    int run_from = 0, run_to = 0, run_count = 0;
    auto flush = [&] {
      if (run_count > 0) s.next_contacts.copy_range(s.contacts, run_from, run_count, run_to);
      run_count = 0;
    };
    int at = chunk_begin[k];
    for (std::ptrdiff_t pi = begin; pi < end; ++pi) {
      Pair& pair = s.pairs[pi];
      const int count = new_count(pair);
      if (pair.rebuilt_count >= 0) {
        flush();
        s.next_contacts.copy_range(s.chunk_contacts[k], pair.rebuilt_begin, pair.rebuilt_count, at);
        pair.sub_count = pair.rebuilt_count;
      } else if (pair.sub_count > 0) {
        if (run_count > 0 && pair.sub_begin != run_from + run_count) flush();  // after a dead range, or appended
        if (run_count == 0) run_from = pair.sub_begin, run_to = at;
        run_count += pair.sub_count;
      }
      pair.sub_begin = at;
      at += count;
    }
    flush();
  });
  std::swap(s.contacts, s.next_contacts);
  s.contacts_dead = 0;
}

// The layout mended where pairs changed their counts (Layout::regroup).
void mend_layout(State& s, bool pair_list_changed) {
  ++s.profile.contact_regroups;
  if (pair_list_changed) return regroup(s);
  append_changed(s);
  if (std::int64_t{s.contacts_dead} * kDeadShare > sub_contact_count(s)) regroup(s);  // nothing rebuilt left: a compaction
}

}  // namespace

void compact_contacts(const Model& m, State& s) {
  if (s.contacts_dead == 0) return;
  if (!s.pair_index_valid) update_pair_index(m, s);
  for (Pair& pair : s.pairs) pair.rebuilt_count = -1;  // every pair kept where it lies
  regroup(s);
}

void update_contacts(const Model& m, State& s, bool first_detection, double dt_s, ContactLaw* law) {
  if (!s.pair_index_valid) update_pair_index(m, s);  // the pair list changed: its chunks
  const bool pair_list_changed = s.pairs_changed;
  const Layout layout = build_manifolds(m, s, first_detection, dt_s, law);
  s.step_motion_read = true;  // the pairs' bounds have taken the blocks' motions in
  if (layout == Layout::unchanged) return;  // every pair updated or rebuilt in place (or still apart)
  mend_layout(s, pair_list_changed);
  // The chunks with a pair of a new count: their law on its new range. (A regroup moved
  // the others' sub-contacts with what their law wrote.)
  if (law)
    parallel_ranges(s.pair_chunk_begin.data(), static_cast<int>(s.chunk_rebuilt.size()),
                    [&](std::ptrdiff_t, std::ptrdiff_t, int k) {
                      if (!s.chunk_rebuilt[k].empty()) law->run_chunk(k);
                    });
}

}  // namespace ishibashi
