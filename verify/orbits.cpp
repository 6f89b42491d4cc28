#include "verify/orbits.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <random>
#include <sstream>

#include "analysis/cycle_expansion.hpp"
#include "geometry/periodic.hpp"
#include "io/files.hpp"
#include "io/json.hpp"
#include "numeric/input.hpp"
#include "verify/orbit_checkpoint.hpp"
#include "version.hpp"

namespace rotleak {

namespace {

// ---- small dense linear algebra, generic (double, Mpfr) ----

/// x with a x = b (n x n, row-major, partial pivoting); false when a pivot vanishes.
template <class R>
bool solve(std::vector<R> a, std::vector<R> b, std::size_t n, std::vector<R>& x) {
  using std::abs;
  for (std::size_t k = 0; k < n; ++k) {
    std::size_t piv = k;
    for (std::size_t i = k + 1; i < n; ++i)
      if (abs(a[i * n + k]) > abs(a[piv * n + k])) piv = i;
    if (a[piv * n + k] == R(0)) return false;
    if (piv != k) {
      for (std::size_t j = 0; j < n; ++j) std::swap(a[k * n + j], a[piv * n + j]);
      std::swap(b[k], b[piv]);
    }
    for (std::size_t i = k + 1; i < n; ++i) {
      const R f = a[i * n + k] / a[k * n + k];
      for (std::size_t j = k; j < n; ++j) a[i * n + j] = a[i * n + j] - f * a[k * n + j];
      b[i] = b[i] - f * b[k];
    }
  }
  x.assign(n, R(0));
  for (std::size_t k = n; k-- > 0;) {
    R s = b[k];
    for (std::size_t j = k + 1; j < n; ++j) s = s - a[k * n + j] * x[j];
    x[k] = s / a[k * n + k];
  }
  return true;
}

template <class R>
bool inverse(const std::vector<R>& a, std::size_t n, std::vector<R>& inv) {
  inv.assign(n * n, R(0));
  std::vector<R> e(n, R(0)), col;
  for (std::size_t j = 0; j < n; ++j) {
    std::fill(e.begin(), e.end(), R(0));
    e[j] = R(1);
    if (!solve(a, e, n, col)) return false;
    for (std::size_t i = 0; i < n; ++i) inv[i * n + j] = col[i];
  }
  return true;
}

double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

/// Newton in double from u (damped: a step is halved until the gradient shrinks and every u stays
/// inside its piece). True when |g| < 1e-12 at an admissible point.
bool newton_double(const periodic::Shape<double>& s, const OrbitCode& code, std::vector<double>& u) {
  const std::size_t n = code.size();
  auto e = periodic::equations(s, code, u);
  double norm = max_abs(e.g);
  for (int it = 0; it < 60 && norm > 1e-13; ++it) {
    std::vector<double> step, minus_g(n);
    for (std::size_t i = 0; i < n; ++i) minus_g[i] = -e.g[i];
    if (!solve(e.hessian(), minus_g, n, step)) return false;
    bool taken = false;
    for (double lambda = 1; lambda > 1.0 / 1024; lambda /= 2) {
      std::vector<double> v(n);
      bool inside = true;
      for (std::size_t i = 0; i < n && inside; ++i) {
        v[i] = u[i] + lambda * step[i];
        inside = std::abs(v[i]) < s.bound(code[i]);
      }
      if (!inside) continue;
      auto ev = periodic::equations(s, code, v);
      const double nv = max_abs(ev.g);
      if (nv < norm || (it < 3 && std::isfinite(nv))) {  // the first steps may climb: Newton's basin, not |g|'s
        u = v, e = ev, norm = nv, taken = true;
        break;
      }
    }
    if (!taken) return false;
  }
  if (!(norm < 1e-12)) return false;
  for (std::size_t i = 0; i < n; ++i)
    if (!(std::abs(u[i]) < s.bound(code[i]) * (1 - 1e-9))) return false;
  for (const auto& sg : e.seg)
    if (!(sg.length > 1e-9)) return false;
  return true;
}

Mpfi point_interval(const Mpfr& x) {
  Mpfi r;
  mpfi_set_fr(r.data(), x.data());
  return r;
}

/// Whether a is inside the interior of b, component by component.
bool strictly_inside(const std::vector<Mpfi>& a, const std::vector<Mpfi>& b) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (mpfi_is_strictly_inside(a[i].data(), b[i].data()) <= 0) return false;
  return true;
}

}  // namespace

