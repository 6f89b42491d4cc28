#include "verify/orbit_checkpoint.hpp"

#include <sstream>
#include <stdexcept>

#include "io/files.hpp"
#include "numeric/input.hpp"
#include "verify/checkpoint_text.hpp"

namespace rotleak {

namespace {

constexpr const char* kMagic = "rotleak-orbits-checkpoint 1";

}  // namespace

std::string orbit_search_inputs(const ExactReal& d, const ExactReal& r, const OrbitOptions& opt) {
  return "d=" + d.text() + " r=" + r.text() + " bits=" + std::to_string(opt.bits) +
         " starts=" + std::to_string(opt.starts) + " seed=" + std::to_string(opt.seed);
}

std::string orbit_checkpoint_text(const std::string& inputs, const OrbitSearch& s) {
  std::ostringstream out;
  out << kMagic << "\ninputs " << inputs << "\n";
  std::size_t at = 0;
  for (const PeriodTally& t : s.periods) {
    out << "period " << t.period << ' ' << t.codes << ' ' << t.codes_with_orbits << ' ' << t.candidates << ' '
        << t.proven << ' ' << t.unproven << ' ' << t.prime_cycles << ' ' << t.by_symmetry << ' ' << t.family_codes
        << ' ' << shortest(t.seconds) << '\n';
    for (std::size_t k = 0; k < t.proven; ++k, ++at) {
      const ProvenOrbit& o = s.orbits.at(at);
      out << "orbit " << orbit_code_text(o.code) << ' ' << o.weight;
      for (const Mpfr& u : o.point) {  // exactly, in hexadecimal: the resumed proof starts where this one did
        char* hex = nullptr;
        mpfr_asprintf(&hex, "%Ra", u.data());
        out << ' ' << hex;
        mpfr_free_str(hex);
      }
      out << '\n';
    }
  }
  return out.str();
}

OrbitCheckpoint parse_orbit_checkpoint(const std::string& text, const std::string& where) {
  CheckpointReader r(text, kMagic, where);
  OrbitCheckpoint c;
  c.inputs = r.inputs();
  std::size_t owed = 0;  // orbits the last period line announced and not yet read
  for (std::vector<std::string> w; r.next(w);) {
    if (!w.empty() && w[0] == "period" && w.size() == 11) {
      if (owed != 0) r.fail("a period before the last one's orbits");
      PeriodTally t;
      t.period = static_cast<int>(r.count(w[1]));
      if (t.period != static_cast<int>(c.periods.size()) + 2) r.fail("periods out of order");
      std::size_t* fields[] = {&t.codes,    &t.codes_with_orbits, &t.candidates,  &t.proven,
                               &t.unproven, &t.prime_cycles,      &t.by_symmetry, &t.family_codes};
      for (std::size_t i = 0; i < 8; ++i) *fields[i] = r.count(w[2 + i]);
      try {
        t.seconds = std::stod(w[10]);
      } catch (const std::exception&) {
        r.fail("seconds unreadable");
      }
      owed = t.proven;
      c.periods.push_back(t);
    } else if (!w.empty() && w[0] == "orbit" && w.size() >= 5) {
      if (owed == 0) r.fail("an orbit no period line announced");
      OrbitCheckpoint::Orbit o;
      try {
        o.code = parse_orbit_code(w[1], "orbit");
      } catch (const InputError& e) {
        r.fail(e.what());
      }
      if (static_cast<int>(o.code.size()) != c.periods.back().period || w.size() != 3 + o.code.size())
        r.fail("an orbit of another period");
      o.weight = static_cast<int>(r.count(w[2]));
      if (o.weight != 1 && o.weight != 2) r.fail("weight " + w[2]);
      o.u.assign(w.begin() + 3, w.end());
      c.orbits.push_back(std::move(o));
      --owed;
    } else {
      r.fail("unreadable line");
    }
  }
  if (owed != 0) r.fail("truncated: orbits missing");
  return c;
}

OrbitSearch resume_orbit_search(const ExactReal& d, const ExactReal& r, const OrbitCheckpoint& c,
                                const OrbitOptions& opt) {
  OrbitSearch s;
  s.periods = c.periods;
  const MpfrPrecision guard(opt.bits);
  for (const OrbitCheckpoint::Orbit& o : c.orbits) {
    std::vector<Mpfr> u(o.u.size());
    for (std::size_t i = 0; i < u.size(); ++i)
      if (mpfr_set_str(u[i].data(), o.u[i].c_str(), 0, MPFR_RNDN) != 0)
        throw std::runtime_error("orbit checkpoint: a parameter of " + orbit_code_text(o.code) + " unreadable");
    ProvenOrbit p;
    if (!prove_orbit(d, r, o.code, u, opt.bits, p))
      throw std::runtime_error("orbit checkpoint: " + orbit_code_text(o.code) + " is not proven again");
    p.weight = o.weight;
    s.orbits.push_back(std::move(p));
  }
  return s;
}

}  // namespace rotleak
