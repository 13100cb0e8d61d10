// gdsmc SDK, physics toolkit: per-bin moment accumulators. The sums of 1, v_a, v_a v_b (and,
// optionally, |v|^2 v_a) of the particles in each sampling bin along y, accumulated over N_t
// samples, and the per-bin fields of paper 004 Eqs. (13)-(16), (31) (000 Eqs. 4.4-4.7 for one
// sample) from them. Mergeable, so that the parts of one run accumulated apart combine:
//  - merge(o): o holds other particles of the same samples (a thread's slice, a rank's slab):
//    the sums add, the sample counts must be equal;
//  - append(o): o holds later samples (a batch of records): the sums and the sample counts add.
//
// Order rule (what makes results bit-identical). Every sum is a left fold in double precision:
// add() adds one particle's terms to its bin's sums, and merge(o) / append(o) add each of o's sums
// as one term (this->s += o.s, bin by bin, sum by sum). Two accumulations give the same bits
// exactly when they fold the same terms in the same order:
//  - Parts that hold disjoint sets of bins (a slab decomposition whose parts own whole bins) merge
//    to the bits of the whole accumulated in one piece, whatever the number of parts and in any
//    merge order, provided each part adds its particles of a bin in the order the whole would
//    (storage order): x + 0 = x exactly, and a sum that starts at +0 never becomes -0.
//  - Parts that share bins (slices of the particles, batches of samples) combine to a result that
//    depends on where the parts are cut: floating-point addition is not associative. They are
//    bit-reproducible when the cuts do not depend on the number of threads or ranks (fixed
//    pieces, each accumulated from zero, combined in piece order: copy_from the first, then
//    merge or append the others), never when they do.
// Sizing happens in begin() only: add(), add_sample(), merge(), append(), subtract(), copy_from()
// and clear() never allocate.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "gdsmc/context.hpp"
#include "gdsmc/particles.hpp"
#include "gdsmc/state.hpp"

namespace gdsmc {

// The fields of one bin, from its sums over N_t samples in a bin of volume V_bin (BinSums::moments).
struct BinMoments {
  double count = 0;  // N_b: particles found in the bin, summed over the samples
  // n = N_b / (N_t V_bin): number density (004 Eqs. 13-14 per unit mass; 000 Eq. 4.4); 0 for a
  // bin no particle visited (with samples), NaN without samples.
  double density = std::nan("");
  // u_a = sum v_a / N_b (004 Eq. 15, 000 Eq. 4.5). NaN for an empty bin, like every field below.
  double mean[3] = {std::nan(""), std::nan(""), std::nan("")};
  // P_ab = (m / (N_t V_bin)) sum (v_a - u_a)(v_b - u_b) (004 Eq. 31, 000 Eq. 4.7), in the order
  // xx, yy, zz, xy, xz, yz, from the sums expanded about u: sum V_a V_b = sum v_a v_b - N_b u_a u_b.
  double pressure[6] = {std::nan(""), std::nan(""), std::nan(""), std::nan(""), std::nan(""), std::nan("")};
  double pressure_scalar = std::nan("");  // p = tr P / 3
  double temperature = std::nan("");      // T = p / n (004 Eq. 16, 000 Eq. 4.6; k_B = 1)
  // q_a = (m / (2 N_t V_bin)) sum |v - u|^2 (v_a - u_a), from sum |V|^2 V_a = sum |v|^2 v_a -
  // u_a sum |v|^2 - 2 u_b sum v_b v_a + 2 N_b |u|^2 u_a. NaN unless third moments are accumulated.
  double heat_flux[3] = {std::nan(""), std::nan(""), std::nan("")};
};

class BinSums {
 public:
  // The sums of one bin, in this order (kSecond of them without third moments).
  enum Sum : std::size_t { kCount, kVx, kVy, kVz, kVxx, kVyy, kVzz, kVxy, kVxz, kVyz, kWx, kWy, kWz, kSums };
  static constexpr std::size_t kSecond = kWx;

  // Size for `bins` bins (SystemInfo::bins) and zero every sum; third_moments: also |v|^2 v_a,
  // for the heat flux (three more sums per bin and per particle).
  void begin(std::size_t bins, bool third_moments) {
    bins_ = bins;
    stride_ = third_moments ? kSums : kSecond;
    sums_.assign(bins_ * stride_, 0.0);
    samples_ = 0;
  }
  std::size_t bins() const { return bins_; }
  std::size_t stride() const { return stride_; }
  bool third_moments() const { return stride_ == kSums; }
  double samples() const { return samples_; }                         // N_t
  const double* sums(std::size_t bin) const { return &sums_[bin * stride_]; }  // stride() values