double ProvenOrbit::log_multiplier() const { return std::log(std::abs(num_traits<Mpfi>::to_double(multiplier))); }

std::vector<Mpfr> box_midpoint(const std::vector<Mpfi>& box) {
  std::vector<Mpfr> mid(box.size());
  for (std::size_t i = 0; i < box.size(); ++i) mpfi_mid(mid[i].data(), box[i].data());
  return mid;
}

std::pair<Mpfr, Mpfr> orbit_bounce_birkhoff(const ExactReal& d, const ExactReal& r, const OrbitCode& code,
                                            const std::vector<Mpfr>& u, std::size_t i) {
  const auto shape = periodic::Shape<Mpfr>::of(d, r);
  const Stadium<Mpfr> st(d, r);
  const std::size_t j = (i + 1) % code.size();
  const Vec2<Mpfr> q = periodic::point(shape, code[i], u[i]).q, next = periodic::point(shape, code[j], u[j]).q;
  const Vec2<Mpfr> dq = next - q;
  const Mpfr len = sqrt(dot(dq, dq));
  return {st.s_of(code[i], q), st.birkhoff_p(code[i], q, Vec2<Mpfr>{dq.x / len, dq.y / len})};
}

std::string ProvenOrbit::stability() const {
  try {
    if (trace > Mpfi(2)) return "hyperbolic";
    if (trace < Mpfi(-2)) return "inverse_hyperbolic";
    if (abs(trace) < Mpfi(2)) return "elliptic";
  } catch (const UncertainDecision&) {
  }
  return "undecided";
}

namespace {

/// u refined by Newton in MPFR at opt.bits (quadratic convergence from a double zero).
std::vector<Mpfr> refined(const periodic::Shape<Mpfr>& sm, const OrbitCode& code, std::vector<Mpfr> m, long bits) {
  const std::size_t n = code.size();
  Mpfr tiny(1);
  mpfr_mul_2si(tiny.data(), tiny.data(), -(bits - 8), MPFR_RNDN);
  for (int it = 0; it < 12; ++it) {
    const auto e = periodic::equations(sm, code, m);
    std::vector<Mpfr> minus_g(n), step;
    for (std::size_t i = 0; i < n; ++i) minus_g[i] = -e.g[i];
    if (!solve(e.hessian(), minus_g, n, step)) break;
    Mpfr big(0);
    for (std::size_t i = 0; i < n; ++i) big = std::max(big, abs(step[i]));
    if (big < tiny) break;  // not taken: refining a refined point changes nothing (a resumed search's proofs)
    for (std::size_t i = 0; i < n; ++i) m[i] += step[i];
  }
  return m;
}

/// The Krawczyk image K(X) = m - C g(m) + (I - C H(X)) (X - m) of X = m + [-eps, eps]^n, with C the inverse
/// of the Hessian at m (a point matrix) and g(m) enclosed. K(X) inside X's interior proves that X holds
/// exactly one zero of g, and that it lies in K(X).
struct Krawczyk {
  const periodic::Shape<Mpfi>& si;
  const OrbitCode& code;
  std::vector<Mpfi> m, gm, c;  ///< the point, g there, C (as point intervals)

