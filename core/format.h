#pragma once
// Numbers as people read them in summaries and progress lines: "0 s" rather
// than "4.3e-07 s", "1.13 M lookups/s" rather than "1.12742e+06 lookups/s".
// Files (log.csv, meta.json) keep full precision; only messages use these.
#include <string>

namespace lb {

// "0 s" below a millisecond, "12 ms", "3.45 s", "42.1 s", "2m05s", "1h02m".
std::string formatSeconds(double seconds);
// Three significant digits with an SI prefix: "950", "12.3 k", "1.13 M", "4.56 G";
// `unit` follows after a space ("1.13 M lookups/s").
std::string formatCount(double value, const std::string& unit = "");
// Bytes in binary units: "512 B", "22.8 MiB".
std::string formatBytes(double bytes);

}  // namespace lb
