// The covering model's prediction as rotleak writes it: summary.json's predicted.tail, `rotleak predict`'s
// document and text, and the run's "model" line that sets the measured tail against it (docs/output.md).
#pragma once

#include <string>

#include "analysis/fits.hpp"
#include "analysis/regimes.hpp"
#include "analysis/tail_model.hpp"
#include "io/json.hpp"
#include "sim/model/scene.hpp"

namespace rotleak {

/// The covering model's prediction (summary.json predicted.tail, `rotleak predict --json`; docs/output.md).
json prediction_json(const TailPrediction& p);
/// `rotleak predict --json`'s document: prediction_json and the scene's inputs the model reads.
json prediction_document(const Scene& scene, const TailPrediction& p);
/// It in words, a few lines (`rotleak predict`).
std::string prediction_text(const TailPrediction& p);
/// Measured against predicted: whether a tail was seen as predicted, C against C in errors ("tail as predicted"
/// or "tail NOT as predicted"), the ends where both have one (the summary's "model" line).
std::string prediction_check(const TailPrediction& p, const TailAmplitude& measured, const TailClass& k);

}  // namespace rotleak
