#include "verify/orbit_checkpoint.hpp"

#include <sstream>
#include <stdexcept>

#include "io/files.hpp"
#include "numeric/input.hpp"

namespace rotleak {

namespace {

constexpr const char* kMagic = "rotleak-orbits-checkpoint 1";

std::size_t count(const std::string& word, const std::string& where, std::size_t line) {
  std::size_t at = 0;
  unsigned long long v = 0;
  try {
    v = std::stoull(word, &at);
  } catch (const std::exception&) {
    at = 0;
  }
  if (at != word.size() || word.empty() || word[0] == '-')
    throw std::runtime_error(where + ":" + std::to_string(line) + ": not a count: \"" + word + "\"");
  return static_cast<std::size_t>(v);
}

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
  OrbitCheckpoint c;
  std::istringstream in(text);
  std::string line;
  std::size_t n = 0, owed = 0;  // orbits the last period line announced and not yet read
  const auto fail = [&](const std::string& why) {
    throw std::runtime_error(where + ":" + std::to_string(n) + ": " + why);
  };
  while (std::getline(in, line)) {
    ++n;
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string x; words >> x;) w.push_back(x);
    if (n == 1) {
      if (line != kMagic) fail("not a rotleak orbit checkpoint");
      continue;
    }
    if (n == 2) {
      if (line.rfind("inputs ", 0) != 0) fail("no inputs line");
      c.inputs = line.substr(7);
      continue;
    }
    if (!w.empty() && w[0] == "period" && w.size() == 11) {
      if (owed != 0) fail("a period before the last one's orbits");
      PeriodTally t;
      t.period = static_cast<int>(count(w[1], where, n));
      if (t.period != static_cast<int>(c.periods.size()) + 2) fail("periods out of order");
      std::size_t* fields[] = {&t.codes,    &t.codes_with_orbits, &t.candidates,  &t.proven,
                               &t.unproven, &t.prime_cycles,      &t.by_symmetry, &t.family_codes};
      for (std::size_t i = 0; i < 8; ++i) *fields[i] = count(w[2 + i], where, n);
      try {
        t.seconds = std::stod(w[10]);
      } catch (const std::exception&) {
        fail("seconds unreadable");
      }
      owed = t.proven;
      c.periods.push_back(t);
    } else if (!w.empty() && w[0] == "orbit" && w.size() >= 5) {
      if (owed == 0) fail("an orbit no period line announced");
      OrbitCheckpoint::Orbit o;
      try {
        o.code = parse_orbit_code(w[1], "orbit");
      } catch (const InputError& e) {
        fail(e.what());
      }
      if (static_cast<int>(o.code.size()) != c.periods.back().period || w.size() != 3 + o.code.size())
        fail("an orbit of another period");
      o.weight = static_cast<int>(count(w[2], where, n));
      if (o.weight != 1 && o.weight != 2) fail("weight " + w[2]);
      o.u.assign(w.begin() + 3, w.end());
      c.orbits.push_back(std::move(o));
      --owed;
    } else {
      fail("unreadable line");
    }
  }
  if (n < 2) fail("truncated");
  if (owed != 0) fail("truncated: orbits missing");
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
