// The time series of a run's frames: <name>_NNNNNN.vtu files and the .pvd collection that
// lists them with their times, rewritten atomically after each frame.
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "io/atomic_file.h"
#include "io/vtk_output.h"

namespace ishibashi {

VtkSeriesWriter::VtkSeriesWriter(std::filesystem::path directory, std::string name, Kind kind)
    : directory_(std::move(directory)), name_(std::move(name)), kind_(kind) {
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  if (ec) throw std::runtime_error("cannot create output folder " + directory_.string() + ": " + ec.message());
}

void VtkSeriesWriter::resume(const std::vector<double>& times) {
  times_.clear();
  files_.clear();
  for (double t : times) {
    char file[64];
    std::snprintf(file, sizeof file, "_%06d.vtu", frame_count());
    times_.push_back(t);
    files_.push_back(name_ + file);
  }
}

void VtkSeriesWriter::write(const Model& model, const State& state, const Vec3& ground_displacement_m,
                            const Joints* joints) {
  char file[64];
  std::snprintf(file, sizeof file, "_%06d.vtu", frame_count());
  const std::string vtu = name_ + file;
  if (kind_ == Kind::blocks)
    write_blocks_vtu(model, state, directory_ / vtu, ground_displacement_m);
  else if (kind_ == Kind::contacts)
    write_contacts_vtu(model, state, directory_ / vtu, joints);
  else
    write_ties_vtu(model, state, directory_ / vtu);
  times_.push_back(state.time_s);
  files_.push_back(vtu);

  std::ostringstream pvd;
  pvd.precision(12);
  pvd << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <Collection>\n";
  for (std::size_t i = 0; i < times_.size(); ++i)
    pvd << "    <DataSet timestep=\"" << times_[i] << "\" group=\"\" part=\"0\" file=\"" << files_[i] << "\"/>\n";
  pvd << "  </Collection>\n</VTKFile>\n";
  write_text_atomically(pvd_path(), pvd.str());
}

}  // namespace ishibashi
