#include "config/overrides.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <sstream>

#include "util/text.hpp"

namespace gdsmc::host {

std::vector<std::string> key_parts(std::string key) {
  std::replace(key.begin(), key.end(), '[', '.');
  key.erase(std::remove(key.begin(), key.end(), ']'), key.end());
  std::vector<std::string> parts;
  std::stringstream ss(key);
  for (std::string p; std::getline(ss, p, '.');)
    if (!p.empty()) parts.push_back(p);
  return parts;
}

std::string canonical_key(const std::string& key) {
  std::string out;
  for (const auto& part : key_parts(key)) {
    const bool index = !out.empty() && std::all_of(part.begin(), part.end(), [](char ch) { return std::isdigit(static_cast<unsigned char>(ch)); });
    out += index ? "[" + part + "]" : (out.empty() ? "" : ".") + part;
  }
  return out;
}

void apply_override(YAML::Node& root, const std::string& assignment, std::vector<std::string>& errors,
                    const std::string& origin) {
  const std::string from = origin.empty() ? "--set " + assignment : origin;
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    errors.push_back(from + ": expected key.path=value");
    return;
  }
  const std::vector<std::string> parts = key_parts(assignment.substr(0, eq));
  const std::string value = assignment.substr(eq + 1);
  YAML::Node value_node;
  try {
    value_node = YAML::Load(value);
  } catch (const YAML::Exception& e) {
    errors.push_back(from + ": the value is not valid YAML: " + e.msg);
    return;
  }
  // A plugin entry given by its name alone ("- temperature") becomes {plugin: temperature} when a
  // key is set inside it; any other single value has no keys (yaml-cpp would throw a message that
  // names no key path).
  const bool plugin_slot = !parts.empty() && (parts[0] == "initial_state" || parts[0] == "collision" ||
                                              parts[0] == "forcings" || parts[0] == "diagnostics" ||
                                              parts[0] == "boundaries");
  auto single_value = [&](YAML::Node& node, std::size_t k) {
    if (!node.IsScalar()) return false;
    if (plugin_slot && k >= 1) {
      YAML::Node entry(YAML::NodeType::Map);
      entry["plugin"] = node.Scalar();
      node = entry;  // assigns through the handle: the tree now holds the mapping
      return false;
    }
    std::vector<std::string> above(parts.begin(), parts.begin() + static_cast<std::ptrdiff_t>(k));
    errors.push_back(from + ": " + canonical_key(join(above, ".")) + " is a single value ('" + node.Scalar() +
                     "'), not a mapping, so it has no key '" + parts[k] + "'");
    return true;
  };
  // Walk with fresh handles (yaml-cpp node assignment rebinds, so use reset()).
  YAML::Node cur;
  cur.reset(root);
  for (std::size_t k = 0; k + 1 < parts.size(); ++k) {
    if (single_value(cur, k)) return;
    YAML::Node next;
    if (cur.IsSequence()) {
      char* end = nullptr;
      const long idx = std::strtol(parts[k].c_str(), &end, 10);
      if (*end || idx < 0 || static_cast<std::size_t>(idx) >= cur.size()) {
        errors.push_back(from + ": '" + parts[k] + "' is not an index of the list (size " +
                         std::to_string(cur.size()) + ")");
        return;
      }
      next.reset(cur[static_cast<std::size_t>(idx)]);
    } else {
      next.reset(cur[parts[k]]);
    }
    cur.reset(next);
  }
  if (parts.empty()) {
    errors.push_back(from + ": empty key path");
    return;
  }
  if (single_value(cur, parts.size() - 1)) return;
  if (cur.IsSequence()) {
    char* end = nullptr;
    const long idx = std::strtol(parts.back().c_str(), &end, 10);
    if (*end || idx < 0 || static_cast<std::size_t>(idx) >= cur.size()) {
      errors.push_back(from + ": '" + parts.back() + "' is not an index of the list");
      return;
    }
    cur[static_cast<std::size_t>(idx)] = value_node;
  } else {
    cur[parts.back()] = value_node;
  }
}

}  // namespace gdsmc::host
