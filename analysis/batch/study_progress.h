// What `ishibashi study` says while its jobs run: which jobs are running and how far each
// has got, how many are done, and about how long the whole study has left.
#pragma once
#include <chrono>
#include <cstddef>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

namespace ishibashi {

struct JobProgress {
  enum State { pending, running, done, failed, skipped };
  std::string name;       // e.g. "run nishida_b_kobe_dry"
  bool is_run = false;    // a seismic run (else a frequency analysis)
  State state = pending;
  double fraction = 0;    // of its shaking, for a running run
  double elapsed_s = 0;   // wall time since it started (running) or in all (done)
  // Where the pace of a run is measured from: a fresh run from its start (0 of its shaking,
  // 0 s); a run that goes on from a checkpoint from its first report (the fraction it had
  // reached, and the seconds it took to load and get there), so the part already done
  // before the checkpoint is not taken as done in no time.
  bool awaiting_origin = false;  // a resumed run before its first report
  double origin_fraction = 0;
  double origin_s = 0;
};

// Wall seconds the study has left with `workers` jobs at once, from the jobs so far: a run
// at fraction f after e s, from its origin (f0, e0), takes (e - e0) / (f - f0) for its whole
// shaking (once f - f0 >= 0.05; for a fresh run e / f); a pending job as long as the
// mean of the done and projected jobs of its kind. Jobs of a kind with nothing to go by yet
// (say the frequency analyses, which run last) are left out and counted in `not_counted`.
struct TimeLeft {
  double seconds = 0;
  int not_counted = 0;
};
TimeLeft estimate_time_left(const std::vector<JobProgress>& jobs, int workers);

// "1 h 05 min", "12 min", "40 s".
std::string duration_text(double seconds);

struct State;
// Wraps `frame` (a run's on_frame, or none) with a line to `event` at every tenth of the
// shaking: `name`, how far it is and, at its pace since this process saw its first frame
// (settling, or a resume, before it), how long it has to go. For what runs for hours with
// no terminal to draw a bar on (an ensemble's members, a run into a log file).
std::function<void(const State&, double)> with_progress_lines(std::function<void(const State&, double)> frame,
                                                               const std::string& name,
                                                               const std::function<void(const std::string&)>& event);

// A line to `event` every 0.25 s of the settling (a large bridge settles for minutes in
// which a run otherwise says nothing): `name`, the time settled of at most settle_max_s and
// the kinetic energy against the threshold below which the settling ends. A run's
// on_settle_frame.
std::function<void(const State&, double, double)> settling_lines(const std::string& name,
                                                                 const std::function<void(const std::string&)>& event);

// Thread-safe: each worker reports its own job; a line goes to `print` when a job starts
// or ends and at most every `every_s` seconds while runs advance.
class StudyProgress {
 public:
  StudyProgress(std::vector<JobProgress> jobs, int workers, double every_s, std::function<void(const std::string&)> print);
  void started(std::size_t job, bool resumed = false);  // resumed: goes on from a checkpoint
  void advanced(std::size_t job, double fraction);
  void finished(std::size_t job, JobProgress::State how);  // done, failed or skipped

 private:
  using Clock = std::chrono::steady_clock;
  void print_locked();  // with lock_ held
  std::mutex lock_;
  std::vector<JobProgress> jobs_;
  std::vector<Clock::time_point> started_;
  int workers_;
  double every_s_;
  Clock::time_point last_print_;
  std::function<void(const std::string&)> print_;
};

}  // namespace ishibashi
