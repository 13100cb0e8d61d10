// The collision stage's weighted pairs (run.pair_selection: weighted): one layer's envelope events
// and candidates over a step, drawn from a copy of its stream or sixteen Philox blocks at a time.
#include <cmath>

#include "engine/bulk_rng.hpp"
#include "engine/candidate_batch.hpp"
#include "engine/collision_stage.hpp"
#include "engine/interrupt.hpp"
#include "engine/majorant.hpp"
#include "engine/weighted_layer.hpp"

namespace gdsmc::host {

using namespace candidates;

namespace {
// The time counter of a layer's envelope events: since the anchor time t0 with credit f0 at rate
// R, event k (k >= 1) is at t0 + (k - f0) / R; `events` of them drawn so far, those at or before
// dt while events + 1 <= budget.
struct EventClock {
  double t0 = 0, f0 = 0, rate = 0, inverse_rate = 0, budget = 0;
  std::uint64_t events = 0;
  // The counter at the step's start, with the credit carried in from the last step as it is.
  void start(double credit, double r, double dt) {
    f0 = credit;
    rate = r;
    inverse_rate = 1.0 / rate;
    budget = std::isfinite(rate) ? f0 + rate * dt : 0.0;
  }
  // The counter from time t with credit f (clamped into [0, 1)) at rate r, for the rest of [t, dt].
  void anchor(double t, double f, double r, double dt) {
    t0 = t;
    f0 = std::min(std::max(f, 0.0), std::nextafter(1.0, 0.0));
    rate = r;
    inverse_rate = 1.0 / rate;
    // A speed that is not finite (a rule that broke a velocity) ends the layer's step here; the
    // engine's checks of the state name it.
    budget = std::isfinite(rate) ? f0 + rate * (dt - t0) : 0.0;
    events = 0;
  }
  double due(double t) const { return f0 + rate * (t - t0); }  // the events due by t, with the credit
  double draw_time() const { return t0 + (static_cast<double>(events) - f0) * inverse_rate; }
};

// What a rule's pass over a batch adds to the batch's results, saved before it so that the pass
// can be undone: the rule's stream, the counts and sums, and the tallies.
struct BatchResults {
  Rng kernel;
  std::uint64_t collided, exceeded;
  double max_rate, energy, missed;
  void save(const PairBatch& b, std::vector<double>& tally) {
    kernel = *b.rng;
    collided = b.collided, exceeded = b.exceeded, max_rate = b.max_rate, energy = b.energy_change, missed = b.missed;
    if (b.tally) std::copy(b.tally, b.tally + tally.size(), tally.begin());
  }
  void restore(PairBatch& b, const std::vector<double>& tally) const {
    *b.rng = kernel;
    b.collided = collided, b.exceeded = exceeded, b.max_rate = max_rate, b.energy_change = energy, b.missed = missed;
    if (b.tally) std::copy(tally.begin(), tally.end(), b.tally);
  }
};

// The first extra event of a closed batch: each collided particle whose bound rose by dB at its
// pair's time t_q draws its next extra event at t_q + Exp(K dB). Scanned in the pairs' order and
// stopped at the first pair after the earliest event so far; `kept` pairs come before it.
struct ExtraEvent {
  double time = INFINITY;
  std::uint32_t particle = 0, kept = 0;
  bool rose = false;
};
template <class Draws>
ExtraEvent first_extra_event(const BatchScratch& s, std::uint32_t m, const WeightedSides& sides, Draws& select) {
  ExtraEvent x;
  x.kept = m;
  for (std::uint32_t q = 0; q < m; ++q) {
    if (s.t[q] > x.time) {
      x.kept = q;
      break;
    }
    if (!s.accepted[q]) continue;
    const Vec3 after[2] = {s.v1[q], s.v2[q]};
    for (int e = 0; e < 2; ++e) {
      const std::uint32_t a = e == 0 ? s.la[q] : s.lb[q];
      const int side = sides.side_of(a);
      WeightedLayer& layer = *sides.layer[side];
      const double lift =
          layer.rise(a - sides.offset[side], layer.peculiar_square(after[e].x, after[e].y, after[e].z));
      if (lift > 0) {
        x.rose = true;
        const double t = s.t[q] - std::log1p(-select.uniform()) / (sides.per_bound[side] * lift);
        if (t < x.time) x.time = t, x.particle = a;
      }
    }
  }
  return x;
}

// The rule's pass over the batch's first m pairs, then its first extra event; with one before the
// batch's last pair, the pass undone and run again on the pairs before it (the same draws, so the
// same outcomes for them, and results and tallies that hold those pairs only).
template <class Draws>
ExtraEvent collide_to_first_extra(const CollisionRule& rule, PairBatch& batch, BatchScratch& s, std::uint32_t m,
                                  const WeightedSides& sides, Draws& select, const ParticleSpan& p,
                                  std::vector<double>& saved_tally) {
  s.load_velocities(m, p.vx.data, p.vy.data, p.vz.data);
  BatchResults before;
  before.save(batch, saved_tally);
  batch.count = m;
  rule.collide_batch(batch);
  const ExtraEvent extra = first_extra_event(s, m, sides, select);
  if (extra.kept < m) {
    before.restore(batch, saved_tally);
    s.load_velocities(extra.kept, p.vx.data, p.vy.data, p.vz.data);
    batch.count = extra.kept;
    rule.collide_batch(batch);
  }
  return extra;
}
// An envelope event from x uniform in [0, 1): its side (two sides: by their shares of the events,
// x rescaled within the side's) and the member that initiates it (WeightedLayer::pick).
std::uint32_t pick_initiator(const WeightedSides& sides, double x, int& side, double& thin, bool& from_bulk) {
  side = 0;
  if (sides.n == 2) {
    const double r0 = sides.per_bound[0] * sides.layer[0]->envelope(), total = sides.rate();
    const double y = x * total;
    side = y < r0 ? 0 : 1;
    x = side == 0 ? y / r0 : (y - r0) / (total - r0);
    x = std::min(std::max(x, 0.0), std::nextafter(1.0, 0.0));
  }
  return sides.layer[side]->pick(x, thin, from_bulk);
}
}  // namespace

// Weighted pairs of one layer over the step (000 Eq. 4.13 with pair majorants c_a + c_b): envelope
// events at the rate R = K E, K = sigma^2 pi scale (2 P(N_c) / N_c) / V_c, on a time counter whose
// credit is carried from step to step (as the uniform candidates' remainder). Particle a initiates
// candidates at the rate K c_a, with a partner drawn uniformly, so the pair (a, b) is a candidate at
// the rate K (c_a + c_b) / (N_c - 1) = (P / C(N_c, 2)) sigma^2 pi scale (c_a + c_b) / V_c, and
// collides with probability |g| / (c_a + c_b): the hard-sphere rate, pair by pair.
// A batch holds no particle twice, and a drawn pair that meets a particle of the open batch closes
// it first, so every test sees current speeds. When a collision lifts a particle's bound by dB at
// time t_q, its extra events (rate K dB, initiated by it, partner uniform) until the envelope takes
// them over are drawn: none before the batch's last event is the rule, and the batch stands; else
// the batch is cut at the first one's time E (the rule's work on the pairs after E is undone by
// running it again on the pairs before E from the saved stream, results and tallies), that event is
// the next candidate, and the time counter starts again at E. Returns the credit left at dt.
template <class Draws>
double CollisionStage::weighted_step(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c,
                                     const WeightedSides& sides, double credit, double dt, Draws& select,
                                     PairBatch& batch) {
  double* const vx = particles.vx.data;
  double* const vy = particles.vy.data;
  double* const vz = particles.vz.data;
  // the bulk's pair bound (for a rule that looks)
  batch.speed_bound = sides.n == 1 ? 2.0 * sides.layer[0]->bulk_bound()
                                   : sides.layer[0]->bulk_bound() + sides.layer[1]->bulk_bound();
  batch.rate_bound = rule.rate_bound(batch.speed_bound);
  thread_local BatchScratch s;
  s.open(batch);
  batch.speed_bounds = s.w;
  std::uint32_t m = 0;
  std::uint64_t candidates = 0;
  EventClock clock;
  clock.start(credit, sides.rate(), dt);
  std::int64_t initiator = -1;  // an extra event's particle (local index), the next candidate (at t0)
  thread_local std::vector<double> saved_tally;  // the tallies before a pass, should it be undone
  saved_tally.resize(tally_count_);
  // Close the batch, whose newest event is at `last`: the rule's pass, every collided particle's new
  // speed, the extra events of those that rose. True if the batch was cut (an extra event before
  // `last`: `initiator` is set, and the time counter starts again at its time).
  const auto flush = [&](double last) -> bool {
    const ExtraEvent extra = collide_to_first_extra(rule, batch, s, m, sides, select, particles, saved_tally);
    s.store_accepted(extra.kept, vx, vy, vz);
    candidates += extra.kept;
    s.close(m);
    m = 0;
    if (extra.time <= last) {
      // The envelope events after E are dropped; the counter goes on from E with the new envelope.
      const double due = clock.due(extra.time);
      clock.anchor(extra.time, due - std::floor(due), sides.rate(), dt);
      initiator = extra.particle;
      return true;
    }
    if (extra.rose) clock.anchor(last, clock.due(last) - static_cast<double>(clock.events), sides.rate(), dt);
    return false;
  };
  for (;;) {
    std::uint32_t a;
    int side = 0;
    double t, thin;
    bool from_bulk = false;
    if (initiator >= 0) {
      side = sides.side_of(static_cast<std::uint32_t>(initiator));
      a = static_cast<std::uint32_t>(initiator) - sides.offset[side];
      initiator = -1;
      t = clock.t0;
      thin = select.uniform();
    } else if (static_cast<double>(clock.events + 1) <= clock.budget) {
      ++clock.events;
      if ((clock.events & 0xFFFF) == 0) poll_interrupt(interrupt_);
      t = clock.draw_time();
      a = pick_initiator(sides, select.uniform(), side, thin, from_bulk);
    } else {
      if (m > 0 && flush(dt)) continue;
      break;
    }
    const WeightedLayer& layer = *sides.layer[side];
    const int other = sides.n == 1 ? 0 : 1 - side;
    // a thinned first (its speed is current once no open pair holds it), then its partner and the
    // acceptance number for a candidate only.
    const std::uint32_t la = sides.offset[side] + a;
    if (m > 0 && s.holds(la) && flush(t)) continue;  // cut before t: this draw goes
    if (!layer.candidate(a, thin, from_bulk)) continue;
    std::uint32_t b = select.below(sides.n == 1 ? sides.count[0] - 1 : sides.count[other]);
    if (sides.n == 1) b += (b >= a);  // the partner from the same list: not a itself
    const double u = select.uniform32();
    const std::uint32_t lb = sides.offset[other] + b;
    if (m > 0 && s.holds(lb) && flush(t)) continue;
    s.put(m, la, lb, sides.members[side][a], sides.members[other][b], u, vx, vy, vz);
    s.t[m] = t;
    s.w[m] = layer.speed(a) + sides.layer[other]->speed(b);
    if (++m == kPairBatch) flush(t);
  }
  counts_[3 * c] += candidates;
  return clock.due(dt) - static_cast<double>(clock.events);
}

// A layer-step draws two numbers an envelope event and two more a candidate: a few Philox blocks at
// least, which sixteen side by side (AVX2, AVX-512) cost less than one after the other; without a
// vector version, from a local copy of the stream.
double CollisionStage::collide_weighted(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c,
                                        const WeightedSides& sides, double credit, double dt, Rng& stream,
                                        PairBatch& batch) {
  double left = 0;
  draw_from(stream, philox_sixteen_vectorized(),
            [&](auto& draws) { left = weighted_step(rule, particles, c, sides, credit, dt, draws, batch); });
  return left;
}

void CollisionStage::envelope_velocity(const ParticleSpan& particles, std::size_t c, const std::uint32_t* members,
                                       std::uint32_t count, double (&u)[3]) const {
  u[0] = u[1] = u[2] = 0;
  if (cells_ && cells_[c].count >= 2) {
    std::copy(cells_[c].mean_velocity, cells_[c].mean_velocity + 3, u);
    return;
  }
  for (std::uint32_t a = 0; a < count; ++a) {
    const std::uint32_t i = members[a];
    u[0] += particles.vx.data[i], u[1] += particles.vy.data[i], u[2] += particles.vz.data[i];
  }
  for (double& x : u) x /= count;
}

// One group's step with weighted pairs: the envelope of its members' speeds built, then its events
// and candidates (collide_weighted).
void CollisionStage::collide_group_weighted(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c,
                                            double dt, Rng& select, PairBatch& batch) {
  const Group& group = groups_[c];
  const bool in_storage_order = group.members == identity_.data();
  std::uint64_t* const counts = counts_.data() + 3 * c;
  thread_local WeightedLayer layer;
  // With the bulk bound kBulkSpeedBound times the rms speed.
  double u[3];
  envelope_velocity(particles, c, group.members, group.count, u);
  // A homogeneous system of one group: storage order, and B_0 from the reference temperature
  // (kBulkSpeedBound times the rms speed sqrt(3 T_ref/m)), so one pass builds the envelope.
  if (in_storage_order ? !layer.build_contiguous(particles, group.count, u, kBulkSpeedBound * std::sqrt(3.0) * speed_[c])
                       : !layer.build(particles, group.members, group.count, u, kBulkSpeedBound)) {
    remainder_[c] = 0;
    return;
  }
  // This step's velocities are not followed by the kept bounds (a homogeneous system of one
  // group: no other group runs meanwhile); they are rebuilt at the next uniform step.
  kept_.invalidate();
  // The remainder is a fraction of an envelope event here and of a uniform candidate otherwise:
  // in [0, 1) either way, so a layer that changes its draw (run.pair_selection at a resume)
  // carries less than one.
  // K = sigma^2 pi scale (2 P(N_c) / N_c) / V_c (weighted_step)
  WeightedSides sides;
  sides.layer[0] = &layer;
  sides.members[0] = group.members;
  sides.count[0] = group.count;
  sides.per_bound[0] = 2.0 * pair_count(scheme_, group.count) / group.count * batch.sigma * batch.sigma * M_PI *
                       rule.rate_bound(1.0) / group.volume;
  remainder_[c] = collide_weighted(rule, particles, c, sides, remainder_[c], dt, select, batch);
  counts[1] = batch.collided;
  counts[2] = batch.exceeded;
  energy_[c] = batch.energy_change;
  missed_[c] = batch.missed;
}

}  // namespace gdsmc::host
