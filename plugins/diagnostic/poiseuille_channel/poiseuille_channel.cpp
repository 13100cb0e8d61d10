// The acceleration-driven Poiseuille channel of paper 004: steady profiles after the total energy
// has settled (Appendix), and every derived quantity of Secs. IV-VI with jackknife errors. The
// plugin samples and batches; the fits of paper 004 are profile_fits.cpp, the columns columns.hpp,
// the trends of its records (E's drift, Q's growth) record_trends.hpp;
// the steady test and the jackknife are the SDK toolkit's (gdsmc/physics/steady.hpp, jackknife.hpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics/bins.hpp>
#include <gdsmc/physics/jackknife.hpp>
#include <gdsmc/physics/steady.hpp>

#include "columns.hpp"
#include "profile_fits.hpp"
#include "record_trends.hpp"

namespace {

using namespace poiseuille;

constexpr std::size_t kMaxBatches = 64;

class PoiseuilleChannel final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "poiseuille_channel";
  static constexpr const char* version = "1.10.0";
  static constexpr const char* summary =
      "Granular Poiseuille flow (004): steady profiles once E(t) settles, slip, bimodality, N1, N2, chi, Q, balances";
  static constexpr const char* documentation = kDocumentation;

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("steady_window", "window of the energy test of the steady state (bare: tau0)")
                .above(0.0)
                .unit(gdsmc::Dimension::time),
            gdsmc::ParamSpec::real("steady_tolerance", "largest relative change of the window mean of E(t) when steady")
                .above(0.0)
                .default_value(0.005),
            gdsmc::ParamSpec::real("steady_sigmas",
                                   "a change of the window mean within this many standard errors (noise) also counts as settled; 0: tolerance only")
                .at_least(0.0)
                .default_value(2.0),
            gdsmc::ParamSpec::real("min_time", "never steady before this time (bare: tau0)")
                .at_least(0.0)
                .unit(gdsmc::Dimension::time)
                .default_value(0.0),
            gdsmc::ParamSpec::real("wall_temperature", "T_w of the units and of the temperature slip (bare: T0)")
                .above(0.0)
                .unit(gdsmc::Dimension::temperature)
                .default_value(1.0),
            gdsmc::ParamSpec::real("centre_fit", "half-width of the curvature fit at the centre line, in W").range(0.05, 0.5).default_value(0.25),
            gdsmc::ParamSpec::integer("wall_fit_bins", "bins next to each wall in the gradient fit (at most bins/2 - 1 are used)")
                .range(2, 50)
                .default_value(3),
            gdsmc::ParamSpec::real("wall_fit_reach",
                                   "distance from each wall of the quadratic fit that gives the wall values u_s_wall ... (bare: lambda0; 0: off)")
                .at_least(0.0)
                .unit(gdsmc::Dimension::length)
                .default_value(0.0)};
  }
  explicit PoiseuilleChannel(const gdsmc::Params& p)
      : window_(p.real("steady_window")),
        tolerance_(p.real("steady_tolerance")),
        sigmas_(p.real("steady_sigmas")),
        min_time_(p.real("min_time")),
        t_wall_(p.real("wall_temperature")),
        centre_fit_(p.real("centre_fit")),
        wall_bins_(static_cast<std::size_t>(p.integer("wall_fit_bins"))),
        wall_reach_(p.real("wall_fit_reach")) {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& quantities, gdsmc::OutputSink& out) override {
    // What it measures is a steady state: `gdsmc plot` draws the steady means of its series.
    out.attribute("stationary", "all");
    if (sys.geometry != gdsmc::Geometry::slab)
      throw std::runtime_error("poiseuille_channel: needs a slab system (system.domain: slab) between two walls");
    sys_ = sys;
    // Written as the run begins, so that `gdsmc validate` shows them (the samples then read a).
    const double* a = quantities.find("body_acceleration");
    accel_ = a ? *a : 0.0;
    out.scalar("a_hat", a_hat(), "1", "dimensionless acceleration a_hat = a W / (2 T_w/m) (004 Eq. 17)");
    bins_ = sys.bins;
    // The wall fits use at most the wall-side half of the bins (less the central one).
    wall_fit_ = std::min(wall_bins_, bins_ / 2 > 0 ? bins_ / 2 - 1 : 0);
    // The fixed-reach fit: the bins whose centres lie within wall_fit_reach of the wall.
    reach_bins_ = 0;
    if (wall_reach_ > 0) {
      const double bin = sys_.bin_width();
      while (reach_bins_ + 1 < bins_ / 2 && (static_cast<double>(reach_bins_) + 0.5) * bin <= wall_reach_) ++reach_bins_;
      if (reach_bins_ < 3) {
        char why[512];
        std::snprintf(why, sizeof why,
                      "poiseuille_channel: wall_fit_reach = %.4g lambda0 holds %zu bin centre(s) next to each wall "
                      "(bins %.4g lambda0 wide, %zu bins); the quadratic wall fit needs 3: give wall_fit_reach >= %.4g "
                      "lambda0, more bins (system.bins), or 0 to switch it off",
                      wall_reach_ / sys_.mean_free_path0, reach_bins_, bin / sys_.mean_free_path0, bins_,
                      2.5 * bin / sys_.mean_free_path0);
        throw std::runtime_error(why);
      }
    }
    batches_.resize(kMaxBatches);
    for (auto& b : batches_) b.begin(bins_, false);
    total_.begin(bins_, false);
    work_.begin(bins_, false);
    extras_.assign(kMaxBatches * kExtra, 0.0);
    filled_ = 0;
    batch_records_ = 1;
    records_in_batch_ = 0;
    steady_ = false;
    steady_from_ = std::nan("");
    steady_test_.configure(window_, tolerance_, sigmas_);
    steady_test_.start(0.0);
    record_e_ = record_vx_ = record_t_ = 0;
    record_samples_ = 0;
    have_last_ = false;
    trends_.clear();
    id_e_ = out.series("E", "T_w", "kinetic energy per particle E(t) = (m/2) sum v^2 / N (004 Eq. A1), mean over the record");
    id_steady_ = out.series("steady", "1", "1 once E(t) has settled (the averaging window), else 0");
    id_q_ = out.series("Q_record", "1", "flow rate of Eq. 40 over the record's samples");
  }

  // From the host's moments and sums in every bin (SampledMoments::bin_sums); no particle is read.
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    const gdsmc::SampledMoments& m = *ctx.moments;
    const double e = m.kinetic_energy / static_cast<double>(m.local.count);
    const double sum_vx = m.local.mean[0] * static_cast<double>(m.local.count);  // of the layers' sums: not of the bins
    record_e_ += e;
    record_vx_ += sum_vx;
    record_t_ += ctx.time_in_tau0();  // the record's time is the mean of its samples', as the host's
    ++record_samples_;
    accel_ = ctx.body_acceleration.x;
    if (!steady_) {
      // The energy test of the Appendix (gdsmc::SteadyTest): consecutive window means of E(t).
      if (!steady_test_.add(ctx.time, e) || ctx.time < min_time_) return;
      steady_ = true;
      steady_from_ = ctx.time;
      filled_ = 1;  // open the first batch; this sample is its first
      have_last_ = false;
    }
    // Accumulate into the open batch (the last filled_ slot).
    batches_[filled_ - 1].append_sample(m);
    double* x = &extras_[(filled_ - 1) * kExtra];
    x[eSumVx] += sum_vx;
    const Ledger now = ledger(ctx);
    if (have_last_) {
      x[eTime] += ctx.time - last_.time;
      x[eWallMomentum] += now.wall_momentum - last_.wall_momentum;
      x[eWallEnergy] += now.wall_energy - last_.wall_energy;
      x[eCollisions] += now.collisions - last_.collisions;
      x[eForcings] += now.forcings - last_.forcings;
    }
    last_ = now;
    have_last_ = true;
  }

  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    const double ns = static_cast<double>(record_samples_);
    const double e = record_samples_ ? record_e_ / ns / t_wall_ : std::nan("");
    const double scale = u_ref() * a_hat();  // 0 without a body force: Q undefined (NaN), not +-inf
    const double q = record_samples_ && scale != 0 ? record_vx_ / (ns * static_cast<double>(sys_.particles)) / scale
                                                   : std::nan("");
    out.append(id_e_, e);
    out.append(id_steady_, steady_ ? 1.0 : 0.0);
    out.append(id_q_, q);
    // The averaging window's records: those whose time (the mean of their samples') is steady_from or later.
    if (record_samples_) trends_.add(record_t_ / ns, e, q, steady_ && record_t_ / ns >= steady_from_ / sys_.time_unit0);
    record_e_ = record_vx_ = record_t_ = 0;
    record_samples_ = 0;
    if (!steady_ || filled_ == 0) return;
    // Close the record in the open batch; open the next batch when this one has its length.
    if (++records_in_batch_ < batch_records_) return;
    records_in_batch_ = 0;
    if (filled_ == kMaxBatches) {  // merge neighbours: 8 batches of twice the length
      for (std::size_t k = 0; k < kMaxBatches / 2; ++k) {
        batches_[k].copy_from(batches_[2 * k]);
        batches_[k].append(batches_[2 * k + 1]);
        double* dst = &extras_[k * kExtra];
        const double* a = &extras_[2 * k * kExtra];
        const double* c = &extras_[(2 * k + 1) * kExtra];
        for (std::size_t j = 0; j < kExtra; ++j) dst[j] = a[j] + c[j];
      }
      for (std::size_t k = kMaxBatches / 2; k < kMaxBatches; ++k) batches_[k].clear();
      std::fill(extras_.begin() + static_cast<std::ptrdiff_t>(kMaxBatches / 2 * kExtra), extras_.end(), 0.0);
      filled_ = kMaxBatches / 2;
      batch_records_ *= 2;
    }
    ++filled_;  // the next batch opens (empty)
  }

  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    out.scalar("Kn", sys_.mean_free_path0 / sys_.box[1], "1", "Knudsen number lambda0 / W (004 Eq. 18)");
    out.scalar("steady_from", steady_ ? steady_from_ / sys_.time_unit0 : std::nan(""), "tau0",
               "time at which E(t) was found steady and averaging began");
    // The batches that hold samples (the open one may be empty).
    std::size_t used = 0;
    for (std::size_t k = 0; k < filled_; ++k)
      if (batches_[k].samples() > 0) ++used;
    out.scalar("batches", static_cast<double>(used), "1", "batches of the steady window in the jackknife");
    // The whole window: the batches appended in order (the order rule of gdsmc/physics/bins.hpp).
    total_.clear();
    std::vector<double> total(kExtra, 0.0);
    for (std::size_t k = 0; k < used; ++k) {
      total_.append(batches_[k]);
      for (std::size_t j = 0; j < kExtra; ++j) total[j] += extras_[k * kExtra + j];
    }
    out.scalar("averaged_time", total[eTime] / sys_.time_unit0, "tau0", "length of the steady window");

    const ProfileFits fits(sys_, t_wall_, accel_, centre_fit_, wall_fit_, reach_bins_);
    Result whole = fits.evaluate(total_, total.data());
    Result err;
    err.scalars.assign(kScalar, std::nan(""));
    err.profiles.assign(kProfile * bins_, std::nan(""));
    if (used >= 2) {
      std::vector<Result> jack;
      std::vector<double> work(kExtra);
      for (std::size_t k = 0; k < used; ++k) {
        work_.copy_from(total_);
        work_.subtract(batches_[k]);
        for (std::size_t j = 0; j < kExtra; ++j) work[j] = total[j] - extras_[k * kExtra + j];
        jack.push_back(fits.evaluate(work_, work.data(), whole.peak_half_width));
      }
      jackknife(jack, kScalar, err.scalars, [](const Result& r) -> const std::vector<double>& { return r.scalars; });
      jackknife(jack, whole.profiles.size(), err.profiles, [](const Result& r) -> const std::vector<double>& { return r.profiles; });
    }
    // The peak's width is fixed by the whole window (the jackknife fits over the same bins): its error
    // is the resolution of its two edges, a bin width / sqrt(6).
    if (std::isfinite(whole.scalars[centre_peak_width]))
      err.scalars[centre_peak_width] = 1.0 / (static_cast<double>(bins_) * std::sqrt(6.0));
    write_columns(out, sys_, whole, err, used, reach_bins_);
    trends_.write(out);
    char line[512];
    if (!steady_) {
      out.summary("poiseuille_channel: E(t) never settled within the steady tolerance: no steady averages (NaN); "
                  "run longer or loosen steady_tolerance");
      return;
    }
    std::snprintf(line, sizeof line,
                  "poiseuille_channel: steady from t = %.4g tau0 over %.4g tau0: Q = %.5g +- %.2g, rho(0) = %.4g, "
                  "u_s = %.4g, Delta T = %.4g +- %.2g, N1(0) = %.3g, N2(0) = %.3g; momentum balance max %.2g, "
                  "wall/body force %.5g, energy closure %.2g",
                  steady_from_ / sys_.time_unit0, total[eTime] / sys_.time_unit0, whole.scalars[Q],
                  err.scalars[Q], whole.scalars[rho_centre], whole.scalars[u_s], whole.scalars[delta_T],
                  err.scalars[delta_T], whole.scalars[N1_centre], whole.scalars[N2_centre],
                  whole.scalars[momentum_balance_max], whole.scalars[wall_momentum_ratio],
                  whole.scalars[energy_balance_closure]);
    out.summary(line);
  }
  void save_state(gdsmc::StateWriter& out) const override {
    for (std::size_t k = 0; k < kMaxBatches; ++k) batches_[k].save(out, "batch" + std::to_string(k));
    out.write("batch_extras", extras_);
    const std::uint64_t counts[3] = {filled_, batch_records_, records_in_batch_};
    out.write("batch_counts", counts, 3);
    out.write("steady", steady_);
    out.write("steady_from", steady_from_);
    steady_test_.save(out, "steady_test");
    out.write("record_samples", static_cast<std::uint64_t>(record_samples_));
    out.write("record_e", record_e_);
    out.write("record_vx", record_vx_);
    out.write("accel", accel_);  // set by the first sample; a_hat() needs it
    out.write("have_last", have_last_);
    const double last[5] = {last_.time, last_.wall_momentum, last_.wall_energy, last_.collisions, last_.forcings};
    out.write("last", last, 5);
    out.write("record_t", record_t_);
    trends_.save(out, "trends");
  }
  void load_state(gdsmc::StateReader& in) override {
    for (std::size_t k = 0; k < kMaxBatches; ++k) batches_[k].load(in, "batch" + std::to_string(k));  // as begin() sized them
    in.read("batch_extras", extras_.data(), extras_.size());
    std::uint64_t counts[3];
    in.read("batch_counts", counts, 3);
    if (counts[0] > kMaxBatches || counts[1] == 0 || counts[2] >= counts[1])
      throw gdsmc::StateError("checkpoint entry 'batch_counts': not a batch state of poiseuille_channel");
    filled_ = static_cast<std::size_t>(counts[0]);
    batch_records_ = static_cast<std::size_t>(counts[1]);
    records_in_batch_ = static_cast<std::size_t>(counts[2]);
    in.read("steady", steady_);
    in.read("steady_from", steady_from_);
    steady_test_.load(in, "steady_test");
    std::uint64_t record_samples = 0;
    in.read("record_samples", record_samples);
    record_samples_ = static_cast<std::size_t>(record_samples);
    in.read("record_e", record_e_);
    in.read("record_vx", record_vx_);
    in.read("accel", accel_);
    in.read("have_last", have_last_);
    double last[5];
    in.read("last", last, 5);
    last_ = {last[0], last[1], last[2], last[3], last[4]};
    in.read("record_t", record_t_);
    trends_.load(in, "trends");
  }

  // Sampled on both sides of the collision stage (BracketedSampling): its means carry no O(dt) bias.
  // Reads the mean, the kinetic energy and the bin sums of the host's sampled moments, no particle (MomentsRead).
  const void* extension(const char* id) const override {
    if (const void* e = gdsmc::offer_bracketed_sampling(id)) return e;
    return gdsmc::offer_moments_read<gdsmc::moments_means | gdsmc::moments_energy | gdsmc::moments_bins,
                                     gdsmc::reads_no_particles>(id);
  }
 private:
  struct Ledger {
    double time = 0, wall_momentum = 0, wall_energy = 0, collisions = 0, forcings = 0;
  };

  static Ledger ledger(const gdsmc::StepContext& ctx) {
    Ledger l;
    l.time = ctx.time;
    for (std::size_t w = 0; w < ctx.boundary_count; ++w) {
      l.wall_momentum += ctx.boundaries[w].momentum[0];
      l.wall_energy += ctx.boundaries[w].energy;
    }
    for (std::size_t k = 0; k < ctx.energy_ledger_size; ++k) {  // no std::string: called every sample
      const char* stage = ctx.energy_ledger[k].stage;
      if (std::strcmp(stage, "collisions") == 0) l.collisions += ctx.energy_ledger[k].energy;
      else if (std::strcmp(stage, "y_min") != 0 && std::strcmp(stage, "y_max") != 0) l.forcings += ctx.energy_ledger[k].energy;
    }
    return l;
  }

  double u_ref() const { return reference_speed(t_wall_, sys_.mass); }
  double a_hat() const { return poiseuille::a_hat(accel_, sys_.box[1], u_ref()); }  // 004 Eq. 17

  // err[j] = the jackknife error (gdsmc::jackknife_error) of whole[j] from the delete-one results.
  template <class Get>
  static void jackknife(const std::vector<Result>& jack, std::size_t n, std::vector<double>& err, Get get) {
    std::vector<double> v(jack.size());
    for (std::size_t j = 0; j < n; ++j) {
      for (std::size_t k = 0; k < jack.size(); ++k) v[k] = get(jack[k])[j];
      err[j] = gdsmc::jackknife_error(v.data(), v.size());
    }
  }

  double window_, tolerance_, sigmas_, min_time_, t_wall_, centre_fit_;
  std::size_t wall_bins_, wall_fit_ = 0;
  double wall_reach_;           // wall_fit_reach (reduced length; 0: off)
  std::size_t reach_bins_ = 0;  // bins of the quadratic wall fit
  gdsmc::SystemInfo sys_;
  std::size_t bins_ = 0, filled_ = 0, batch_records_ = 1, records_in_batch_ = 0;
  std::vector<gdsmc::BinSums> batches_;  // kMaxBatches per-bin sums
  std::vector<double> extras_;           // kMaxBatches x kExtra whole-system sums
  gdsmc::BinSums total_, work_;          // finish(): the whole window, the window less one batch
  bool steady_ = false, have_last_ = false;
  double steady_from_ = 0;
  gdsmc::SteadyTest steady_test_;
  std::size_t record_samples_ = 0;
  double record_e_ = 0, record_vx_ = 0, record_t_ = 0, accel_ = 0;
  Ledger last_;
  RecordTrends trends_;  // E and Q_record of every record, for their trends at the end
  std::size_t id_e_ = 0, id_steady_ = 0, id_q_ = 0;
};

}  // namespace

GDSMC_PLUGIN(PoiseuilleChannel)

// What `gdsmc conformance` runs it in when no --context is given.
// A channel: a slab of 12 layers (its wall-gradient fits) between diffuse walls, driven along x.
GDSMC_CONFORMANCE_CONTEXT(
    "system: {density: 1.0e-3, temperature: 1.0, domain: slab, box: {y: 1.0}, layers: 12}\n"
    "forcings: [{plugin: body_acceleration, acceleration: 0.5}]\n"
    "boundaries: {y: diffuse_wall}")
