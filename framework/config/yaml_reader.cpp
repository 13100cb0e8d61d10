#include "config/yaml_reader.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
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
