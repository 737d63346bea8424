// `ishibashi study [study file]`: the natural frequencies of the study's models and its
// seismic runs, several at once, then the report (report.md, report.html, figures/).
#pragma once
#include <filesystem>

#include "io/run_settings.h"

namespace ishibashi {

struct StudyCommandOptions {
  std::filesystem::path file;  // empty: the Nishida study (scenarios/nishida_study.toml)
  std::filesystem::path out;   // empty: out/study (out/study_quick with --quick)
  bool quick = false;
  int jobs = 1;
  int threads_per_job = 0;
  int members = -1;  // >= 0: each run an ensemble of this many members (0, 1: single runs), replacing the file's
  RunOverrides run_overrides;  // the run settings given on the command line, for every run
  bool force = false;
  bool no_report = false;
};

// Returns 0 when every job ran or was current and the report was written, 1 otherwise.
int run_study_command(const StudyCommandOptions& options);

}  // namespace ishibashi
