#pragma once
// One writer per run folder: flock(2) on <run>/.lightbench.lock, held while
// the run writes. Without it a `lightbench run --resume` started while the run
// is still going rewrites log.csv under it and the first one's last rows
// vanish. The lock dies with its process (even on SIGKILL), so a leftover
// file never blocks a later resume; the file itself is kept, since deleting it
// would let two processes lock two different files of the same name.
#include <string>

namespace lb {

class RunLock {
 public:
  static constexpr const char* FileName = ".lightbench.lock";
  // Takes the lock or throws a ConfigError (at `experimentFile`) naming the
  // process that holds it; the folder is left as it was.
  // `what` names the folder in that message (the references cache uses it too).
  RunLock(const std::string& runDir, const std::string& experimentFile, const std::string& what = "run folder");
  ~RunLock();
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace lb
