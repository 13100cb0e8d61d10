// "Did you mean ...?": close spellings of a mistyped name.
#pragma once
#include <string>
#include <vector>

namespace gdsmc::host {

// Levenshtein distance between a and b.
std::size_t edit_distance(const std::string& a, const std::string& b);

// Closest names to `word` among `candidates` (edit distance), best first, at most 3.
std::vector<std::string> closest_names(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace gdsmc::host
