// The command-line flags of the run settings (io/run_settings.h): one per setting, its
// name, help and range from the settings' list, each filling a RunOverrides.
#pragma once
#include <CLI/CLI.hpp>

#include <cmath>
#include <initializer_list>
#include <vector>

#include "io/run_settings.h"

namespace ishibashi {

// A number check with a message that reads well ("--duration: -1 must be >= 0"): CLI11's
// own (PositiveNumber, NonNegativeNumber, Range) print an open range's end, the largest
// double, in 309 digits. min excluded when open_min; max inf: no upper bound.
CLI::Validator number_in(double min, double max = INFINITY, bool open_min = false);

// Adds the flags of the settings whose keys are in `keys` (empty: every setting) to `cmd`;
// a flag given on the command line sets its value in `overrides`. Returns the options added.
std::vector<CLI::Option*> add_run_setting_flags(CLI::App* cmd, RunOverrides& overrides,
                                                std::initializer_list<const char*> keys = {});

}  // namespace ishibashi
