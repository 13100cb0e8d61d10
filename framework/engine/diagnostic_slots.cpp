#include "engine/diagnostic_slots.hpp"

#include <algorithm>
#include <stdexcept>

#include "engine/stop.hpp"

namespace gdsmc::host {

void DiagnosticSlots::add(Diagnostic* object, const PluginUse* use, const PluginCallSite* site) {
  slots_.push_back(Slot{object, use, site});
}

std::uint32_t DiagnosticSlots::begin(const Pipeline& p, const SystemInfo& system, QuantityBoard& board,
                                     bool sample_alone, std::vector<std::string>* summary) {
  if (p.stop_steady) {
    steady_stop_ = &*p.stop_steady;
    for (std::size_t k = 0; k < slots_.size(); ++k)
      if (slots_[k].use->instance_name == p.stop_steady->group) steady_slot_ = static_cast<int>(k);
  }
  const std::vector<double> centres = bin_centres_lambda0(system);
  std::uint32_t parts = 0;
  outputs_.reserve(slots_.size());
  for (auto& slot : slots_) {
    outputs_.emplace_back(slot.use->instance_name, summary);
    outputs_.back().set_bins(centres);
    try {
      PluginCall call(*slot.site, "begin");
      slot.object->begin(system, board, outputs_.back());
      PluginCall query(*slot.site, "extension");
      // With the collisions as the only process (the HCS) the state after the step is exact at
      // t + dt and the one before it is the state at t: the sample is taken alone.
      slot.bracketed = p.sampling_bracketed && !sample_alone && slot.object->extension(bracketed_sampling_id) != nullptr;
      const auto* read = static_cast<const MomentsRead*>(slot.object->extension(moments_read_id));
      parts |= read ? read->parts : static_cast<std::uint32_t>(moments_all);
      slot.reads_particles = !read || read->version < 2 || read->particles != 0;
    } catch (const std::exception& e) {
      throw std::runtime_error(where_text(*slot.use) + ": " + e.what());
    }
    outputs_.back().attribute("sampling", slot.bracketed ? "bracketed: the state just before and just after the collision stage "
                                                           "of each sampled step, at t + dt (run.sampling)"
                                                         : "after_step: the state after each sampled step");
    any_bracketed_ = any_bracketed_ || slot.bracketed;
  }
  return parts;
}

bool DiagnosticSlots::samples_at(std::uint64_t step) const {
  return std::any_of(slots_.begin(), slots_.end(), [&](const Slot& slot) { return slot.samples_at(step); });
}

bool DiagnosticSlots::bracketed_at(std::uint64_t step) const {
  return std::any_of(slots_.begin(), slots_.end(), [&](const Slot& slot) { return slot.bracketed && slot.samples_at(step); });
}

bool DiagnosticSlots::due_at(std::uint64_t step) const {
  return std::any_of(slots_.begin(), slots_.end(), [&](const Slot& slot) { return slot.due_at(step); });
}

bool DiagnosticSlots::bracketed_due_at(std::uint64_t step) const {
  return std::any_of(slots_.begin(), slots_.end(), [&](const Slot& slot) { return slot.bracketed && slot.due_at(step); });
}

bool DiagnosticSlots::lone_sample_at(std::uint64_t step, bool force_record, bool of_particles) const {
  return std::any_of(slots_.begin(), slots_.end(), [&](const Slot& slot) {
    return (slot.reads_particles || !of_particles) && slot.last_record_step != step &&
           (force_record || slot.samples_at(step)) && slot.bracketed_step != step;  // as sample_and_record decides
  });
}

bool DiagnosticSlots::bracketed_particles_at(std::uint64_t step) const {
  return std::any_of(slots_.begin(), slots_.end(),
                     [&](const Slot& slot) { return slot.reads_particles && slot.bracketed && slot.samples_at(step); });
}

void DiagnosticSlots::sample_bracketed(StepContext& ctx, const ParticleSpan& span, const StreamFactory& streams,
                                       const SampledMoments& moments, SamplePhase phase) {
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    Slot& slot = slots_[k];
    if (!slot.bracketed || !slot.samples_at(ctx.step)) continue;
    // The streams of the sample before the collisions are apart from those after (instance k).
    sample(k, ctx, span, streams, moments,
           static_cast<std::uint32_t>(k) | (phase == SamplePhase::before_collisions ? 0x80000000u : 0u), phase);
    slot.bracketed_step = ctx.step;
  }
}

