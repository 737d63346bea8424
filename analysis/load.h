// Models for the analyses: the blocks generated from a model file (or imported from block
// files), validated with CGAL and compiled for the engine.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "engine/model.h"
#include "geometry/bridge.h"
#include "geometry/validate.h"
#include "io/model_file.h"

namespace ishibashi {

// The blocks a model file describes, not yet validated. Throws InputError naming the file.
std::vector<BridgeBlock> model_blocks(const ModelFile& file, const std::filesystem::path& path);

// CGAL validation of the blocks: each sound and convex, no overlaps, joints on shared faces.
ValidationReport validate_model_blocks(const std::vector<BridgeBlock>& blocks);

// The blocks of a model file, validated and ready to build with an analysis's options;
// prints the validation errors and throws InputError when there are any.
ModelBuilder load_model_builder(const ModelFile& file, const std::filesystem::path& path);

// The Model of a model file with `options`; throws InputError naming the file when an
// option is out of range.
Model build_model(const ModelBuilder& builder, const ModelOptions& options, const std::filesystem::path& path);
inline Model load_model(const ModelFile& file, const std::filesystem::path& path, const ModelOptions& options = {}) {
  return build_model(load_model_builder(file, path), options, path);
}

// A model file, or a scenario file's model with the scenario's mortar and contact
// subdivision (in `options`): what the modal and impulse analyses of that file study.
struct LoadedModel {
  std::string name;
  std::filesystem::path file;
  ModelBuilder builder;
  ModelOptions options;
  Model build(const ModelOptions& with) const { return build_model(builder, with, file); }
  Model build() const { return build(options); }
};
LoadedModel load_model_or_scenario(const std::filesystem::path& file);

}  // namespace ishibashi
