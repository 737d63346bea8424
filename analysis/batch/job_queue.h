// What the study and a sweep share to run many analyses: the queue their workers take
// jobs from, the test of whether a job's outputs are current, and the call of a report
// script (analysis/report/) on their output folder.
#pragma once
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace ishibashi {

// Jobs (indices) taken one at a time by any number of threads, in the given order (the long
// ones first), until the list ends or a stop is requested (stop_requested, seismic_run.h).
class JobQueue {
 public:
  explicit JobQueue(std::vector<int> jobs) : jobs_(std::move(jobs)) {}
  ~JobQueue() { join(); }

  int take();  // the next job, or -1 when none is left or a stop was requested (thread-safe)
  // job(i) for each job taken, on `threads` new threads (join() waits for them) or on this one.
  void start(int threads, const std::function<void(int)>& job);
  void work(const std::function<void(int)>& job);
  void join();

 private:
  std::mutex lock_;  // outside any time step
  std::vector<int> jobs_;
  std::size_t next_ = 0;
  std::vector<std::thread> threads_;
};

// Indices 0 .. count-1, for a queue of every job.
std::vector<int> every_job(int count);

// A job's outputs are current when its folder holds the stamp of the same inputs key: the
// program and everything the outputs depend on (inputs_key), written once the outputs are
// complete (stamp_outputs, last), so that a job cut short or run by another program or on
// other inputs runs again.
std::string inputs_key(const std::string& inputs);  // 16 hex digits of the program's and the inputs' fingerprint
bool outputs_current(const std::filesystem::path& folder, const std::string& key);
void stamp_outputs(const std::filesystem::path& folder, const std::string& key);

// Runs analysis/report/<script> of the source tree this program was built from, with
// Debian's python3, on `out` (and `title`, when given). Returns "" when it succeeded, else
// why not (the script missing, python3 missing, or the status it ended with).
std::string run_report_script(const char* script, const std::filesystem::path& out, const std::string& title = "");

}  // namespace ishibashi
