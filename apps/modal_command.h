// `ishibashi modal <model or scenario file>`: natural frequencies by modal analysis of
// the bonded (linear) assembly, with effective modal masses and mode shapes for ParaView.
#pragma once
#include <filesystem>

namespace ishibashi {

struct ModalOptions {
  std::filesystem::path file;  // a model file, or a scenario file naming one
  std::filesystem::path out;   // empty: out/<name>_modal
  int modes = 12;
  double impulse_s = 0.0;      // > 0: also impulse responses of this length in x, y, z
};

int run_modal(const ModalOptions& options);

}  // namespace ishibashi
