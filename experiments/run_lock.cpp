#include "experiments/run_lock.h"
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/file.h>
#include <unistd.h>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include "core/error.h"

namespace lb {

namespace {
// The pid the holder wrote, or "" (it may not have written it yet).
std::string holderPid(int fd) {
  char buf[32] = {0};
  ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
  std::string pid;
  for (ssize_t i = 0; i < n && buf[i] >= '0' && buf[i] <= '9'; ++i) pid += buf[i];
  return pid;
}
}  // namespace

RunLock::RunLock(const std::string& runDir, const std::string& experimentFile, const std::string& what) {
  std::string path = (std::filesystem::path(runDir) / FileName).string();
  // O_CLOEXEC: the report script run at the end must not inherit (and so
  // prolong) the lock.
  // O_NOFOLLOW and O_NONBLOCK, and a regular file only: the pid written
  // below went through a symbolic link of that name to whatever it named
  // (issue 34: --resume overwrote /etc/passwd), and a FIFO would block.
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0644);
  // Before anything renders, so an unusable lock (a directory of that name,
  // a read-only folder) is bad input: exit 2 and one line, not a late failure.
  if (fd_ < 0) {
    int err = errno;
    std::error_code ec;
    throw ConfigError(experimentFile, 0, "", "cannot open the lock file " + path + ": " +
                                                 (err == ELOOP ? std::string("it is a symbolic link (remove it)")
                                                               : std::string(std::strerror(err))) +
                                                 (std::filesystem::is_directory(path, ec) ? " (remove that directory)" : ""));
  }
  struct stat st {};
  // A second hard link would be written through as a symbolic link was.
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode) || st.st_nlink != 1) {
    ::close(fd_);
    fd_ = -1;
    throw ConfigError(experimentFile, 0, "", "the lock file " + path +
                                                 " is not a regular file of its own (a device, FIFO or hard link); remove it");
  }
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    int err = errno;
    std::string pid = holderPid(fd_);
    ::close(fd_);
    if (err == EWOULDBLOCK)
      throw ConfigError(experimentFile, 0, "",
                        what + " " + runDir + " is in use by another lightbench process" +
                            (pid.empty() ? std::string() : " (pid " + pid + ")"));
    throw ConfigError(experimentFile, 0, "", "cannot lock " + path + ": " + std::strerror(err));
  }
  // Only once locked: a refused process must not touch the file. The pid is
  // informative (for the message above), so a failed write is not an error.
  std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd_, 0) == 0) {
    ssize_t written = ::pwrite(fd_, pid.data(), pid.size(), 0);
    (void)written;
  }
}

RunLock::~RunLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

}  // namespace lb
