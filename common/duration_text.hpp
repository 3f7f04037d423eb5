// A duration for progress lines, as a person reads it: "42 s", "3 min 5 s", "2 h 10 min". A
// duration that is not finite or negative (nothing done yet to extrapolate from), or longer than
// 10 000 hours (a run that will not end as set up), reads "unknown".
#pragma once
#include <cmath>
#include <sstream>
#include <string>

namespace grainbank::common {

inline std::string duration_text(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0 || seconds > 3.6e7) return "unknown";
  const long s = std::lround(seconds);
  std::ostringstream out;
  if (s >= 3600) out << s / 3600 << " h " << (s % 3600) / 60 << " min";
  else if (s >= 60) out << s / 60 << " min " << s % 60 << " s";
  else out << s << " s";
  return out.str();
}

}  // namespace grainbank::common
