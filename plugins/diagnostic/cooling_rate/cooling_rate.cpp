// Collisional cooling rate zeta measured from the energy lost in collisions, beside zeta0 (000 Eqs. 2.9, 2.16).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <algorithm>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class CoolingRate final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "cooling_rate";
  static constexpr const char* version = "1.3.2";
  static constexpr const char* summary = "Cooling rate zeta from the collisional energy loss, beside zeta0 (Eqs. 2.9, 2.16)";
  static constexpr const char* documentation =
      "Between consecutive samples the host's running sum of the kinetic-energy change declared by\n"
      "every accepted collision (ctx.collision_energy_change, m = 1) changes by dE_coll; with T_a, T_b\n"
      "the temperatures of the two samples (the host's ctx.moments: T of all particles in a homogeneous\n"
      "system, T-bar of Eq. 4.8 in a slab) and dt their distance in time,\n"
      "  -dE_coll = zeta tau (3/2) N int T dt / tau(T),  tau(T) = lambda0/sqrt(2T/m)      (paper 000, Eq. 2.9)\n"
      "with zeta tau (the reduced cooling rate zeta*) constant over the interval and the integral taken\n"
      "exactly for T^(-1/2) linear in t (Haff's law, 000 Eq. 2.16 / 001 Eq. 2.15; exact also for constant T):\n"
      "  int T^(3/2) dt = (dt/2) T_a T_b (T_a^(-1/2) + T_b^(-1/2)).\n"
      "A record window sums -dE_coll and the weights of its sample intervals: zeta_tau = sum(-dE_coll) /\n"
      "sum((3/2) N int T dt / tau(T)). (Version 1.2 divided by the mean T of the window's samples, each\n"
      "taken after its step's collisions: in a cooling gas that is T half a sample interval late, and\n"
      "zeta came out high by about (3/4) zeta x (sample interval): +2.5 % at alpha = 0.3 with samples every\n"
      "0.1 tau.) Beside it the local-equilibrium value zeta0 = 2(1-alpha^2)/(3 sqrt(pi) tau(T_w)),\n"
      "(Eq. 2.16), T_w the mean temperature of the window's samples, alpha the collision rule's 'restitution'.\n"
      "Series: zeta (= zeta_tau / tau(T_w)) and zeta0 in 1/tau0; zeta_tau (zeta* = zeta tau(T)) and zeta0_tau\n"
      "(= 2(1-alpha^2)/(3 sqrt(pi)), constant) per tau(T); zeta_over_zeta0 (= <V12^3>/<V12^3>_0 for IHS by\n"
      "Eq. 2.10). A window without two samples (the first record, t = 0) is NaN. Noisy: only colliding\n"
      "pairs contribute (Sec. V.B); use long record windows. For the EHS rule the collisions are elastic,\n"
      "zeta = 0, and the cooling is the drag's 2 gamma = zeta0 (or the refined value). After the run, over\n"
      "the record windows that lie in the run's steady averaging window (run.average_after; the host sets\n"
      "ctx.in_average_window, this diagnostic has no parameter of its own): zeta_tau_mean = the ratio of\n"
      "the sums over those windows of -dE_coll / (N T_w) and of the weights / (N T_w) (each window counts by\n"
      "its length in mean free times; version 1.2 summed them in absolute units, so in a cooling gas the\n"
      "first windows after the start of the average outweighed the rest), its batch-means standard error\n"
      "from the per-window values, and zeta_over_zeta0_mean = zeta_tau_mean / zeta0_tau. The host's running\n"
      "sum of the collisional energy rounds by eps |sum| at each step: once the gas has cooled by ~1e10\n"
      "since t = 0 a sample interval's loss is no longer resolved; such intervals (loss below 1e4 x that\n"
      "rounding) are left out, counted in the scalar unresolved_intervals and named in the summary.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit CoolingRate(const gdsmc::Params&) {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& board, gdsmc::OutputSink& out) override {
    const double* a = board.find("restitution");
    alpha_ = a ? *a : 1.0;
    if (!a) out.attribute("note", "no 'restitution' published: zeta0 computed with alpha = 1 (zero)");
    N_ = static_cast<double>(sys.particles);
    lambda0_ = sys.mean_free_path0;
    tau0_ = sys.time_unit0;
    zeta0_tau_ = gdsmc::cooling_rate0_times_tau(alpha_);  // Eq. 2.16
    ids_[0] = out.series("zeta", "1/tau0", "collisional cooling rate -(dE_coll/dt)/((3/2) N T) over the record window (Eq. 2.9)");
    ids_[1] = out.series("zeta0", "1/tau0", "local-equilibrium cooling rate 2(1-alpha^2)/(3 sqrt(pi) tau(T)) (Eq. 2.16)");
    ids_[2] = out.series("zeta_tau", "1", "zeta times tau(T) = lambda0/sqrt(2T/m)");
    ids_[3] = out.series("zeta0_tau", "1", "zeta0 times tau(T) = 2(1-alpha^2)/(3 sqrt(pi))");
    ids_[4] = out.series("zeta_over_zeta0", "1", "zeta/zeta0 (= <V12^3>/<V12^3>_0 for IHS, Eq. 2.10)");
    out.theory("zeta0", "zeta", "000 Eq. 2.16");
    out.theory("zeta0_tau", "zeta_tau", "000 Eq. 2.16");
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    const double T = ctx.moments->local.temperature;
    const double E = ctx.collision_energy_change;
    if (have_prev_ && ctx.time > prev_time_ && T > 0 && prev_T_ > 0) {
      const double dt = ctx.time - prev_time_;
      // The host's running sum carries a rounding of eps |sum| per step: an interval whose loss is
      // not above 1e4 times that (a gas cooled by 1e10 or more since t = 0) is left out and counted.
      const double steps = static_cast<double>(ctx.step - prev_step_);
      const double resolution = std::numeric_limits<double>::epsilon() * std::fabs(E) * std::max(1.0, steps);
      if (resolution > 0 && !(std::fabs(E - prev_energy_) > 1e4 * resolution)) {  // elastic: E = 0, resolved
        ++unresolved_;
        prev_T_ = T;
        prev_time_ = ctx.time;
        prev_energy_ = E;
        prev_step_ = ctx.step;
        T_sum_ += T;
        ++T_count_;
        return;
      }
      // int T^(3/2) dt for T^(-1/2) linear in t between the samples (Haff's law)
      const double integral = 0.5 * dt * prev_T_ * T * (1.0 / std::sqrt(prev_T_) + 1.0 / std::sqrt(T));
      win_loss_ += -(E - prev_energy_);
      win_weight_ += 1.5 * N_ * std::sqrt(2.0) / lambda0_ * integral;  // (3/2) N int T dt / tau(T)
    }
    prev_T_ = T;
    prev_time_ = ctx.time;
    prev_energy_ = E;
    prev_step_ = ctx.step;
    have_prev_ = true;
    T_sum_ += T;
    ++T_count_;
  }
  void record(const gdsmc::StepContext& ctx, gdsmc::OutputSink& out) override {
    const double Tw = T_count_ ? T_sum_ / static_cast<double>(T_count_) : std::nan("");
    double zeta = std::nan(""), zeta_tau = std::nan("");
    const double tau = gdsmc::characteristic_time(lambda0_, Tw);
    if (win_weight_ > 0 && Tw > 0) {
      zeta_tau = win_loss_ / win_weight_;
      zeta = zeta_tau / tau;
      if (last_in_window_ && ctx.in_average_window) {  // the whole record window is steady
        // per unit N T_w: each window weighs by its length in mean free times, whatever T has
        // fallen to (in absolute units a cooling gas's first windows would outweigh the rest)
        loss_ += win_loss_ / (N_ * Tw);
        weight_ += win_weight_ / (N_ * Tw);
        per_window_.add(zeta_tau);
      }
    }
    out.append(ids_[0], zeta * tau0_);
    out.append(ids_[1], zeta0_tau_ / tau * tau0_);
    out.append(ids_[2], zeta_tau);
    out.append(ids_[3], zeta0_tau_);
    out.append(ids_[4], zeta_tau / zeta0_tau_);
    last_in_window_ = ctx.in_average_window;
    win_loss_ = win_weight_ = 0;
    T_sum_ = 0;
    T_count_ = 0;
  }
  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    const double zt = weight_ > 0 ? loss_ / weight_ : std::nan("");
    out.scalar("zeta_tau_mean", zt, "1", "steady zeta tau(T) over the record windows in the averaging window (ratio of sums)");
    out.scalar("zeta_tau_standard_error", per_window_.standard_error(), "1", "batch-means standard error from the per-window values");
    out.scalar("zeta_over_zeta0_mean", zt / zeta0_tau_, "1", "zeta_tau_mean / zeta0_tau");
    out.scalar("unresolved_intervals", static_cast<double>(unresolved_), "1",
               "sample intervals left out: collisional energy loss below 1e4 x the rounding of the host's running sum");
    char buf[300];
    std::snprintf(buf, sizeof buf,
                  "cooling_rate: in the averaging window (%zu windows): zeta tau = %.5f +- %.5f, zeta0 tau = %.5f, zeta/zeta0 = %.4f (alpha = %g)",
                  per_window_.count(), zt, per_window_.standard_error(), zeta0_tau_, zt / zeta0_tau_, alpha_);
    out.summary(buf);
    if (unresolved_ > 0) {
      std::snprintf(buf, sizeof buf,
                    "cooling_rate: %zu sample intervals left out: their collisional energy loss is below 1e4 x the "
                    "rounding of the host's running sum (the gas has cooled by ~1e10 or more); zeta is from the others",
                    unresolved_);
      out.summary(buf);
    }
  }
  void save_state(gdsmc::StateWriter& out) const override {
    out.write("T_sum", T_sum_);
    out.write("T_count", static_cast<std::uint64_t>(T_count_));
    out.write("have_prev", have_prev_);
    out.write("last_in_window", last_in_window_);
    out.write("prev_T", prev_T_);
    out.write("prev_time", prev_time_);
    out.write("prev_energy", prev_energy_);
    out.write("prev_step", static_cast<std::uint64_t>(prev_step_));
    out.write("unresolved", static_cast<std::uint64_t>(unresolved_));
    out.write("win_loss", win_loss_);
    out.write("win_weight", win_weight_);
    out.write("loss", loss_);
    out.write("weight", weight_);
    per_window_.save(out, "per_window");
  }
  void load_state(gdsmc::StateReader& in) override {
    in.read("T_sum", T_sum_);
    std::uint64_t count = 0;
    in.read("T_count", count);
    T_count_ = static_cast<std::size_t>(count);
    in.read("have_prev", have_prev_);
    in.read("last_in_window", last_in_window_);
    in.read("prev_T", prev_T_);
    in.read("prev_time", prev_time_);
    in.read("prev_energy", prev_energy_);
    std::uint64_t u64 = 0;
    in.read("prev_step", u64);
    prev_step_ = u64;
    in.read("unresolved", u64);
    unresolved_ = static_cast<std::size_t>(u64);
    in.read("win_loss", win_loss_);
    in.read("win_weight", win_weight_);
    in.read("loss", loss_);
    in.read("weight", weight_);
    per_window_.load(in, "per_window");
  }

  // Reads the host's moments and no particle (MomentsRead).
  const void* extension(const char* id) const override {
    return gdsmc::offer_moments_read<gdsmc::moments_all, gdsmc::reads_no_particles>(id);
  }
 private:
  double alpha_ = 1, N_ = 1, lambda0_ = 1, tau0_ = 1, zeta0_tau_ = 0;
  std::size_t ids_[5] = {};
  double T_sum_ = 0;
  std::size_t T_count_ = 0;
  bool have_prev_ = false, last_in_window_ = false;
  double prev_T_ = 0, prev_time_ = 0, prev_energy_ = 0;
  double win_loss_ = 0, win_weight_ = 0;
  std::uint64_t prev_step_ = 0;
  std::size_t unresolved_ = 0;
  double loss_ = 0, weight_ = 0;
  gdsmc::BatchMeans per_window_;
};

}  // namespace

GDSMC_PLUGIN(CoolingRate)
