// What a seismic run found, defined once: its fields (the list below, which the checkpoint
// visits) and the quantities its outputs give (result_columns: summary.json, and the study's
// runs.csv and a sweep's sweep.csv).
#pragma once
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "engine/joints.h"

namespace ishibashi {

// X(type, name, initial value): every field of SeismicRunResult.
#define ISHIBASHI_RUN_RESULT_FIELDS(X)                                                                     \
  X(bool, settled, false)              /* the kinetic energy fell below the scenario's threshold */       \
  X(bool, interrupted, false)          /* stopped by SIGINT/SIGTERM (outputs valid up to then) */          \
  X(bool, stopped_early, false)        /* ended at a frame where options.stop_when or stop_at said so */   \
  X(double, settle_time_s, 0)                                                                              \
  X(double, shaking_time_s, 0)         /* simulated after settling */                                      \
  X(double, first_opening_s, -1)       /* seconds of shaking until the first crack; -1: none */            \
  X(double, bond_utilisation_peak, -1) /* largest_bond_utilisation until the first crack; -1: no bond */    \
  X(double, largest_crown_drop_m, 0)   /* of the monitored block, relative to the ground */                \
  X(int, fallen_stones, 0)                                                                                 \
  X(int, fallen_ring_stones, 0)                                                                            \
  X(int, blocks_left_model, 0)                                                                             \
  X(bool, collapse, false)             /* a ring stone fell, or more than 5 % of the blocks */             \
  X(int, tie_rods, 0)                                                                                      \
  X(int, ties_yielded, 0)              /* rods with a plastic elongation */                                \
  X(double, peak_tie_tension_n, 0)     /* the largest tension any rod reached */                           \
  X(int, joints, 0)                                                                                        \
  X(int, bonds_broken_settling, 0)                                                                         \
  X(JointCounts, joint_counts, {})     /* at the end */                                                    \
  X(double, balance_error_j, 0)                                                                            \
  X(double, balance_error_relative, 0) /* of the energy exchanged */                                       \
  X(double, reclip_j, 0)               /* made by re-clipped pairs' springs (Energy::reclip_j) */          \
  X(double, reclip_relative, 0)        /* of the energy exchanged */                                       \
  X(long, steps, 0)                                                                                        \
  X(std::uint64_t, state_hash, 0)                                                                          \
  X(std::uint64_t, motion_hash, 0)     /* the blocks' part of state_hash (World::motion_hash) */         \
  X(double, wall_s, 0)                                                                                     \
  X(double, output_wall_s, 0)          /* of wall_s, recording frames: counts, ParaView files, history */ \
  X(std::string, failure_mode, "")     /* how_it_fails.h, failure_mode_of; empty before the first frame */ \
  X(int, most_ring_hinges, -1)         /* at once before a ring stone fell (RingHinges); -1: no ring */

struct SeismicRunResult {
#define ISHIBASHI_DECLARE_RESULT_FIELD(type, name, initial) type name = initial;
  ISHIBASHI_RUN_RESULT_FIELDS(ISHIBASHI_DECLARE_RESULT_FIELD)
#undef ISHIBASHI_DECLARE_RESULT_FIELD

  // Calls fn(field) for every field in the list's order (the checkpoint's).
  template <class Fn>
  void for_each_field(Fn&& fn) {
#define ISHIBASHI_VISIT_RESULT_FIELD(type, name, initial) fn(name);
    ISHIBASHI_RUN_RESULT_FIELDS(ISHIBASHI_VISIT_RESULT_FIELD)
#undef ISHIBASHI_VISIT_RESULT_FIELD
  }
};

// A quantity of the result as the outputs give it: nothing (JSON null, an empty CSV field),
// a flag, a count, a number or a text.
using OutputValue = std::variant<std::monostate, bool, long long, double, std::string>;

// The result's quantities, listed once (run_result.cpp): each name is summary.json's key
// and a table's column, its unit the name's suffix (_s, _m, _j; none: a count, a flag or a
// fraction). summary.json gives them all, in this order; the study's runs.csv and a sweep's
// sweep.csv put their own columns (which run, at what intensity) around them.
struct ResultColumn {
  const char* name;
  OutputValue (*value)(const SeismicRunResult& r);
};
const std::vector<ResultColumn>& result_columns();
std::string result_csv_header();  // "interrupted,settled,...,wall_s" (no newline)
std::string result_csv_values(const SeismicRunResult& r);
// A CSV field: empty for nothing, "yes"/"no" for a flag, 9 significant digits for a number.
std::string csv_field(const OutputValue& v);

}  // namespace ishibashi
