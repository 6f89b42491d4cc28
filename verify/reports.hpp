// The verify layer's results as documents: JSON for files and --json, CSV for plots, and the lines
// a person reads. Commands call these; they build none of it themselves.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "io/json.hpp"
#include "verify/audit.hpp"
#include "verify/certify.hpp"
#include "verify/certify_sample.hpp"
#include "verify/lyapunov.hpp"
#include "verify/shadow.hpp"

namespace rotleak {

json shadow_json(const ShadowResult& r, double tolerance);
/// shadow.csv: per collision the truth (t, s, p, in_leak, mupo), then per tier its divergence and own t, s, p.
std::string shadow_csv(const ShadowResult& r);
std::string shadow_text(const ShadowResult& r);

json audit_json(const AuditReport& r, const std::string& scene_source);
std::string audit_text(const AuditReport& r, const std::string& scene_source);

json lyapunov_json(const LyapunovStudy& s);
std::string lyapunov_text(const LyapunovStudy& s, const std::string& scene_source);

json certify_json(std::uint64_t particle, const std::vector<Certificate>& attempts);
std::string certify_text(const std::vector<Certificate>& attempts);

/// The lines `rotleak certify --sample` prints: what was proven, the bracket, each tier against it.
std::string sample_text(const SampleCertificate& c, const SampleOptions& opt);

}  // namespace rotleak