  // One particle's terms into bin `bin`.
  void add(std::size_t bin, double vx, double vy, double vz) {
    double* a = &sums_[bin * stride_];
    a[kCount] += 1.0;
    a[kVx] += vx; a[kVy] += vy; a[kVz] += vz;
    a[kVxx] += vx * vx; a[kVyy] += vy * vy; a[kVzz] += vz * vz;
    a[kVxy] += vx * vy; a[kVxz] += vx * vz; a[kVyz] += vy * vz;
    if (stride_ == kSums) {
      const double v2 = vx * vx + vy * vy + vz * vz;
      a[kWx] += v2 * vx; a[kWy] += v2 * vy; a[kWz] += v2 * vz;
    }
  }
  // One sample: every particle of the span into its sampling bin (SystemInfo::bin_of), in index
  // order, and one more sample counted.
  void add_sample(const SystemInfo& sys, const ParticleSpan& p) {
    if (stride_ == kSums) add_all<true>(sys, p);
    else add_all<false>(sys, p);
    samples_ += 1.0;
  }
  // Count one more sample (after adding its particles with add()).
  void end_sample() { samples_ += 1.0; }
  // One sample from the host's bin sums of the state (SampledMoments::bin_sums, SDK 6.6; a
  // diagnostic that reads them declares moments_bins, or moments_bin_heat for third moments): each
  // bin's sums added as one term, one more sample counted. A diagnostic that accumulates this way
  // reads no particle, and costs a decomposed run no gather (MomentsRead::particles).
  void append_sample(const SampledMoments& m) {
    if (m.bin_sums && m.bin_count != bins_)
      throw std::invalid_argument("BinSums::append_sample: sized for " + std::to_string(bins_) +
                                  " bins; the host's bin sums have SystemInfo::bins = " + std::to_string(m.bin_count));
    if (!m.bin_sums || m.bin_sum_stride < stride_)
      throw std::invalid_argument(std::string("BinSums::append_sample: the host measured no bin sums") +
                                  (m.bin_sums ? " with third moments: declare moments_bin_heat"
                                              : ": declare moments_bins (moments_bin_heat for third moments) in MomentsRead"));
    for (std::size_t b = 0; b < bins_; ++b) {
      double* a = &sums_[b * stride_];
      const double* s = m.bin_sums + b * m.bin_sum_stride;
      for (std::size_t j = 0; j < stride_; ++j) a[j] += s[j];
    }
    samples_ += 1.0;
  }

  // Add the sums of another part of the same samples (other particles): the sample counts must
  // agree (the order rule above).
  void merge(const BinSums& o) {
    check_shape(o, "merge");
    if (o.samples_ != samples_)
      throw std::invalid_argument("BinSums::merge: parts of different samples (" + std::to_string(samples_) + " and " +
                                  std::to_string(o.samples_) + "); append() adds later samples");
    for (std::size_t j = 0; j < sums_.size(); ++j) sums_[j] += o.sums_[j];
  }
  // Add the sums and the sample count of later samples (a batch; the order rule above).
  void append(const BinSums& o) {
    check_shape(o, "append");
    for (std::size_t j = 0; j < sums_.size(); ++j) sums_[j] += o.sums_[j];
    samples_ += o.samples_;
  }
  // Take out the sums and samples of a batch that was appended (a delete-one jackknife: the whole
  // less one batch). Not exact in general: (a + b) - b need not be a.
  void subtract(const BinSums& o) {
    check_shape(o, "subtract");
    for (std::size_t j = 0; j < sums_.size(); ++j) sums_[j] -= o.sums_[j];
    samples_ -= o.samples_;
  }
  // Copy the sums of an accumulator of the same shape (no allocation).
  void copy_from(const BinSums& o) {
    check_shape(o, "copy_from");
    for (std::size_t j = 0; j < sums_.size(); ++j) sums_[j] = o.sums_[j];
    samples_ = o.samples_;
  }
  void clear() {
    for (double& s : sums_) s = 0.0;
    samples_ = 0;
  }

