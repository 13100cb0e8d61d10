#include "engine/stage_clock.hpp"

#include <algorithm>
#include <vector>

#include "util/text.hpp"

namespace gdsmc::host {

const char* stage_name(Stage s) {
  static const char* const names[] = {"forcings", "flight", "sort", "reorder", "collisions", "moments", "diagnostics"};
  return names[static_cast<int>(s)];
}

std::string stage_times_text(const StageSeconds& seconds) {
  std::vector<std::size_t> order;
  double total = 0;
  for (std::size_t k = 0; k < kStages; ++k) {
    total += seconds[k];
    if (seconds[k] > 0) order.push_back(k);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return seconds[a] > seconds[b]; });
  std::string text = fmt("%.3g", total);
  for (std::size_t i = 0; i < order.size(); ++i)
    text += std::string(i == 0 ? " = " : ", ") + stage_name(static_cast<Stage>(order[i])) + " " +
            fmt("%.3g", seconds[order[i]]) + fmt(" (%.0f %%)", 100.0 * seconds[order[i]] / total);
  return text;
}

}  // namespace gdsmc::host
