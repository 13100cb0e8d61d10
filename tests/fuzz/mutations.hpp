// The generator of the fuzzing test (fuzz_test.cpp, README.md): mutations of a pipeline's text, each
// a pure function of (base seed, config file name, index), and the test of whether a mutation left
// an entry of the pipeline alone.
#pragma once
#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gdsmc::test::fuzz {

// splitmix64: the same stream on every platform (std distributions are not specified that way).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : s_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (s_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  std::size_t below(std::size_t n) { return n ? static_cast<std::size_t>(next() % n) : 0; }

 private:
  std::uint64_t s_;
};

inline std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : s) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

inline std::uint64_t mutation_seed(std::uint64_t base, const std::string& config, int index) {
  Rng r(base ^ fnv1a(config) ^ (0x632be59bd9b4e019ull * static_cast<std::uint64_t>(index + 1)));
  return r.next();
}

struct Line {
  std::size_t begin, end;  // byte offsets of the line, without its '\n'
};
inline std::vector<Line> lines_of(const std::string& text) {
  std::vector<Line> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t nl = text.find('\n', start);
    const std::size_t end = nl == std::string::npos ? text.size() : nl;
    lines.push_back({start, end});
    start = end + 1;
  }
  return lines;
}

// Where a line's content ends: at a comment ('#' at the start or after a blank, outside quotes).
inline std::size_t content_end(const std::string& text, const Line& l) {
  char quote = 0;
  for (std::size_t i = l.begin; i < l.end; ++i) {
    const char c = text[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '#' && (i == l.begin || text[i - 1] == ' ' || text[i - 1] == '\t')) {
      return i;
    }
  }
  return l.end;
}

inline bool has_content(const std::string& text, const Line& l) {
  for (std::size_t i = l.begin; i < content_end(text, l); ++i)
    if (text[i] != ' ' && text[i] != '\t') return true;
  return false;
}

struct Token {
  std::size_t begin, end;  // byte offsets in the whole text
  std::size_t line;        // 0-based
  bool key;
};

// The scalars of the YAML text line by line (keys and values, block and flow), enough for the
// shipped configs: a token runs to a flow delimiter, ": " or the comment.
inline std::vector<Token> tokens_of(const std::string& text) {
  std::vector<Token> out;
  const auto lines = lines_of(text);
  for (std::size_t n = 0; n < lines.size(); ++n) {
    const std::size_t end = content_end(text, lines[n]);
    std::size_t i = lines[n].begin;
    auto colon_at = [&](std::size_t k) { return k < end && text[k] == ':' && (k + 1 == end || text[k + 1] == ' '); };
    while (i < end) {
      const char c = text[i];
      if (c == ' ' || c == '\t' || c == '{' || c == '}' || c == '[' || c == ']' || c == ',' || colon_at(i) ||
          (c == '-' && (i + 1 == end || text[i + 1] == ' '))) {
        ++i;
        continue;
      }
      std::size_t j = i;
      if (c == '"' || c == '\'') {
        j = text.find(c, i + 1);
        j = (j == std::string::npos || j >= end) ? end : j + 1;
      } else {
        while (j < end && !colon_at(j) && std::string_view(",{}[]").find(text[j]) == std::string_view::npos) ++j;
        while (j > i && text[j - 1] == ' ') --j;
      }
      std::size_t k = j;
      while (k < end && text[k] == ' ') ++k;
      out.push_back({i, j, n, colon_at(k)});
      i = j;
    }
  }
  return out;
}

struct Mutation {
  std::string config;  // file name in configs/
  int index = -1;      // -1: the config itself, unmutated
  std::uint64_t seed = 0;
  std::string kind = "none", what = "unmutated";
  std::string text;
  std::string id() const { return config + ":" + std::to_string(index); }
};

// `text` with line `n` (0-based) shown for a message.
inline std::string show_line(const std::string& text, const std::vector<Line>& lines, std::size_t n) {
  return "line " + std::to_string(n + 1) + " `" + text.substr(lines[n].begin, lines[n].end - lines[n].begin) + "`";
}

// The kind cycles with the index. A retyped value reaches the run more often than a deleted line
// or a truncation (which validate mostly refuses), hence three of eight.
const std::vector<std::string> kKinds = {"delete-line", "retype-value", "duplicate-line", "swap-values",
                                         "retype-value", "truncate", "indent", "retype-value"};
const std::vector<std::string> kReplacements = {
    "[1, 2]", "{a: 1}", "text", "\"a string\"", "1.0e308", "1.0e400", "1.0e-308", "1.0e-30", "1.0e12", "-1", "-1.0e6",
    "0", "-0", ".nan", ".inf", "-.inf", "", "~", "true", "2.5", "4294967296", "99999999999999999999", "0x10"};