  // The fields of bin `bin` (BinMoments) for a bin of volume `bin_volume` (SystemInfo::bin_width()
  // * cross_section()) and particles of mass `mass`.
  BinMoments moments(std::size_t bin, double bin_volume, double mass) const {
    BinMoments r;
    const double* a = sums(bin);
    const double N = a[kCount];
    r.count = N;
    if (samples_ <= 0) return r;
    if (N <= 0) {
      r.density = 0.0;
      return r;
    }
    const double norm = 1.0 / (samples_ * bin_volume);  // 1 / (N_t V_bin)
    r.density = N * norm;
    const double u[3] = {a[kVx] / N, a[kVy] / N, a[kVz] / N};
    for (int c = 0; c < 3; ++c) r.mean[c] = u[c];
    // sum V_a V_b = sum v_a v_b - N u_a u_b
    const double cxx = a[kVxx] - N * u[0] * u[0], cyy = a[kVyy] - N * u[1] * u[1], czz = a[kVzz] - N * u[2] * u[2];
    const double cxy = a[kVxy] - N * u[0] * u[1], cxz = a[kVxz] - N * u[0] * u[2], cyz = a[kVyz] - N * u[1] * u[2];
    const double pn = mass * norm;  // P_ab = m sum V_a V_b / (N_t V_bin)
    r.pressure[0] = pn * cxx;
    r.pressure[1] = pn * cyy;
    r.pressure[2] = pn * czz;
    r.pressure[3] = pn * cxy;
    r.pressure[4] = pn * cxz;
    r.pressure[5] = pn * cyz;
    r.pressure_scalar = (r.pressure[0] + r.pressure[1] + r.pressure[2]) / 3.0;
    r.temperature = r.pressure_scalar / r.density;
    if (stride_ == kSums) {
      const double K = a[kVxx] + a[kVyy] + a[kVzz];
      const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
      const double hx = a[kWx] - u[0] * K - 2.0 * (u[0] * a[kVxx] + u[1] * a[kVxy] + u[2] * a[kVxz]) + 2.0 * N * uu * u[0];
      const double hy = a[kWy] - u[1] * K - 2.0 * (u[0] * a[kVxy] + u[1] * a[kVyy] + u[2] * a[kVyz]) + 2.0 * N * uu * u[1];
      const double hz = a[kWz] - u[2] * K - 2.0 * (u[0] * a[kVxz] + u[1] * a[kVyz] + u[2] * a[kVzz]) + 2.0 * N * uu * u[2];
      r.heat_flux[0] = 0.5 * pn * hx;
      r.heat_flux[1] = 0.5 * pn * hy;
      r.heat_flux[2] = 0.5 * pn * hz;
    }
    return r;
  }

  // Checkpoints: the sums and the sample count under `prefix` (the shape is set again by begin()).
  void save(StateWriter& out, const std::string& prefix) const {
    out.write(prefix + ".sums", sums_);
    out.write(prefix + ".samples", samples_);
  }
  void load(StateReader& in, const std::string& prefix) {
    in.read(prefix + ".sums", sums_.data(), sums_.size());  // exact count: another shape is refused
    in.read(prefix + ".samples", samples_);
  }

 private:
  template <bool Third>
  void add_all(const SystemInfo& sys, const ParticleSpan& p) {
    for (std::size_t i = 0; i < p.count; ++i) {
      double* a = &sums_[sys.bin_of(p.y[i]) * stride_];
      const double vx = p.vx[i], vy = p.vy[i], vz = p.vz[i];
      a[kCount] += 1.0;
      a[kVx] += vx; a[kVy] += vy; a[kVz] += vz;
      a[kVxx] += vx * vx; a[kVyy] += vy * vy; a[kVzz] += vz * vz;
      a[kVxy] += vx * vy; a[kVxz] += vx * vz; a[kVyz] += vy * vz;
      if constexpr (Third) {
        const double v2 = vx * vx + vy * vy + vz * vz;
        a[kWx] += v2 * vx; a[kWy] += v2 * vy; a[kWz] += v2 * vz;
      }
    }
  }
  void check_shape(const BinSums& o, const char* what) const {
    if (o.bins_ != bins_ || o.stride_ != stride_)
      throw std::invalid_argument(std::string("BinSums::") + what + ": accumulators of different shapes (" +
                                  std::to_string(bins_) + " bins x " + std::to_string(stride_) + " sums, other " +
                                  std::to_string(o.bins_) + " x " + std::to_string(o.stride_) + ")");
  }

  std::size_t bins_ = 0, stride_ = kSecond;
  std::vector<double> sums_;  // bins x stride
  double samples_ = 0;        // N_t (a double, so that append and subtract treat it as the sums)
};

}  // namespace gdsmc
