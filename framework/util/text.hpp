// Small text helpers shared by the host: one copy of each.
#pragma once
#include <cstdarg>
#include <cstdio>
#include <string>
#include <vector>

namespace gdsmc::host {

// The items separated by `sep`: join({"a", "b"}, ", ") == "a, b".
inline std::string join(const std::vector<std::string>& items, const std::string& sep) {
  std::string s;
  for (std::size_t k = 0; k < items.size(); ++k) s += (k ? sep : "") + items[k];
  return s;
}

// s in double quotes, with '"' and '\' escaped (a YAML or C string literal).
inline std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

// printf-style formatting into a std::string (messages, summary lines; up to 2047 characters).
inline std::string fmt(const char* format, ...) __attribute__((format(printf, 1, 2)));
inline std::string fmt(const char* format, ...) {
  char buf[2048];
  va_list ap;
  va_start(ap, format);
  std::vsnprintf(buf, sizeof buf, format, ap);
  va_end(ap);
  return buf;
}

// A size in bytes as people read it: "512 bytes", "9.8 MiB", "298 GiB" (binary units).
inline std::string bytes_text(double bytes) {
  static const char* const units[] = {"KiB", "MiB", "GiB", "TiB", "PiB"};
  if (bytes < 1024) return fmt("%.0f bytes", bytes);
  int u = -1;
  while (bytes >= 1024 && u < 4) bytes /= 1024, ++u;
  return fmt(bytes < 10 ? "%.1f %s" : "%.0f %s", bytes, units[u]);
}

}  // namespace gdsmc::host
