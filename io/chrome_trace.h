// The timeline of a run's traced steps (World::trace_steps) in the Chrome trace-event JSON
// format, which Perfetto (ui.perfetto.dev) and Chromium's about:tracing open: one track
// per thread (the calling thread's holds each step, its stages inside), one slice per
// stage per step on every thread that ran part of it.
#pragma once
#include <filesystem>
#include <string>

#include "engine/profile.h"

namespace ishibashi {

// Writes `trace` to `file` atomically; `title` names the process track (the model, say).
void write_chrome_trace(const StageTrace& trace, const std::string& title, const std::filesystem::path& file);

}  // namespace ishibashi
