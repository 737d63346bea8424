// `ishibashi modal <model or scenario file>`: natural frequencies by modal analysis of
// the bonded (linear) assembly, with effective modal masses and mode shapes for ParaView.
#pragma once
#include <filesystem>

namespace ishibashi {

struct ModalOptions {
  std::filesystem::path file;  // a model file, or a scenario file naming one
  std::filesystem::path out;   // empty: out/<name>_modal
  int modes = 12;
};

int run_modal(const ModalOptions& options);

}  // namespace ishibashi
