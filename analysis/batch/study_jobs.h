// The jobs of a study (study.h): a seismic run, a run as an ensemble, or the frequency
// analysis of a model; each writes its outputs in its own folder and returns its row of
// the study's tables (runs.csv, frequencies.csv).
#pragma once
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "io/run_settings.h"
#include "io/scenario_file.h"
#include "io/study_file.h"

namespace ishibashi {

enum class JobKind { frequencies, run };

struct Job {
  JobKind kind;
  std::filesystem::path input;   // model or scenario file
  std::filesystem::path folder;  // its outputs
  std::optional<Scenario> scenario{};  // the input, parsed once, when it is a scenario
  std::string joint_rule{};  // a frequency analysis under this rule; empty: the model's own
  std::string key{};  // fingerprint of everything the outputs depend on
  std::string status = "pending", error{};
  double seconds = 0;
};

// The study's jobs, their keys made: the long runs first (the frequency analyses fill the
// gaps at the end); a run's settings replaced by `overrides` (study --damping ...), which its
// key includes.
std::vector<Job> make_jobs(const StudyFile& study, const std::filesystem::path& out, const RunOverrides& overrides);

std::string job_name(const Job& job);  // "run nishida_b_kobe_dry", "frequencies nishida_a"
bool is_current(const Job& job);       // its row and outputs stamped with its key
// A run stopped part way (Ctrl-C, a session's or a cluster job's end) with a checkpoint
// of the same job key (same program, inputs and duration).
bool resumable(const Job& job);

// The header of runs.csv: which run, its result (run_result.h) and how it ran. A run of an
// ensemble (study members >= 2) gives the result of its most common outcome's member, then
// its probabilities (a single run: members 1, the rest empty).
extern const std::string kRunHeader;
extern const char* const kFrequencyHeader;  // of frequencies.csv

// Each job's row (with the header line first), its outputs in job.folder.
// `reports`: each member that runs draws its report.png.
std::string ensemble_job(const Job& job, const StudyFile& study, int threads, bool reports);
// `on_fraction`: how much of its shaking is done, after each frame; `resumed`: it goes on
// from its checkpoint (else it starts afresh).
std::string seismic_job(const Job& job, const StudyFile& study, int threads,
                        const std::function<void(double)>& on_fraction, bool resumed);
std::string frequency_job(const Job& job, const StudyFile& study);
// One member of a run's ensemble (study members >= 2) in the run's folder, for a job of its
// own; its run's ensemble_job then keeps it. Returns "ran", "current" (kept), "interrupted"
// or "failed".
std::string ensemble_member(const Job& job, int member, const StudyFile& study, int threads, bool reports);

}  // namespace ishibashi
