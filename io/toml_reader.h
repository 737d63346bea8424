// Strict reading of TOML tables: typed fields, and an error naming the file, line and key
// for an unknown key, a wrong type or a value outside the allowed choices.
#pragma once
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <climits>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "engine/model.h"
#include "geometry/input_error.h"

namespace ishibashi {

// Reads one TOML table into typed fields, remembering which keys were used, so that
// unknown keys can be reported with their line.
class TableReader {
 public:
  TableReader(const std::filesystem::path& file, const toml::table& root, const std::string& name)
      : file_(file), name_(name), table_(root[name].as_table()) {
    if (root.contains(name) && !table_)
      fail(*root.get(name), "[" + name + "] must be a table");
  }

  // A reader of a table found elsewhere (a nested table), named for messages.
  TableReader(const std::filesystem::path& file, const toml::table* table, const std::string& name)
      : file_(file), name_(name), table_(table) {}

  bool present() const { return table_ != nullptr; }

  void number(const char* key, double& out) {
    if (const toml::node* n = find(key)) {
      const auto v = n->value<double>();
      if (!v) fail(*n, std::string("'") + key + "' must be a number");
      // TOML has nan and inf, and every range check below lets a NaN through.
      if (!std::isfinite(*v))
        fail(*n, std::string("'") + key + "' is " + (std::isnan(*v) ? "nan" : *v > 0 ? "inf" : "-inf") + "; it must be a finite number");
      out = *v;
    }
  }
  // A number that must lie in a range: the error names the line and the range.
  void positive(const char* key, double& out) { number_in(key, out, 0.0, 1e300, true); }
  void non_negative(const char* key, double& out) { number_in(key, out, 0.0, 1e300, false); }
  void number_in(const char* key, double& out, double min, double max, bool min_excluded = false) {
    number(key, out);
    if (const toml::node* n = find(key)) {
      if ((min_excluded ? out > min : out >= min) && out <= max) return;
      std::ostringstream s;
      s << "'" << key << "' is " << out << "; it must be " << (min_excluded ? "> " : ">= ") << min;
      if (max < 1e300) s << " and <= " << max;
      fail(*n, s.str());
    }
  }
  void integer_at_least(const char* key, int& out, int min) { integer_in(key, out, min, INT_MAX); }
  void integer_in(const char* key, int& out, int min, int max) {
    integer(key, out);
    if (const toml::node* n = find(key); n && (out < min || out > max))
      fail(*n, std::string("'") + key + "' is " + std::to_string(out) + "; it must be at least " + std::to_string(min) +
                   (max < INT_MAX ? " and at most " + std::to_string(max) : std::string()));
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
  // One of an option enum's values, by name (choice_names in engine/model.h).
  template <class E>
  void choice(const char* key, E& out) {
    if (const toml::node* n = find(key)) {
      auto v = n->value<std::string>();
      if (!v) fail(*n, std::string("'") + key + "' must be a string");
      const int i = choice_index<E>(*v);
      if (i < 0) {
        std::string list;
        for (const char* a : choice_names(E{})) list += std::string(list.empty() ? "" : ", ") + "\"" + a + "\"";
        fail(*n, std::string("'") + key + "' is \"" + *v + "\"; allowed: " + list);
      }
      out = static_cast<E>(i);
    }
  }
  void integers(const char* key, std::vector<int>& out) {
    if (const toml::node* n = find(key)) {
      const toml::array* a = n->as_array();
      if (!a) fail(*n, std::string("'") + key + "' must be an array of integers");
      for (const toml::node& e : *a) {
        if (!e.as_integer()) fail(e, std::string("'") + key + "' must hold integers");
        out.push_back(static_cast<int>(e.as_integer()->get()));
      }
    }
  }
  // [lo, hi]: two numbers, lo <= hi, both within [min, max]; replaces `out` when present.
  void range(const char* key, std::array<double, 2>& out, double min, double max) {
    if (const toml::node* n = find(key)) {
      const toml::array* a = n->as_array();
      std::ostringstream expected;
      expected << "'" << key << "' must be [lo, hi], two numbers with " << min << " <= lo <= hi <= " << max;
      if (!a || a->size() != 2) fail(*n, expected.str());
      const auto lo = (*a)[0].value<double>(), hi = (*a)[1].value<double>();
      if (!lo || !hi || !(*lo >= min && *hi <= max && *lo <= *hi)) fail(*n, expected.str());  // NaN fails too
      out = {*lo, *hi};
    }
  }
  // [x, y, z]: three finite numbers; replaces `out` when present.
  void point(const char* key, Vec3& out) {
    if (const toml::node* n = find(key)) {
      const toml::array* a = n->as_array();
      const std::string expected = std::string("'") + key + "' must be a point [x, y, z] of three numbers, m";
      if (!a || a->size() != 3) fail(*n, expected);
      for (int i = 0; i < 3; ++i) {
        const auto v = (*a)[i].value<double>();
        if (!v || !std::isfinite(*v)) fail(*n, expected);
        out[i] = *v;
      }
    }
  }
  // An array of numbers >= 0 (e.g. times in seconds); replaces `out` when present.
  void non_negative_numbers(const char* key, std::vector<double>& out) {
    numbers_at_least(key, out, 0, "finite numbers >= 0");
  }
  // An array of finite numbers (e.g. positions in m); replaces `out` when present.
  void finite_numbers(const char* key, std::vector<double>& out) { numbers_at_least(key, out, -INFINITY, "finite numbers"); }
  void numbers_at_least(const char* key, std::vector<double>& out, double min, const char* what) {
    if (const toml::node* n = find(key)) {
      const toml::array* a = n->as_array();
      if (!a) fail(*n, std::string("'") + key + "' must be an array of numbers, e.g. [1.0, 2.5]");
      out.clear();
      for (const toml::node& e : *a) {
        auto v = e.value<double>();
        if (!v || !(*v >= min && std::isfinite(*v))) fail(e, std::string("'") + key + "' must hold " + what);
        out.push_back(*v);
      }
    }
  }
  // A non-empty array of strings, each one of `allowed`; replaces `out` when present.
  template <std::size_t N>
  void texts(const char* key, std::vector<std::string>& out, const std::array<const char*, N>& allowed) {
    if (const toml::node* n = find(key)) {
      std::string list;
      for (const char* choice : allowed) list += std::string(list.empty() ? "\"" : ", \"") + choice + "\"";
      const toml::array* a = n->as_array();
      if (!a || a->empty()) fail(*n, std::string("'") + key + "' must be an array of one or more of " + list);
      out.clear();
      for (const toml::node& e : *a) {
        auto v = e.value<std::string>();
        if (!v || std::find(allowed.begin(), allowed.end(), *v) == allowed.end())
          fail(e, std::string("'") + key + "' may only hold " + list);
        out.push_back(*v);
      }
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
  // The same for files whose stems name folders (a study's or a sweep's runs): two files of
  // one stem would write into one folder, at once when jobs run side by side.
  void paths_of_distinct_stems(const char* key, const std::filesystem::path& base, std::vector<std::filesystem::path>& out) {
    const std::size_t first = out.size();
    paths(key, base, out);
    std::set<std::string> stems;
    for (std::size_t i = first; i < out.size(); ++i) {
      const std::string stem = out[i].stem().string();
      if (!stems.insert(stem).second)
        fail(*find(key)->as_array()->get(i - first),
             std::string("'") + key + "' names '" + stem + "' twice (each one's outputs go to a folder of that name)");
    }
  }
  void boolean(const char* key, bool& out) {
    if (const toml::node* n = find(key)) {
      if (auto v = n->value_exact<bool>()) out = *v;  // value<bool> would take 0 and 1
      else fail(*n, std::string("'") + key + "' must be true or false");
    }
  }
  // A nested table (e.g. x = { file = ... }) as its own reader.
  const toml::table* subtable(const char* key) {
    const toml::node* n = find(key);
    if (!n) return nullptr;
    if (!n->as_table()) fail(*n, std::string("'") + key + "' must be a table");
    return n->as_table();
  }
  void material(Material& m) {
    text("name", m.name);
    positive("density_kg_m3", m.density_kg_m3);
    positive("young_pa", m.young_pa);
    number_in("poisson", m.poisson, 0.0, 0.4999);
    number_in("friction_deg", m.friction_deg, 0.0, 89.9);
    non_negative("damping_normal", m.damping_normal);
    non_negative("damping_shear", m.damping_shear);
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


// The four kinds of input file and the top-level tables each may hold, in one list, so
// that a table of another kind's file can say the command was given the wrong file
// (`run models/nishida_a.toml`: [bridge] belongs in a model file).
struct InputFileKind {
  const char* name;  // for messages
  std::vector<std::string_view> tables;
};
inline const InputFileKind kModelFile{"a model file (models/)", {"model", "ring", "bridge", "stone", "soil", "import", "tie", "tie_row"}};
inline const InputFileKind kScenarioFile{"a scenario file (scenarios/)", {"model", "run", "ground_motion", "monitor", "ensemble"}};
inline const InputFileKind kSweepFile{"a sweep file (scenarios/*_sweep.toml)", {"sweep", "failure", "record"}};
inline const InputFileKind kStudyFile{"a study file (scenarios/nishida_study.toml)", {"study", "frequencies", "quick", "reference"}};

// The one kind of file whose own table `key` is (nullptr: none, or more than one kind's).
inline const char* file_kind_of_table(std::string_view key) {
  const char* found = nullptr;
  for (const InputFileKind* kind : {&kModelFile, &kScenarioFile, &kSweepFile, &kStudyFile})
    for (std::string_view table : kind->tables)
      if (key == table) {
        if (found) return nullptr;
        found = kind->name;
      }
  return found;
}

// Parses a TOML file of the given kind: its top level may only hold the kind's tables;
// errors name the file and the line.
inline toml::table parse_toml_file(const std::filesystem::path& file, const InputFileKind& kind) {
  if (!std::filesystem::exists(file)) throw InputError(file.string() + ": no such file");
  // A mesh where a TOML file goes (`[model] file = "stones.off"`, `build stones.stl`) read as
  // TOML said "expected '='" at its first line.
  std::string extension = file.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".off" || extension == ".obj" || extension == ".stl")
    throw InputError(file.string() + ": a mesh given where " + kind.name + " goes, a TOML file; a model file imports " +
                     "meshes as blocks with [import] files = [\"" + file.filename().string() +
                     "\"] (as models/examples/stack_of_three.toml does)");
  toml::table root;
  try {
    root = toml::parse_file(file.string());
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << file.string() << ":" << e.source().begin.line << ": " << e.description();
    throw InputError(s.str());
  }
  for (const auto& [key, node] : root) {
    bool known = false;
    std::string list;
    for (std::string_view table : kind.tables) {
      known = known || key.str() == table;
      list += std::string(list.empty() ? "" : ", ") + "[" + std::string(table) + "]";
    }
    if (!known) {
      std::ostringstream s;
      s << file.string() << ":" << node.source().begin.line << ": unknown table or key '" << key.str()
        << "'; allowed: " << list;
      if (const char* other = file_kind_of_table(key.str()))
        s << " ([" << key.str() << "] belongs in " << other << ": is this the file the command takes?)";
      throw InputError(s.str());
    }
  }
  return root;
}

}  // namespace ishibashi
