#include "analysis/batch/study_progress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/state.h"

namespace ishibashi {

TimeLeft estimate_time_left(const std::vector<JobProgress>& jobs, int workers) {
  constexpr double kFirstFraction = 0.05;  // before it, a run's pace is mostly its settling
  // The whole duration of each kind's jobs so far: done ones as they took, running runs
  // projected; both at the pace measured since their origin (a resumed run's part after its
  // checkpoint stands for the whole).
  auto covered = [](const JobProgress& j) { return j.fraction - j.origin_fraction; };
  auto projected = [&](const JobProgress& j) {
    return j.state == JobProgress::running && j.is_run && covered(j) >= kFirstFraction;
  };
  double sum[2] = {0, 0};
  int count[2] = {0, 0};
  for (const JobProgress& j : jobs) {
    double total = -1;
    if (j.state == JobProgress::done && 1 - j.origin_fraction >= kFirstFraction)
      total = (j.elapsed_s - j.origin_s) / (1 - j.origin_fraction);
    if (projected(j)) total = (j.elapsed_s - j.origin_s) / covered(j);
    if (total >= 0) sum[j.is_run] += total, ++count[j.is_run];
  }
  TimeLeft t;
  double work = 0, longest = 0;  // seconds of work left in all; the longest single job's
  for (const JobProgress& j : jobs) {
    if (j.state != JobProgress::pending && j.state != JobProgress::running) continue;
    double left;
    if (projected(j))
      left = (j.elapsed_s - j.origin_s) / covered(j) * (1 - j.fraction);
    else if (count[j.is_run] > 0)
      left = std::max(0.0, sum[j.is_run] / count[j.is_run] * (1 - j.origin_fraction) -
                               (j.state == JobProgress::running ? j.elapsed_s - j.origin_s : 0.0));
    else {
      ++t.not_counted;
      continue;
    }
    work += left;
    longest = std::max(longest, left);
  }
  t.seconds = std::max(longest, work / std::max(workers, 1));
  return t;
}

std::string duration_text(double seconds) {
  char text[64];
  const long s = std::lround(seconds);
  if (s >= 3600)
    std::snprintf(text, sizeof text, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
  else if (s >= 60)
    std::snprintf(text, sizeof text, "%ld min", (s + 30) / 60);
  else
    std::snprintf(text, sizeof text, "%ld s", s);
  return text;
}

std::function<void(const State&, double)> with_progress_lines(std::function<void(const State&, double)> frame,
                                                               const std::string& name,
                                                               const std::function<void(const std::string&)>& event) {
  struct Pace {  // from the first frame this process saw (settling, or a resume, before it)
    std::chrono::steady_clock::time_point start;
    double done_at_start = -1;
    int next_tenth = 0;
  };
  return [frame = std::move(frame), name, event, pace = Pace{}](const State& s, double done) mutable {
    if (frame) frame(s, done);
    if (pace.done_at_start < 0) {
      pace.start = std::chrono::steady_clock::now();
      pace.done_at_start = done;
      pace.next_tenth = static_cast<int>(std::floor(10 * done + 1e-9)) + 1;
      return;
    }
    if (10 * done + 1e-9 < pace.next_tenth || done >= 1) return;
    pace.next_tenth = static_cast<int>(std::floor(10 * done + 1e-9)) + 1;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - pace.start).count();
    char share[40];
    std::snprintf(share, sizeof share, ": %.0f %% of the shaking done", 100 * done);
    event(name + share + ", about " + duration_text(elapsed * (1 - done) / (done - pace.done_at_start)) + " to go");
  };
}

std::function<void(const State&, double, double)> settling_lines(const std::string& name,
                                                                 const std::function<void(const std::string&)>& event) {
  return [name, event, lines = 0](const State& s, double settle_max_s, double settled_below_j) mutable {
    if (s.time_s < 0.25 * (lines + 1) - 1e-9) return;
    lines = static_cast<int>(s.time_s / 0.25 + 1e-9);
    char text[160];
    std::snprintf(text, sizeof text, ": settling, %.2f s of at most %.2f s, kinetic energy %.3g J (settled below %.3g J)",
                  s.time_s, settle_max_s, s.energy.kinetic_j, settled_below_j);
    event(name + text);
  };
}

StudyProgress::StudyProgress(std::vector<JobProgress> jobs, int workers, double every_s,
                             std::function<void(const std::string&)> print)
    : jobs_(std::move(jobs)),
      started_(jobs_.size()),
      workers_(workers),
      every_s_(every_s),
      last_print_(Clock::now()),
      print_(std::move(print)) {}

void StudyProgress::started(std::size_t job, bool resumed) {
  const std::lock_guard<std::mutex> guard(lock_);
  jobs_[job].state = JobProgress::running;
  jobs_[job].awaiting_origin = resumed;
  started_[job] = Clock::now();
}

void StudyProgress::advanced(std::size_t job, double fraction) {
  const std::lock_guard<std::mutex> guard(lock_);
  JobProgress& j = jobs_[job];
  j.fraction = fraction;
  if (j.awaiting_origin) {
    j.awaiting_origin = false;
    j.origin_fraction = fraction;
    j.origin_s = std::chrono::duration<double>(Clock::now() - started_[job]).count();
  }
  if (std::chrono::duration<double>(Clock::now() - last_print_).count() >= every_s_) print_locked();
}

void StudyProgress::finished(std::size_t job, JobProgress::State how) {
  const std::lock_guard<std::mutex> guard(lock_);
  JobProgress& j = jobs_[job];
  j.state = how;
  if (how == JobProgress::skipped) return;
  j.elapsed_s = std::chrono::duration<double>(Clock::now() - started_[job]).count();
  print_locked();
}

void StudyProgress::print_locked() {
  last_print_ = Clock::now();
  int done = 0, failed = 0, total = 0;
  std::string running;
  for (std::size_t k = 0; k < jobs_.size(); ++k) {
    JobProgress& j = jobs_[k];
    if (j.state == JobProgress::skipped) continue;
    ++total;
    done += j.state == JobProgress::done;
    failed += j.state == JobProgress::failed;
    if (j.state != JobProgress::running) continue;
    j.elapsed_s = std::chrono::duration<double>(last_print_ - started_[k]).count();
    char text[200];
    if (j.is_run)
      std::snprintf(text, sizeof text, "%s%s %.0f %% of its shaking", running.empty() ? "" : ", ", j.name.c_str(), 100 * j.fraction);
    else
      std::snprintf(text, sizeof text, "%s%s", running.empty() ? "" : ", ", j.name.c_str());
    running += text + (" (" + duration_text(j.elapsed_s) + ")");
  }
  const TimeLeft left = estimate_time_left(jobs_, workers_);
  std::string line = "progress: " + std::to_string(done) + " of " + std::to_string(total) + " jobs done";
  if (failed) line += ", " + std::to_string(failed) + " failed";
  total -= failed;  // what is left to do
  if (!running.empty()) line += "; running " + running;
  if (done < total && left.not_counted == total - done)
    line += "; time left not known yet";
  else if (done < total)
    line += "; about " + duration_text(left.seconds) + " left" +
            (left.not_counted ? " (and " + std::to_string(left.not_counted) + " more not estimated: none of their kind has run yet)" : "");
  print_(line);
}

}  // namespace ishibashi
