#include "analysis/run/run_result.h"

#include <cstdio>
#include <sstream>

namespace ishibashi {
namespace {
std::string hex(std::uint64_t hash) {
  char text[17];
  std::snprintf(text, sizeof text, "%llx", static_cast<unsigned long long>(hash));
  return text;
}
}  // namespace

const std::vector<ResultColumn>& result_columns() {
  using R = SeismicRunResult;
  static const std::vector<ResultColumn> columns = {
      {"interrupted", [](const R& r) -> OutputValue { return r.interrupted; }},
      {"settled", [](const R& r) -> OutputValue { return r.settled; }},
      {"settle_time_s", [](const R& r) -> OutputValue { return r.settle_time_s; }},
      {"shaking_time_s", [](const R& r) -> OutputValue { return r.shaking_time_s; }},
      {"first_opening_s", [](const R& r) -> OutputValue {
         if (r.first_opening_s < 0) return {};  // no joint opened
         return r.first_opening_s;
       }},
      {"bond_utilisation_peak", [](const R& r) -> OutputValue {
         if (r.bond_utilisation_peak < 0) return {};  // no bond (a dry model)
         return r.bond_utilisation_peak;
       }},
      {"collapse", [](const R& r) -> OutputValue { return r.collapse; }},
      {"fallen_stones", [](const R& r) -> OutputValue { return (long long)r.fallen_stones; }},
      {"fallen_ring_stones", [](const R& r) -> OutputValue { return (long long)r.fallen_ring_stones; }},
      {"blocks_left_model", [](const R& r) -> OutputValue { return (long long)r.blocks_left_model; }},
      {"failure_mode", [](const R& r) -> OutputValue {
         if (r.failure_mode.empty()) return {};
         return r.failure_mode;
       }},
      {"most_ring_hinges", [](const R& r) -> OutputValue {
         if (r.most_ring_hinges < 0) return {};  // no ring
         return (long long)r.most_ring_hinges;
       }},
      {"tie_rods", [](const R& r) -> OutputValue { return (long long)r.tie_rods; }},
      {"ties_yielded", [](const R& r) -> OutputValue {
         if (r.tie_rods == 0) return {};
         return (long long)r.ties_yielded;
       }},
      {"peak_tie_tension_n", [](const R& r) -> OutputValue {
         if (r.tie_rods == 0) return {};
         return r.peak_tie_tension_n;
       }},
      {"joints", [](const R& r) -> OutputValue { return (long long)r.joints; }},
      {"joints_cracked", [](const R& r) -> OutputValue { return (long long)r.joint_counts.cracked; }},
      {"joints_open_at_end", [](const R& r) -> OutputValue { return (long long)r.joint_counts.open; }},
      {"joints_slipped_at_end", [](const R& r) -> OutputValue { return (long long)r.joint_counts.slipped; }},
      {"joints_bond_broken_while_settling", [](const R& r) -> OutputValue { return (long long)r.bonds_broken_settling; }},
      {"largest_opening_m", [](const R& r) -> OutputValue { return r.joint_counts.largest_opening_m; }},
      {"largest_slip_m", [](const R& r) -> OutputValue { return r.joint_counts.largest_slip_m; }},
      {"largest_crown_drop_m", [](const R& r) -> OutputValue { return r.largest_crown_drop_m; }},
      {"energy_balance_error_j", [](const R& r) -> OutputValue { return r.balance_error_j; }},
      {"energy_balance_error_relative", [](const R& r) -> OutputValue { return r.balance_error_relative; }},
      {"energy_reclip_j", [](const R& r) -> OutputValue { return r.reclip_j; }},
      {"energy_reclip_relative", [](const R& r) -> OutputValue { return r.reclip_relative; }},
      {"steps", [](const R& r) -> OutputValue { return (long long)r.steps; }},
      {"state_hash", [](const R& r) -> OutputValue { return hex(r.state_hash); }},
      {"motion_hash", [](const R& r) -> OutputValue { return hex(r.motion_hash); }},
      {"wall_s", [](const R& r) -> OutputValue { return r.wall_s; }},
  };
  return columns;
}

std::string csv_field(const OutputValue& v) {
  std::ostringstream s;
  s.precision(9);
  if (const bool* flag = std::get_if<bool>(&v)) s << (*flag ? "yes" : "no");
  else if (const long long* count = std::get_if<long long>(&v)) s << *count;
  else if (const double* number = std::get_if<double>(&v)) s << *number;
  else if (const std::string* text = std::get_if<std::string>(&v)) s << *text;
  return s.str();
}

std::string result_csv_header() {
  std::string header;
  for (const ResultColumn& c : result_columns()) {
    if (!header.empty()) header += ',';
    header += c.name;
  }
  return header;
}

std::string result_csv_values(const SeismicRunResult& r) {
  std::string row;
  for (const ResultColumn& c : result_columns()) {
    if (&c != &result_columns().front()) row += ',';
    row += csv_field(c.value(r));
  }
  return row;
}

}  // namespace ishibashi
