// Model files (TOML): the parameters of a generated bridge, as in models/*.toml.
// Every key is checked: an unknown key, a wrong type or an impossible value is an error
// that names the file, the line and the key.
#pragma once
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/bridge.h"
#include "geometry/input_error.h"

namespace ishibashi {

// A [[tie]] table: a steel tie rod between two anchor points, each inside one free stone
// (ModelBuilder::add_tie).
struct TieSpec {
  Vec3 from = Vec3::Zero(), to = Vec3::Zero();  // anchor points, m (the model's frame)
  double diameter_m = 0.0;
  double young_pa = 2.0e11;  // steel
  double yield_pa = 2.35e8;  // mild steel (S235); wrought iron of old ties: about 2e8
  double pretension_n = 0;   // tension as built (post-tensioned); 0: snug
  int line = 0;              // of its [[tie]] in the model file, for messages
  double area_m2() const { return 0.25 * 3.14159265358979323846 * diameter_m * diameter_m; }
};

// A [[tie_row]] table: rods across the bridge's width (along y), one at each of x_m, at
// height z_m, each anchored inset_m inside the outer faces of the free stones its line passes
// through: compile_model places them (tie_row_rods) once the blocks are made.
struct TieRowSpec {
  std::vector<double> x_m;  // along the bridge, m
  double z_m = 0;           // height, m
  double inset_m = 0.05;    // an anchor plate's bearing point inside the wall's outer face, m
  TieSpec rod;              // each rod's steel, pretension and the table's line (its from and to unused)
};

struct ModelFile {
  std::string name;        // [model] name, or the file's stem
  std::string description; // [model] description
  BridgeSpec bridge;       // [ring], [bridge], [stone], [soil]: a generated bridge
  // [import]: blocks from mesh files instead (paths resolved against the model file).
  std::vector<std::filesystem::path> import_files;  // free blocks
  std::vector<std::filesystem::path> fixed_files;   // fixed blocks (ground, abutments)
  double import_scale = 1;  // metres per unit of the mesh files (0.001: drawn in millimetres)
  std::vector<TieSpec> ties;  // [[tie]]: tie rods, a retrofit (generated or imported blocks)
  std::vector<TieRowSpec> tie_rows;  // [[tie_row]]: rows of rods across the width
  bool imported() const { return !import_files.empty() || !fixed_files.empty(); }
};

ModelFile read_model_file(const std::filesystem::path& file);

// "4 tie rods, d = 30 mm, f_y = 235 MPa, yield force 166 kN" (ranges where they differ) of
// the [[tie]] and [[tie_row]] rods, or "" when there are none: for the build and run commands.
std::string ties_description(const ModelFile& model);

// The mortar's two fracture energies go together (both 0: brittle; both > 0: softening):
// an InputError naming `file` and `table` otherwise.
void require_both_fracture_energies(const std::filesystem::path& file, const std::string& table, const BridgeSpec& b);

class TableReader;
// A table's mortar_parts (["ring"], ...): replaces `parts` when given.
void read_mortar_parts(TableReader& table, std::vector<Part>& parts);

}  // namespace ishibashi
