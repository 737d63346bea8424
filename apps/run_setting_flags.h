// The command-line flags of the run settings (io/run_settings.h): one per setting, its
// name, help and range from the settings' list, each filling a RunOverrides.
#pragma once
#include <CLI/CLI.hpp>

#include <cmath>
#include <initializer_list>
#include <string>
#include <vector>

#include "io/run_settings.h"

namespace ishibashi {

// CLI11's number checks (PositiveNumber, Range) compare, and a NaN passes every comparison:
// every floating-point option checks this first, so "nan" and "inf" get an error.
inline CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) {
        double value = 0;
        if (CLI::detail::lexical_cast(text, value) && !std::isfinite(value)) return text + " is not a finite number";
        return std::string();  // not a number at all: the option's own parse says so
      },
      "FINITE");
}

// Adds the flags of the settings whose keys are in `keys` (empty: every setting) to `cmd`;
// a flag given on the command line sets its value in `overrides`. Returns the options added.
std::vector<CLI::Option*> add_run_setting_flags(CLI::App* cmd, RunOverrides& overrides,
                                                std::initializer_list<const char*> keys = {});

}  // namespace ishibashi
