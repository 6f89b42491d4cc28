#include "sim/model/sampling.hpp"

#include <mpfi.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "leak/leak.hpp"
#include "leak/table_leak.hpp"

namespace rotleak {

namespace {

class UniformSampler final : public Sampler {
 public:
  explicit UniformSampler(const Scene& scene) : ic_(initial_conditions(scene)) {}
  InitialDraw draw(std::uint64_t id) const override { return ic_.draw(id); }
  double weight(const InitialDraw&) const override { return 1; }
  bool weighted() const override { return false; }
  const InitialConditions* uniform_birkhoff() const override {
    return ic_.kind() == InitKind::birkhoff ? &ic_ : nullptr;
  }

 private:
  InitialConditions ic_;
};

/// Particles that enter through one stationary leak: the Birkhoff measure restricted to the hole, s uniform in the
/// leak's window (centre + width (u - 1/2), u the uniform draw's s) and p uniform in (-1, 1): the flux of a
/// uniform gas outside it. Every particle weighs 1; its creation time is the uniform scheme's.
class EntrySampler final : public Sampler {
 public:
  explicit EntrySampler(const Scene& scene) : ic_(initial_conditions(scene)) {
    const LeakSpec spec = leak_specs(scene).at(static_cast<std::size_t>(scene.enter_through));
    loop_ = spec.loop;
    centre_ = LeakSchedule<double>(spec.start, spec.omega).start();
    width_ = round_exact<double>(spec.width);
    if (scene.table) table_ = std::make_shared<const Table<double>>(table_spec(scene));
  }
  InitialDraw draw(std::uint64_t id) const override {
    InitialDraw d = ic_.draw(id);
    double s = centre_ + width_ * (d.s - 0.5);
    if (s < 0) s += 1;
    if (s >= 1) s -= 1;
    d.s = table_ ? table_->boundary_share(loop_, s) : s;  // a share of the whole boundary, as initial_state reads it
    return d;
  }
  double weight(const InitialDraw&) const override { return 1; }
  bool weighted() const override { return false; }

 private:
  InitialConditions ic_;
  int loop_ = 0;
  double centre_ = 0, width_ = 0;
  std::shared_ptr<const Table<double>> table_;  ///< any table's loops (null: the stadium's one)
};

/// What both MUPO schemes share: the mixture, the log-uniform magnitude, the Philox words.
class MupoBase : public Sampler {
 public:
  MupoBase(const Scene& scene, const SamplingSpec& spec)
      : ic_(initial_conditions(scene)),
        seed_(scene.seed),
        eps_(spec.eps),
        p_min_(spec.p_min),
        p_max_(spec.p_max),
        log_range_(std::log(spec.p_max / spec.p_min)) {}
  bool weighted() const override { return true; }

 protected:
  static constexpr std::uint64_t kPurposeMupo = 1;

  /// Philox words of the biased draw, and whether this particle takes the uniform component.
  bool uniform_component(std::uint64_t id, r123::Philox4x64::ctr_type& w) const {
    w = sampling_words(seed_, id, kPurposeMupo);
    return InitialConditions::unit(w[0]) < eps_;
  }
  /// |p| log-uniform in [p_min, p_max] from the top 53 bits.
  double magnitude(std::uint64_t bits) const {
    const double m = p_min_ * std::exp(InitialConditions::unit(bits) * log_range_);
    return m < p_min_ ? p_min_ : m > p_max_ ? p_max_ : m;
  }
  /// Density of a signed value whose magnitude is log-uniform in [p_min, p_max] (0 outside).
  double log_uniform_density(double v) const {
    const double a = std::abs(v);
    return a >= p_min_ && a <= p_max_ ? 1 / (2 * a * log_range_) : 0.0;
  }
  /// u / q with q = eps u + (1 - eps) g.
  double mixture_weight(double u, double g) const { return u / (eps_ * u + (1 - eps_) * g); }