  bool image(long shift, std::vector<Mpfi>& x, std::vector<Mpfi>& k) const {
    const std::size_t n = code.size();
    Mpfr eps(1);
    mpfr_mul_2si(eps.data(), eps.data(), -shift, MPFR_RNDU);
    x = m;
    for (Mpfi& xi : x) mpfi_increase(xi.data(), eps.data());
    const std::vector<Mpfi> hx = periodic::equations(si, code, x).hessian();
    k.assign(n, Mpfi(0));
    for (std::size_t i = 0; i < n; ++i) {
      Mpfi acc = m[i];
      for (std::size_t j = 0; j < n; ++j) acc -= c[i * n + j] * gm[j];
      for (std::size_t j = 0; j < n; ++j) {
        Mpfi a(i == j ? 1 : 0);
        for (std::size_t l = 0; l < n; ++l) a -= c[i * n + l] * hx[l * n + j];
        acc += a * (x[j] - m[j]);
      }
      k[i] = acc;
    }
    return strictly_inside(k, x);
  }
};

/// The proven orbit's length, trace, multiplier, width and start (bounce 0 in the core's Birkhoff
/// coordinates, from the box's midpoint: orbit_bounce_birkhoff).
void describe(const ExactReal& d, const ExactReal& r, const periodic::Shape<Mpfi>& si, ProvenOrbit& out) {
  const auto ek = periodic::equations(si, out.code, out.box);
  out.length = ek.length;
  out.trace = ek.trace();
  try {  // Lambda = (tr + sign(tr) sqrt(tr^2 - 4)) / 2, |Lambda| >= 1
    const bool neg = out.trace < Mpfi(0);
    const Mpfi root = sqrt(out.trace * out.trace - Mpfi(4));
    out.multiplier = (out.trace + (neg ? -root : root)) / Mpfi(2);
  } catch (const UncertainDecision&) {
    out.multiplier = out.trace;
  }
  out.box_width = 0;
  for (const Mpfi& v : out.box) out.box_width = std::max(out.box_width, v.width());
  const auto [s0, p0] = orbit_bounce_birkhoff(d, r, out.code, box_midpoint(out.box), 0);
  out.s0 = point_interval(s0);
  out.p0 = point_interval(p0);
}

/// The operator's point data at m: m, g(m) enclosed and C = H(m)^-1 (false where H(m) is singular).
bool krawczyk_at(const ExactReal& d, const ExactReal& r, const std::vector<Mpfr>& m, Krawczyk& kr) {
  std::vector<Mpfr> c;
  if (!inverse(periodic::equations(periodic::Shape<Mpfr>::of(d, r), kr.code, m).hessian(), kr.code.size(), c))
    return false;
  for (const Mpfr& v : m) kr.m.push_back(point_interval(v));
  kr.gm = periodic::equations(kr.si, kr.code, kr.m).g;
  for (const Mpfr& v : c) kr.c.push_back(point_interval(v));
  return true;
}

/// The Krawczyk proof around m, a point already refined (prove_orbit refines first; settle has).
bool prove_refined(const ExactReal& d, const ExactReal& r, const OrbitCode& code, const std::vector<Mpfr>& m, long bits,
                   ProvenOrbit& out) {
  const std::size_t n = code.size();
  const auto si = periodic::Shape<Mpfi>::of(d, r);
  Krawczyk kr{si, code, {}, {}, {}};
  if (!krawczyk_at(d, r, m, kr)) return false;
  // uniqueness in a wide box (radius 2^-(bits/4): two zeros closer than that are one orbit), then the zero
  // enclosed tightly in a small box inside it
  std::vector<Mpfi> x, k;
  if (!kr.image(bits / 4, x, k) && !kr.image(bits / 2, x, k)) return false;
  try {  // admissible: every bounce strictly inside its piece (|u| < bound, decided by the enclosure)
    for (std::size_t i = 0; i < n; ++i)
      if (!(abs(x[i]) < si.bound(code[i]))) return false;
  } catch (const UncertainDecision&) {
    return false;
  }
  out.code = code;
  out.point = m;
  out.proof_box = x;
  out.box = k;
  std::vector<Mpfi> xt, kt;
  for (long shift = bits - 24; shift > bits / 2; shift -= 24)
    if (kr.image(shift, xt, kt) && strictly_inside(xt, x)) {
      out.box = kt;
      break;
    }
  describe(d, r, si, out);
  return true;
}

}  // namespace

bool krawczyk_contracts(const ExactReal& d, const ExactReal& r, const OrbitCode& code, const std::vector<Mpfr>& m,
                        long shift) {
  const auto si = periodic::Shape<Mpfi>::of(d, r);
  Krawczyk kr{si, code, {}, {}, {}};
  if (!krawczyk_at(d, r, m, kr)) return false;
  std::vector<Mpfi> x, k;
  return kr.image(shift, x, k);
}

bool prove_orbit(const ExactReal& d, const ExactReal& r, const OrbitCode& code, const std::vector<Mpfr>& u, long bits,
                 ProvenOrbit& out) {
  const MpfrPrecision guard(bits);
  const std::vector<Mpfr> m =
      refined(periodic::Shape<Mpfr>::of(d, r), code, std::vector<Mpfr>(u.begin(), u.end()), bits);
  return prove_refined(d, r, code, m, bits, out);
}

