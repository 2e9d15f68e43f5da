#pragma once
// Calling experiments/report.py at the end of a run: as an argument list (no
// shell, so any path works), with an interpreter that can be chosen, and a
// message naming what is missing when it cannot run.
#include <string>

namespace lb {

// The interpreter: `python` if given, else $LIGHTBENCH_PYTHON, else
// /usr/bin/python3 (Debian's, which has python3-matplotlib).
std::string reportInterpreter(const std::string& python);

// Runs `interpreter report.py runDir`, with this build's Python package on
// PYTHONPATH (the report reads EXRs through it). Returns "" on success, else
// one line saying what failed (the interpreter missing, matplotlib missing,
// the script's exit status).
// With `mixedMachines`, runs timed on different kinds of machines (the log's
// cpu and threads columns) are compared anyway; else the report refuses.
std::string runReportScript(const std::string& interpreter, const std::string& runDir, bool mixedMachines = false);

}  // namespace lb
