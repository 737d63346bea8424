#include "apps/modal_command.h"

#include <chrono>
#include <cstdio>
#include <sstream>

#include "apps/build_command.h"
#include "engine/impulse.h"
#include "engine/modal.h"
#include "engine/spectrum.h"
#include "geometry/bridge.h"
#include "engine/world.h"
#include "io/atomic_file.h"
#include "io/scenario_file.h"
#include "io/vtk_output.h"

namespace ishibashi {

int run_modal(const ModalOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  // A scenario names its model file; otherwise the file is the model.
  ModelFile file;
  std::filesystem::path model_path = o.file;
  if (is_scenario_file(o.file)) {
    const Scenario sc = read_scenario(o.file);
    file = sc.model;
    model_path = sc.model_file;
  } else {
    file = read_model_file(o.file);
  }
  const Model model = load_model(file, model_path);
  const World world(model, 1e-9);  // finds the joints in contact at the start
  const ModalResult r = modal_analysis(model, world.state(), o.modes);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const std::filesystem::path out = o.out.empty() ? std::filesystem::path("out") / (o.file.stem().string() + "_modal") : o.out;
  std::filesystem::create_directories(out);
  std::ostringstream csv;
  csv << "mode,frequency_hz,effective_mass_x,effective_mass_y,effective_mass_z,dominant\n";
  std::printf("%s: %zu free blocks, %zu sub-contacts (subdivision %d), joints held linear\n", file.name.c_str(),
              r.free_blocks.size(), world.state().contacts.size(), model.contact.subdivision);
  std::printf("mode  frequency (Hz)  effective mass x / y / z (of %.1f t)  dominant\n", r.total_mass_kg / 1000);
  const char* axis = "xyz";
  const char* axis_name = axis;
  double first[3] = {0, 0, 0};
  for (std::size_t k = 0; k < r.frequency_hz.size(); ++k) {
    const Vec3& e = r.effective_mass_ratio[k];
    const int d = r.dominant_direction(static_cast<int>(k));
    std::printf("%4zu  %14.3f  %8.3f %8.3f %8.3f           %c\n", k + 1, r.frequency_hz[k], e.x(), e.y(), e.z(), axis[d]);
    csv << k + 1 << "," << r.frequency_hz[k] << "," << e.x() << "," << e.y() << "," << e.z() << "," << axis[d] << "\n";
    if (first[d] == 0 && e[d] > 0.05) first[d] = r.frequency_hz[k];
  }
  std::printf("first natural frequency (effective mass above 5 %%): x %.3f Hz, y %.3f Hz, z %.3f Hz (%.1f s)\n", first[0],
              first[1], first[2], seconds);
  write_text_atomically(out / "modes.csv", csv.str());

  if (o.impulse_s > 0) {
    // Impulse responses of the unit on top of the crown (MODEL.md 6.1), compared with the
    // mode of largest effective mass in the same direction.
    const Model linear = linear_joint_model(model);
    int monitor = crown_unit(model);
    if (monitor < 0) monitor = r.free_blocks.front();
    std::printf("impulse responses of %s, %.2f s each, joints linear, no damping:\n", model.block_label(monitor).c_str(), o.impulse_s);
    std::printf("axis  first peak (Hz)  first mode above 5 %% eff. mass (Hz)  difference  largest eff. mass mode (Hz)\n");
    for (int axis = 0; axis < 3; ++axis) {
      const ImpulseResponse response = impulse_response(linear, axis, monitor, o.impulse_s);
      const Spectrum spectrum = amplitude_spectrum(response.displacement_m, response.dt_s);
      const double peak = first_peak_hz(spectrum);
      std::size_t best = 0;
      for (std::size_t k = 0; k < r.frequency_hz.size(); ++k)
        if (r.effective_mass_ratio[k][axis] > r.effective_mass_ratio[best][axis]) best = k;
      std::printf("   %c  %15.3f  %34.3f  %9.2f %%  %27.3f\n", axis_name[axis], peak, first[axis],
                  100 * (peak - first[axis]) / first[axis], r.frequency_hz[best]);
      std::ostringstream spec;
      spec << "frequency_hz,amplitude_m\n";
      for (std::size_t k = 0; k < spectrum.frequency_hz.size(); ++k)
        spec << spectrum.frequency_hz[k] << "," << spectrum.amplitude[k] << "\n";
      write_text_atomically(out / (std::string("spectrum_") + axis_name[axis] + ".csv"), spec.str());
    }
  }
  write_modes_vtu(model, world.state(), r.shapes, r.free_blocks, out / "modes.vtu");
  std::printf("wrote %s/modes.csv and modes.vtu (point arrays mode_1 ...: warp by vector in ParaView)\n", out.c_str());
  return 0;
}

}  // namespace ishibashi
