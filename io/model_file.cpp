#include "io/model_file.h"

#include <toml++/toml.h>

#include "io/toml_reader.h"

#include "geometry/materials.h"

#include <set>
#include <sstream>

namespace ishibashi {

ModelFile read_model_file(const std::filesystem::path& file) {
  const toml::table root = parse_toml_file(file, {"model", "ring", "bridge", "stone", "soil", "import"});

  ModelFile m;
  m.name = file.stem().string();
  BridgeSpec& b = m.bridge;
  b.stone = nishida_stone();
  b.soil = nishida_soil();

  TableReader model(file, root, "model");
  model.text("name", m.name);
  model.text("description", m.description);
  model.finish();

  TableReader ring(file, root, "ring");
  ring.number("span_m", b.ring.span_m);
  ring.number("rise_m", b.ring.rise_m);
  ring.number("thickness_m", b.ring.thickness_m);
  ring.number("width_m", b.ring.width_m);
  ring.number("stone_m", b.ring.stone_m);
  ring.integer("voussoirs", b.ring.voussoirs);
  std::string bond = "stack";
  ring.text("bond", bond, {"stack", "running"});
  b.ring.bond = bond == "running" ? Bond::running : Bond::stack;
  ring.finish();

  TableReader bridge(file, root, "bridge");
  bridge.integer("spans", b.spans);
  bridge.number("pier_width_m", b.pier_width_m);
  bridge.number("fill_height_m", b.fill_height_m);
  bridge.number("length_m", b.length_m);
  std::string backfill = "stone";
  bridge.text("backfill", backfill, {"stone", "soil"});
  b.backfill = backfill == "soil" ? Backfill::soil : Backfill::stone;
  bridge.number("side_wall_width_m", b.side_wall_width_m);
  bridge.number("ground_thickness_m", b.ground_thickness_m);
  bridge.number("mortar_pa", b.mortar_pa);
  bridge.finish();

  TableReader import(file, root, "import");
  const std::filesystem::path base = std::filesystem::absolute(file).parent_path();
  import.paths("files", base, m.import_files);
  import.paths("fixed_files", base, m.fixed_files);
  import.finish();
  if (import.present() && (ring.present() || bridge.present()))
    throw InputError(file.string() + ": [import] and [ring]/[bridge] exclude each other: a model is either imported or generated");

  TableReader stone(file, root, "stone");
  stone.material(b.stone);
  stone.finish();
  TableReader soil(file, root, "soil");
  soil.material(b.soil);
  soil.finish();
  return m;
}

}  // namespace ishibashi
