// Narrowphase: the sub-contacts of every candidate pair for this step, in three stages
// (narrowphase.h): the separating-axis search, the manifold of each pair that touches, and
// the contact history passed on to it; then the arrays are regrouped when needed.
//
// Most pairs of a masonry structure barely move relative to each other from one step to
// the next: their sub-contacts are updated where they lie, and only pairs whose manifold
// is rebuilt go through per-chunk buffers. The arrays are regrouped only when a pair
// gains or loses sub-contacts or the pair list changed.
#include <algorithm>
#include <array>
#include <cstdint>

#include "engine/narrowphase.h"
#include "engine/parallel.h"
#include "engine/pipeline.h"

namespace ishibashi {
namespace {

enum class Layout : std::uint8_t { unchanged = 0, same = 1, regroup = 2 };

// Every pair: searched, and its manifold rebuilt into its chunk's buffer (with history),
// or its sub-contacts updated in place. Returns how the sub-contact layout changed.
Layout build_manifolds(const Model& m, State& s, bool first_detection, double dt_s) {
  const int chunks = static_cast<int>(s.pair_chunk_begin.size()) - 1;
  s.chunk_contacts.resize(chunks);
  s.chunk_regroup.assign(chunks, 0);
  parallel_ranges(s.pair_chunk_begin.data(), chunks, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    SubContacts& out = s.chunk_contacts[k];
    out.clear();
    thread_local Manifold manifold;  // one per thread, reused
    thread_local PairWorld world;
    for (std::ptrdiff_t pi = begin; pi < end; ++pi) {
      Pair& pair = s.pairs[pi];
      pair.rebuilt_count = -1;
      if (!pair_manifold(m, s, pair, world, manifold)) {
        if (pair.sub_count > 0) update_in_place(s, pair);
        continue;
      }
      pair.rebuilt_begin = static_cast<int>(out.size());
      pair.rebuilt_count = manifold.size();
      const Layout change = manifold.size() != pair.sub_count ? Layout::regroup
                            : manifold.size() > 0             ? Layout::same
                                                              : Layout::unchanged;
      s.chunk_regroup[k] = std::max(s.chunk_regroup[k], static_cast<std::uint8_t>(change));
      append_rebuilt(m, s, pair, manifold, first_detection, dt_s, out);
    }
  });
  std::uint8_t change = s.pairs_changed ? 2 : 0;
  for (std::uint8_t r : s.chunk_regroup) change = std::max(change, r);
  s.pairs_changed = false;
  return static_cast<Layout>(change);
}

// Same layout: rebuilt pairs overwrite their own ranges.
void overwrite_rebuilt(State& s) {
  parallel_ranges(s.pair_chunk_begin.data(), static_cast<int>(s.pair_chunk_begin.size()) - 1, [&](std::ptrdiff_t begin, std::ptrdiff_t end, int k) {
    for (std::ptrdiff_t pi = begin; pi < end; ++pi) {
      const Pair& pair = s.pairs[pi];
      if (pair.rebuilt_count > 0)
        s.contacts.copy_range(s.chunk_contacts[k], pair.rebuilt_begin, pair.rebuilt_count, pair.sub_begin);
    }
  });
}

// A pair gained or lost sub-contacts, or the pair list changed: every pair's range is laid
// out anew in next_contacts, rebuilt pairs from their chunk's buffer and the rest from the
// current arrays, which it then replaces. Each chunk counts its own pairs' sub-contacts,
// so only the chunks' offsets are summed by one thread (a regroup comes every other step
// of a cracked bridge: a serial pass over the pairs held the other threads up each time).
void regroup(State& s) {
  const int chunks = static_cast<int>(s.pair_chunk_begin.size()) - 1;
  ++s.profile.contact_regroups;
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
    // Runs of pairs that kept their sub-contacts are contiguous in both layouts: one
    // copy per run, not one per pair (a regroup typically changes a handful of pairs).
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
        if (run_count == 0) run_from = pair.sub_begin, run_to = at;
        run_count += pair.sub_count;
      }
      pair.sub_begin = at;
      at += count;
    }
    flush();
  });
  std::swap(s.contacts, s.next_contacts);
}

}  // namespace

void update_contacts(const Model& m, State& s, bool first_detection, double dt_s) {
  if (!s.pair_index_valid) update_pair_index(m, s);  // the pair list changed: its chunks
  switch (build_manifolds(m, s, first_detection, dt_s)) {
    case Layout::unchanged: return;  // every pair updated in place (or still apart)
    case Layout::same: return overwrite_rebuilt(s);
    case Layout::regroup: return regroup(s);
  }
}

}  // namespace ishibashi
