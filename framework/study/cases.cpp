#include "study/cases.hpp"

namespace gdsmc::host {

std::vector<StudyCase> expand_cases(const Pipeline& base, const std::vector<std::string>& overrides,
                                    const std::vector<std::filesystem::path>& extra_plugin_paths) {
  std::vector<StudyCase> cases;
  if (base.sweep.empty()) {
    cases.push_back(StudyCase{"", {}, base});
    return cases;
  }
  // Cartesian product of the axes, the last axis varying fastest.
  std::vector<std::size_t> index(base.sweep.size(), 0);
  std::vector<std::string> errors;
  while (true) {
    StudyCase c;
    std::vector<std::string> sets = overrides;
    for (std::size_t a = 0; a < base.sweep.size(); ++a) {
      const auto& value = base.sweep[a].values[index[a]];
      c.axis_values.emplace_back(base.sweep[a].name, value.label);
      c.label += (c.label.empty() ? "" : ", ") + base.sweep[a].name + "=" + value.label;
      for (const auto& o : value.overrides) sets.push_back(o);
    }
    try {
      c.pipeline = load_pipeline(base.file, sets, extra_plugin_paths, base.registry);
      c.pipeline.sweep.clear();
      c.pipeline.output_file = base.output_file;
      cases.push_back(std::move(c));
    } catch (const PipelineError& e) {
      for (const auto& m : e.messages()) errors.push_back("sweep case " + std::to_string(cases.size() + errors.size()) +
                                                          " (" + c.label + "): " + m);
    }
    std::size_t a = base.sweep.size();
    while (a-- > 0) {
      if (++index[a] < base.sweep[a].values.size()) break;
      index[a] = 0;
    }
    if (a == static_cast<std::size_t>(-1)) break;
  }
  if (!errors.empty()) throw PipelineError(errors);
  return cases;
}

}  // namespace gdsmc::host
