#include "util/options.hpp"

namespace gdsmc::host {

const std::vector<std::string>& Args::all(const std::string& name) const {
  static const std::vector<std::string> none;
  auto it = values.find(name);
  return it == values.end() ? none : it->second;
}

bool parse_args(int argc, char** argv, int first, const std::vector<OptionSpec>& specs, Args& out, std::string& error) {
  for (int k = first; k < argc; ++k) {
    const std::string a = argv[k];
    if (a.size() < 2 || a[0] != '-') {
      out.positional.push_back(a);
      continue;
    }
    const auto eq = a.find('=');
    const std::string name = a.substr(0, eq);
    const OptionSpec* spec = nullptr;
    for (const auto& s : specs)
      for (const auto& n : s.names)
        if (n == name) spec = &s;
    if (!spec || (spec->needs.empty() && eq != std::string::npos)) {
      error = "unknown option '" + a + "'";
      return false;
    }
    auto& values = out.values[spec->names.front()];
    if (spec->needs.empty()) {
      values.push_back("");
    } else if (eq != std::string::npos) {
      values.push_back(a.substr(eq + 1));
    } else if (k + 1 < argc) {
      values.push_back(argv[++k]);
    } else {
      error = name + " needs " + spec->needs;
      return false;
    }
  }
  return true;
}

}  // namespace gdsmc::host
