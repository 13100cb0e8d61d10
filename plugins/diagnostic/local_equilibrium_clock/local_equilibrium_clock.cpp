// Local-equilibrium collision clock s0(t) (000 Eq. 3.13; Eq. 3.11 in a slab) beside the measured s(t).
#include <cmath>
#include <cstdio>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class LocalEquilibriumClock final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "local_equilibrium_clock";
  static constexpr const char* version = "1.2.2";
  static constexpr const char* summary =
      "s0(t) = (beta/sqrt(pi)) int dt/tau(T) (Eq. 3.13; layer sum of Eq. 3.11 in a slab) beside the measured s(t), and s/s0";
  static constexpr const char* documentation =
      "The local-equilibrium number of collisions per particle of a homogeneous state (paper 000,\n"
      "Eq. 3.13): s0(t) = (beta/sqrt(pi)) int_0^t dt'/tau(t'), tau = lambda0/sqrt(2T/m), with beta = 1\n"
      "for IHS and beta = the EHS rule's published 'rate_factor' (tau' = tau/beta, Eq. 2.19; set\n"
      "rate_factor: one to use beta = 1 regardless). In a slab the general form, Eq. (3.11), is used:\n"
      "  ds0/dt = (beta/2)(2/sqrt(pi)) (1/(n-bar L)) sum_I n_I delta_y / tau_I,\n"
      "over the cell_count layers of width delta_y = L/M, with tau_I = lambda_I/sqrt(2 T_I/m) and\n"
      "lambda_I = lambda0 n-bar/n_I (Eqs. 2.12-2.13) from each layer's n_I and T_I (ctx.cells, as of\n"
      "the host's last moment update, run.moments_every; layers with fewer than 2 particles, T_I = 0,\n"
      "contribute nothing); with uniform n and T it reduces to Eq. (3.13). The rate is evaluated at\n"
      "every sample (homogeneous: T of that state, ctx.moments) and integrated with the trapezoidal\n"
      "rule over this diagnostic's samples: the clock only sees the states it samples, so\n"
      "sample_every: 1 makes it exact (up to the trapezoidal error). That error per run is\n"
      "-(h^2/12) int (d^2/dt^2)(1/tau) dt, h = sample spacing: with sample_every: 1 and\n"
      "dt = 1e-3 tau it is ~1e-7 relative; with the paper's sample_every: 4 it is still < 1e-5\n"
      "relative in the runs of Figs. 5-6 (1/tau varies on the scale of many tau). Sample every step\n"
      "(sample_every: 1) when T changes fast (large a tau0 at the start). Series (window means):\n"
      "s0, s (accepted collisions / N), s_over_s0 (Fig. 6), s_over_beta (s'/beta, the EHS clock of\n"
      "Figs. 3-5), all [1]; scalars s0_final (s0 at the last sample) and s_over_s0_final [1].";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::choice("rate_factor", {"from_collision", "one"},
                                     "beta in s0: the collision rule's 'rate_factor' (1 if none) or 1")
                .default_value("from_collision")};
  }
  explicit LocalEquilibriumClock(const gdsmc::Params& p) : use_board_(p.string("rate_factor") == "from_collision") {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& board, gdsmc::OutputSink& out) override {
    const double* b = board.find("rate_factor");
    beta_ = (use_board_ && b) ? *b : 1.0;
    lambda0_ = sys.mean_free_path0;
    window_.declare(out, {{"s0", "1", "local-equilibrium collisions per particle (Eq. 3.13, trapezoidal)"},
                          {"s", "1", "measured collisions per particle"},
                          {"s_over_s0", "1", "s/s0 (Fig. 6)"},
                          {"s_over_beta", "1", "s/beta (the EHS clock s'/beta of Figs. 3-5)"}});
    out.theory("s0", "s", "000 Eqs. 3.11, 3.13");
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.10g", beta_);
    out.attribute("beta", buf);
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    const double rate = ctx.system->geometry == gdsmc::Geometry::slab ? layer_rate(ctx) : homogeneous_rate(ctx);
    if (have_prev_) s0_ += 0.5 * (rate + prev_rate_) * (ctx.time - prev_time_);
    prev_rate_ = rate;
    prev_time_ = ctx.time;
    have_prev_ = true;
    const double s = ctx.collisions_per_particle();
    window_.add({s0_, s, s0_ > 0 ? s / s0_ : std::nan(""), s / beta_});
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { window_.commit(out); }
  // ds0/dt in a homogeneous state (Eq. 3.13).
  double homogeneous_rate(const gdsmc::StepContext& ctx) const {
    return beta_ / (std::sqrt(M_PI) * gdsmc::characteristic_time(lambda0_, ctx.moments->local.temperature));
  }
  // ds0/dt = (beta/2)(2/sqrt(pi)) (1/(n-bar L)) sum_I n_I delta_y_I / tau_I (Eq. 3.11).
  double layer_rate(const gdsmc::StepContext& ctx) const {
    const gdsmc::SystemInfo& sys = *ctx.system;
    double sum = 0;  // sum_I n_I delta_y_I / tau_I
    for (std::size_t I = 0; I < ctx.cell_count; ++I) {
      const gdsmc::CellMoments& c = ctx.cells[I];
      if (c.count < 2 || !(c.temperature > 0) || !(c.number_density > 0)) continue;
      sum += c.number_density * sys.layer_width(I) /
             gdsmc::characteristic_time(lambda0_ * sys.number_density / c.number_density, c.temperature);
    }
    return 0.5 * beta_ * (2.0 / std::sqrt(M_PI)) * sum / (sys.number_density * sys.box[1]);
  }
  void finish(const gdsmc::StepContext& ctx, gdsmc::OutputSink& out) override {
    out.scalar("s0_final", s0_, "1", "s0 at the last sample");
    out.theory("s0_final", "", "000 Eqs. 3.11, 3.13");
    out.scalar("s_over_s0_final", ctx.collisions_per_particle() / s0_, "1", "s/s0 at the end of the run");
    char buf[200];
    std::snprintf(buf, sizeof buf, "local_equilibrium_clock: s = %.4g, s0 = %.4g, s/s0 = %.4f (beta = %g)",
                  ctx.collisions_per_particle(), s0_, ctx.collisions_per_particle() / s0_, beta_);
    out.summary(buf);
  }
  void save_state(gdsmc::StateWriter& out) const override {
    out.write("have_prev", have_prev_);
    out.write("prev_rate", prev_rate_);
    out.write("prev_time", prev_time_);
    out.write("s0", s0_);
    window_.save(out);
  }
  void load_state(gdsmc::StateReader& in) override {
    in.read("have_prev", have_prev_);
    in.read("prev_rate", prev_rate_);
    in.read("prev_time", prev_time_);
    in.read("s0", s0_);
    window_.load(in);
  }

  // Reads the host's moments and no particle (MomentsRead).
  const void* extension(const char* id) const override {
    return gdsmc::offer_moments_read<gdsmc::moments_all, gdsmc::reads_no_particles>(id);
  }
 private:
  bool use_board_;
  double beta_ = 1, lambda0_ = 1;
  bool have_prev_ = false;
  double prev_rate_ = 0, prev_time_ = 0, s0_ = 0;
  gdsmc::WindowAverage window_;
};

}  // namespace

GDSMC_PLUGIN(LocalEquilibriumClock)