  InitialConditions ic_;
  std::uint64_t seed_;
  double eps_, p_min_, p_max_, log_range_;
};

/// Birkhoff starts: u = 1/2 on [0, 1) x (-1, 1); g: s uniform on the straight edges, |p| log-uniform in
/// [p_min, p_max] with weight 1 - ride, and with weight ride / K log-uniform in each of the K riding bands.
class MupoBirkhoff final : public MupoBase {
 public:
  MupoBirkhoff(const Scene& scene, const Stadium<double>& st)
      : MupoBase(scene, scene.sampling),
        st_(st),
        straight_(st.junction(0) + (st.junction(2) - st.junction(1)) + (1 - st.junction(3))),
        bands_(scene.sampling.ride > 0 ? riding_bands(scene) : std::vector<RidingBand>{}),
        ride_(bands_.empty() ? 0.0 : scene.sampling.ride) {}

  InitialDraw draw(std::uint64_t id) const override {
    r123::Philox4x64::ctr_type w;
    if (uniform_component(id, w)) return ic_.draw(id);
    InitialDraw d = ic_.draw(id);  // its creation time tau
    // s uniform over the straight parts [0, j0) + [j1, j2) + [j3, 1), laid end to end
    const double v = InitialConditions::unit(w[1]) * straight_;
    const double top_right = st_.junction(0), bottom = st_.junction(2) - st_.junction(1);
    d.s = v < top_right            ? v
          : v < top_right + bottom ? st_.junction(1) + (v - top_right)
                                   : st_.junction(3) + (v - top_right - bottom);
    if (!st_.on_straight(d.s)) d.s = 0;  // rounding at a junction: the edge's midpoint instead (measure zero)
    // the component: w[3]'s top 53 bits (its lowest bit is the sign); with ride = 0 never a band, so the
    // draws are those of the scheme without riding bands, bit for bit
    const double c = InitialConditions::unit(w[3]);
    double m = 0;
    if (c < ride_) {
      const std::size_t k =
          std::min(bands_.size() - 1, static_cast<std::size_t>(c / ride_ * static_cast<double>(bands_.size())));
      const RidingBand& b = bands_[k];
      m = b.lo * std::exp(InitialConditions::unit(w[2]) * std::log(b.hi / b.lo));
      m = m < b.lo ? b.lo : m > b.hi ? b.hi : m;
    } else {
      m = magnitude(w[2]);
    }
    d.p = (w[3] & 1) ? -m : m;
    return d;
  }

  double weight(const InitialDraw& d) const override {
    if (!st_.on_straight(d.s)) return mixture_weight(0.5, 0.0);
    double g = (1 - ride_) * log_uniform_density(d.p);
    const double a = std::abs(d.p);
    for (const RidingBand& b : bands_)  // in band order: the same sum on every engine
      if (a >= b.lo && a <= b.hi) g += ride_ / static_cast<double>(bands_.size()) / (2 * a * std::log(b.hi / b.lo));
    return mixture_weight(0.5, g / straight_);
  }

 private:
  Stadium<double> st_;
  double straight_;
  std::vector<RidingBand> bands_;
  double ride_;
};

/// Flow starts: u = 1 / area in (x, y) times 1 in u = angle / 2 pi; g: (x, y) uniform in the
/// rectangle between the straight edges, the angle pi/2 or 3pi/2 (up or down) plus delta with
/// |delta| log-uniform in [p_min, p_max].
class MupoFlow final : public MupoBase {
 public:
  MupoFlow(const Scene& scene, const Stadium<double>& st) : MupoBase(scene, scene.sampling) {
    half_d_ = st.half_d();
    r_ = st.r();
    area_ = st.area();
  }

  InitialDraw draw(std::uint64_t id) const override {
    r123::Philox4x64::ctr_type w;
    if (uniform_component(id, w)) return ic_.draw(id);
    InitialDraw d = ic_.draw(id);  // its creation time tau
    d.flow = true;
    d.x = half_d_ * (2 * InitialConditions::unit(w[1]) - 1);
    d.y = r_ * (2 * InitialConditions::unit(w[2]) - 1);
    const double delta = magnitude(w[3]) * ((w[3] & 1) ? -1 : 1);
    d.u = ((w[3] & 2) ? 0.75 : 0.25) + delta / (2 * std::numbers::pi);
    return d;
  }