inline Mutation mutate(const std::string& config, const std::string& original, int index, std::uint64_t base_seed) {
  Mutation m;
  m.config = config;
  m.index = index;
  m.seed = mutation_seed(base_seed, config, index);
  Rng rng(m.seed);
  const auto lines = lines_of(original);
  std::vector<std::size_t> content;
  for (std::size_t n = 0; n < lines.size(); ++n)
    if (has_content(original, lines[n])) content.push_back(n);
  std::vector<Token> values;
  for (const auto& t : tokens_of(original))
    if (!t.key) values.push_back(t);
  m.kind = kKinds[static_cast<std::size_t>(index) % kKinds.size()];
  if ((m.kind == "swap-values" && values.size() < 2) || (m.kind == "retype-value" && values.empty())) m.kind = "delete-line";
  if (content.empty() && m.kind != "truncate") m.kind = "truncate";
  std::string t = original;
  const auto line_text = [&](std::size_t n) { return original.substr(lines[n].begin, lines[n].end - lines[n].begin); };
  if (m.kind == "delete-line") {
    const std::size_t n = content[rng.below(content.size())];
    m.what = show_line(original, lines, n) + " deleted";
    t.erase(lines[n].begin, std::min(lines[n].end + 1, t.size()) - lines[n].begin);
  } else if (m.kind == "duplicate-line") {
    const std::size_t n = content[rng.below(content.size())];
    m.what = show_line(original, lines, n) + " duplicated";
    t.insert(lines[n].begin, line_text(n) + "\n");
  } else if (m.kind == "swap-values") {
    std::size_t a = rng.below(values.size()), b = rng.below(values.size());
    for (int tries = 0; tries < 20; ++tries) {  // two different values if there are any
      const auto va = original.substr(values[a].begin, values[a].end - values[a].begin);
      const auto vb = original.substr(values[b].begin, values[b].end - values[b].begin);
      if (a != b && va != vb) break;
      b = rng.below(values.size());
    }
    if (values[a].begin > values[b].begin) std::swap(a, b);
    const Token &ta = values[a], &tb = values[b];
    const std::string va = original.substr(ta.begin, ta.end - ta.begin), vb = original.substr(tb.begin, tb.end - tb.begin);
    m.what = "values `" + va + "` (line " + std::to_string(ta.line + 1) + ") and `" + vb + "` (line " +
             std::to_string(tb.line + 1) + ") swapped";
    t.replace(tb.begin, tb.end - tb.begin, va);
    t.replace(ta.begin, ta.end - ta.begin, vb);
  } else if (m.kind == "retype-value") {
    const Token& v = values[rng.below(values.size())];
    const std::string& r = kReplacements[rng.below(kReplacements.size())];
    m.what = "value `" + original.substr(v.begin, v.end - v.begin) + "` (line " + std::to_string(v.line + 1) +
             ") replaced by `" + r + "`";
    t.replace(v.begin, v.end - v.begin, r);
  } else if (m.kind == "truncate") {
    const std::size_t cut = rng.below(original.size());
    m.what = "truncated to " + std::to_string(cut) + " of " + std::to_string(original.size()) + " bytes";
    t.resize(cut);
  } else {  // indent
    const std::size_t n = content[rng.below(content.size())];
    std::size_t spaces = 0;
    while (lines[n].begin + spaces < lines[n].end && original[lines[n].begin + spaces] == ' ') ++spaces;
    const std::size_t choice = rng.below(5);
    std::string prefix;
    std::size_t remove = 0;
    if (choice == 0) prefix = " ";
    else if (choice == 1) prefix = "  ";
    else if (choice == 2) prefix = "\t";
    else remove = std::min(spaces, choice == 3 ? std::size_t{1} : std::size_t{2});
    if (prefix.empty() && remove == 0) prefix = " ";  // nothing to remove: indent instead
    m.what = show_line(original, lines, n) +
             (remove ? " dedented by " + std::to_string(remove) : prefix == "\t" ? " indented by a tab" : " indented by " + std::to_string(prefix.size()));
    t.erase(lines[n].begin, remove);
    t.insert(lines[n].begin, prefix);
  }
  m.text = std::move(t);
  return m;
}

// Whether the mutation left the entry `key` alone: its line, the more-indented lines under it and
// the line after them are still there, once, exactly as in the original.
inline bool untouched(const std::string& original, const std::string& mutated, const std::string& key) {
  const auto lines = lines_of(original);
  auto indent = [&](const Line& l) {
    std::size_t k = l.begin;
    while (k < l.end && original[k] == ' ') ++k;
    return k - l.begin;
  };
  for (std::size_t n = 0; n < lines.size(); ++n) {
    const std::size_t ind = indent(lines[n]);
    if (original.compare(lines[n].begin + ind, key.size() + 1, key + ":") != 0) continue;
    std::size_t last = n + 1;
    while (last < lines.size() && (!has_content(original, lines[last]) || indent(lines[last]) > ind)) ++last;
    const std::size_t stop = std::min(last + 1, lines.size());  // the line after the block, too
    const std::string block = original.substr(lines[n].begin, lines[stop - 1].end - lines[n].begin);
    auto count = [&block](const std::string& s) {
      std::size_t c = 0;
      for (std::size_t p = s.find(block); p != std::string::npos; p = s.find(block, p + 1)) ++c;
      return c;
    };
    return count(original) == 1 && count(mutated) == 1;
  }
  return false;  // no such entry: leave the pipeline as it is
}

}  // namespace gdsmc::test::fuzz
