// A scene: everything one run needs, validated. Every error names the key, the value and what is allowed.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "numeric/exact.hpp"

namespace rotleak {

/// Bad input. what() is one line: "<key> = <value>: <what is allowed>".
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& key, const std::string& value, const std::string& allowed)
      : std::runtime_error(key + " = " + value + ": " + allowed), key_(key) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

/// An exact value read from user text; bad text is an InputError naming `key`.
ExactReal parse_exact_input(const std::string& key, const std::string& text);

enum class InitKind { birkhoff, flow };
/// auto_: chosen per scene by the audit (rotleak simulate resolves it before running).
enum class Tier { float_, double_, long_double, auto_ };

std::string to_string(InitKind k);
std::string to_string(Tier t);

struct TimeWindow {
  double from = 0, to = 0;
};

struct CollisionDensitySpec {
  int bins = 1000;
  std::vector<TimeWindow> windows;
};

struct Scene {
  // Exact inputs, with the text the user wrote.
  ExactReal d = ExactReal::parse("2"), r = ExactReal::parse("1");
  ExactReal width = ExactReal::parse("0.01"), start = ExactReal::parse("0"), omega = ExactReal::parse("0");
  std::string d_text = "2", r_text = "1", width_text = "0.01", start_text = "0", omega_text = "0";

  std::uint64_t particles = 1000000;
  std::uint64_t seed = 1;
  InitKind init = InitKind::birkhoff;
  double creation_window = 4;  ///< particles are created at times uniform in [0, creation_window]

  double t_max = 20000;
  Tier tier = Tier::double_;
  bool fast_forward = false;  ///< closed-form bouncing-ball phases (sim/particle.hpp fast_forward)

  double survival_dt = 1;
  std::optional<CollisionDensitySpec> collision_density;
  bool escape_records = false;

  TimeWindow kappa_window{0, 300};

  std::string source;  ///< file it came from, if any

  /// Number of survival bins, ceil(t_max / survival_dt).
  std::size_t survival_bins() const;
};

/// Reads and validates a TOML scene. `overrides` are "section.key=value" strings applied on top of
/// the file before validation (values for exact keys are taken verbatim as text).
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});
/// Same from TOML text (for tests and for scenes built in memory).
Scene parse_scene(const std::string& toml_text, const std::vector<std::string>& overrides = {},
                  const std::string& source = "<string>");

/// The scene as TOML text that parse_scene reads back to the same scene.
std::string scene_to_toml(const Scene& s);

}  // namespace rotleak
