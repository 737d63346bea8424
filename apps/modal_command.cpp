#include "apps/modal_command.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "analysis/batch/job_queue.h"
#include "analysis/dynamics/frequencies.h"
#include "analysis/model/compile_model.h"

namespace ishibashi {

int run_modal(const ModalOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const LoadedModel loaded = load_model_or_scenario(o.file, o.overrides);
  FrequencyOptions options;
  options.modes = o.modes;
  options.impulse_s = o.impulse_s;
  if (!o.excite.empty()) {
    const int excite = axis_index(o.excite);
    options.impulses.push_back({excite, o.read.empty() ? excite : axis_index(o.read), o.block});
  } else if (!o.read.empty() || o.block >= 0) {
    for (int axis = 0; axis < 3; ++axis)
      options.impulses.push_back({axis, o.read.empty() ? axis : axis_index(o.read), o.block});
  }
  const std::filesystem::path out = o.out.empty() ? std::filesystem::path("out") / (o.file.stem().string() + "_modal") : o.out;
  const FrequencyAnalysis a = analyse_frequencies(loaded, options, out);
  const ModalResult& r = a.modal;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::printf("%s: %zu free blocks, %zu sub-contacts (subdivision %d, joint rule %s, shear spring %s), joints held linear\n",
              loaded.name.c_str(), r.free_blocks.size(), a.sub_contacts, loaded.options().subdivision,
              joint_rule_name(loaded.options().joint_rule), shear_spring_name(loaded.options().shear_spring));
  std::printf("mode  frequency (Hz)  effective mass x / y / z (of %.1f t)  dominant\n", r.total_mass_kg / 1000);
  for (std::size_t k = 0; k < r.frequency_hz.size(); ++k) {
    const Vec3& e = r.effective_mass_ratio[k];
    std::printf("%4zu  %14.3f  %8.3f %8.3f %8.3f           %c\n", k + 1, r.frequency_hz[k], e.x(), e.y(), e.z(),
                axis_letter(r.dominant_direction(static_cast<int>(k))));
  }
  std::printf("first natural frequency (effective mass above 5 %%): x %.3f Hz, y %.3f Hz, z %.3f Hz (%.1f s)\n",
              a.first_mode_hz[0], a.first_mode_hz[1], a.first_mode_hz[2], seconds);
  // A mode at 0 Hz moves blocks that no joint holds: the frequencies above it describe a
  // structure that is not supported, which a user should hear of rather than read as 0 Hz.
  const long free_modes = std::count_if(r.frequency_hz.begin(), r.frequency_hz.end(), [](double f) { return f < 1e-3; });
  if (free_modes > 0)
    std::printf("  warning: %ld modes at 0 Hz: blocks move as rigid bodies that no joint holds (is a fixed block, e.g. the "
                "ground, touching them?)\n", free_modes);
  // Which joints hold each first mode's strain energy: the stiffness its frequency rests on.
  for (int axis = 0; axis < 3; ++axis) {
    if (a.first_mode[axis] < 0) continue;
    std::printf("  strain energy of the first %c mode by joint (normal + shear springs):", axis_letter(axis));
    const std::vector<JointEnergyShare>& shares = a.energy[a.first_mode[axis]];
    for (std::size_t j = 0; j < shares.size() && j < 5; ++j)
      if (shares[j].normal + shares[j].shear >= 0.01)
        std::printf("%s %s %.0f %% (%.0f + %.0f)", j ? "," : "", shares[j].joint.c_str(), 100 * (shares[j].normal + shares[j].shear),
                    100 * shares[j].normal, 100 * shares[j].shear);
    std::printf("\n");
  }
  if (!a.impulses.empty())
    std::printf("impulse responses, %.2f s each, joints linear, no damping; spectral peaks above 5 %% of the largest:\n",
                o.impulse_s);
  for (const ImpulseResult& i : a.impulses) {
    const int e = i.spec.excitation_axis, c = i.spec.response_axis;
    std::printf("  %c step, %s read in %c:", axis_letter(e), i.monitor_label.c_str(),
                axis_letter(c));
    for (const SpectralPeak& p : i.peaks) std::printf(" %.3f Hz (%.2f)", p.frequency_hz, p.relative_amplitude);
    const double first_clear_peak = first_peak_hz(i.spectrum);  // above 30 % of the largest
    if (e == c && a.first_mode_hz[e] > 0 && first_clear_peak > 0)
      std::printf("; first clear peak %.3f Hz, %+.2f %% from the first %c mode", first_clear_peak,
                  100 * (first_clear_peak / a.first_mode_hz[e] - 1), axis_letter(e));
    std::printf("\n");
  }
  std::printf("wrote %s/modes.csv, modes_energy.csv and modes.vtu (point arrays mode_1 ...: warp by vector in ParaView)%s\n", out.c_str(),
              a.impulses.empty() ? "" : ", spectrum_*.csv and peaks.csv");
  std::fflush(stdout);  // before the script's own lines
  const std::string not_drawn =
      run_report_script("mode_shapes.py", out, loaded.name + ", " + joint_rule_name(loaded.options().joint_rule) + " rule");
  if (!not_drawn.empty()) std::printf("warning: mode_shapes.png not drawn: %s\n", not_drawn.c_str());
  return 0;
}

}  // namespace ishibashi
