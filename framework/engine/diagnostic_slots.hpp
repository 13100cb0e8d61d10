// The run's diagnostics as the step loop drives them: when each samples and records, the pair of
// samples that a bracketed diagnostic takes around the collision stage, the means of t and s over
// a record's samples, the steady-state stop, and every diagnostic's output.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <gdsmc/plugin.hpp>
#include <gdsmc/state.hpp>

#include "config/pipeline.hpp"
#include "engine/plugin_calls.hpp"
#include "engine/streams.hpp"
#include "output/diagnostic_output.hpp"

namespace gdsmc::host {

class DiagnosticSlots {
 public:
  void add(Diagnostic* object, const PluginUse* use, const PluginCallSite* site);
  // Every diagnostic's begin() with its output opened (the bins' centres; `summary` collects the
  // lines they write), whether it samples bracketed (run.sampling; never when `sample_alone`: the
  // HCS, whose collisions are its only process), and the slot the steady stop reads. Returns the
  // MomentsPart bits some diagnostic reads (MomentsRead; all for one without the extension).
  std::uint32_t begin(const Pipeline& p, const SystemInfo& system, QuantityBoard& board, bool sample_alone,
                      std::vector<std::string>* summary);
  bool any_bracketed() const { return any_bracketed_; }
  // Whether some diagnostic samples or records after step `step`; some bracketed one does.
  bool samples_at(std::uint64_t step) const;
  bool bracketed_at(std::uint64_t step) const;
  // The same from the pipeline alone (every `sample_every` or `record_every` step), without what the
  // slots have done: true whenever samples_at (bracketed_at) is, on every rank of a decomposed run.
  bool due_at(std::uint64_t step) const;
  bool bracketed_due_at(std::uint64_t step) const;
  // Whether sample_and_record will take a lone sample for some diagnostic (`of_particles`: for one
  // whose sample() reads the particles, MomentsRead::particles), and whether sample_bracketed will
  // hand the particles to one, from what the slots have done: rank 0 of a decomposed run, which
  // drives them, tells the others whether to measure the moments and whether to gather.
  bool lone_sample_at(std::uint64_t step, bool force_record, bool of_particles) const;
  bool bracketed_particles_at(std::uint64_t step) const;
  // The bracketed diagnostics' samples of the state now, just before or just after the collision
  // stage of the step that ctx.step is (already advanced to the step after).
  void sample_bracketed(StepContext& ctx, const ParticleSpan& span, const StreamFactory& streams,
                        const SampledMoments& moments, SamplePhase phase);
  // After a step: the samples and records due (all of them with `force_record`: the initial state,
  // the end of the run). `moments` measures the sampled moments when first needed. Returns whether
  // the steady stop's diagnostic has recorded and what it found (nothing otherwise).
  std::optional<bool> sample_and_record(StepContext& ctx, const ParticleSpan& span, const StreamFactory& streams,
                                        bool force_record, const std::function<const SampledMoments&()>& moments);
  // Every diagnostic's finish() at the end of the run.
  void finish(StepContext& ctx);
  std::vector<DiagnosticOutput>& outputs() { return outputs_; }
  const std::vector<DiagnosticOutput>& outputs() const { return outputs_; }
  void save(StateWriter& out) const;
  void load(StateReader& in);

 private:
  struct Slot {
    Diagnostic* object;
    const PluginUse* use;
    const PluginCallSite* site = nullptr;
    double time_sum = 0, s_sum = 0;
    std::uint64_t samples = 0;
    std::uint64_t last_record_step = static_cast<std::uint64_t>(-1);
    bool bracketed = false;  // sampled on both sides of the collision stage (BracketedSampling, run.sampling)
    bool reads_particles = true;  // MomentsRead::particles
    std::uint64_t bracketed_step = static_cast<std::uint64_t>(-1);  // the step of its last bracketed pair
    // Whether it samples (or records) after step `step`, unless forced to record.
    bool samples_at(std::uint64_t step) const { return last_record_step != step && due_at(step); }
    bool due_at(std::uint64_t step) const { return step % use->record_every == 0 || step % use->sample_every == 0; }
  };
  void sample(std::size_t k, StepContext& ctx, const ParticleSpan& span, const StreamFactory& streams,
              const SampledMoments& moments, std::uint32_t instance, SamplePhase phase);

  std::vector<Slot> slots_;
  std::vector<DiagnosticOutput> outputs_;
  const SteadyStop* steady_stop_ = nullptr;
  int steady_slot_ = -1;
  bool any_bracketed_ = false;
};

}  // namespace gdsmc::host
