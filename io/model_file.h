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

struct ModelFile {
  std::string name;        // [model] name, or the file's stem
  std::string description; // [model] description
  BridgeSpec bridge;       // [ring], [bridge], [stone], [soil]: a generated bridge
  // [import]: blocks from mesh files instead (paths resolved against the model file).
  std::vector<std::filesystem::path> import_files;  // free blocks
  std::vector<std::filesystem::path> fixed_files;   // fixed blocks (ground, abutments)
  double import_scale = 1;  // metres per unit of the mesh files (0.001: drawn in millimetres)
  bool imported() const { return !import_files.empty() || !fixed_files.empty(); }
};

ModelFile read_model_file(const std::filesystem::path& file);

// The mortar's two fracture energies go together (both 0: brittle; both > 0: softening):
// an InputError naming `file` and `table` otherwise.
void require_both_fracture_energies(const std::filesystem::path& file, const std::string& table, const BridgeSpec& b);

class TableReader;
// A table's mortar_parts (["ring"], ...): replaces `parts` when given.
void read_mortar_parts(TableReader& table, std::vector<Part>& parts);

}  // namespace ishibashi
