// Species-resolved moments of a mixture: partial densities, flows, temperatures and their ratio to
// the mixture temperature, partial pressure tensors and heat fluxes, fourth cumulants, partial
// cooling rates, per-species profiles of a slab and per-species wall fluxes.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>
#include <gdsmc/physics/bins.hpp>

namespace {

// The sums over the particles of one species at one sample, in this order: the count, the
// laboratory velocity, and the peculiar moments V V, |V|^2 V and |V|^4 (V = v - u, u the
// barycentric flow of the particle's cell).
enum Acc : std::size_t { aN, aVx, aVy, aVz, aXX, aYY, aZZ, aXY, aXZ, aYZ, aQx, aQy, aQz, aV4, kAcc };

// The series of one species, in this order (per species, then the mixture's T).
enum Col : std::size_t { cN, cUx, cUy, cUz, cT, cTratio, cPxx, cPyy, cPzz, cPxy, cPxz, cPyz, cQx, cQy, cQz, cA2, kCol };

// The profiles of one species (slab), and of the mixture (the same names without [name]).
enum Prof : std::size_t { pN, pUx, pUy, pUz, pT, pTratio, kProf };

class SpeciesMoments final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "species_moments";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary =
      "Per-species n_i, u_i, T_i, T_i/T, P_i, q_i, a2_i, partial cooling rates, slab profiles and wall fluxes";
  static constexpr const char* documentation =
      "A mixture's species one by one (system.species; SDK 6.5). <name> is a species' name (its index 0, 1, ...\n"
      "when the run names none) and X the species in formulas: N_X its number of particles, m_X its mass, Omega the volume, N and n0 = N/Omega\n"
      "the total number and density. V = v - u is the velocity relative to the mixture's barycentric flow\n"
      "u = sum m_i v_i / sum m_i of the particle's collision cell, exactly as the host's moments take it\n"
      "(ctx.moments->cell_mean_velocity; gdsmc/context.hpp): of all particles in a homogeneous system, of\n"
      "the particle's layer in a slab, so that the mixture T below is the host's T (T-bar of 000 Eq. 4.8 in\n"
      "a slab) to round-off. <.>_X is the mean over species X's particles at one sample. Series, each\n"
      "record the mean of the samples since the previous record:\n"
      "  n[<name>]  = N_X / Omega                                   [n0]\n"
      "  u_<a>[<name>] = <v_a>_X, a = x, y, z (laboratory frame)   [sqrt(2T0/m)]\n"
      "  T[<name>]  = m_X <|V|^2>_X / 3                             [T0]  (000 Eq. 4.15 per species)\n"
      "  T         = sum_X (N_X/N) T_X, the mixture temperature   [T0]\n"
      "  T_ratio[<name>] = T_X / T                                     [1]   (1 for all X at equipartition)\n"
      "  P_<ab>[<name>] = (N_X/Omega) m_X <V_a V_b>_X, ab = xx yy zz xy xz yz   [n0 T0]  (000 Eq. 4.16)\n"
      "  q_<a>[<name>] = (N_X/Omega) (m_X/2) <|V|^2 V_a>_X             [n0 T0 sqrt(2T0/m)]\n"
      "  a2[<name>] = m_X^2 <|V|^4>_X / (15 T_X^2) - 1                [1]   (000 Eq. 4.17 per species)\n"
      "so sum_X P_X is the pressure tensor of pressure_tensor and sum_X n_X T_X = n T. A species\n"
      "without particles gives NaN. Partial cooling rates: with E_X the rule's running tally\n"
      "species_energy_change[<name>] (the kinetic-energy change of X's particles summed over collisions;\n"
      "inelastic_hard_spheres keeps it in a mixture; in a one-species run the host's\n"
      "collision_energy_change, which is the same sum) and E the host's collision_energy_change, over\n"
      "each record window, summed over its sample intervals [t_a, t_b],\n"
      "  zeta_X = -sum dE_X / ((3/2) N_X sum int T_X dt),  zeta = -sum dE / ((3/2) N sum int T dt)\n"
      "(000 Eq. 2.9: dT/dt = -zeta T per species and for the mixture) with int T dt = (t_b - t_a)\n"
      "sqrt(T_a T_b), exact when T^(-1/2) is linear in t (Haff's law, 000 Eq. 2.16) and for constant T;\n"
      "series zeta[<name>] (zeta_X), zeta [1/tau0] and zeta_ratio[<name>] = zeta_X/zeta [1] (1 for every species in\n"
      "the scaled homogeneous cooling state, where all T_X/T are constant). The first record (t = 0) is NaN;\n"
      "so is zeta_ratio when zeta = 0 (elastic collisions), and zeta[<name>] when the rule keeps no tally\n"
      "species_energy_change[<name>] (the summary says so). These are collisional rates: energy that a forcing\n"
      "or a wall adds is not in them.\n"
      "Slab systems also get profiles (record x bin) in the sampling bins along y, window sums as the\n"
      "profiles diagnostic accumulates them (004 Eq. 13; gdsmc::BinSums per species): with N_Xb the\n"
      "count of X in bin b over the N_t samples of the window, V_bin the bin volume and u_b = sum_X m_X\n"
      "sum v / sum_X m_X N_Xb the window's barycentric flow in the bin (the bin's, not the layer's: the\n"
      "profiles' own flow, so the profiles do not depend on the collision layers),\n"
      "  n_profile[<name>] = N_Xb / (N_t V_bin) [n0],  u_<a>_profile[<name>] = sum v_a / N_Xb [sqrt(2T0/m)],\n"
      "  T_profile[<name>] = T_Xb = m_X sum |v - u_b|^2 / (3 N_Xb) [T0],  T_ratio_profile[<name>] = T_Xb / T_b [1],\n"
      "and the mixture's n_profile, u_<a>_profile (= u_b), T_profile (T_b = sum_X N_Xb T_Xb / sum_X N_Xb) [same units]\n"
      "and T_ratio_profile (1 where the bin has particles);\n"
      "NaN where the species (T_ratio: the bin) had no particle in the window. In a slab mixture, from the\n"
      "host's per-species boundary tallies (StepContext::species_boundaries), between records over the\n"
      "time dt_w between them and the wall area A = Lx Lz, for w = y_min, y_max (as wall_fluxes does for\n"
      "the whole gas; their sums over X are wall_fluxes' values):\n"
      "  <w>_hit_rate[<name>] = d(hits) / (A dt_w) [1/(lambda0^2 tau0)],\n"
      "  <w>_momentum_flux_<a>[<name>] = d(momentum_a) / (A dt_w) [n0 T0],  <w>_energy_flux[<name>] = d(energy) / (A dt_w)\n"
      "  [n0 T0 sqrt(2T0/m)]: momentum and energy given to the gas by the wall, per unit area and time\n"
      "  (NaN, and a summary line, if the host hands no per-species tallies).\n"
      "With run.average_after the host writes every series' and profile's steady mean and standard error\n"
      "(<series>.steady_mean, .steady_stderr: over realizations when there are several, else batch means\n"
      "with Wolff's integrated autocorrelation time; user guide, 'Steady averages and their errors').\n"
      "Declared stationary (group attribute `stationary`): T_ratio[<name>], a2[<name>], zeta_ratio[<name>], constant in\n"
      "the scaled homogeneous cooling state and in steady states. A one-species run works and gives the\n"
      "one-species moments (T_ratio = zeta_ratio = 1; a2 is cumulants' a2): no refusal.\n"
      "Sampled on both sides of the collision stage when the host brackets (the moments carry no O(dt)\n"
      "bias; the cooling rates sum over the sample intervals whatever their phase); reads only the\n"
      "host's mean velocities (moments_read: means).";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit SpeciesMoments(const gdsmc::Params&) {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    S_ = sys.species_count;
    N_ = static_cast<double>(sys.particles);
    volume_ = sys.volume;
    t0_ = sys.initial_temperature;
    v0_ = std::sqrt(2.0 * sys.initial_temperature / sys.mass);
    n0_ = sys.number_density;
    tau0_ = sys.time_unit0;
    slab_ = sys.geometry == gdsmc::Geometry::slab;
    names_.assign(S_, "");
    tally_names_.assign(S_, "");
    mass_.assign(S_, 1.0);
    for (std::size_t s = 0; s < S_; ++s) {
      names_[s] = sys.species && sys.species[s].name && *sys.species[s].name ? sys.species[s].name : std::to_string(s);
      if (names_[s].find_first_of("/,[]") != std::string::npos)
        throw std::runtime_error("species_moments: species '" + names_[s] +
                                 "' cannot name a dataset: a species name for this diagnostic has no '/', ',', '[' or ']'");
      tally_names_[s] = "species_energy_change[" + names_[s] + "]";
      mass_[s] = sys.species_mass(s);
    }
    declare_series(out);
    acc_.assign(S_ * kAcc, 0.0);
    values_.assign(S_ * kCol + 1, 0.0);
    T_now_.assign(S_, 0.0);
    count_.assign(S_, 0.0);
    zeta_.assign(4 * S_, 0.0);  // per species: previous T, previous E, window loss, window weight
    prev_T_mix_ = prev_E_mix_ = loss_mix_ = weight_mix_ = prev_time_ = 0;
    have_prev_ = false;
    tallies_missing_ = walls_missing_ = false;
    if (slab_) begin_profiles(sys, out);
    walls_ = slab_ && S_ > 1;
    if (walls_) begin_walls(sys, out);
  }

  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const gdsmc::SampledMoments& sm = *ctx.moments;
    const double* cell_u = sm.cell_mean_velocity;
    std::fill(acc_.begin(), acc_.end(), 0.0);
    for (std::size_t i = 0; i < p.count; ++i) {
      const std::size_t s = p.species_of(i);
      double* a = &acc_[s * kAcc];
      const double* u = (cell_u && p.cell) ? cell_u + 3 * static_cast<std::size_t>(p.cell[i]) : sm.local.mean;
      const double vx = p.vx[i], vy = p.vy[i], vz = p.vz[i];
      const double X = vx - u[0], Y = vy - u[1], Z = vz - u[2], V2 = X * X + Y * Y + Z * Z;
      a[aN] += 1.0;
      a[aVx] += vx; a[aVy] += vy; a[aVz] += vz;
      a[aXX] += X * X; a[aYY] += Y * Y; a[aZZ] += Z * Z;
      a[aXY] += X * Y; a[aXZ] += X * Z; a[aYZ] += Y * Z;
      a[aQx] += V2 * X; a[aQy] += V2 * Y; a[aQz] += V2 * Z;
      a[aV4] += V2 * V2;
      if (slab_) bins_[s].add(ctx.system->bin_of(p.y[i]), vx, vy, vz);
    }
    if (slab_)
      for (gdsmc::BinSums& b : bins_) b.end_sample();
    species_values();
    window_.add(values_);
    cooling_sample(ctx);
    if (walls_) wall_sample(ctx);
  }

  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    window_.commit(out);
    cooling_record(out);
    if (slab_) profile_record(out);
    if (walls_) wall_record(out);
  }

  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    if (walls_missing_)
      out.summary("species_moments: the run handed no per-species boundary tallies (StepContext::species_boundaries): "
                  "its per-species wall series are NaN");
    if (!tallies_missing_) return;
    out.attribute("note", "the collision rule keeps no species_energy_change[<name>] tallies: zeta[<name>] and "
                          "zeta_ratio[<name>] are NaN");
    out.summary("species_moments: the collision rule keeps no species_energy_change[<name>] tallies, so the partial "
                "cooling rates zeta[<name>] are NaN (inelastic_hard_spheres keeps them in a mixture)");
  }

  // values_, T_now_, count_, acc_ are scratch of one sample: not saved.
  void save_state(gdsmc::StateWriter& out) const override {
    window_.save(out);
    out.write("cooling.species", zeta_);
    const double mix[5] = {prev_T_mix_, prev_E_mix_, loss_mix_, weight_mix_, prev_time_};
    out.write("cooling.mixture", mix, 5);
    out.write("cooling.have_prev", have_prev_);
    out.write("cooling.tallies_missing", tallies_missing_);
    out.write("walls.missing", walls_missing_);
    for (std::size_t s = 0; s < bins_.size(); ++s) bins_[s].save(out, "bins." + std::to_string(s));
    if (walls_) {
      save_tallies(out, "walls.previous", previous_);
      save_tallies(out, "walls.current", current_);
      const double times[2] = {wall_previous_time_, wall_current_time_};
      out.write("walls.times", times, 2);
    }
  }
  void load_state(gdsmc::StateReader& in) override {
    window_.load(in);
    in.read("cooling.species", zeta_.data(), zeta_.size());
    double mix[5];
    in.read("cooling.mixture", mix, 5);
    prev_T_mix_ = mix[0], prev_E_mix_ = mix[1], loss_mix_ = mix[2], weight_mix_ = mix[3], prev_time_ = mix[4];
    in.read("cooling.have_prev", have_prev_);
    in.read("cooling.tallies_missing", tallies_missing_);
    in.read("walls.missing", walls_missing_);
    for (std::size_t s = 0; s < bins_.size(); ++s) bins_[s].load(in, "bins." + std::to_string(s));
    if (walls_) {
      load_tallies(in, "walls.previous", previous_);
      load_tallies(in, "walls.current", current_);
      double times[2];
      in.read("walls.times", times, 2);
      wall_previous_time_ = times[0], wall_current_time_ = times[1];
    }
  }

  // Handles a mixture (gdsmc.species); bracketed sampling; reads only the host's mean velocities.
  const void* extension(const char* id) const override {
    if (const void* e = gdsmc::offer_species(id)) return e;
    if (const void* e = gdsmc::offer_bracketed_sampling(id)) return e;
    return gdsmc::offer_moments_read<gdsmc::moments_means>(id);
  }

 private:
  static constexpr const char* kAxes[3] = {"x", "y", "z"};

  std::string of(const char* quantity, std::size_t s) const { return std::string(quantity) + "[" + names_[s] + "]"; }

  void declare_series(gdsmc::OutputSink& out) {
    namespace u = gdsmc::units;
    std::vector<gdsmc::WindowAverage::Column> cols;
    std::string stationary;
    for (std::size_t s = 0; s < S_; ++s) {
      const std::string& X = names_[s];
      cols.push_back({of("n", s), u::density, "partial number density N_X / Omega of species " + X});
      for (int a = 0; a < 3; ++a)
        cols.push_back({of((std::string("u_") + kAxes[a]).c_str(), s), u::speed,
                        std::string("flow velocity <v_") + kAxes[a] + "> of species " + X + " (laboratory frame)"});
      cols.push_back({of("T", s), u::temperature,
                      "partial temperature m_X <|v - u|^2>/3 of species " + X + ", u the barycentric flow (000 Eq. 4.15)"});
      cols.push_back({of("T_ratio", s), u::dimensionless, "T[" + X + "] / T, T the mixture temperature"});
      const char* P[6] = {"P_xx", "P_yy", "P_zz", "P_xy", "P_xz", "P_yz"};
      for (const char* c : P)
        cols.push_back({of(c, s), u::pressure, std::string("partial pressure tensor n_X m_X <V V>, element ") + (c + 2) +
                                                   ", species " + X + " (000 Eq. 4.16)"});
      for (int a = 0; a < 3; ++a)
        cols.push_back({of((std::string("q_") + kAxes[a]).c_str(), s), u::heat_flux,
                        std::string("partial heat flux n_X (m_X/2) <|V|^2 V_") + kAxes[a] + ">, species " + X});
      cols.push_back({of("a2", s), u::dimensionless,
                      "fourth cumulant m_X^2 <|V|^4> / (15 T_X^2) - 1 of species " + X + " (000 Eq. 4.17)"});
      stationary += (s ? "," : "") + of("T_ratio", s) + "," + of("a2", s) + "," + of("zeta_ratio", s);
    }
    cols.push_back({"T", u::temperature, "mixture temperature sum_X (N_X/N) T[X] (the host's T to round-off)"});
    window_.declare(out, cols);
    zeta_ids_.assign(2 * S_, 0);
    for (std::size_t s = 0; s < S_; ++s) {
      zeta_ids_[2 * s] = out.series(of("zeta", s), u::rate,
                                    "partial cooling rate -(dE_X/dt) / ((3/2) N_X T_X) over the record window (000 Eq. 2.9)");
      zeta_ids_[2 * s + 1] = out.series(of("zeta_ratio", s), u::dimensionless, "zeta[" + names_[s] + "] / zeta");
    }
    zeta_mix_id_ = out.series("zeta", u::rate, "mixture cooling rate -(dE/dt) / ((3/2) N T) over the record window (000 Eq. 2.9)");
    out.attribute("stationary", stationary);
  }

  // The sample's series values from acc_ (the formulas of the documentation).
  void species_values() {
    const double nan = std::nan(""), nT0 = n0_ * t0_;
    double sum_NT = 0, total = 0;
    for (std::size_t s = 0; s < S_; ++s) {
      const double* a = &acc_[s * kAcc];
      double* v = &values_[s * kCol];
      const double Ns = a[aN], m = mass_[s];
      count_[s] = Ns;
      total += Ns;
      v[cN] = Ns / volume_ / n0_;
      const double T = Ns > 0 ? m * (a[aXX] + a[aYY] + a[aZZ]) / (3.0 * Ns) : nan;  // 000 Eq. 4.15, species s
      T_now_[s] = T;
      if (!(Ns > 0)) {
        for (std::size_t k = cUx; k < kCol; ++k) v[k] = nan;
        continue;
      }
      sum_NT += Ns * T;
      for (int c = 0; c < 3; ++c) v[cUx + c] = a[aVx + c] / Ns / v0_;
      v[cT] = T / t0_;
      for (int k = 0; k < 6; ++k) v[cPxx + k] = m * a[aXX + k] / volume_ / nT0;               // 000 Eq. 4.16, species s
      for (int c = 0; c < 3; ++c) v[cQx + c] = 0.5 * m * a[aQx + c] / volume_ / (nT0 * v0_);  // (m/2) sum |V|^2 V / Omega
      v[cA2] = m * m * (a[aV4] / Ns) / (15.0 * T * T) - 1.0;                                 // 000 Eq. 4.17, species s
    }
    T_mix_ = total > 0 ? sum_NT / total : nan;  // T = sum_X x_X T_X
    for (std::size_t s = 0; s < S_; ++s) values_[s * kCol + cTratio] = T_now_[s] / T_mix_;
    values_[S_ * kCol] = T_mix_ / t0_;
  }

  // The cooling-rate sums of one sample interval (documentation: int T dt = dt sqrt(T_a T_b)).
  void cooling_sample(const gdsmc::StepContext& ctx) {
    const double E_mix = ctx.collision_energy_change;
    const double dt = ctx.time - prev_time_;
    for (std::size_t s = 0; s < S_; ++s) {
      double* z = &zeta_[4 * s];  // previous T, previous E, loss, weight
      const double* tally = S_ == 1 ? &ctx.collision_energy_change : ctx.collision_tally(tally_names_[s]);
      if (!tally) tallies_missing_ = true;
      const double E = tally ? *tally : std::nan("");
      if (have_prev_ && dt >= 0) {
        z[2] += -(E - z[1]);
        z[3] += 1.5 * count_[s] * dt * std::sqrt(z[0] * T_now_[s]);  // (3/2) N_X int T_X dt (000 Eq. 2.9)
      }
      z[0] = T_now_[s];
      z[1] = E;
    }
    if (have_prev_ && dt >= 0) {
      loss_mix_ += -(E_mix - prev_E_mix_);
      weight_mix_ += 1.5 * N_ * dt * std::sqrt(prev_T_mix_ * T_mix_);  // (3/2) N int T dt
    }
    prev_T_mix_ = T_mix_;
    prev_E_mix_ = E_mix;
    prev_time_ = ctx.time;
    have_prev_ = true;
  }

  void cooling_record(gdsmc::OutputSink& out) {
    const double nan = std::nan("");
    const double zeta = weight_mix_ > 0 ? loss_mix_ / weight_mix_ : nan;  // per reduced time
    for (std::size_t s = 0; s < S_; ++s) {
      double* z = &zeta_[4 * s];
      const double zs = z[3] > 0 ? z[2] / z[3] : nan;
      out.append(zeta_ids_[2 * s], zs * tau0_);
      out.append(zeta_ids_[2 * s + 1], zeta != 0 ? zs / zeta : nan);
      z[2] = z[3] = 0;
    }
    out.append(zeta_mix_id_, zeta * tau0_);
    loss_mix_ = weight_mix_ = 0;
  }

  void begin_profiles(const gdsmc::SystemInfo& sys, gdsmc::OutputSink& out) {
    namespace u = gdsmc::units;
    nb_ = sys.bins;
    bin_volume_ = sys.bin_width() * sys.cross_section();
    bins_.assign(S_, gdsmc::BinSums{});
    for (gdsmc::BinSums& b : bins_) b.begin(nb_, false);
    profile_ids_.assign((S_ + 1) * kProf, 0);
    profile_values_.assign((S_ + 1) * kProf * nb_, 0.0);
    for (std::size_t s = 0; s <= S_; ++s) {
      const bool mix = s == S_;
      auto name = [&](const char* q) { return mix ? std::string(q) : of(q, s); };
      const std::string who = mix ? std::string("the mixture") : "species " + names_[s];
      std::size_t* id = &profile_ids_[s * kProf];
      id[pN] = out.profile(name("n_profile"), u::density, "number density n(y) of " + who + " (004 Eq. 14)");
      for (int a = 0; a < 3; ++a)
        id[pUx + a] = out.profile(name((std::string("u_") + kAxes[a] + "_profile").c_str()), u::speed,
                                  std::string("flow velocity u_") + kAxes[a] + "(y) of " + who +
                                      (mix ? " (barycentric)" : "") + " (004 Eq. 15)");
      id[pT] = out.profile(name("T_profile"), u::temperature,
                           "temperature T(y) of " + who + ", about the bin's barycentric flow (004 Eq. 16 per species)");
      id[pTratio] = out.profile(name("T_ratio_profile"), u::dimensionless, "T_profile of " + who + " / T_profile of the mixture");
    }
  }

  // One record of the profiles from the window's per-species bin sums (documentation).
  void profile_record(gdsmc::OutputSink& out) {
    const double nan = std::nan("");
    const std::size_t mix = S_;
    auto at = [&](std::size_t s, std::size_t k, std::size_t b) -> double& { return profile_values_[(s * kProf + k) * nb_ + b]; };
    for (std::size_t b = 0; b < nb_; ++b) {
      const double samples = bins_[0].samples();
      double mass = 0, momentum[3] = {0, 0, 0}, count = 0;
      for (std::size_t s = 0; s < S_; ++s) {
        const double* a = bins_[s].sums(b);
        mass += mass_[s] * a[gdsmc::BinSums::kCount];
        count += a[gdsmc::BinSums::kCount];
        for (int c = 0; c < 3; ++c) momentum[c] += mass_[s] * a[gdsmc::BinSums::kVx + c];
      }
      const double norm = samples > 0 ? 1.0 / (samples * bin_volume_) : nan;
      const double u[3] = {momentum[0] / mass, momentum[1] / mass, momentum[2] / mass};  // barycentric u_b
      double sum_NT = 0;
      for (std::size_t s = 0; s < S_; ++s) {
        const double* a = bins_[s].sums(b);
        const double Nb = a[gdsmc::BinSums::kCount];
        at(s, pN, b) = Nb * norm / n0_;  // 004 Eq. 14
        if (!(Nb > 0)) {
          for (std::size_t k = pUx; k < kProf; ++k) at(s, k, b) = nan;
          continue;
        }
        const double v2 = a[gdsmc::BinSums::kVxx] + a[gdsmc::BinSums::kVyy] + a[gdsmc::BinSums::kVzz];
        const double uv = u[0] * a[gdsmc::BinSums::kVx] + u[1] * a[gdsmc::BinSums::kVy] + u[2] * a[gdsmc::BinSums::kVz];
        const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
        const double T = mass_[s] * (v2 - 2.0 * uv + Nb * uu) / (3.0 * Nb);  // m_X sum |v - u_b|^2 / (3 N_Xb)
        for (int c = 0; c < 3; ++c) at(s, pUx + c, b) = a[gdsmc::BinSums::kVx + c] / Nb / v0_;  // 004 Eq. 15
        at(s, pT, b) = T / t0_;
        sum_NT += Nb * T;
      }
      const double Tb = count > 0 ? sum_NT / count : nan;
      for (std::size_t s = 0; s < S_; ++s)
        if (count_in(s, b) > 0) at(s, pTratio, b) = at(s, pT, b) * t0_ / Tb;
      at(mix, pN, b) = count * norm / n0_;
      for (int c = 0; c < 3; ++c) at(mix, pUx + c, b) = count > 0 ? u[c] / v0_ : nan;
      at(mix, pT, b) = Tb / t0_;
      at(mix, pTratio, b) = count > 0 ? 1.0 : nan;
    }
    for (std::size_t s = 0; s <= S_; ++s)
      for (std::size_t k = 0; k < kProf; ++k) out.append_profile(profile_ids_[s * kProf + k], &profile_values_[(s * kProf + k) * nb_]);
    for (gdsmc::BinSums& b : bins_) b.clear();
  }
  double count_in(std::size_t s, std::size_t b) const { return bins_[s].sums(b)[gdsmc::BinSums::kCount]; }

  void begin_walls(const gdsmc::SystemInfo& sys, gdsmc::OutputSink& out) {
    namespace u = gdsmc::units;
    area_ = sys.cross_section();
    const double nT0 = n0_ * t0_;
    rate_unit_ = 1.0 / (sys.mean_free_path0 * sys.mean_free_path0 * sys.time_unit0);
    momentum_unit_ = nT0;
    energy_unit_ = nT0 * v0_;
    previous_.assign(2 * S_, gdsmc::BoundaryTally{});
    current_.assign(2 * S_, gdsmc::BoundaryTally{});
    wall_previous_time_ = wall_current_time_ = 0;
    wall_ids_.assign(2 * S_ * 5, 0);
    const char* walls[2] = {"y_min", "y_max"};
    for (std::size_t w = 0; w < 2; ++w)
      for (std::size_t s = 0; s < S_; ++s) {
        const std::string p = walls[w], X = names_[s];
        std::size_t* id = &wall_ids_[(w * S_ + s) * 5];
        id[0] = out.series(of((p + "_hit_rate").c_str(), s), u::wall_hit_rate,
                           "hits of species " + X + " on " + p + " per unit area and time");
        for (int a = 0; a < 3; ++a)
          id[1 + a] = out.series(of((p + "_momentum_flux_" + kAxes[a]).c_str(), s), u::pressure,
                                 std::string(kAxes[a]) + " momentum given to species " + X + " by " + p + " per unit area and time");
        id[4] = out.series(of((p + "_energy_flux").c_str(), s), u::heat_flux,
                           "energy given to species " + X + " by " + p + " per unit area and time");
      }
  }
  // A context without per-species tallies (a harness that drives the diagnostic by hand) leaves the
  // wall series NaN, and finish() says so.
  void wall_sample(const gdsmc::StepContext& ctx) {
    if (!ctx.species_boundaries || ctx.boundary_count < 2) {
      walls_missing_ = true;
    } else {
      for (std::size_t k = 0; k < 2 * S_; ++k) current_[k] = ctx.species_boundaries[k];
    }
    wall_current_time_ = ctx.time;
  }
  void wall_record(gdsmc::OutputSink& out) {
    const double dt = wall_current_time_ - wall_previous_time_;
    const double inv = dt > 0 && !walls_missing_ ? 1.0 / (area_ * dt) : std::nan("");
    for (std::size_t k = 0; k < 2 * S_; ++k) {
      const gdsmc::BoundaryTally &c = current_[k], &p = previous_[k];
      const std::size_t* id = &wall_ids_[k * 5];
      out.append(id[0], static_cast<double>(c.hits - p.hits) * inv / rate_unit_);
      for (int a = 0; a < 3; ++a) out.append(id[1 + a], (c.momentum[a] - p.momentum[a]) * inv / momentum_unit_);
      out.append(id[4], (c.energy - p.energy) * inv / energy_unit_);
      previous_[k] = c;
    }
    wall_previous_time_ = wall_current_time_;
  }
  static void save_tallies(gdsmc::StateWriter& out, const std::string& prefix, const std::vector<gdsmc::BoundaryTally>& t) {
    std::vector<std::uint64_t> hits;
    std::vector<double> rest;
    for (const auto& x : t) {
      hits.push_back(x.hits);
      rest.insert(rest.end(), {x.momentum[0], x.momentum[1], x.momentum[2], x.energy});
    }
    out.write(prefix + ".hits", hits);
    out.write(prefix + ".momentum_energy", rest);
  }
  static void load_tallies(gdsmc::StateReader& in, const std::string& prefix, std::vector<gdsmc::BoundaryTally>& t) {
    std::vector<std::uint64_t> hits(t.size());
    std::vector<double> rest(4 * t.size());
    in.read(prefix + ".hits", hits.data(), hits.size());
    in.read(prefix + ".momentum_energy", rest.data(), rest.size());
    for (std::size_t k = 0; k < t.size(); ++k) {
      t[k].hits = hits[k];
      for (int a = 0; a < 3; ++a) t[k].momentum[a] = rest[4 * k + a];
      t[k].energy = rest[4 * k + 3];
    }
  }

  // Setup.
  std::size_t S_ = 1;
  double N_ = 1, volume_ = 1, t0_ = 1, v0_ = 1, n0_ = 1, tau0_ = 1;
  bool slab_ = false, walls_ = false;
  std::vector<std::string> names_, tally_names_;
  std::vector<double> mass_;
  // Series.
  gdsmc::WindowAverage window_;
  std::vector<double> acc_, values_, T_now_, count_;
  double T_mix_ = 0;
  // Cooling rates.
  std::vector<std::size_t> zeta_ids_;
  std::size_t zeta_mix_id_ = 0;
  std::vector<double> zeta_;
  double prev_T_mix_ = 0, prev_E_mix_ = 0, loss_mix_ = 0, weight_mix_ = 0, prev_time_ = 0;
  bool have_prev_ = false, tallies_missing_ = false, walls_missing_ = false;
  // Profiles (slab).
  std::size_t nb_ = 0;
  double bin_volume_ = 1;
  std::vector<gdsmc::BinSums> bins_;
  std::vector<std::size_t> profile_ids_;
  std::vector<double> profile_values_;
  // Wall fluxes (slab mixture).
  double area_ = 1, rate_unit_ = 1, momentum_unit_ = 1, energy_unit_ = 1;
  std::vector<std::size_t> wall_ids_;
  std::vector<gdsmc::BoundaryTally> previous_, current_;
  double wall_previous_time_ = 0, wall_current_time_ = 0;
};

}  // namespace

GDSMC_PLUGIN(SpeciesMoments)
