#include "io/model_file.h"

#include <toml++/toml.h>

#include "geometry/demo_scenes.h"

#include <set>
#include <sstream>

namespace ishibashi {
namespace {

// Reads one TOML table into typed fields, remembering which keys were used, so that
// unknown keys can be reported with their line.
class TableReader {
 public:
  TableReader(const std::filesystem::path& file, const toml::table& root, const std::string& name)
      : file_(file), name_(name), table_(root[name].as_table()) {
    if (root.contains(name) && !table_)
      fail(*root.get(name), "[" + name + "] must be a table");
  }

  bool present() const { return table_ != nullptr; }

  void number(const char* key, double& out) {
    if (const toml::node* n = find(key)) {
      if (auto v = n->value<double>()) out = *v;
      else fail(*n, std::string("'") + key + "' must be a number");
    }
  }
  void integer(const char* key, int& out) {
    if (const toml::node* n = find(key)) {
      if (auto v = n->as_integer()) out = static_cast<int>(v->get());
      else fail(*n, std::string("'") + key + "' must be an integer");
    }
  }
  void text(const char* key, std::string& out, std::initializer_list<const char*> allowed = {}) {
    if (const toml::node* n = find(key)) {
      auto v = n->value<std::string>();
      if (!v) fail(*n, std::string("'") + key + "' must be a string");
      if (allowed.size()) {
        std::string list;
        bool ok = false;
        for (const char* a : allowed) {
          ok = ok || *v == a;
          list += std::string(list.empty() ? "" : ", ") + "\"" + a + "\"";
        }
        if (!ok) fail(*n, std::string("'") + key + "' is \"" + *v + "\"; allowed: " + list);
      }
      out = *v;
    }
  }
  void paths(const char* key, const std::filesystem::path& base, std::vector<std::filesystem::path>& out) {
    if (const toml::node* n = find(key)) {
      const toml::array* a = n->as_array();
      if (!a) fail(*n, std::string("'") + key + "' must be an array of file names");
      for (const toml::node& e : *a) {
        auto v = e.value<std::string>();
        if (!v) fail(e, std::string("'") + key + "' must hold strings (file names)");
        out.push_back(base / *v);
      }
    }
  }
  void material(Material& m) {
    text("name", m.name);
    number("density_kg_m3", m.density_kg_m3);
    number("young_pa", m.young_pa);
    number("poisson", m.poisson);
    number("friction_deg", m.friction_deg);
    number("damping_normal", m.damping_normal);
    number("damping_shear", m.damping_shear);
  }
  // Every key of the table must have been read.
  void finish() {
    if (!table_) return;
    for (const auto& [key, node] : *table_)
      if (!used_.count(std::string(key.str())))
        fail(node, "unknown key '" + std::string(key.str()) + "' in [" + name_ + "]");
  }

  [[noreturn]] void fail(const toml::node& n, const std::string& what) const {
    std::ostringstream s;
    s << file_.string() << ":" << n.source().begin.line << ": " << what;
    throw InputError(s.str());
  }

 private:
  const toml::node* find(const char* key) {
    if (!table_) return nullptr;
    used_.insert(key);
    return table_->get(key);
  }
  std::filesystem::path file_;
  std::string name_;
  const toml::table* table_;
  std::set<std::string> used_;
};

}  // namespace

ModelFile read_model_file(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) throw InputError(file.string() + ": no such file");
  toml::table root;
  try {
    root = toml::parse_file(file.string());
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << file.string() << ":" << e.source().begin.line << ": " << e.description();
    throw InputError(s.str());
  }
  for (const auto& [key, node] : root)
    if (key != "model" && key != "ring" && key != "bridge" && key != "stone" && key != "soil" && key != "import") {
      std::ostringstream s;
      s << file.string() << ":" << node.source().begin.line << ": unknown table or key '" << key.str()
        << "'; allowed: [model], [ring], [bridge], [stone], [soil], [import]";
      throw InputError(s.str());
    }

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
