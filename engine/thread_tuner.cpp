#include "engine/thread_tuner.h"

#include <algorithm>
#include <cmath>

namespace ishibashi {

ThreadTuner::ThreadTuner(int max_threads, bool adaptive) : adaptive_(adaptive) {
  max_threads = std::max(1, max_threads);
  for (int n = 1; n < max_threads; n *= 2) ladder_.push_back(n);
  ladder_.push_back(max_threads);
  cost_.assign(ladder_.size(), 0.0);
  current_ = best_ = static_cast<int>(ladder_.size()) - 1;  // start with every thread
}

void ThreadTuner::set_adaptive(bool adaptive) {
  adaptive_ = adaptive;
  if (!adaptive_) current_ = best_ = static_cast<int>(ladder_.size()) - 1;
}

void ThreadTuner::record(double step_s) {
  if (!adaptive_ || ladder_.size() == 1) return;
  window_s_ += step_s;
  if (++window_steps_ < 4 || window_s_ < kWindowS) return;
  const double per_step = window_s_ / window_steps_;
  window_s_ = 0;
  window_steps_ = 0;
  if (current_ != best_) {  // a probe ended: move if it was clearly faster
    cost_[current_] = per_step;
    if (per_step < kMargin * cost_[best_]) {
      best_ = current_;
      probe_every_ = kProbeEvery;
    } else if (kMargin * per_step > cost_[best_]) {  // clearly slower: the next probe later
      probe_every_ = std::min(2 * probe_every_, kProbeEveryMost);
    }
    current_ = best_;
    windows_to_probe_ = probe_every_;
    cost_after_probe_ = 0;
    return;
  }
  // The best size's cost follows the machine's load (a running average of its windows).
  cost_[best_] = cost_[best_] > 0 ? 0.5 * (cost_[best_] + per_step) : per_step;
  if (cost_after_probe_ == 0) {
    cost_after_probe_ = cost_[best_];
  } else if (std::abs(cost_[best_] - cost_after_probe_) > kLoadChange * cost_after_probe_) {
    probe_every_ = kProbeEvery;  // the load changed since the last probe: as at first
    windows_to_probe_ = std::min(windows_to_probe_, kProbeEvery);
  }
  if (--windows_to_probe_ > 0) return;
  const int last = static_cast<int>(ladder_.size()) - 1;
  int probe = best_ + (probe_down_ ? -1 : 1);
  if (probe < 0 || probe > last) probe = best_ + (probe_down_ ? 1 : -1);
  probe_down_ = !probe_down_;
  current_ = std::clamp(probe, 0, last);
}

}  // namespace ishibashi