  double weight(const InitialDraw& d) const override {
    double g = 0;
    if (std::abs(d.x) <= half_d_ && std::abs(d.y) < r_) {
      const double centre = d.u < 0.5 ? 0.25 : 0.75;
      const double delta = 2 * std::numbers::pi * (d.u - centre);
      // density in u: 1/2 (up or down) x 2 pi x density of delta
      g = 1 / (4 * half_d_ * r_) * 0.5 * 2 * std::numbers::pi * log_uniform_density(delta);
    }
    return mixture_weight(1 / area_, g);
  }

 private:
  double half_d_, r_, area_;
};

}  // namespace

std::vector<RidingBand> riding_bands(const Scene& scene) {
  std::vector<RidingBand> out;
  if (scene.omega.sign() == 0) return out;
  // 2X = 4 r omega, its fractional part to double precision: an enclosure with bits for the integer part too
  const ExactReal x2 = ExactReal::parse("4") * scene.r * scene.omega;
  const double mag = std::abs(x2.to_double());
  const long bits = 80 + (mag > 1 ? static_cast<long>(std::ceil(std::log2(mag))) : 0);
  mpfi_t e;
  mpfi_init2(e, bits);
  x2.enclose(e, bits);
  mpfr_t mid, fl;
  mpfr_inits2(bits, mid, fl, static_cast<mpfr_ptr>(nullptr));
  mpfi_mid(mid, e);
  mpfr_floor(fl, mid);
  mpfr_sub(mid, mid, fl, MPFR_RNDN);
  const double f = mpfr_get_d(mid, MPFR_RNDN);
  mpfr_clears(mid, fl, static_cast<mpfr_ptr>(nullptr));
  mpfi_clear(e);
  const Stadium<double> st(scene.d, scene.r);
  const double L = st.perimeter(), r = st.r(), d = 2 * st.half_d(), lambda = scene.width.to_double();
  const double kappa0 = lambda * L / (std::numbers::pi * st.area());
  const auto b_max = static_cast<long long>(std::min(1e6, std::floor(1 / lambda)));
  double best = 2;
  for (long long b = 1; b <= b_max; ++b) {
    const long long a = std::llround(f * static_cast<double>(b));
    const double eta = f - static_cast<double>(a) / static_cast<double>(b);
    if (!(std::abs(eta) < best)) continue;  // not a best approximation
    best = std::abs(eta);
    if (static_cast<double>(b) * lambda >= 1 || eta == 0) continue;
    RidingBand band{a, b, eta, L * std::abs(eta) / (4 * r), 0, 0};
    const double h = std::min(0.5, L * (1 / static_cast<double>(b) - lambda) / d);
    band.lo = band.p * (1 - h);
    band.hi = std::min(band.p * (1 + h), 0.999);
    // an orbit rides at most while it crosses the edge, d / p: only bands whose crossing outlasts the chaotic
    // sea's decay time 1 / kappa0 (kappa0 = lambda L / (pi area)) carry P where the chaotic part cannot
    if (band.p >= scene.sampling.p_min && band.p <= std::min(scene.sampling.p_max, d * kappa0)) out.push_back(band);
  }
  return out;
}

std::unique_ptr<Sampler> make_sampler(const Scene& scene, const Stadium<double>& st) {
  if (scene.enter_through >= 0) return std::make_unique<EntrySampler>(scene);
  if (!scene.sampling.weighted()) return std::make_unique<UniformSampler>(scene);
  if (scene.init == InitKind::flow) return std::make_unique<MupoFlow>(scene, st);
  return std::make_unique<MupoBirkhoff>(scene, st);
}

std::unique_ptr<Sampler> make_sampler(const Scene& scene) {
  if (scene.enter_through >= 0) return std::make_unique<EntrySampler>(scene);
  if (!scene.sampling.weighted()) return std::make_unique<UniformSampler>(scene);
  return make_sampler(scene, Stadium<double>(scene.d, scene.r));
}

}  // namespace rotleak
