#include "analysis/batch/job_queue.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <vector>

#include "analysis/model/fingerprint.h"
#include "analysis/model/program_files.h"
#include "analysis/run/seismic_run.h"
#include "io/atomic_file.h"
#include "io/vtk_output.h"

namespace ishibashi {

int JobQueue::take() {
  const std::lock_guard<std::mutex> guard(lock_);
  return next_ < jobs_.size() && !stop_requested() ? jobs_[next_++] : -1;
}

void JobQueue::start(int threads, const std::function<void(int)>& job) {
  if (threads > 0) make_vtk_ready_for_threads();  // every job writes ParaView files
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

std::string inputs_key(const std::string& inputs) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx",
                static_cast<unsigned long long>(fnv1a(inputs, fnv1a(std::to_string(program_fingerprint())))));
  return hex;
}

bool outputs_current(const std::filesystem::path& folder, const std::string& key) {
  const std::filesystem::path stamp = folder / "inputs.key";
  return std::filesystem::exists(stamp) && file_bytes(stamp) == key + "\n";
}

void stamp_outputs(const std::filesystem::path& folder, const std::string& key) {
  write_text_atomically(folder / "inputs.key", key + "\n");
}

std::string run_report_script(const char* script, const std::filesystem::path& out, const std::string& title) {
  const std::string python = std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string path = program_file("analysis/report/" + std::string(script)).string(), folder = out.string();
  if (!std::filesystem::exists(path))  // a program copied away from its checkout
    return path + " is missing: the program runs the report scripts installed beside it (cmake --install: "
                  "PREFIX/share/ishibashi) or else those of the source tree it was built from";
  // Started with its arguments as they are, no shell between: a folder or title with
  // spaces, quotes or $ reaches the script unchanged.
  std::vector<char*> argv{const_cast<char*>(python.c_str()), const_cast<char*>(path.c_str()),
                          const_cast<char*>(folder.c_str())};
  if (!title.empty()) argv.push_back(const_cast<char*>(title.c_str()));
  argv.push_back(nullptr);
  pid_t child = 0;
  if (const int error = posix_spawnp(&child, python.c_str(), nullptr, nullptr, argv.data(), environ); error != 0)
    return "cannot start " + python + ": " + std::strerror(error) + " (bash scripts/setup.sh installs it)";
  int status = 0;
  while (waitpid(child, &status, 0) < 0)
    if (errno != EINTR) return std::string("lost ") + script + ": " + std::strerror(errno);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
  return python + " " + script + (WIFEXITED(status) ? " ended with status " + std::to_string(WEXITSTATUS(status))
                                                    : " was stopped by signal " + std::to_string(WTERMSIG(status))) +
         " (its own message is above; it needs matplotlib and vtk: bash scripts/setup.sh)";
}

}  // namespace ishibashi
