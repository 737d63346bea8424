// The demo command: a masonry wall on a shaking or tilting base, written for ParaView.
#pragma once
#include <filesystem>
#include <string>

namespace ishibashi {

struct DemoOptions {
  std::string scene = "shake";   // "shake" or "tilt"
  std::filesystem::path out = "out/demo";
  double duration_s = 4.0;
  double frames_per_s = 25.0;
  double dt_s = 1e-5;  // below the damped stability limit of these stones (1.3e-5 s)
  int courses = 6, stones_per_course = 5;
};

// Runs the demo and prints a summary; returns the process exit code.
int run_demo(const DemoOptions& options);

}  // namespace ishibashi
