#include "config/yaml_reader.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <set>

#include "config/errors.hpp"
#include "config/overrides.hpp"
#include "config/suggest.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

std::string read_pipeline_text(const std::filesystem::path& file) {
  auto refuse = [&](const std::string& why) {
    throw PipelineError({file.string() + ": cannot read the pipeline file (" + why + ")"});
  };
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) refuse(std::strerror(errno));
  if (S_ISDIR(st.st_mode)) refuse("it is a directory");
  if (!S_ISREG(st.st_mode)) {
    const char* kind = S_ISCHR(st.st_mode) ? "a character device" : S_ISBLK(st.st_mode) ? "a block device"
                       : S_ISFIFO(st.st_mode) ? "a pipe" : S_ISSOCK(st.st_mode) ? "a socket" : "not a file";
    refuse(std::string("it is ") + kind + ", not a regular file; a pipeline is a YAML text file of at most " +
           bytes_text(kMaxPipelineBytes));
  }
  const auto too_large = [&](const std::string& size) {
    refuse("it is " + size + "; a pipeline file is at most " + bytes_text(kMaxPipelineBytes));
  };
  if (static_cast<std::uintmax_t>(st.st_size) > kMaxPipelineBytes)
    too_large(bytes_text(static_cast<double>(st.st_size)) + " (" + std::to_string(st.st_size) + " bytes)");
  std::ifstream in(file, std::ios::binary);
  if (!in) refuse(std::strerror(errno));
  std::string text;
  text.reserve(static_cast<std::size_t>(st.st_size));
  char buf[1 << 16];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    text.append(buf, static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxPipelineBytes) too_large("more than " + bytes_text(kMaxPipelineBytes) + " (it grew while it was read)");
  }
  if (in.bad()) refuse(std::strerror(errno));
  return text;
}

SourceLocation Checker::where(const std::string& path, const YAML::Node& node) const {
  auto sets = [&](const std::string& assignment) {
    const std::string key = canonical_key(assignment.substr(0, assignment.find('=')));
    return path == key || path.rfind(key + ".", 0) == 0 || path.rfind(key + "[", 0) == 0;
  };
  for (auto it = from_sweep_.rbegin(); it != from_sweep_.rend(); ++it)
    if (sets(it->first)) return it->second;
  for (const auto& o : overrides_)
    if (sets(o)) return SourceLocation{"--set " + o, 0, 0};
  const YAML::Mark m = node.Mark();
  if (m.line >= 0) return SourceLocation{file_.string(), m.line + 1, m.column + 1};  // yaml-cpp marks are 0-based
  // A node the file does not hold: an assignment made it, one that sets something below `path`
  // (a misspelt first key, "colision.alpha", is reported at "colision"; "collision.alpha.x" at
  // "collision.alpha"). Located at that assignment: a sweep entry's file:line:column.
  auto below = [&](const std::string& assignment) {
    const std::string key = canonical_key(assignment.substr(0, assignment.find('=')));
    return !path.empty() && (key.rfind(path + ".", 0) == 0 || key.rfind(path + "[", 0) == 0);
  };
  for (auto it = from_sweep_.rbegin(); it != from_sweep_.rend(); ++it)
    if (below(it->first)) return it->second;
  for (const auto& o : overrides_)
    if (below(o)) return SourceLocation{"--set " + o, 0, 0};
  return SourceLocation{file_.string(), 0, 0};
}

void Checker::error(const SourceLocation& at, const std::string& path, const std::string& message,
                    const std::string& valid) {
  errors_.push_back(ConfigError{at.str(), path, plugin_, parameter_, message, valid, ErrorOrigin::host_check, ""});
}

void Checker::error(const std::string& path, const YAML::Node& node, const std::string& message,
                    const std::string& valid) {
  error(where(path, node), path, message, valid);
}

void Checker::plugin_error(const SourceLocation& at, const std::string& path, ErrorOrigin origin,
                           const std::string& message) {
  error(at, path, message);
  errors_.back().origin = origin;
}

Checker::About::About(Checker& c, const std::string& plugin, const std::string& parameter)
    : c_(c), plugin_(c.plugin_), parameter_(c.parameter_) {
  c.plugin_ = plugin;
  c.parameter_ = parameter;
}

Checker::About::~About() {
  c_.plugin_ = plugin_;
  c_.parameter_ = parameter_;
}

