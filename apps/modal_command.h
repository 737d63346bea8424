// `ishibashi modal <model or scenario file>`: natural frequencies by modal analysis of
// the bonded (linear) assembly, with effective modal masses and mode shapes for ParaView,
// and optionally impulse responses with every spectral peak.
#pragma once
#include <filesystem>
#include <string>

namespace ishibashi {

struct ModalOptions {
  std::filesystem::path file;  // a model file, or a scenario file naming one (its subdivision and mortar apply)
  std::filesystem::path out;   // empty: out/<name>_modal
  int modes = 12;
  double impulse_s = 0.0;      // > 0: also impulse responses of this length
  std::string excite;          // "x", "y" or "z": one impulse along this axis; empty: x, y and z
  std::string read;            // the component read ("x", "y", "z"); empty: the excitation's
  int block = -1;              // the monitored block; -1: the unit on top of the crown
  std::string joint_rule;      // "corners" or "moments"; empty: the scenario's (corners for a model file)
  std::string shear_spring;    // "shear_modulus" or "normal"; empty: the scenario's (shear_modulus for a model file)
};

int run_modal(const ModalOptions& options);

}  // namespace ishibashi
