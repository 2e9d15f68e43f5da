#pragma once
// log.csv of an experiment run: one row per snapshot of every run
// (LogColumns), appended and flushed row by row, so a run that is killed
// keeps every row written before. On --resume, rows of runs without their
// final row, and torn lines, are dropped; finished runs stay.
#include <fstream>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace lb {

// Columns of log.csv, in order (nullptr-terminated). `host`, `cpu` and
// `threads` say where a run was timed: the report compares times only
// between runs of one kind of machine (cpu and threads). The metrics are
// experiments/metrics.h's: raw, and the squared errors also corrected for
// the reference's noise (`*_corrected`).
extern const char* const LogColumns[];
size_t logColumnCount();

// A run's identity in the log: scene, label and repeat.
std::string runKey(const std::string& scene, const std::string& label, const std::string& repeat);

// A number with 9 significant digits, as the log holds it.
std::string logNumber(double v);
// A CSV field, quoted when it needs to be (RFC 4180).
std::string csvField(const std::string& s);
// Splits one CSV line; false on a torn line.
bool parseCsvLine(const std::string& line, std::vector<std::string>& out);

// The rows of a log to resume (in today's columns) of the runs that
// finished, and their keys; throws a ConfigError naming the file and line if
// it is not a lightbench log or a row before the last is torn (only a kill
// mid-write tears a line, and only the last). Writes nothing: the runner
// calls it before anything else, so a refused resume is one line.
std::vector<std::string> readResumableLog(const std::string& path, std::set<std::string>* completed);

class LogWriter {
 public:
  // Starts the log at `path`; with `resume`, keeps the rows of the runs that
  // finished and adds their keys to `completed`.
  LogWriter(const std::string& path, bool resume, std::set<std::string>* completed);
  void write(const std::vector<std::string>& fields);  // thread-safe
  // Several rows in one write and flush (a run's final rows: a kill cannot
  // fall between them, only tear the last).
  void write(const std::vector<std::vector<std::string>>& rows);

 private:
  std::ofstream out_;
  std::mutex mutex_;
};

}  // namespace lb