namespace {

/// Zeros near the points of `queue` (refined, proven) into res unless an orbit there is known: a point inside
/// a proven box, or whose shift by the code's period is (the same cycle started at another bounce). Each new
/// orbit's reverse joins the queue when it has this code too.
void settle(const ExactReal& d, const ExactReal& r, const OrbitCode& code, std::vector<std::vector<Mpfr>> queue,
            const OrbitOptions& opt, CodeOrbits& res) {
  const MpfrPrecision guard(opt.bits);
  const std::size_t n = code.size(), period = code_period(code);
  const long rev = reversal_shift(code);
  const auto sm = periodic::Shape<Mpfr>::of(d, r);
  const auto known = [&](const std::vector<Mpfr>& u) {
    for (const ProvenOrbit& o : res.orbits)
      for (std::size_t s = 0; s < n; s += period) {
        bool in = true;
        for (std::size_t i = 0; i < n && in; ++i) in = o.proof_box[i].contains(u[(i + s) % n].data());
        if (in) return true;
      }
    return false;
  };
  for (std::size_t q = 0; q < queue.size(); ++q) {
    const std::vector<Mpfr> m = refined(sm, code, queue[q], opt.bits);
    if (known(m)) continue;
    ProvenOrbit o;
    if (!prove_refined(d, r, code, m, opt.bits, o)) {
      ++res.unproven;
      continue;
    }
    // a code w^k: the orbit repeats a shorter one when its shift by |w| lands in its own proof box
    if (period < n && strictly_inside(rotated_values(o.box, period), o.proof_box)) {
      ++res.repeats;
      continue;
    }
    o.weight = rev < 0 ? 2 : 1;
    const std::vector<Mpfr> mid = box_midpoint(o.box);
    res.orbits.push_back(std::move(o));
    if (rev >= 0) queue.push_back(reversed_values(mid, static_cast<std::size_t>(rev)));  // the orbit backwards
  }
}

/// Newton's starts for a code, from a generator seeded by the code and the seed. Along a true orbit u is an
/// arithmetic progression within a run of bounces on one arc (a circle keeps the angle of incidence, so the
/// centre angle advances by a constant step) or alternating between the two edges (parallel lines keep the
/// slope, so x does): a start places each run's values so, between two random ends; or uniformly in the box.
class Starts {
 public:
  Starts(const periodic::Shape<double>& s, const OrbitCode& code, std::uint64_t seed)
      : s_(s), code_(code), run_start_(code.size()) {
    std::uint64_t h = seed * 0x9E3779B97F4A7C15ull;
    for (Piece p : code) h = (h ^ static_cast<std::uint64_t>(p)) * 0x100000001B3ull;
    gen_.seed(h);
    const std::size_t n = code.size();
    const auto same_run = [&](std::size_t i) {  // bounce i continues the run of bounce i - 1
      const Piece a = code[(i + n - 1) % n], b = code[i];
      return straight_piece(a) ? straight_piece(b) && a != b : a == b;
    };
    std::size_t first = 0;
    while (first < n && same_run(first)) ++first;
    if (first == n) first = 0;  // one run around the whole code
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = (first + k) % n;
      run_start_[i] = k > 0 && same_run(i) ? run_start_[(i + n - 1) % n] : i;
    }
  }

  std::vector<double> next(bool uniform_box) {
    const std::size_t n = code_.size();
    std::vector<double> u(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (uniform_box) {
        u[i] = s_.bound(code_[i]) * 0.98 * (2 * uniform() - 1);
        continue;
      }
      if (run_start_[i] != i) continue;
      std::size_t len = 1;
      while (len < n && run_start_[(i + len) % n] == i) ++len;
      const double b = s_.bound(code_[i]) * 0.98, lo = b * (2 * uniform() - 1), hi = b * (2 * uniform() - 1);
      for (std::size_t j = 0; j < len; ++j)
        u[(i + j) % n] = len == 1 ? lo : lo + (hi - lo) * static_cast<double>(j) / static_cast<double>(len - 1);
    }
    return u;
  }

 private:
  double uniform() { return static_cast<double>(gen_() >> 11) * 0x1p-53; }
  const periodic::Shape<double>& s_;
  const OrbitCode& code_;
  std::vector<std::size_t> run_start_;  ///< the first bounce of the run that holds bounce i
  std::mt19937_64 gen_;
};

}  // namespace

