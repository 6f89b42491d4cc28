#include "io/tally_file.hpp"

#include <cstring>
#include <sstream>
#include <stdexcept>

#include "io/bytes.hpp"
#include "io/files.hpp"
#include "io/json.hpp"

namespace rotleak {

namespace {

constexpr const char* kMagic = "rotleak-tallies 4\n";
/// An escape record's last word: its fate + kLeakShift x its leak.
constexpr std::uint64_t kLeakShift = 256;

/// The file's checksum: FNV-1a started from 1469598103934665603 (not FNV's offset basis; the format has
/// always carried this start, and docs/output.md and the readers use it).
std::uint64_t checksum(const char* p, std::size_t n) { return fnv1a(p, n, 1469598103934665603ull); }

// a sum: its lowest limb's index, its limb count, the limbs (trimmed: equal sums, equal bytes)
void put_sum(ByteWriter& w, const FixedSum& f) {
  const std::vector<std::uint64_t> limbs = f.limbs();
  w.word(static_cast<std::uint64_t>(f.base()));
  w.word(limbs.size());
  w.words(limbs);
}
void put_sums(ByteWriter& w, const std::vector<FixedSum>& v) {
  for (const FixedSum& f : v) put_sum(w, f);
}
FixedSum get_sum(ByteReader& r) {
  const long base = static_cast<long>(r.word());
  const std::uint64_t n = r.word();
  if (n > 4096) throw std::runtime_error("tally file: an exact sum of " + std::to_string(n) + " limbs");
  if (n > 0 && (base < FixedSum::kLowestLimb || base > FixedSum::kLimbEnd - static_cast<long>(n)))
    throw std::runtime_error("tally file: an exact sum at limbs " + std::to_string(base) + " + " + std::to_string(n) +
                             ", outside [" + std::to_string(FixedSum::kLowestLimb) + ", " +
                             std::to_string(FixedSum::kLimbEnd) + ")");
  std::vector<std::uint64_t> limbs(n);
  r.words(limbs);
  return FixedSum::from_limbs(base, std::move(limbs));
}
void get_sums(ByteReader& r, std::vector<FixedSum>& v) {
  for (auto& f : v) f = get_sum(r);
}

/// A split run's section: the line sums, counts, conservation sums and unsplit cells.
void put_lines(ByteWriter& w, const LinesEstimator& e) {
  for (const auto* v : {&e.line_in, &e.line_out, &e.line2_in, &e.line2_out, &e.linex_in, &e.linex_out}) put_sums(w, *v);
  w.words(e.lines_ended);
  w.words(e.born_per_bin);
  w.words(e.culled_per_bin);
  for (std::uint64_t x : {e.splits, e.culls, e.levels, e.max_population, e.max_line}) w.word(x);
  for (const FixedSum* sum : {&e.w_start, &e.w_gained, &e.w_escaped, &e.w_removed, &e.w_alive_end}) put_sum(w, *sum);
  const auto put_cell = [&w](const UnsplitCell& c) {
    w.word(c.lines);
    put_sum(w, c.w);
    put_sum(w, c.w2);
  };
  for (const UnsplitCell& c : e.unsplit_start) put_cell(c);
  w.word(e.unsplit_left.size());
  for (const auto& [key, cell] : e.unsplit_left) {
    w.word(key);
    put_cell(cell);
  }
}

}  // namespace

std::string encode_tally_file(const TallyFile& f) {
  const Tally& t = f.tally;
  json done = json::array();
  for (const auto& [lo, hi] : f.done.intervals()) done.push_back({lo, hi});
  const json header = {{"inputs", f.inputs},
                       {"particles", f.particles},
                       {"first_id", f.first_id},
                       {"of", f.of},
                       {"block_size", kBlockSize},
                       {"done", done},
                       {"survival_bins", t.escapes_per_bin.size()},
                       {"density_bins", t.collision_density.size()},
                       {"weighted", t.weighted()},
                       {"split", t.get_if<LinesEstimator>() != nullptr},
                       {"records", f.records.size()}};
  json with_time = header;
  if (!t.escapes_by_leak.empty()) with_time["leak_bins"] = t.escapes_by_leak.size();  // several leaks only
  if (f.wall_seconds > 0) with_time["wall_seconds"] = f.wall_seconds;                 // checkpoints only: not an input
  const std::string h = with_time.dump();
  ByteWriter w;
  w.out = std::string(kMagic) + std::to_string(h.size()) + "\n" + h;
  w.words(t.escapes_per_bin);
  w.words(t.collision_density);
  w.words(t.escapes_by_leak);
  for (std::uint64_t x : {t.collisions, t.escaped, t.survived, t.stuck}) w.word(x);
  if (t.weighted()) {
    // format 3's weighted section: a weighted run's escape sums and totals (a split run's places hold no
    // escape sums and two zero totals), then the weighted density
    if (const auto* e = t.get_if<WeightedEstimator>()) {
      put_sums(w, e->escaped_w);
      put_sums(w, e->escaped_w2);
      put_sum(w, e->total_w);
      put_sum(w, e->total_w2);
    } else {
      put_sum(w, FixedSum{});
      put_sum(w, FixedSum{});
    }
    put_sums(w, t.collision_density_w);
  }
  if (const auto* e = t.get_if<LinesEstimator>()) put_lines(w, *e);
  for (const EscapeRecord& r : f.records) {
    w.real(r.t);
    w.real(r.s);
    w.word(r.collisions);
    w.word(static_cast<std::uint64_t>(r.fate) + kLeakShift * static_cast<std::uint64_t>(r.leak));
  }
  return sealed_tally_bytes(std::move(w.out));
}

std::string sealed_tally_bytes(std::string body) {
  const std::uint64_t sum = checksum(body.data(), body.size());
  body.append(reinterpret_cast<const char*>(&sum), 8);
  return body;
}

namespace {

/// The header's fields into f (sizes checked against the file's bytes before anything is allocated).
void read_header(const json& h, std::size_t size, std::size_t nl, TallyFile& f) {
  const std::uint64_t room = (size - nl) / 8;  // words after the header, at most
  // every number is checked for its type before it is read: a float where a count belongs (5.7e54) was
  // converted with undefined behaviour (found by fuzz_tally), and a size is held against the bytes that
  // follow before anything is allocated for it
  const auto count = [&](const json& v, const char* what) {
    if (!v.is_number_unsigned()) throw std::runtime_error(std::string(what) + " is not a count: " + v.dump());
    return v.get<std::uint64_t>();
  };
  const auto flag = [&](const char* key) {
    if (!h.at(key).is_boolean()) throw std::runtime_error(std::string(key) + " is not true or false");
    return h.at(key).get<bool>();
  };
  if (count(h.at("block_size"), "block_size") != kBlockSize)
    throw std::runtime_error("written with blocks of " + h.at("block_size").dump() + " particles, this build uses " +
                             std::to_string(kBlockSize));
  if (!h.at("inputs").is_string()) throw std::runtime_error("inputs is not a text");
  f.inputs = h.at("inputs").get<std::string>();
  f.particles = count(h.at("particles"), "particles");
  f.first_id = count(h.at("first_id"), "first_id");
  f.of = count(h.at("of"), "of");
  if (h.contains("wall_seconds") && !h.at("wall_seconds").is_number()) throw std::runtime_error("wall_seconds");
  f.wall_seconds = h.value("wall_seconds", 0.0);
  if (!(f.wall_seconds >= 0 && f.wall_seconds < 1e12)) throw std::runtime_error("wall_seconds out of range");
  if (!h.at("done").is_array()) throw std::runtime_error("done is not a list");
  for (const json& iv : h.at("done"))
    if (!iv.is_array() || !f.done.insert(count(iv.at(0), "done"), count(iv.at(1), "done")))
      throw std::runtime_error("overlapping done blocks");
  const std::uint64_t survival_bins = count(h.at("survival_bins"), "survival_bins"),
                      density_bins = count(h.at("density_bins"), "density_bins"),
                      records = count(h.at("records"), "records");
  if (survival_bins > room || density_bins > room || records > room / 4)
    throw std::runtime_error("sizes larger than the file (" + std::to_string(survival_bins) + " bins, " +
                             std::to_string(density_bins) + " density bins, " + std::to_string(records) +
                             " records in " + std::to_string(size) + " bytes)");
  f.tally.escapes_per_bin.assign(survival_bins, 0);
  f.tally.collision_density.assign(density_bins, 0);
  const std::uint64_t leak_bins = h.contains("leak_bins") ? count(h.at("leak_bins"), "leak_bins") : 0;
  // leak bins come as whole rows of survival bins: none without survival bins (the records' leaks divide by them)
  if (leak_bins > room || (leak_bins != 0 && (survival_bins == 0 || leak_bins % survival_bins != 0)))
    throw std::runtime_error("leak_bins " + std::to_string(leak_bins) + " is not a number of leaks times " +
                             std::to_string(survival_bins) + " bins within the file");
  f.tally.escapes_by_leak.assign(leak_bins, 0);
  const bool weighted = flag("weighted"), split = flag("split");
  if (split && !weighted) throw std::runtime_error("a split run whose members carry no weights");
  if (split)
    f.tally.estimator = LinesEstimator{};
  else if (weighted)
    f.tally.estimator = WeightedEstimator{};
  f.records.resize(records);
}

/// The weighted section (format 3, as put): a weighted run's escape sums by bin and totals (a split
/// run's: two totals, zero), then the weighted density.
void read_weighted(ByteReader& r, Tally& t) {
  if (auto* e = t.get_if<WeightedEstimator>()) {
    e->resize(t.escapes_per_bin.size());
    get_sums(r, e->escaped_w);
    get_sums(r, e->escaped_w2);
    e->total_w = get_sum(r);
    e->total_w2 = get_sum(r);
  } else if (!(get_sum(r) == FixedSum{}) || !(get_sum(r) == FixedSum{})) {
    throw std::runtime_error("tally file: a split run with weight totals");
  }
  t.collision_density_w.resize(t.collision_density.size());
  get_sums(r, t.collision_density_w);
}

/// A split run's line sums, counts, conservation sums and unsplit cells (their number held against the bytes
/// left, their keys increasing and on the grid).
void read_lines(ByteReader& r, LinesEstimator& e, std::size_t bins, std::size_t size, const std::string& where) {
  e.resize(bins);
  for (auto* v : {&e.line_in, &e.line_out, &e.line2_in, &e.line2_out, &e.linex_in, &e.linex_out}) get_sums(r, *v);
  r.words(e.lines_ended);
  r.words(e.born_per_bin);
  r.words(e.culled_per_bin);
  for (std::uint64_t* x : {&e.splits, &e.culls, &e.levels, &e.max_population, &e.max_line}) *x = r.word();
  for (FixedSum* sum : {&e.w_start, &e.w_gained, &e.w_escaped, &e.w_removed, &e.w_alive_end}) *sum = get_sum(r);
  const auto get_cell = [&r](UnsplitCell& c) {
    c.lines = r.word();
    c.w = get_sum(r);
    c.w2 = get_sum(r);
  };
  for (UnsplitCell& c : e.unsplit_start) get_cell(c);
  const std::uint64_t cells = r.word();
  // a cell takes at least 5 words: a count larger than the bytes left is damage, not an allocation
  if (cells > (size - r.at) / 40)
    throw std::runtime_error(where + ": tally file: " + std::to_string(cells) + " unsplit cells");
  std::uint64_t previous = 0;
  for (std::uint64_t k = 0; k < cells; ++k) {
    const std::uint64_t key = r.word();
    if ((k > 0 && key <= previous) || key / kUnsplitClasses > bins)
      throw std::runtime_error(where + ": tally file: unsplit cells out of order or off the grid");
    previous = key;
    get_cell(e.unsplit_left[key]);
  }
}

}  // namespace

TallyFile decode_tally_file(const std::string& in, const std::string& where) {
  const std::size_t magic = std::strlen(kMagic);
  if (in.compare(0, magic, kMagic) != 0) throw std::runtime_error(where + ": not a rotleak tally file");
  if (in.size() < magic + 8 || [&] {
        std::uint64_t sum;
        std::memcpy(&sum, in.data() + in.size() - 8, 8);
        return sum != checksum(in.data(), in.size() - 8);
      }())
    throw std::runtime_error(where + ": tally file damaged (checksum mismatch)");
  const std::size_t nl = in.find('\n', magic);
  std::size_t hlen = 0;
  try {
    hlen = std::stoull(in.substr(magic, nl - magic));
  } catch (const std::exception&) {
    throw std::runtime_error(where + ": tally file header length unreadable");
  }
  TallyFile f;
  try {
    read_header(json::parse(in.substr(nl + 1, hlen)), in.size(), nl, f);
  } catch (const std::exception& e) {
    throw std::runtime_error(where + ": tally file header unreadable: " + e.what());
  }
  ByteReader r{in, nl + 1 + hlen, where + ": tally file"};
  Tally& t = f.tally;
  r.words(t.escapes_per_bin);
  r.words(t.collision_density);
  r.words(t.escapes_by_leak);
  t.collisions = r.word();
  t.escaped = r.word();
  t.survived = r.word();
  t.stuck = r.word();
  if (t.weighted()) read_weighted(r, t);
  if (auto* e = t.get_if<LinesEstimator>()) read_lines(r, *e, t.escapes_per_bin.size(), in.size(), where);
  const std::uint64_t leaks = t.escapes_by_leak.empty() ? 1 : t.escapes_by_leak.size() / t.escapes_per_bin.size();
  for (EscapeRecord& e : f.records) {
    e.t = r.real();
    e.s = r.real();
    e.collisions = r.word();
    const std::uint64_t word = r.word(), fate = word % kLeakShift, leak = word / kLeakShift;
    if (fate > static_cast<std::uint64_t>(Fate::stuck) || leak >= leaks)
      throw std::runtime_error(where + ": an escape record's fate word " + std::to_string(word) +
                               " is not a fate (0 escaped, 1 survived, 2 stuck) + 256 x a leak below " +
                               std::to_string(leaks));
    e.fate = static_cast<Fate>(fate);
    e.leak = static_cast<int>(leak);
  }
  if (r.at + 8 != in.size()) throw std::runtime_error(where + ": tally file has trailing data");
  return f;
}

void write_tally_file(const std::filesystem::path& path, const TallyFile& f) {
  write_file_atomic(path, encode_tally_file(f), /*durable=*/true);
}

TallyFile read_tally_file(const std::filesystem::path& path) {
  return decode_tally_file(read_file(path), path.string());
}

std::string inputs_difference(const std::string& a, const std::string& b) {
  if (a == b) return "";
  std::istringstream sa(a), sb(b);
  std::string la, lb, section;
  while (true) {
    const bool ga = static_cast<bool>(std::getline(sa, la)), gb = static_cast<bool>(std::getline(sb, lb));
    if (!ga && !gb) return "they differ";
    if (ga && gb && la == lb) {
      if (!la.empty() && la[0] == '[') section = la.substr(1, la.size() - 2) + ".";
      continue;
    }
    const std::string key = (ga ? la : lb).substr(0, (ga ? la : lb).find(" = "));
    const auto value = [](const std::string& line, bool got) {
      if (!got) return std::string("(absent)");
      const auto eq = line.find(" = ");
      return eq == std::string::npos ? line : line.substr(eq + 3);
    };
    if (key.rfind("# engine", 0) == 0) return "engine: " + value(la, ga) + " vs " + value(lb, gb);
    return section + key + ": " + value(la, ga) + " vs " + value(lb, gb);
  }
}

}  // namespace rotleak
