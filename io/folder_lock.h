// One run at a time in an output folder: two runs given the same --out (or a resume while
// the run is still going) would write each other's frames, history and summary, and leave
// a folder that no run made. The claim is an flock on the folder itself: the kernel drops
// it when the process ends, however it ends, so a killed run leaves no stale claim.
#pragma once
#include <filesystem>

namespace ishibashi {

class FolderLock {
 public:
  // Claims `folder` (which must exist) until destroyed; throws InputError naming it when
  // another process holds it. Where the file system cannot lock a folder (some network
  // file systems), nothing is claimed.
  explicit FolderLock(const std::filesystem::path& folder);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace ishibashi