CodeOrbits code_orbits(const ExactReal& d, const ExactReal& r, const OrbitCode& code, const OrbitOptions& opt) {
  CodeOrbits res;
  const std::size_t n = code.size();
  if (std::all_of(code.begin(), code.end(), straight_piece)) {  // (TB)^k: the bouncing-ball family, not isolated
    res.family = true;
    return res;
  }
  const auto sd = periodic::Shape<double>::of(d, r);
  Starts starts(sd, code, opt.seed);
  std::vector<std::vector<double>> found;
  for (int k = 0; k < opt.starts; ++k) {
    std::vector<double> u = starts.next(k % 4 == 3);
    if (!newton_double(sd, code, u)) continue;
    const bool seen = std::any_of(found.begin(), found.end(), [&](const std::vector<double>& v) {
      for (std::size_t i = 0; i < n; ++i)
        if (std::abs(v[i] - u[i]) > 1e-7) return false;
      return true;
    });
    if (!seen) found.push_back(u);
  }
  res.candidates = static_cast<int>(found.size());
  std::vector<std::vector<Mpfr>> queue;
  {
    const MpfrPrecision guard(opt.bits);
    for (const auto& u : found) queue.emplace_back(u.begin(), u.end());
  }
  settle(d, r, code, std::move(queue), opt, res);
  return res;
}

void close_under_symmetry(const ExactReal& d, const ExactReal& r, const std::vector<OrbitCode>& codes,
                          const OrbitOptions& opt, std::vector<CodeOrbits>& got) {
  std::map<OrbitCode, std::size_t> index;
  for (std::size_t i = 0; i < codes.size(); ++i) index[codes[i]] = i;
  const MpfrPrecision guard(opt.bits);
  for (std::size_t i = 0; i < codes.size(); ++i) {
    const std::size_t held = got[i].orbits.size();
    for (std::size_t k = 0; k < held; ++k) {
      const std::vector<Mpfr> mid = box_midpoint(got[i].orbits[k].box);
      for (const auto& [mx, my] : {std::pair{true, false}, {false, true}, {true, true}}) {
        auto [code, u] = mirror_orbit(codes[i], mid, mx, my);
        const auto at = index.find(code);
        if (at == index.end()) continue;  // not a code of this enumeration (cannot happen for admissible codes)
        const std::size_t before = got[at->second].orbits.size();
        settle(d, r, code, {std::move(u)}, opt, got[at->second]);
        got[at->second].by_symmetry += static_cast<int>(got[at->second].orbits.size() - before);
      }
    }
  }
}

OrbitSearch find_orbits(const ExactReal& d, const ExactReal& r, int period_max, const OrbitOptions& opt, int threads,
                        void (*progress)(const PeriodTally&), const std::filesystem::path& checkpoint) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  const std::string inputs = orbit_search_inputs(d, r, opt);
  OrbitSearch s;
  if (!checkpoint.empty() && std::filesystem::exists(checkpoint)) {  // resume: its periods proven again
    const OrbitCheckpoint c = parse_orbit_checkpoint(read_file(checkpoint), checkpoint.string());
    if (c.inputs != inputs)
      throw InputError("--out", checkpoint.string(),
                       "a checkpoint of other inputs (" + c.inputs + ", not " + inputs + "): remove it, or run those");
    s = resume_orbit_search(d, r, c, opt);
    while (!s.periods.empty() && s.periods.back().period > period_max) {  // a shorter search than the checkpoint's
      s.orbits.resize(s.orbits.size() - s.periods.back().proven);
      s.periods.pop_back();
    }
    if (progress)
      for (const PeriodTally& t : s.periods) progress(t);
  }
  s.threads = threads > 0 ? threads : omp_get_max_threads();
  for (int n = static_cast<int>(s.periods.size()) + 2; n <= period_max; ++n) {
    const auto t0 = clock::now();
    const std::vector<OrbitCode> codes = orbit_codes(n);
    std::vector<CodeOrbits> got(codes.size());
#pragma omp parallel for schedule(dynamic, 4) num_threads(s.threads)
    for (std::size_t i = 0; i < codes.size(); ++i) got[i] = code_orbits(d, r, codes[i], opt);
    close_under_symmetry(d, r, codes, opt, got);
    PeriodTally t;
    t.period = n;
    t.codes = codes.size();
    for (CodeOrbits& c : got) {
      t.codes_with_orbits += c.orbits.empty() ? 0 : 1;
      t.candidates += static_cast<std::size_t>(c.candidates);
      t.unproven += static_cast<std::size_t>(c.unproven);
      t.proven += c.orbits.size();
      t.by_symmetry += static_cast<std::size_t>(c.by_symmetry);
      t.family_codes += c.family ? 1 : 0;
      for (ProvenOrbit& o : c.orbits) {
        t.prime_cycles += static_cast<std::size_t>(o.weight);
        s.orbits.push_back(std::move(o));
      }
    }
    t.seconds = std::chrono::duration<double>(clock::now() - t0).count();
    s.periods.push_back(t);
    if (!checkpoint.empty()) write_file_atomic(checkpoint, orbit_checkpoint_text(inputs, s), /*durable=*/true);
    if (progress) progress(t);
  }
  s.seconds = std::chrono::duration<double>(clock::now() - start).count();
  return s;
}

