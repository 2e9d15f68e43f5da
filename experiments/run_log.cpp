#include "experiments/run_log.h"
#include <algorithm>
#include <filesystem>
#include <sstream>
#include "core/error.h"
#include "core/image.h"

namespace lb {

const char* const LogColumns[] = {
    "scene", "label", "integrator", "repeat", "seed", "time_s", "preprocess_s", "spp", "rmse", "relmse", "mape",
    "variance", "nonfinite", "rmse_crop", "relmse_crop", "mape_crop", "over_budget_s", "host", "cpu", "threads",
    // Issue 32: the trimmed relMSE, and the squared errors corrected for the
    // reference's noise (experiments/metrics.h; MSE, since a corrected MSE
    // can be negative). `final` stays last: a run is finished by its last field.
    "relmse_trimmed", "mse_corrected", "relmse_corrected", "relmse_trimmed_corrected", "mse_crop_corrected",
    "relmse_crop_corrected", "final", nullptr};

size_t logColumnCount() {
  size_t n = 0;
  while (LogColumns[n]) ++n;
  return n;
}

std::string runKey(const std::string& scene, const std::string& label, const std::string& repeat) {
  return scene + "\x1f" + label + "\x1f" + repeat;
}

std::string logNumber(double v) {
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

bool parseCsvLine(const std::string& line, std::vector<std::string>& out) {
  out.clear();
  std::string field;
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"')
        field += '"', ++i;
      else if (c == '"')
        quoted = false;
      else
        field += c;
    } else if (c == '"')
      quoted = true;
    else if (c == ',')
      out.push_back(field), field.clear();
    else
      field += c;
  }
  out.push_back(field);
  return !quoted;
}

std::vector<std::string> readResumableLog(const std::string& path, std::set<std::string>* completed) {
  std::vector<std::string> kept;
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw ConfigError(path, 0, "", "not a regular file (a run's log is one); remove it to start the log again");
  if (std::filesystem::exists(path)) {
    std::ifstream in(path);
    std::string line;
    std::vector<std::vector<std::string>> rows;
    // A log written by an older version has fewer columns: its rows are
    // carried over by column name, the new columns left empty.
    std::vector<std::string> header, f;
    const bool empty = !std::getline(in, line);
    parseCsvLine(line, header);
    std::vector<int> from;  // for each current column, its index in the file (-1: absent)
    for (size_t c = 0; LogColumns[c]; ++c) {
      auto at = std::find(header.begin(), header.end(), LogColumns[c]);
      from.push_back(at == header.end() ? -1 : int(at - header.begin()));
    }
    // A file that is not a log (overwritten, corrupted) must not be taken
    // for an empty one and silently started again: every version's log
    // has these columns, `final` last.
    for (const char* column : {"scene", "label", "repeat", "final"})
      if (!empty && std::find(header.begin(), header.end(), column) == header.end())
        throw ConfigError(path, 1, "", std::string("not a lightbench log: its header has no '") + column +
                                           "' column (move the file aside, or run without --resume)");
    if (!empty && header.back() != "final")
      throw ConfigError(path, 1, "", "not a lightbench log: its header does not end with 'final'");
    // Only the last line may be torn (a run killed while writing it).
    std::vector<std::string> lines;
    while (std::getline(in, line)) lines.push_back(line);
    for (size_t n = 0; n < lines.size(); ++n) {
      const bool parsed = parseCsvLine(lines[n], f) && f.size() == header.size();
      if (!parsed && n + 1 < lines.size())
        throw ConfigError(path, int(n + 2), "",
                          "a malformed row (" + std::to_string(f.size()) + " fields, the header has " +
                              std::to_string(header.size()) + ") before the last line: the log is corrupt");
      if (!parsed) continue;  // a torn last line
      std::vector<std::string> row;
      for (int i : from) row.push_back(i < 0 ? "" : f[size_t(i)]);
      std::string text;
      for (size_t i = 0; i < row.size(); ++i) text += (i ? "," : "") + csvField(row[i]);
      rows.push_back(row), kept.push_back(text);
    }
    for (const auto& r : rows)
      if (r.back() == "1") completed->insert(runKey(r[0], r[1], r[3]));
    std::vector<std::string> filtered;
    for (size_t i = 0; i < rows.size(); ++i)
      if (completed->count(runKey(rows[i][0], rows[i][1], rows[i][3]))) filtered.push_back(kept[i]);
    kept = filtered;
  }
  return kept;
}

LogWriter::LogWriter(const std::string& path, bool resume, std::set<std::string>* completed) {
  std::vector<std::string> kept;
  if (resume) kept = readResumableLog(path, completed);
  std::string header;
  for (size_t i = 0; LogColumns[i]; ++i) header += (i ? "," : "") + std::string(LogColumns[i]);
  std::string content = header + "\n";
  for (const auto& l : kept) content += l + "\n";
  writeTextFile(path, content);
  out_.open(path, std::ios::app);
}

void LogWriter::write(const std::vector<std::string>& fields) { write(std::vector<std::vector<std::string>>{fields}); }

void LogWriter::write(const std::vector<std::vector<std::string>>& rows) {
  std::string text;
  for (const auto& fields : rows) {
    for (size_t i = 0; i < fields.size(); ++i) text += (i ? "," : "") + csvField(fields[i]);
    text += "\n";
  }
  std::lock_guard<std::mutex> lock(mutex_);
  out_ << text;
  out_.flush();
}

}  // namespace lb
