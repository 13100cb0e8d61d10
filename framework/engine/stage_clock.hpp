// Where a run's steps spend their wall time, stage by stage (as SPARTA and LAMMPS print at the end
// of a run): the stages, their names in the output, and the clock that the step loop laps.
#pragma once
#include <array>
#include <chrono>
#include <cstddef>
#include <string>

namespace gdsmc::host {

// Forcings, free flight with walls (or a homogeneous body acceleration's kick), the layers'
// counting sort, the reordering of storage by layer, collisions, moment updates, and diagnostics
// (sampling, recording).
enum class Stage { forcings, flight, sort, reorder, collisions, moments, diagnostics, count };
inline constexpr std::size_t kStages = static_cast<std::size_t>(Stage::count);
using StageSeconds = std::array<double, kStages>;  // indexed by Stage

const char* stage_name(Stage s);
// The /run attribute that keeps a stage's seconds: "stage_seconds.<stage_name>".
inline std::string stage_attribute(Stage s) { return std::string("stage_seconds.") + stage_name(s); }
// "2.03 = flight 1.09 (54 %), collisions 0.6 (30 %), ...": the total, then the stages that took
// any time, longest first, each with its share (the run's summary and `gdsmc inspect`).
std::string stage_times_text(const StageSeconds& seconds);

// Seconds per stage, summed over the steps (and over the segments of a resumed run): start() at
// the step's start, then lap(s) after each stage adds the time since the last lap to stage s.
class StageClock {
 public:
  void start() { lap_start_ = std::chrono::steady_clock::now(); }
  void lap(Stage s) {
    const auto now = std::chrono::steady_clock::now();
    seconds_[static_cast<std::size_t>(s)] += std::chrono::duration<double>(now - lap_start_).count();
    lap_start_ = now;
  }
  const StageSeconds& seconds() const { return seconds_; }
  StageSeconds& seconds() { return seconds_; }  // restored from a checkpoint

 private:
  StageSeconds seconds_{};
  std::chrono::steady_clock::time_point lap_start_;
};

}  // namespace gdsmc::host
