#include "analysis/dynamics/frequencies.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <string>

#include "analysis/dynamics/impulse.h"
#include "engine/world.h"
#include "geometry/bridge.h"
#include "io/atomic_file.h"
#include "io/folder_lock.h"
#include "io/model_file.h"
#include "io/vtk_output.h"

namespace ishibashi {

char axis_letter(int axis) { return "xyz"[axis]; }

std::vector<ImpulseSpec> study_impulses() {
  constexpr int crown = ImpulseSpec::kCrownUnit, face = ImpulseSpec::kFaceUnitBesideCrown;
  return {{0, 0, crown}, {1, 1, crown}, {2, 2, crown}, {0, 2, face}, {1, 2, face}, {0, 0, face}, {1, 1, face}};
}

int axis_index(const std::string& letter) {
  return letter == "x" ? 0 : letter == "y" ? 1 : letter == "z" ? 2 : -1;
}

FrequencyAnalysis analyse_frequencies(const LoadedModel& loaded, const FrequencyOptions& o, const std::filesystem::path& out) {
  const Model& model = loaded.model();
  const World world(model, 1e-9);  // finds the joints in contact at the start
  FrequencyAnalysis a;
  a.modal = modal_analysis(model, world.state(), o.modes);
  a.sub_contacts = sub_contact_count(world.state());
  const ModalResult& r = a.modal;
  std::filesystem::create_directories(out);
  const FolderLock claim(out);
  std::ostringstream csv;
  csv << "mode,frequency_hz,effective_mass_x,effective_mass_y,effective_mass_z,dominant\n";
  for (std::size_t k = 0; k < r.frequency_hz.size(); ++k) {
    const Vec3& e = r.effective_mass_ratio[k];
    const int d = r.dominant_direction(static_cast<int>(k));
    csv << k + 1 << "," << r.frequency_hz[k] << "," << e.x() << "," << e.y() << "," << e.z() << "," << axis_letter(d) << "\n";
    for (int axis = 0; axis < 3; ++axis)
      if (a.first_mode_hz[axis] == 0 && e[axis] > 0.05) {
        a.first_mode_hz[axis] = r.frequency_hz[k];
        a.first_mode[axis] = static_cast<int>(k);
      }
  }
  write_text_atomically(out / "modes.csv", csv.str());
  std::ostringstream energy_csv;
  energy_csv << "mode,frequency_hz,joint,normal_share,shear_share\n";
  for (std::size_t k = 0; k < r.frequency_hz.size(); ++k) {
    a.energy.push_back(modal_energy_shares(model, world.state(), r, static_cast<int>(k)));
    for (const JointEnergyShare& j : a.energy.back())
      energy_csv << k + 1 << "," << r.frequency_hz[k] << ",\"" << j.joint << "\"," << j.normal << "," << j.shear << "\n";
  }
  write_text_atomically(out / "modes_energy.csv", energy_csv.str());
  write_modes_vtu(model, world.state(), r.shapes, r.free_blocks, out / "modes.vtu");
  if (o.impulse_s <= 0) return a;

  std::vector<ImpulseSpec> specs = o.impulses;
  if (specs.empty()) specs = study_impulses();
  ModelOptions linear_options = loaded.options();
  linear_options.linear_joints = true;
  const Model linear = loaded.build(linear_options);
  // The step: frequencies within 0.2 % ((omega dt)^2 / 24) up to the highest mode computed,
  // and at most half the per-block stability limit (the assembly's highest omega is at most
  // sqrt(2) times the largest block's: Gershgorin, each coupling at most the block's own
  // stiffness). For a bridge that is the limit's half, five times a tenth of it.
  const double top_omega = 2 * M_PI * (r.frequency_hz.empty() ? 0.0 : r.frequency_hz.back());
  double dt = 0.5 * World(linear, 1e-9).critical_time_step_s();
  if (top_omega > 0) dt = std::min(dt, 0.2 / top_omega);
  std::map<std::pair<int, int>, ImpulseResponse> responses;
  std::ostringstream peaks;
  peaks << "excitation,response,block,peak,frequency_hz,relative_amplitude\n";
  const int crown = crown_unit(model) >= 0 ? crown_unit(model) : r.free_blocks.front();
  const int face = face_unit_beside_crown(model) >= 0 ? face_unit_beside_crown(model) : crown;
  for (const ImpulseSpec& requested : specs) {
    ImpulseSpec spec = requested;
    if (spec.monitor_block == ImpulseSpec::kCrownUnit) spec.monitor_block = crown;
    if (spec.monitor_block == ImpulseSpec::kFaceUnitBesideCrown) spec.monitor_block = face;
    if (spec.monitor_block >= model.block_count || model.motion[spec.monitor_block] != Motion::free)
      throw InputError("impulse response: block " + std::to_string(spec.monitor_block) + " is not a free block of " +
                       std::to_string(model.block_count));
    // One response per step and block, read along as many axes as asked.
    const auto key = std::make_pair(spec.excitation_axis, spec.monitor_block);
    if (!responses.count(key))
      responses[key] = impulse_response(linear, spec.excitation_axis, spec.monitor_block, o.impulse_s, dt);
    const ImpulseResponse& response = responses.at(key);
    ImpulseResult result{requested, spec, model.block_label(spec.monitor_block),
                         amplitude_spectrum(response.displacement_m[spec.response_axis], response.dt_s), {}};
    result.peaks = spectral_peaks(result.spectrum);
    const std::string tag = std::string(1, axis_letter(spec.excitation_axis)) + axis_letter(spec.response_axis);
    std::ostringstream spectrum;
    spectrum << "frequency_hz,amplitude_m\n";
    for (std::size_t k = 0; k < result.spectrum.frequency_hz.size(); ++k)
      spectrum << result.spectrum.frequency_hz[k] << "," << result.spectrum.amplitude[k] << "\n";
    write_text_atomically(out / ("spectrum_" + tag + "_block" + std::to_string(spec.monitor_block) + ".csv"), spectrum.str());
    for (std::size_t k = 0; k < result.peaks.size(); ++k)
      peaks << axis_letter(spec.excitation_axis) << "," << axis_letter(spec.response_axis) << "," << spec.monitor_block << ","
            << k + 1 << "," << result.peaks[k].frequency_hz << "," << result.peaks[k].relative_amplitude << "\n";
    a.impulses.push_back(std::move(result));
  }
  write_text_atomically(out / "peaks.csv", peaks.str());
  return a;
}

}  // namespace ishibashi