bool Checker::check_keys(const YAML::Node& map, const std::string& path, const std::vector<std::string>& allowed) {
  std::set<std::string> seen;
  bool known = true;
  for (auto it = map.begin(); it != map.end(); ++it) {
    const std::string key = it->first.Scalar();
    const std::string sub = path.empty() ? key : path + "." + key;
    if (!seen.insert(key).second) error(sub, it->first, "duplicate key '" + key + "'");
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      known = false;
      auto close = closest_names(key, allowed);
      error(sub, it->first, "unknown key '" + key + "'" +
                                (close.empty() ? "" : "; did you mean " + join(close, ", ") + "?") +
                                " (valid keys: " + join(allowed, ", ") + ")");
    }
  }
  return known;
}

namespace {
// A decimal integer literal: optional sign, then digits only (what strtoll reads in base 10).
bool is_decimal_integer(const std::string& t) {
  std::size_t i = (!t.empty() && (t[0] == '+' || t[0] == '-')) ? 1 : 0;
  if (i == t.size()) return false;
  for (; i < t.size(); ++i)
    if (t[i] < '0' || t[i] > '9') return false;
  return true;
}
// Why a scalar YAML reads as a number but not as a usable one, or "" if it is usable: beyond the
// range of a double (yaml-cpp then refuses it), NaN or infinity, or so small that it reads as 0 or
// a subnormal number (which has lost precision).
std::string range_problem(const std::string& text, double& v) {
  errno = 0;
  char* end = nullptr;
  v = std::strtod(text.c_str(), &end);
  const bool parsed = end != text.c_str() && *end == '\0';
  if (!parsed) return "";
  if (std::isnan(v) || (std::isinf(v) && errno != ERANGE)) return "'" + text + "' is not a finite number";
  if (std::isinf(v)) return "'" + text + "' is out of range: numbers must be at most about 1.8e308 in magnitude";
  if (v != 0 && !std::isnormal(v))
    return "'" + text + "' is too small to represent exactly: nonzero numbers must be at least about 2.2e-308 in magnitude";
  if (v == 0 && errno == ERANGE)
    return "'" + text + "' is too small to represent (it would read as 0): nonzero numbers must be at least about 2.2e-308 "
           "in magnitude";
  return "";
}
}  // namespace

std::optional<double> Checker::real(const YAML::Node& n, const std::string& path) {
  double v;
  if (n.IsScalar()) {
    double parsed;
    const std::string problem = range_problem(n.Scalar(), parsed);
    if (!problem.empty()) {
      error(path, n, problem);
      return std::nullopt;
    }
  }
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v)) {
    error(path, n, "expected a number, got " + describe(n));
    return std::nullopt;
  }
  return v;
}

std::optional<std::int64_t> Checker::integer(const YAML::Node& n, const std::string& path) {
  // A decimal literal is read exactly (a double would round above 2^53), so that the caller's
  // range check can say what the valid range is.
  if (n.IsScalar() && is_decimal_integer(n.Scalar())) {
    errno = 0;
    const long long v = std::strtoll(n.Scalar().c_str(), nullptr, 10);
    if (errno == ERANGE) {
      error(path, n, "'" + n.Scalar() + "' is out of range: whole numbers must be between -9223372036854775808 and "
                     "9223372036854775807 (2^63 - 1)");
      return std::nullopt;
    }
    return static_cast<std::int64_t>(v);
  }
  double v;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v) || v != std::floor(v)) {
    error(path, n, "expected a whole number, got " + describe(n));
    return std::nullopt;
  }
  // 2^63: the first double that does not fit a 64-bit whole number.
  if (std::fabs(v) >= 9223372036854775808.0) {
    error(path, n, "'" + n.Scalar() + "' is out of range: whole numbers must be between -9.2e18 and 9.2e18 (2^63)");
    return std::nullopt;
  }
  return static_cast<std::int64_t>(v);
}

std::optional<bool> Checker::boolean(const YAML::Node& n, const std::string& path) {
  bool v;
  if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v)) {
    error(path, n, "expected true or false, got " + describe(n));
    return std::nullopt;
  }
  return v;
}

std::string Checker::describe(const YAML::Node& n) {
  if (n.IsMap()) return "a mapping";
  if (n.IsSequence()) return "a list";
  if (n.IsNull()) return "nothing";
  return "'" + n.Scalar() + "'";
}

}  // namespace gdsmc::host
