#include "io/model_file.h"

#include <toml++/toml.h>

#include "io/toml_reader.h"

#include "geometry/materials.h"

#include <set>
#include <iomanip>
#include <sstream>

namespace ishibashi {

void require_both_fracture_energies(const std::filesystem::path& file, const std::string& table, const BridgeSpec& b) {
  if ((b.mortar_tension_fracture_j_m2 > 0) != (b.mortar_shear_fracture_j_m2 > 0))
    throw InputError(file.string() + ": " + table + " mortar_tension_fracture_j_m2 and mortar_shear_fracture_j_m2 " +
                     "must both be > 0 (a softening bond, e.g. 12 and 50 J/m^2) or both 0 (brittle)");
}

void read_mortar_parts(TableReader& table, std::vector<Part>& parts) {
  std::vector<std::string> names;
  table.texts("mortar_parts", names, kMortarPartNames);
  if (names.empty()) return;  // absent
  parts.clear();
  for (const std::string& name : names) parts.push_back(parse_mortar_part(name));
}

std::string ties_description(const ModelFile& model) {
  std::vector<TieSpec> ties = model.ties;
  for (const TieRowSpec& row : model.tie_rows) ties.insert(ties.end(), row.x_m.size(), row.rod);
  if (ties.empty()) return "";
  double d[2] = {INFINITY, 0}, fy[2] = {INFINITY, 0}, force[2] = {INFINITY, 0}, pre[2] = {INFINITY, 0};
  for (const TieSpec& t : ties) {
    d[0] = std::min(d[0], t.diameter_m), d[1] = std::max(d[1], t.diameter_m);
    fy[0] = std::min(fy[0], t.yield_pa), fy[1] = std::max(fy[1], t.yield_pa);
    force[0] = std::min(force[0], t.yield_pa * t.area_m2()), force[1] = std::max(force[1], t.yield_pa * t.area_m2());
    pre[0] = std::min(pre[0], t.pretension_n), pre[1] = std::max(pre[1], t.pretension_n);
  }
  const auto range = [](const double (&r)[2], double scale) {
    std::ostringstream s;
    s << std::setprecision(3) << r[0] * scale;
    if (r[1] > r[0]) s << "-" << r[1] * scale;
    return s.str();
  };
  return std::to_string(ties.size()) + (ties.size() == 1 ? " tie rod" : " tie rods") + ", d = " + range(d, 1e3) +
         " mm, f_y = " + range(fy, 1e-6) + " MPa, yield force " + range(force, 1e-3) + " kN" +
         (pre[1] > 0 ? ", pretension " + range(pre, 1e-3) + " kN" : "");
}

namespace {

// Each table of the array of tables `name` ([[tie]], [[tie_row]]) with its line, once it is
// shown to hold the `required` keys (`needs` says what they are).
template <class ReadTable>
void each_table(const std::filesystem::path& file, const toml::table& root, const char* name,
                std::initializer_list<const char*> required, const char* needs, ReadTable read_table) {
  const toml::node* node = root.get(name);
  if (!node) return;
  const toml::array* list = node->as_array();
  const auto at = [&](const toml::node& n) { return file.string() + ":" + std::to_string(n.source().begin.line) + ": "; };
  if (!list) throw InputError(at(*node) + "'" + name + "' must be [[" + name + "]] tables (each: " + needs + ")");
  for (const toml::node& entry : *list) {
    const toml::table* table = entry.as_table();
    if (!table) throw InputError(at(entry) + "[[" + name + "]] must be a table");
    for (const char* key : required)
      if (!table->contains(key))
        throw InputError(at(entry) + "[[" + name + "]] needs " + needs + "; '" + key + "' is missing");
    TableReader reader(file, table, name);
    read_table(reader, static_cast<int>(entry.source().begin.line), at(entry));
    reader.finish();
  }
}

void read_rod(TableReader& reader, int line, TieSpec& rod) {
  rod.line = line;
  reader.positive("diameter_m", rod.diameter_m);
  reader.positive("young_pa", rod.young_pa);
  reader.positive("yield_pa", rod.yield_pa);
  reader.non_negative("pretension_n", rod.pretension_n);
}

void read_ties(const std::filesystem::path& file, const toml::table& root, ModelFile& m) {
  each_table(file, root, "tie", {"from", "to", "diameter_m"},
             "from = [x, y, z], to = [x, y, z] (anchor points inside two stones, m) and diameter_m",
             [&](TableReader& reader, int line, const std::string&) {
               TieSpec tie;
               reader.point("from", tie.from);
               reader.point("to", tie.to);
               read_rod(reader, line, tie);
               m.ties.push_back(tie);
             });
  each_table(file, root, "tie_row", {"x_m", "z_m", "diameter_m"},
             "x_m = [x, ...] (where the rods cross the bridge, m), z_m (their height, m) and diameter_m",
             [&](TableReader& reader, int line, const std::string& at) {
               TieRowSpec row;
               reader.finite_numbers("x_m", row.x_m);
               if (row.x_m.empty()) throw InputError(at + "[[tie_row]] x_m is empty: give where each rod crosses the bridge, m");
               reader.number("z_m", row.z_m);
               reader.positive("inset_m", row.inset_m);
               read_rod(reader, line, row.rod);
               m.tie_rows.push_back(row);
             });
}

}  // namespace

ModelFile read_model_file(const std::filesystem::path& file) {
  const toml::table root = parse_toml_file(file, kModelFile);

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
  ring.positive("span_m", b.ring.span_m);
  ring.positive("rise_m", b.ring.rise_m);
  ring.positive("thickness_m", b.ring.thickness_m);
  ring.positive("width_m", b.ring.width_m);
  ring.positive("stone_m", b.ring.stone_m);
  ring.integer_at_least("voussoirs", b.ring.voussoirs, 1);
  std::string bond = "stack";
  ring.text("bond", bond, {"stack", "running"});
  b.ring.bond = bond == "running" ? Bond::running : Bond::stack;
  ring.finish();

  TableReader bridge(file, root, "bridge");
  bridge.integer_at_least("spans", b.spans, 1);
  bridge.non_negative("pier_width_m", b.pier_width_m);
  bridge.non_negative("fill_height_m", b.fill_height_m);
  bridge.non_negative("length_m", b.length_m);
  std::string backfill = "stone";
  bridge.text("backfill", backfill, {"stone", "soil"});
  b.backfill = backfill == "soil" ? Backfill::soil : Backfill::stone;
  bridge.non_negative("side_wall_width_m", b.side_wall_width_m);
  bridge.positive("ground_thickness_m", b.ground_thickness_m);
  bridge.non_negative("ground_margin_m", b.ground_margin_m);
  std::string ground = b.ground == GroundMaterial::soil ? "soil" : "stone";
  bridge.text("ground", ground, {"stone", "soil"});
  b.ground = ground == "soil" ? GroundMaterial::soil : GroundMaterial::stone;
  bridge.boolean("fixed_bottom_course", b.fixed_bottom_course);
  bridge.non_negative("mortar_pa", b.mortar_pa);
  bridge.non_negative("mortar_tension_fracture_j_m2", b.mortar_tension_fracture_j_m2);
  bridge.non_negative("mortar_shear_fracture_j_m2", b.mortar_shear_fracture_j_m2);
  read_mortar_parts(bridge, b.mortar_parts);
  bridge.finish();
  require_both_fracture_energies(file, "[bridge]", b);

  TableReader import(file, root, "import");
  const std::filesystem::path base = std::filesystem::absolute(file).parent_path();
  import.paths("files", base, m.import_files);
  import.paths("fixed_files", base, m.fixed_files);
  import.positive("scale", m.import_scale);
  import.finish();
  if (import.present() && (ring.present() || bridge.present()))
    throw InputError(file.string() + ": [import] and [ring]/[bridge] exclude each other: a model is either imported or generated");

  read_ties(file, root, m);

  TableReader stone(file, root, "stone");
  stone.material(b.stone);
  stone.finish();
  TableReader soil(file, root, "soil");
  soil.material(b.soil);
  soil.finish();
  return m;
}

}  // namespace ishibashi
