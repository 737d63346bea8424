// `ishibashi build <model file>`: generate the bridge, validate it with CGAL, print a
// summary and write the initial model for ParaView.
#pragma once
#include <filesystem>
#include <string>

#include "io/run_settings.h"

namespace ishibashi {

struct BuildOptions {
  std::filesystem::path model_file;
  std::filesystem::path out = "out/build";
  std::filesystem::path export_file;  // optional: the blocks as .off or .obj
  RunOverrides overrides;  // --joint-rule, --subdivision, --shear-spring: the joints of the stability limit it prints
};

// Returns the exit code: 0 when the model is valid, 3 when validation found errors.
int run_build(const BuildOptions& options);

}  // namespace ishibashi
