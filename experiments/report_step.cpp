#include "experiments/report_step.h"
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cstdlib>
#include <vector>

extern char** environ;

namespace lb {

std::string reportInterpreter(const std::string& python) {
  if (!python.empty()) return python;
  if (const char* env = std::getenv("LIGHTBENCH_PYTHON"); env && *env) return env;
  return "/usr/bin/python3";
}

namespace {

// Runs argv (argv[0] looked up on PATH) with `pythonPath` prepended to
// PYTHONPATH; returns the exit status, or -1 if it could not be started.
int spawn(const std::vector<std::string>& argv, const std::string& pythonPath) {
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e)
    if (std::string(*e).rfind("PYTHONPATH=", 0) != 0) env.emplace_back(*e);
  const char* old = std::getenv("PYTHONPATH");
  env.push_back("PYTHONPATH=" + pythonPath + (old && *old ? ":" + std::string(old) : ""));
  std::vector<char*> args, envp;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  for (auto& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, args[0], nullptr, nullptr, args.data(), envp.data()) != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

}  // namespace

std::string runReportScript(const std::string& interpreter, const std::string& runDir, bool mixedMachines) {
  const std::string packageDir = LIGHTBENCH_PYTHON_DIR;
  int probe = spawn({interpreter, "-c", "import matplotlib, numpy"}, packageDir);
  if (probe == -1 || probe == 127)
    return "cannot run the report's interpreter '" + interpreter +
           "' (choose one with --python or LIGHTBENCH_PYTHON; Debian's is /usr/bin/python3)";
  if (probe != 0)
    return "'" + interpreter + "' has no matplotlib or numpy (scripts/install-deps.sh installs python3-matplotlib "
           "for /usr/bin/python3; or choose another with --python)";
  std::vector<std::string> command = {interpreter, std::string(LIGHTBENCH_SOURCE_DIR) + "/experiments/report.py", runDir};
  if (mixedMachines) command.push_back("--mixed-machines");
  int status = spawn(command, packageDir);
  if (status != 0) return "the report script exited with status " + std::to_string(status);
  return "";
}

}  // namespace lb