std::vector<PrimeCycle> prime_cycles(const OrbitSearch& s, const OrbitOptions& opt) {
  const MpfrPrecision guard(opt.bits);
  std::vector<PrimeCycle> cycles;
  for (const ProvenOrbit& o : s.orbits)
    cycles.push_back(
        {static_cast<int>(o.code.size()), num_traits<Mpfi>::to_double(o.length), o.log_multiplier(), o.weight});
  return cycles;
}

std::string orbit_digits(const Mpfi& x, int digits) {
  mpfr_t m;
  mpfr_init2(m, mpfi_get_prec(x.data()));
  mpfi_mid(m, x.data());
  char* text = nullptr;
  mpfr_asprintf(&text, "%.*Re", digits - 1, m);
  std::string s(text);
  mpfr_free_str(text);
  mpfr_clear(m);
  return s;
}

void write_orbits(const std::filesystem::path& dir, const ExactReal& d, const ExactReal& r, const OrbitSearch& s,
                  const OrbitOptions& opt) {
  std::filesystem::create_directories(dir);
  std::ostringstream csv;
  csv << "code,period,length,multiplier,lyapunov,stability,weight,box_width,s0,p0\n";
  for (const ProvenOrbit& o : s.orbits) {
    const MpfrPrecision guard(opt.bits);
    const double lyap = o.log_multiplier() / num_traits<Mpfi>::to_double(o.length);
    csv << orbit_code_text(o.code) << ',' << o.code.size() << ',' << orbit_digits(o.length) << ','
        << orbit_digits(o.multiplier) << ',' << shortest(lyap) << ',' << o.stability() << ',' << o.weight << ','
        << shortest(o.box_width) << ',' << orbit_digits(o.s0) << ',' << orbit_digits(o.p0) << '\n';
  }
  json periods = json::array();
  std::size_t proven = 0, unproven = 0;
  for (const PeriodTally& t : s.periods) {
    periods.push_back({{"period", t.period},
                       {"codes", t.codes},
                       {"codes_with_orbits", t.codes_with_orbits},
                       {"refused", t.codes - t.codes_with_orbits - t.family_codes},
                       {"candidates", t.candidates},
                       {"proven", t.proven},
                       {"unproven", t.unproven},
                       {"prime_cycles", t.prime_cycles},
                       {"by_symmetry", t.by_symmetry},
                       {"family_codes", t.family_codes},
                       {"seconds", t.seconds}});
    proven += t.proven, unproven += t.unproven;
  }
  const int max_period = s.periods.empty() ? 2 : s.periods.back().period;
  json expansion = json::array();
  for (const CycleAverages& a : cycle_averages(prime_cycles(s, opt), max_period))
    expansion.push_back({{"order", a.order},
                         {"entropy", a.entropy},
                         {"entropy_count", a.entropy_count},
                         {"lyapunov_time", a.lyapunov_time},
                         {"lyapunov_collision", a.lyapunov_collision},
                         {"mean_free_path", a.mean_free_path},
                         {"escape_time", a.escape_time}});
  const json summary = {{"command", "orbits"},
                        {"schema", 1},
                        {"version", kVersion},
                        {"stadium", {{"d", d.text()}, {"r", r.text()}}},
                        {"bits", opt.bits},
                        {"starts", opt.starts},
                        {"seed", opt.seed},
                        {"threads", s.threads},
                        {"proven", proven},
                        {"unproven", unproven},
                        {"seconds", s.seconds},
                        {"periods", periods},
                        {"bouncing_ball_family",
                         "codes (TB)^k: vertical bounces at every x in (-d/2, d/2), parabolic (trace 2), not isolated; "
                         "not proven and not counted"},
                        {"cycle_expansion", expansion}};
  write_file_atomic(dir / "orbits.csv", csv.str());
  write_file_atomic(dir / "summary.json", summary.dump(2) + "\n");
}

}  // namespace rotleak
