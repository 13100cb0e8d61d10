// `--set key.path=value`: key paths in one canonical form, and editing the YAML document.
#pragma once
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace gdsmc::host {

// The parts of a key path: "a.b[2].c" and "a.b.2.c" -> {"a", "b", "2", "c"}.
std::vector<std::string> key_parts(std::string key);

// "a.b[2].c" and "a.b.2.c" -> "a.b[2].c", the form the checker uses for paths.
std::string canonical_key(const std::string& key);

// Apply "a.b[2].c=value" (or a.b.2.c) to the document; problems are appended to `errors`, each
// starting with `origin` (default: "--set <assignment>"; a sweep case names its sweep entry).
void apply_override(YAML::Node& root, const std::string& assignment, std::vector<std::string>& errors,
                    const std::string& origin = "");

}  // namespace gdsmc::host
