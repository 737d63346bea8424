#include "analysis/load.h"

#include <cstdio>

#include "geometry/block_files.h"
#include "io/scenario_file.h"

namespace ishibashi {

std::vector<BridgeBlock> model_blocks(const ModelFile& file, const std::filesystem::path& path) {
  std::vector<BridgeBlock> blocks;
  if (file.imported()) {
    for (const auto* list : {&file.import_files, &file.fixed_files})
      for (const auto& p : *list)
        for (const Polyhedron& shape : read_block_file(p))
          blocks.push_back(BridgeBlock{shape, Part::imported, 0, list == &file.fixed_files});
    return blocks;
  }
  try {
    return generate_bridge(file.bridge);
  } catch (const ModelError& e) {
    throw InputError(path.string() + ": " + e.what());
  }
}

ValidationReport validate_model_blocks(const std::vector<BridgeBlock>& blocks) {
  std::vector<Polyhedron> shapes;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    shapes.push_back(blocks[i].shape);
    names.push_back(std::string(part_name(blocks[i].part)) + "-" + std::to_string(i));
  }
  return validate_blocks(shapes, names);
}

ModelBuilder load_model_builder(const ModelFile& file, const std::filesystem::path& path) {
  std::vector<BridgeBlock> blocks = model_blocks(file, path);
  const ValidationReport report = validate_model_blocks(blocks);
  if (!report.ok()) {
    for (const std::string& e : report.errors) std::fprintf(stderr, "  error: %s\n", e.c_str());
    throw InputError(path.string() + ": the blocks failed validation (" + std::to_string(report.errors.size()) + " errors above)");
  }
  // Imported blocks reach the engine with coplanar triangles merged into one face each (a
  // face is a contact plane); only once validation has shown them convex.
  if (file.imported())
    for (BridgeBlock& b : blocks) b.shape = merged_faces(b.shape);
  return bridge_builder(file.bridge, blocks);
}

Model build_model(const ModelBuilder& builder, const ModelOptions& options, const std::filesystem::path& path) {
  try {
    return builder.build(options);
  } catch (const ModelError& e) {
    throw InputError(path.string() + ": " + e.what());
  }
}

LoadedModel load_model_or_scenario(const std::filesystem::path& file) {
  if (!is_scenario_file(file)) {
    const ModelFile model = read_model_file(file);
    return {model.name, file, load_model_builder(model, file), {}};
  }
  const Scenario sc = read_scenario(file);  // its model file, with the scenario's mortar
  ModelOptions options;
  options.subdivision = sc.subdivision;
  options.joint_rule = sc.joint_rule;
  options.shear_spring = sc.shear_spring;
  LoadedModel loaded{sc.model.name, file, load_model_builder(sc.model, sc.model_file), options};
  loaded.build();  // options checked now, with the scenario named
  return loaded;
}

}  // namespace ishibashi