// One sample() of diagnostic k with its streams of `instance`, counted in its record's means of
// t/tau0 and s.
void DiagnosticSlots::sample(std::size_t k, StepContext& ctx, const ParticleSpan& span, const StreamFactory& streams,
                             const SampledMoments& moments, std::uint32_t instance, SamplePhase phase) {
  Slot& slot = slots_[k];
  const Streams slot_streams = streams.streams(StreamPurpose::diagnostic, instance);
  ctx.moments = &moments;
  ctx.streams = &slot_streams;
  ctx.sample_phase = phase;
  {
    PluginCall call(*slot.site, "sample");
    slot.object->sample(ctx, span);
  }
  ctx.sample_phase = SamplePhase::after_step;
  ctx.moments = nullptr;
  ctx.streams = nullptr;
  slot.time_sum += ctx.time_in_tau0();
  slot.s_sum += ctx.collisions_per_particle();
  ++slot.samples;
}

std::optional<bool> DiagnosticSlots::sample_and_record(StepContext& ctx, const ParticleSpan& span,
                                                       const StreamFactory& streams, bool force_record,
                                                       const std::function<const SampledMoments&()>& moments) {
  std::optional<bool> steady;
  const SampledMoments* measured = nullptr;  // once per sampled step, shared by every diagnostic
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    Slot& slot = slots_[k];
    if (slot.last_record_step == ctx.step) continue;
    const bool record = force_record || ctx.step % slot.use->record_every == 0;
    // A bracketed slot has taken its pair in this step; a forced record without one (the initial
    // state, the end of a run) takes a lone sample.
    if ((force_record || slot.samples_at(ctx.step)) && slot.bracketed_step != ctx.step) {
      if (!measured) measured = &moments();
      sample(k, ctx, span, streams, *measured, static_cast<std::uint32_t>(k), SamplePhase::after_step);
    }
    if (!record) continue;
    const double n = static_cast<double>(slot.samples);
    outputs_[k].begin_record(slot.time_sum / n, slot.s_sum / n);
    {
      PluginCall call(*slot.site, "record");
      slot.object->record(ctx, outputs_[k]);
    }
    outputs_[k].check_record(slot.use->plugin->descriptor->name);
    slot.time_sum = slot.s_sum = 0;
    slot.samples = 0;
    slot.last_record_step = ctx.step;
    if (static_cast<int>(k) == steady_slot_) steady = is_steady(*steady_stop_, outputs_[k]);
  }
  return steady;
}

void DiagnosticSlots::finish(StepContext& ctx) {
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    try {
      PluginCall call(*slots_[k].site, "finish");
      slots_[k].object->finish(ctx, outputs_[k]);
    } catch (const std::exception& e) {
      throw std::runtime_error(where_text(*slots_[k].use) + " failed at the end of the run: " + e.what());
    }
  }
}

void DiagnosticSlots::save(StateWriter& out) const {
  for (const Slot& slot : slots_) {
    const double sums[2] = {slot.time_sum, slot.s_sum};
    out.write("sampling.sums", sums, 2);
    const std::uint64_t steps[2] = {slot.samples, slot.last_record_step};
    out.write("sampling.steps", steps, 2);
  }
  for (const DiagnosticOutput& o : outputs_) o.save(out);
}

void DiagnosticSlots::load(StateReader& in) {
  for (Slot& slot : slots_) {
    double sums[2];
    in.read("sampling.sums", sums, 2);
    slot.time_sum = sums[0];
    slot.s_sum = sums[1];
    std::uint64_t steps[2];
    in.read("sampling.steps", steps, 2);
    slot.samples = steps[0];
    slot.last_record_step = steps[1];
  }
  for (std::size_t k = 0; k < outputs_.size(); ++k) {
    try {
      outputs_[k].load(in);
    } catch (const StateError& e) {
      throw StateError(where_text(*slots_[k].use) + ": " + e.what());
    }
  }
}

}  // namespace gdsmc::host
