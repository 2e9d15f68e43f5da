#include "core/format.h"
#include <cmath>
#include <cstdio>

namespace lb {

std::string formatSeconds(double s) {
  char buf[32];
  if (!std::isfinite(s)) return "?";
  if (s < 1e-3) return "0 s";
  // Thresholds just below each unit's rounding edge: 0.9996 s is "1.00 s", not "1000 ms".
  if (s < 0.9995) std::snprintf(buf, sizeof buf, "%.0f ms", s * 1e3);
  else if (s < 9.995) std::snprintf(buf, sizeof buf, "%.2f s", s);
  else if (s < 119.95) std::snprintf(buf, sizeof buf, "%.1f s", s);
  else if (s < 7200) std::snprintf(buf, sizeof buf, "%lldm%02llds", (long long)s / 60, (long long)s % 60);
  else if (s < 1e15) std::snprintf(buf, sizeof buf, "%lldh%02lldm", (long long)s / 3600, (long long)s / 60 % 60);
  else return "forever";
  return buf;
}

namespace {
// 3 significant digits: 1.23, 12.3, 123.
std::string threeDigits(double v) {
  char buf[32];
  double a = std::abs(v);
  std::snprintf(buf, sizeof buf, a < 9.995 ? "%.2f" : a < 99.95 ? "%.1f" : "%.0f", v);
  return buf;
}
}  // namespace

std::string formatCount(double v, const std::string& unit) {
  if (!std::isfinite(v)) return "?" + (unit.empty() ? "" : " " + unit);
  static const char* prefixes[] = {"", "k", "M", "G", "T", "P"};
  int p = 0;
  // Rounding may carry 999.7 k to 1000 k: step up before printing.
  while (std::abs(v) >= 999.5 && p < 5) v /= 1000, ++p;
  std::string out = p == 0 && v == std::floor(v) ? std::to_string((long long)v) : threeDigits(v);
  if (p > 0) out += std::string(" ") + prefixes[p];
  if (!unit.empty()) out += " " + unit;
  return out;
}

std::string formatBytes(double bytes) {
  static const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  int u = 0;
  while (bytes >= 1023.5 && u < 4) bytes /= 1024, ++u;
  return (u == 0 ? std::to_string((long long)bytes) : threeDigits(bytes)) + " " + units[u];
}

}  // namespace lb
