#include "config/yaml_reader.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "config/overrides.hpp"
#include "config/suggest.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

SourceLocation Checker::where(const std::string& path, const YAML::Node& node) const {
  for (const auto& o : overrides_) {
    const std::string key = canonical_key(o.substr(0, o.find('=')));
    if (path == key || path.rfind(key + ".", 0) == 0 || path.rfind(key + "[", 0) == 0)
      return SourceLocation{"--set " + o, 0, 0};
  }
  const YAML::Mark m = node.Mark();
  if (m.line < 0) return SourceLocation{file_.string(), 0, 0};
  return SourceLocation{file_.string(), m.line + 1, m.column + 1};  // yaml-cpp marks are 0-based
}

void Checker::error(const SourceLocation& at, const std::string& path, const std::string& message) {
  errors_.push_back(at.str() + ": " + (path.empty() ? "" : path + ": ") + message);
}

void Checker::error(const std::string& path, const YAML::Node& node, const std::string& message) {
  error(where(path, node), path, message);
}

void Checker::check_keys(const YAML::Node& map, const std::string& path, const std::vector<std::string>& allowed) {
  std::set<std::string> seen;
  for (auto it = map.begin(); it != map.end(); ++it) {
    const std::string key = it->first.Scalar();
    const std::string sub = path.empty() ? key : path + "." + key;
    if (!seen.insert(key).second) error(sub, it->first, "duplicate key '" + key + "'");
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      auto close = closest_names(key, allowed);
      error(sub, it->first, "unknown key '" + key + "'" +
                                (close.empty() ? "" : "; did you mean " + join(close, ", ") + "?") +
                                " (valid keys: " + join(allowed, ", ") + ")");
    }
  }
}

std::optional<double> Checker::real(const YAML::Node& n, const std::string& path) {
  double v;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v)) {
    error(path, n, "expected a number, got " + describe(n));
    return std::nullopt;
  }
  return v;
}

std::optional<std::int64_t> Checker::integer(const YAML::Node& n, const std::string& path) {
  double v;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v) || v != std::floor(v) ||
      std::fabs(v) > 9.0e15) {
    error(path, n, "expected a whole number, got " + describe(n));
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
