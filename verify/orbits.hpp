// Proven periodic orbits of the stadium billiard (docs/model.md, "Periodic orbits"): codes enumerated,
// each orbit found by Newton on the length's gradient (geometry/periodic.hpp) in double from several
// starts, refined in MPFR, and proven to exist, uniquely, in a small box by the Krawczyk operator in MPFI.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "analysis/cycle_expansion.hpp"
#include "geometry/orbit_codes.hpp"
#include "geometry/stadium.hpp"
#include "numeric/exact.hpp"
#include "numeric/tiers.hpp"

namespace rotleak {

struct OrbitOptions {
  long bits = 160;  ///< MPFR / MPFI working precision of the refinement and the proof
  int starts = 48;  ///< Newton starts a code (double, uniform in the code's parameter box)
  std::uint64_t seed = 1;
};

struct ProvenOrbit {
  OrbitCode code;
  std::vector<Mpfi> box;  ///< the Krawczyk image: holds the orbit's u, and no other zero of the gradient lies
                          ///< in the box it was proven in (`proof_box`)
  std::vector<Mpfi> proof_box;
  std::vector<Mpfr> point;         ///< the refined point the proof started from (a checkpoint keeps it exactly)
  Mpfi length, trace, multiplier;  ///< enclosures; multiplier: Lambda with |Lambda| > 1, sign of the trace
  Mpfi s0, p0;  ///< bounce 0 in the core's Birkhoff coordinates (Stadium::s_of, birkhoff_p), at the box's midpoint
  double box_width = 0;  ///< widest component of `box`
  /// 2 when the time-reversed orbit has the reversed code, another class of codes (not listed); 1 when the
  /// reversed orbit is listed under this code (or is this orbit)
  int weight = 1;
  std::string stability() const;
  double log_multiplier() const;  ///< ln|Lambda|, from the enclosure's midpoint
};

/// A box's midpoint, at the working precision: the orbit's parameters to the box's width.
std::vector<Mpfr> box_midpoint(const std::vector<Mpfi>& box);

/// Bounce i of the orbit (code, u) in the core's Birkhoff coordinates: s (Stadium::s_of) and p, the velocity
/// leaving it (towards bounce i + 1) along the core's tangent. In MPFR: the core's s takes an atan2 whose
/// interval form straddles the left arc's branch cut.
std::pair<Mpfr, Mpfr> orbit_bounce_birkhoff(const ExactReal& d, const ExactReal& r, const OrbitCode& code,
                                            const std::vector<Mpfr>& u, std::size_t i);

/// What one code gave.
struct CodeOrbits {
  std::vector<ProvenOrbit> orbits;
  int candidates = 0;   ///< distinct admissible zeros Newton reached
  int unproven = 0;     ///< candidates the Krawczyk test did not prove (a parabolic family, or too wide a box)
  int repeats = 0;      ///< proven orbits that repeat a shorter one (code w^k), not listed
  int by_symmetry = 0;  ///< orbits found as mirror images of another code's (close_under_symmetry)
  bool family = false;  ///< (TB)^k: the bouncing-ball family (parabolic, not isolated), not searched
};

/// The orbits of one code on the stadium d, r.
CodeOrbits code_orbits(const ExactReal& d, const ExactReal& r, const OrbitCode& code, const OrbitOptions& opt);

/// The Krawczyk proof at `bits` around the point u (n doubles or better): the box and its image, or an
/// empty result when it fails. Exposed for the tests (a proof at twice the bits inside the first box).
bool prove_orbit(const ExactReal& d, const ExactReal& r, const OrbitCode& code, const std::vector<Mpfr>& u, long bits,
                 ProvenOrbit& out);

/// The Krawczyk test alone, at the point m as given (not refined) at the current MPFR precision: whether the
/// image of X = m + [-2^-shift, 2^-shift]^n lies strictly inside X (then X holds exactly one zero of the
/// gradient); false also where the Hessian at m is singular. Exposed for the tests (boxes it must refuse).
bool krawczyk_contracts(const ExactReal& d, const ExactReal& r, const OrbitCode& code, const std::vector<Mpfr>& m,
                        long shift);

/// Each orbit of codes[i] (got[i]) mirrored in x, in y and in both: an image that its code's search missed is
/// proven and added (the stadium's symmetry closes the set; `codes` are one period's, all of them).
void close_under_symmetry(const ExactReal& d, const ExactReal& r, const std::vector<OrbitCode>& codes,
                          const OrbitOptions& opt, std::vector<CodeOrbits>& got);

struct PeriodTally {
  int period = 0;
  std::size_t codes = 0, codes_with_orbits = 0, candidates = 0, proven = 0, unproven = 0, prime_cycles = 0,
              by_symmetry = 0, family_codes = 0;
  double seconds = 0;
};

struct OrbitSearch {
  std::vector<ProvenOrbit> orbits;  ///< by period, then code
  std::vector<PeriodTally> periods;
  double seconds = 0;
  int threads = 1;
};

/// Every code of period 2 .. period_max; `progress` (if set) hears each period as it completes. With a
/// `checkpoint` path, each completed period is written there (verify/orbit_checkpoint.hpp), and a search
/// that finds one goes on from it (InputError when it holds other inputs); the caller removes it.
OrbitSearch find_orbits(const ExactReal& d, const ExactReal& r, int period_max, const OrbitOptions& opt, int threads,
                        void (*progress)(const PeriodTally&) = nullptr, const std::filesystem::path& checkpoint = {});

/// DIR/orbits.csv and DIR/summary.json (docs/output.md), each written whole (temp name, then rename).
void write_orbits(const std::filesystem::path& dir, const ExactReal& d, const ExactReal& r, const OrbitSearch& s,
                  const OrbitOptions& opt);

/// The search's cycles as the cycle expansion takes them (period, length, ln|Lambda|, weight).
std::vector<PrimeCycle> prime_cycles(const OrbitSearch& s, const OrbitOptions& opt);

/// An enclosure's midpoint to `digits` significant digits.
std::string orbit_digits(const Mpfi& x, int digits = 30);

}  // namespace rotleak
