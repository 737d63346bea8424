// How far the explicit step's limit spreads over the stones: for each scenario's model at
// its first contact detection, every free block's own stable dt (stability.cpp, the
// study's dashpots), and what a step chosen per block (multi-rate stepping, each block
// at its own limit) could gain over one step for all at the smallest limit.
// Usage: step_limits SCENARIO.toml...   (one CSV row per scenario)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/model/compile_model.h"
#include "engine/pipeline.h"
#include "engine/world.h"

using namespace ishibashi;

namespace {

// The q-quantile (0-1) of sorted values.
double quantile(const std::vector<double>& sorted, double q) {
  return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
}

void report(const char* file) {
  const LoadedModel loaded = load_model_or_scenario(file);
  ModelOptions options = loaded.options();
  options.drive_fixed_blocks = true;  // as a seismic run builds it
  const World world(loaded.build(options), 1e-9);
  const Model& m = world.model();
  std::vector<double> damped;  // s, each free block that touches another
  int rocking = 0;             // blocks whose limit is set by a rotation
  for (const BlockLimit& limit : block_stability_limits(m, world.state(), /*with_damping=*/true)) {
    if (!std::isfinite(limit.dt_s)) continue;
    damped.push_back(limit.dt_s);
    rocking += limit.dof >= 3;
  }
  if (damped.empty()) throw std::runtime_error(std::string(file) + ": no free block touches another, so nothing limits the step");
  std::sort(damped.begin(), damped.end());
  double springs_min = INFINITY;  // the same without dashpots
  for (const BlockLimit& limit : block_stability_limits(m, world.state(), /*with_damping=*/false))
    springs_min = std::min(springs_min, limit.dt_s);
  // Steps of all blocks per simulated second: n / min at one step, sum 1 / dt_b per block.
  double per_block_rate = 0.0;
  for (double dt : damped) per_block_rate += 1.0 / dt;
  const double uniform_rate = static_cast<double>(damped.size()) / damped.front();
  const auto within = std::upper_bound(damped.begin(), damped.end(), 1.25 * damped.front()) - damped.begin();
  std::printf("%s,%zu,%.3g,%.3g,%.3g,%.3g,%.3f,%.3f,%.3g,%.2f\n", loaded.name.c_str(), damped.size(), damped.front(),
              quantile(damped, 0.1), quantile(damped, 0.5), quantile(damped, 0.9),
              static_cast<double>(within) / static_cast<double>(damped.size()),
              static_cast<double>(rocking) / static_cast<double>(damped.size()), springs_min,
              uniform_rate / per_block_rate);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: step_limits SCENARIO.toml...\n");
    return 2;
  }
  std::printf("model,free_blocks,limit_min_s,limit_q10_s,limit_median_s,limit_q90_s,share_within_1.25_of_min,"
              "share_set_by_rotation,springs_only_min_s,multirate_gain_bound\n");
  try {
    for (int i = 1; i < argc; ++i) report(argv[i]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "step_limits: %s\n", e.what());
    return 1;
  }
}
