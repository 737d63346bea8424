#include "io/atomic_file.h"

#include <fstream>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace ishibashi {

void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write) {
  std::filesystem::path temporary = target;
  temporary += ".tmp" + std::to_string(::getpid());
  write(temporary);
  std::error_code ec;
  std::filesystem::rename(temporary, target, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    throw std::runtime_error("cannot write " + target.string() + ": rename failed (" + ec.message() + ")");
  }
}

void write_text_atomically(const std::filesystem::path& target, const std::string& text) {
  write_atomically(target, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) throw std::runtime_error("cannot write " + target.string() + " (disk full or no permission?)");
  });
}

}  // namespace ishibashi
