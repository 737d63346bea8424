// `ishibashi modal <model or scenario file>`: natural frequencies by modal analysis of
// the bonded (linear) assembly, with effective modal masses and mode shapes for ParaView,
// and optionally impulse responses with every spectral peak.
#pragma once
#include <filesystem>
#include <string>

#include "io/run_settings.h"

namespace ishibashi {

struct ModalOptions {
  std::filesystem::path file;  // a model file, or a scenario file naming one (its subdivision and mortar apply)
  std::filesystem::path out;   // empty: out/<name>_modal
  int modes = 12;
  double impulse_s = 0.0;      // > 0: also impulse responses of this length
  std::string excite;          // "x", "y" or "z": one impulse along this axis; empty: x, y and z
  std::string read;            // the component read ("x", "y", "z"); empty: the excitation's
  int block = -1;              // the monitored block; -1: the unit on top of the crown
  RunOverrides overrides;      // --subdivision, --joint-rule, --shear-spring: replace the scenario's (a model file's defaults)
};

int run_modal(const ModalOptions& options);

}  // namespace ishibashi
