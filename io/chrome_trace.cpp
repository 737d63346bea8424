#include "io/chrome_trace.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "io/atomic_file.h"

namespace ishibashi {
namespace {

// Whole nanoseconds, rounded down, so that a slice that ends inside its parent still does
// once both are written in microseconds with three decimals.
std::int64_t nanoseconds(double seconds) { return static_cast<std::int64_t>(std::floor(seconds * 1e9)); }

std::string microseconds(std::int64_t ns) {
  char text[32];
  std::snprintf(text, sizeof text, "%" PRId64 ".%03" PRId64, ns / 1000, ns % 1000);
  return text;
}

std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out + "\"";
}

}  // namespace

void write_chrome_trace(const StageTrace& trace, const std::string& title, const std::filesystem::path& file) {
  std::ostringstream out;
  out << "{\"displayTimeUnit\": \"ms\", \"otherData\": {\"steps\": \"" << trace.first_step << ":" << trace.last_step
      << "\"},\n\"traceEvents\": [\n";
  out << R"({"name": "process_name", "ph": "M", "pid": 1, "tid": 0, "args": {"name": )" << quoted(title) << "}}";
  std::set<int> threads;
  for (const TraceSlice& s : trace.slices) threads.insert(s.thread);
  for (int t : threads)
    out << ",\n" << R"({"name": "thread_name", "ph": "M", "pid": 1, "tid": )" << t << R"(, "args": {"name": ")"
        << (t == 0 ? "thread 0 (steps)" : "thread " + std::to_string(t)) << "\"}}";
  for (const TraceSlice& s : trace.slices) {
    const std::int64_t begin = nanoseconds(s.begin_s), end = std::max(begin, nanoseconds(s.end_s));
    const bool step = s.stage < 0;
    out << ",\n{\"name\": " << quoted(step ? "step " + std::to_string(s.step) : kStageNames[s.stage])
        << ", \"cat\": \"" << (step ? "step" : "stage") << "\", \"ph\": \"X\", \"pid\": 1, \"tid\": " << s.thread
        << ", \"ts\": " << microseconds(begin) << ", \"dur\": " << microseconds(end - begin)
        << ", \"args\": {\"step\": " << s.step;
    if (!step)
      out << ", \"busy_us\": " << microseconds(nanoseconds(s.busy_s)) << ", \"chunks\": " << s.chunks
          << ", \"stolen_chunks\": " << s.stolen;
    out << "}}";
  }
  out << "\n]}\n";
  write_text_atomically(file, out.str());
}

}  // namespace ishibashi
