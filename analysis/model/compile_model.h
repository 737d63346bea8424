// Models for the analyses, compiled in one place (compile_model): the blocks generated from
// a model file (or imported from block files), validated with CGAL and built for the engine.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "engine/model.h"
#include "geometry/bridge.h"
#include "geometry/validate.h"
#include "io/model_file.h"
#include "io/run_settings.h"
#include "io/scenario_file.h"

namespace ishibashi {

// A model file compiled for the engine: its blocks, their validation (each block sound and
// convex, no overlaps, joints on shared faces) and, when they pass, the builder (to build
// again with other options) and the Model with the options asked for.
struct CompiledModel {
  std::vector<BridgeBlock> blocks;  // imported ones with coplanar triangles merged once shown convex
  ValidationReport validation;
  std::vector<TieSpec> ties;        // [[tie]] then each [[tie_row]]'s rods, placed
  ModelBuilder builder;             // empty when validation failed
  Model model;                      // empty when validation failed
};

// Throws InputError naming the file for blocks that cannot be made or an option out of
// range; blocks that fail validation are in the result (validation.ok() false).
CompiledModel compile_model(const ModelFile& file, const std::filesystem::path& path, const ModelOptions& options);

// A [[tie_row]]'s rods: the anchors of the one at x lie row.inset_m inside the outermost
// faces of the free blocks met by the line across the width (along y) at x and row.z_m.
// Throws InputError naming `path`, the row's line and the rod for a line that meets no free
// block or whose stretch in the masonry is not longer than two insets.
std::vector<TieSpec> tie_row_rods(const TieRowSpec& row, const std::vector<BridgeBlock>& blocks, const std::filesystem::path& path);

// compile_model's Model; prints the validation errors and throws InputError when there are any.
Model load_model(const ModelFile& file, const std::filesystem::path& path, const ModelOptions& options);

// A model file, or a scenario file's model with the scenario's mortar, compiled with the
// joints' settings (subdivision, joint rule, shear spring: in `options`) of the scenario and
// of `overrides`: what the modal and impulse analyses of that file study.
struct LoadedModel {
  std::string name;
  std::filesystem::path file;
  CompiledModel compiled;
  const Model& model() const { return compiled.model; }
  const ModelOptions& options() const { return compiled.model.options; }
  Model build(const ModelOptions& with) const;  // the same blocks with other options
};
LoadedModel load_model_or_scenario(const std::filesystem::path& file, const RunOverrides& overrides = {});
LoadedModel load_scenario_model(const Scenario& scenario, const RunOverrides& overrides = {});

}  // namespace ishibashi
