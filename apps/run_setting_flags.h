// The command-line flags of the run settings (io/run_settings.h): one per setting, its
// name, help and range from the settings' list, each filling a RunOverrides.
#pragma once
#include <CLI/CLI.hpp>

#include <initializer_list>
#include <vector>

#include "io/run_settings.h"

namespace ishibashi {

// Adds the flags of the settings whose keys are in `keys` (empty: every setting) to `cmd`;
// a flag given on the command line sets its value in `overrides`. Returns the options added.
std::vector<CLI::Option*> add_run_setting_flags(CLI::App* cmd, RunOverrides& overrides,
                                                std::initializer_list<const char*> keys = {});

}  // namespace ishibashi
