#include "io/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace ishibashi {

void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write) {
  // Beside the target, with its extension (readers that go by it, CGAL's, still know it).
  std::filesystem::path temporary = target;
  temporary.replace_filename(target.stem().string() + ".tmp" + std::to_string(::getpid()) + target.extension().string());
  std::error_code ec;
  try {
    write(temporary);
  } catch (...) {
    std::filesystem::remove(temporary, ec);  // a full disk must not keep the half-written file either
    throw;
  }
  std::filesystem::rename(temporary, target, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    throw std::runtime_error("cannot write " + target.string() + ": rename failed (" + ec.message() + ")");
  }
}

void write_text_atomically(const std::filesystem::path& target, const std::string& text) {
  write_atomically(target, [&](const std::filesystem::path& tmp) {
    // stdio rather than a stream: errno then says why a write failed (a full disk, a
    // file-size limit, no permission), and fclose's own failure is seen.
    std::FILE* out = std::fopen(tmp.c_str(), "wb");
    bool failed = out == nullptr;
    int error = failed ? errno : 0;
    if (out != nullptr) {
      if (std::fwrite(text.data(), 1, text.size(), out) != text.size() || std::fflush(out) != 0)
        failed = true, error = errno;
      if (std::fclose(out) != 0 && !failed) failed = true, error = errno;
    }
    if (failed) throw std::runtime_error("cannot write " + target.string() + ": " + std::strerror(error));
  });
}

}  // namespace ishibashi
