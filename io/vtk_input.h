// Reading the output back with VTK's own parsers (for tests and post-processing).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

class vtkUnstructuredGrid;

namespace ishibashi {

struct PvdEntry {
  double time_s;
  std::filesystem::path file;  // absolute, resolved against the .pvd's folder
};

// Parses a .pvd collection with vtkXMLDataParser. Throws std::runtime_error naming the
// file when it is missing or not a VTK Collection.
std::vector<PvdEntry> read_pvd(const std::filesystem::path& pvd);

// Reads a .vtu with vtkXMLUnstructuredGridReader; the caller owns the result (Delete()).
// Throws std::runtime_error naming the file when VTK cannot read it.
vtkUnstructuredGrid* read_vtu(const std::filesystem::path& vtu);

}  // namespace ishibashi
