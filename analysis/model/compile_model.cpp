#include "analysis/model/compile_model.h"

#include <algorithm>
#include <cstdio>
#include <mutex>
#include <sstream>

#include "geometry/block_files.h"
#include "geometry/line_through_blocks.h"

namespace ishibashi {
namespace {

// Free stones outside these sizes (m, a block's largest extent) are warned of: a masonry
// stone is centimetres to a few metres across.
constexpr double kSmallestPlausibleStone_m = 0.005, kLargestPlausibleStone_m = 20;

// A mesh drawn in millimetres (as CAD programs draw) and read as metres makes stones of
// hundreds of metres that stand and shake as plausibly as real ones: said once a process.
void warn_of_implausible_sizes(const std::vector<BridgeBlock>& blocks, const std::filesystem::path& path) {
  double largest = 0;
  for (const BridgeBlock& b : blocks) {
    if (b.fixed || b.shape.vertices.empty()) continue;  // a ground slab may be as large as it likes
    Vec3 lo = b.shape.vertices.front(), hi = lo;
    for (const Vec3& v : b.shape.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    largest = std::max(largest, (hi - lo).maxCoeff());
  }
  if (largest == 0 || (largest >= kSmallestPlausibleStone_m && largest <= kLargestPlausibleStone_m)) return;
  static std::once_flag warned;
  std::call_once(warned, [&] {
    std::fprintf(stderr, "warning: %s: its largest free block is %.3g m across; mesh coordinates are read as metres times "
                 "[import] scale: a mesh drawn in millimetres needs scale = 0.001, in centimetres 0.01%s\n",
                 path.c_str(), largest,
                 largest > kLargestPlausibleStone_m ? "; a ground slab or abutment that stays still goes in [import] fixed_files" : "");
  });
}

std::vector<BridgeBlock> model_blocks(const ModelFile& file, const std::filesystem::path& path) {
  std::vector<BridgeBlock> blocks;
  if (file.imported()) {
    for (const auto* list : {&file.import_files, &file.fixed_files})
      for (const auto& p : *list)
        for (Polyhedron& shape : read_block_file(p)) {
          for (Vec3& v : shape.vertices) v *= file.import_scale;
          blocks.push_back(BridgeBlock{std::move(shape), Part::imported, 0, list == &file.fixed_files});
        }
    warn_of_implausible_sizes(blocks, path);
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

Model build_model(const ModelBuilder& builder, const ModelOptions& options, const std::filesystem::path& path) {
  try {
    return builder.build(options);
  } catch (const ModelError& e) {
    throw InputError(path.string() + ": " + e.what());
  }
}

void require_valid(const CompiledModel& c, const std::filesystem::path& path) {
  if (c.validation.ok()) return;
  for (const std::string& e : c.validation.errors) std::fprintf(stderr, "  error: %s\n", e.c_str());
  throw InputError(path.string() + ": the blocks failed validation (" + std::to_string(c.validation.errors.size()) +
                   " errors above)");
}

// What a frequency analysis takes of a run's settings: the joints' geometry. It has no
// settling (its joints are bonded from the start) and no dashpot in its linear joints.
ModelOptions frequency_options(RunSettings settings, const RunOverrides& overrides) {
  apply_overrides(settings, overrides);
  ModelOptions options = model_options(settings);
  options.damping = Damping::study;
  options.bonds_when_settled = false;
  return options;
}

void add_ties(ModelBuilder& builder, const std::vector<TieSpec>& ties, const std::filesystem::path& path) {
  for (const TieSpec& tie : ties) try {
      builder.add_tie(tie.from, tie.to, tie.area_m2(), tie.young_pa, tie.yield_pa, tie.pretension_n);
    } catch (const ModelError& e) {
      throw InputError(path.string() + ":" + std::to_string(tie.line) + ": " + e.what());
    }
}

}  // namespace

std::vector<TieSpec> tie_row_rods(const TieRowSpec& row, const std::vector<BridgeBlock>& blocks, const std::filesystem::path& path) {
  std::vector<TieSpec> rods;
  for (const double x : row.x_m) {
    std::ostringstream where;
    where << path.string() << ":" << row.rod.line << ": [[tie_row]] rod at x = " << x << " m, z = " << row.z_m << " m: ";
    const auto extent = free_blocks_along_line(blocks, Vec3(x, 0, row.z_m), Vec3::UnitY());
    if (!extent) throw InputError(where.str() + "its line across the width meets no free stone");
    const auto [y0, y1] = *extent;
    if (y1 - y0 <= 2 * row.inset_m) {
      where << "the masonry it crosses is " << y1 - y0 << " m wide, not more than two insets (inset_m = " << row.inset_m << ")";
      throw InputError(where.str());
    }
    TieSpec rod = row.rod;
    rod.from = Vec3(x, y0 + row.inset_m, row.z_m);
    rod.to = Vec3(x, y1 - row.inset_m, row.z_m);
    rods.push_back(rod);
  }
  return rods;
}

CompiledModel compile_model(const ModelFile& file, const std::filesystem::path& path, const ModelOptions& options) {
  CompiledModel c;
  c.blocks = model_blocks(file, path);
  c.validation = validate_model_blocks(c.blocks);
  if (!c.validation.ok()) return c;
  // Imported blocks reach the engine with coplanar triangles merged into one face each (a
  // face is a contact plane); only once validation has shown them convex.
  if (file.imported())
    for (BridgeBlock& b : c.blocks) b.shape = merged_faces(b.shape);
  try {
    c.builder = bridge_builder(file.bridge, c.blocks);
  } catch (const ModelError& e) {
    throw InputError(path.string() + ": " + e.what());
  }
  c.ties = file.ties;
  for (const TieRowSpec& row : file.tie_rows)
    for (const TieSpec& rod : tie_row_rods(row, c.blocks, path)) c.ties.push_back(rod);
  add_ties(c.builder, c.ties, path);
  c.model = build_model(c.builder, options, path);
  return c;
}

Model load_model(const ModelFile& file, const std::filesystem::path& path, const ModelOptions& options) {
  CompiledModel c = compile_model(file, path, options);
  require_valid(c, path);
  return std::move(c.model);
}

Model LoadedModel::build(const ModelOptions& with) const { return build_model(compiled.builder, with, file); }

LoadedModel load_scenario_model(const Scenario& sc, const RunOverrides& overrides) {
  LoadedModel loaded{sc.model.name, sc.file, compile_model(sc.model, sc.model_file, frequency_options(sc.settings, overrides))};
  require_valid(loaded.compiled, sc.model_file);
  return loaded;
}

LoadedModel load_model_or_scenario(const std::filesystem::path& file, const RunOverrides& overrides) {
  if (is_scenario_file(file)) return load_scenario_model(read_scenario(file), overrides);
  const ModelFile model = read_model_file(file);
  LoadedModel loaded{model.name, file, compile_model(model, file, frequency_options(RunSettings{}, overrides))};
  require_valid(loaded.compiled, file);
  return loaded;
}

}  // namespace ishibashi
