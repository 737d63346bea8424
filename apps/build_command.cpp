#include "apps/build_command.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "analysis/model/compile_model.h"
#include "engine/mass_properties.h"
#include "engine/world.h"
#include "geometry/block_files.h"
#include "geometry/bridge.h"
#include "geometry/validate.h"
#include "io/atomic_file.h"
#include "io/model_file.h"
#include "io/vtk_output.h"

namespace ishibashi {

int run_build(const BuildOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const ModelFile file = read_model_file(o.model_file);
  std::printf("%s%s%s\n", file.name.c_str(), file.description.empty() ? "" : ": ", file.description.c_str());
  RunSettings settings;  // a run's defaults, with the command line's joint settings
  apply_overrides(settings, o.overrides);
  const ModelOptions options = model_options(settings);
  // Validation (CGAL): every block sound, no overlaps, every block on a shared face.
  const CompiledModel compiled = compile_model(file, o.model_file, options);
  const ValidationReport& report = compiled.validation;
  double ground_volume = 0;  // our fixed slab is not part of the design outline
  for (const BridgeBlock& b : compiled.blocks)
    if (b.part == Part::ground) ground_volume += polyhedron_mass_properties(b.shape.vertices, b.shape.faces).volume_m3;
  const double built = report.volume_m3 - ground_volume;
  const double design = file.imported() ? built : design_volume_m3(file.bridge);
  const double volume_error = std::abs(built - design) / design;

  if (!report.ok()) {
    for (const std::string& e : report.errors) std::printf("  error: %s\n", e.c_str());
    std::printf("validation failed: %zu error%s\n", report.errors.size(), report.errors.size() == 1 ? "" : "s");
    return 3;
  }
  const Model& model = compiled.model;
  std::map<std::string, std::pair<int, int>> by_part;  // free, fixed
  double mass = 0;
  Vec3 lo = model.initial_position[0], hi = lo;
  for (int b = 0; b < model.block_count; ++b) {
    auto& count = by_part[part_name(static_cast<Part>(model.block_tag[b].part))];
    (model.motion[b] == Motion::free ? count.first : count.second)++;
    if (model.motion[b] == Motion::free) mass += model.mass_kg[b];
    for (int v = model.vertex_begin[b]; v < model.vertex_begin[b + 1]; ++v) {
      const Vec3 x = model.initial_position[b] + model.initial_orientation[b] * model.vertex_local[v];
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
  }
  std::printf("blocks: %d\n", model.block_count);
  for (const auto& [part, count] : by_part) std::printf("  %-10s %5d free %5d fixed\n", part.c_str(), count.first, count.second);
  std::printf("mass of the free blocks: %.1f t\n", mass / 1000.0);
  if (file.bridge.mortar_pa > 0) std::printf("mortar: %s\n", mortar_description(file.bridge).c_str());
  if (!compiled.ties.empty()) std::printf("ties: %s\n", ties_description(file).c_str());
  for (std::size_t t = 0; t < model.ties.size(); ++t) {  // where each rod is anchored, to check against the drawing
    const Vec3 &from = compiled.ties[t].from, &to = compiled.ties[t].to;
    std::printf("  tie %zu (line %d): %s at (%.3f, %.3f, %.3f) to %s at (%.3f, %.3f, %.3f), %.2f m\n", t, compiled.ties[t].line,
                model.block_label(model.ties[t].block_a).c_str(), from.x(), from.y(), from.z(),
                model.block_label(model.ties[t].block_b).c_str(), to.x(), to.y(), to.z(), model.ties[t].rest_length_m);
  }
  std::printf("bounding box: x %.3f .. %.3f, y %.3f .. %.3f, z %.3f .. %.3f m\n", lo.x(), hi.x(), lo.y(), hi.y(), lo.z(), hi.z());
  std::printf("volume: %.4f m^3, design %.4f m^3 (difference %.2e)\n", built, design, volume_error);
  std::printf("validation: %d pairs meet on shared faces, %d overlapping pairs, %zu errors\n", report.shared_faces,
              report.overlapping_pairs, report.errors.size());
  if (volume_error > 1e-3) std::printf("  error: the blocks' volume differs from the design volume by more than 0.1 %%\n");
  // The explicit step's limit: the joint dashpots (h of the materials) usually set it,
  // through the stiffest block's rocking on its corner sub-contacts.
  int limiting = -1;
  const double limit_s = World(model, 1e-9).critical_time_step_s(&limiting);
  if (limiting < 0) {
    std::printf("time step: no two blocks touch, so no contact sets a stability limit (a run needs dt_s)\n");
  } else {
    std::printf("time step: stability limit %.3g s with the %s joint rule, set by %s (mass %.0f kg); runs use 0.8 of it "
                "unless the scenario sets dt_s\n", limit_s, joint_rule_name(options.joint_rule),
                model.block_label(limiting).c_str(), model.mass_kg[limiting]);
    ModelOptions implicit = options;
    implicit.damping = Damping::implicit;
    const double springs_s = World(compiled.builder.build(implicit), 1e-9).critical_time_step_s();
    std::printf("  with implicit dashpots (damping = \"implicit\") the springs' limit %.3g s; runs use 0.4 of it\n", springs_s);
  }

  if (!o.export_file.empty()) {
    if (o.export_file.has_parent_path()) std::filesystem::create_directories(o.export_file.parent_path());
    std::vector<Polyhedron> shapes_out;
    for (const BridgeBlock& b : compiled.blocks) shapes_out.push_back(b.shape);
    write_atomically(o.export_file, [&](const std::filesystem::path& tmp) {
      try {
        write_block_file(tmp, shapes_out);
      } catch (const std::runtime_error&) {  // it names the temporary file
        throw std::runtime_error("cannot write " + o.export_file.string() + " (a full disk or no permission?)");
      }
    });
    std::printf("exported %zu blocks to %s\n", shapes_out.size(), o.export_file.c_str());
  }
  std::filesystem::create_directories(o.out);
  const auto vtu = o.out / (o.model_file.stem().string() + ".vtu");
  write_blocks_vtu(model, make_initial_state(model), vtu);
  std::printf("wrote %s (%.1f s)\n", vtu.c_str(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return volume_error <= 1e-3 ? 0 : 3;
}

}  // namespace ishibashi
