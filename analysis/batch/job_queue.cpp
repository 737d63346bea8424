#include "analysis/batch/job_queue.h"

#include <cstdlib>
#include <numeric>

#include "analysis/run/seismic_run.h"

namespace ishibashi {

int JobQueue::take() {
  const std::lock_guard<std::mutex> guard(lock_);
  return next_ < jobs_.size() && !stop_requested() ? jobs_[next_++] : -1;
}

void JobQueue::start(int threads, const std::function<void(int)>& job) {
  for (int t = 0; t < threads; ++t) threads_.emplace_back([this, job] { work(job); });
}

void JobQueue::work(const std::function<void(int)>& job) {
  for (int i = take(); i >= 0; i = take()) job(i);
}

void JobQueue::join() {
  for (std::thread& t : threads_) t.join();
  threads_.clear();
}

std::vector<int> every_job(int count) {
  std::vector<int> jobs(static_cast<std::size_t>(std::max(0, count)));
  std::iota(jobs.begin(), jobs.end(), 0);
  return jobs;
}

bool run_report_script(const char* script, const std::filesystem::path& out) {
  const std::string python = std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string command =
      python + " " + ISHIBASHI_SOURCE_DIR "/analysis/report/" + script + " \"" + out.string() + "\"";
  return std::system(command.c_str()) == 0;
}

}  // namespace ishibashi
