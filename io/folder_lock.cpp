#include "io/folder_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>

#include "geometry/input_error.h"

namespace ishibashi {

FolderLock::FolderLock(const std::filesystem::path& folder) {
  // O_CLOEXEC: a child the run starts (the report's Python) must not inherit the claim.
  fd_ = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) return;  // the writes that follow report why the folder cannot be used
  if (::flock(fd_, LOCK_EX | LOCK_NB) == 0) return;
  const bool held = errno == EWOULDBLOCK;
  ::close(fd_);
  fd_ = -1;
  if (held)
    throw InputError(folder.string() +
                     ": another run is writing into this folder now; give this run another --out, or wait until "
                     "that one ends");
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor drops the claim
}

}  // namespace ishibashi
