// Model files (TOML): the parameters of a generated bridge, as in models/*.toml.
// Every key is checked: an unknown key, a wrong type or an impossible value is an error
// that names the file, the line and the key.
#pragma once
#include <filesystem>
#include <stdexcept>
#include <string>

#include "geometry/bridge.h"

namespace ishibashi {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ModelFile {
  std::string name;        // [model] name, or the file's stem
  std::string description; // [model] description
  BridgeSpec bridge;
};

ModelFile read_model_file(const std::filesystem::path& file);

}  // namespace ishibashi
