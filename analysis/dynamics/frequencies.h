// Natural frequencies of a model (MODEL.md section 6.1) two ways: modal analysis of the
// assembly with its joints held linear, and impulse responses (a short ground step along
// one axis, a monitored block read along the same or another axis) whose amplitude
// spectra show every mode the step excites.
#pragma once
#include <array>
#include <filesystem>
#include <vector>

#include "analysis/dynamics/modal.h"
#include "analysis/dynamics/modal_energy.h"
#include "analysis/dynamics/spectrum.h"
#include "analysis/model/compile_model.h"

namespace ishibashi {

struct ImpulseSpec {
  int excitation_axis = 0;  // the ground step's direction: 0 x, 1 y, 2 z
  int response_axis = 0;    // the monitored block's displacement component read
  int monitor_block = kCrownUnit;  // a block, or kCrownUnit or kFaceUnitBesideCrown
  static constexpr int kCrownUnit = -1;            // the unit on top of the crown (the first free block if none)
  static constexpr int kFaceUnitBesideCrown = -2;  // off both symmetry planes (face_unit_beside_crown)
};

struct ImpulseResult {
  ImpulseSpec requested;  // as asked (kCrownUnit, ...)
  ImpulseSpec spec;       // with the monitored block resolved
  std::string monitor_label;  // "block 12 'ring-3'"
  Spectrum spectrum;
  std::vector<SpectralPeak> peaks;  // every peak above 5 % of the largest, ascending
};

struct FrequencyOptions {
  int modes = 12;
  double impulse_s = 0.0;             // > 0: impulse responses of this length
  std::vector<ImpulseSpec> impulses;  // empty: study_impulses()
};

struct FrequencyAnalysis {
  ModalResult modal;
  std::size_t sub_contacts = 0;
  // Per axis, the lowest mode whose effective mass in that axis exceeds 5 % (0: none).
  std::array<double, 3> first_mode_hz{0, 0, 0};
  std::array<int, 3> first_mode{-1, -1, -1};  // their indices in modal
  std::vector<std::vector<JointEnergyShare>> energy;  // per mode: its strain energy by joint class
  std::vector<ImpulseResult> impulses;
};

// Runs the analyses and writes to `out`: modes.csv (frequencies, effective masses),
// modes_energy.csv (each mode's strain energy by joint class and spring), modes.vtu (mode shapes for ParaView), and per impulse response
// spectrum_<excitation><response>_block<N>.csv and a row of peaks.csv.
// The modal analysis studies the model built with the loaded options, the impulse
// responses the same blocks with linear joints (ModelOptions::linear_joints).
FrequencyAnalysis analyse_frequencies(const LoadedModel& loaded, const FrequencyOptions& options, const std::filesystem::path& out);

// The study's convention (MODEL.md section 6.1): x, y and z steps each read along itself at
// the crown unit; then the x and the y step read in z (a study that reads "the vertical
// response" may have read either) and along themselves at the face unit beside the crown,
// off the symmetry planes where the crown's vertical response to them vanishes.
std::vector<ImpulseSpec> study_impulses();

char axis_letter(int axis);
// "x", "y" or "z" as 0, 1, 2; -1 otherwise.
int axis_index(const std::string& letter);

}  // namespace ishibashi
