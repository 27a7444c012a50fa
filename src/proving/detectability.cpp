#include "tread_wear/proving/detectability.h"

#include <Eigen/Dense>
#include <algorithm>
#include <map>
#include <random>
#include <stdexcept>

#include "tread_wear/diagnosis/statistics.h"

namespace tread_wear {
namespace diagnosis {

Detectability detectability(const TireParams& base, const DiagnosisData& truth, const std::string& hidden,
                            const DetectabilityOptions& options) {
  std::string error;
  if (!options.validate(&error)) throw std::invalid_argument(error);
  Term hidden_term = Term::kNone;
  if (hidden != "none" && !parseTerm(hidden, &hidden_term))
    throw std::invalid_argument("detectability: '" + hidden + "' is not a library term or none");

  Detectability d;
  d.hidden = hidden;
  std::vector<Term> applicable;
  for (const TermInfo& info : termLibrary()) {
    if (candidateWanted(options, info.term) && termApplicable(info.term, truth, nullptr))
      applicable.push_back(info.term);
  }
  d.terms_tried = static_cast<int>(applicable.size());

  const int n = measuredValues(truth);
  const LinearisedModel base_model = linearisedFit(base, truth, options, {});
  if (!base_model.usable) throw std::invalid_argument("detectability: the base model cannot be fitted to the truth");
  std::vector<LinearisedModel> candidates;
  for (Term t : applicable) {
    LinearisedModel m = linearisedFit(base, truth, options, {t});
    if (m.usable) candidates.push_back(std::move(m));
  }
  int largest_k = base_model.k;
  for (const LinearisedModel& m : candidates) largest_k = std::max(largest_k, m.k);
  if (n - largest_k - 1 <= 0)
    throw std::invalid_argument("detectability: " + std::to_string(n) + " measured values are too few for models " +
                                "with " + std::to_string(largest_k) + " parameters");
  d.lambda = base_model.residual.squaredNorm();
  const bool hidden_tried = std::find(applicable.begin(), applicable.end(), hidden_term) != applicable.end();
  if (hidden_term != Term::kNone && !hidden_tried) {
    d.power = 0.0;  // the data cannot show it (e.g. no temperatures for a thermal term): never tested
  } else if (hidden_term != Term::kNone) {
    for (const LinearisedModel& m : candidates)
      if (m.terms.front() == hidden_term) d.parameters = m.parameters;
    const int k_term = parameterCount({hidden_term}) - base_model.k;
    d.power = fTestPower(d.lambda, k_term, n - parameterCount({hidden_term}),
                         firstStepLevel(hidden_term, options.alpha_select, d.terms_tried));
  }

  // The first selection step on noise draws. The F test's threshold as a critical value of the statistic:
  // p < level, or for a one-sided term p / 2 < level while its estimate is off the bound.
  std::vector<double> critical;
  for (const LinearisedModel& m : candidates)
    critical.push_back(
        fCritical(m.k - base_model.k, n - m.k, firstStepLevel(m.terms.front(), options.alpha_select, d.terms_tried)));
  std::mt19937_64 rng(options.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd noise(n);
  std::map<std::string, int> counts;
  for (int draw = 0; draw < options.draws; ++draw) {
    for (int i = 0; i < n; ++i) noise(i) = normal(rng);
    const double rss_base = base_model.rss(noise);
    const double aicc_base = aicc(rss_base, n, base_model.k);
    std::string verdict = "none";
    double best_aicc = 0.0;
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      const LinearisedModel& m = candidates[c];
      const double rss = m.rss(noise);
      const double f = ((rss_base - rss) / (m.k - base_model.k)) / (rss / (n - m.k));
      const double a = aicc(rss, n, m.k);
      if (!(f > critical[c]) || aicc_base - a < options.min_aicc_drop) continue;
      if (verdict == "none" || a < best_aicc) {
        verdict = termInfo(m.terms.front()).name;
        best_aicc = a;
      }
    }
    ++counts[verdict];
  }
  for (const auto& [verdict, count] : counts)
    d.verdicts.push_back({verdict, static_cast<double>(count) / options.draws});
  std::sort(d.verdicts.begin(), d.verdicts.end(),
            [](const OracleVerdict& a, const OracleVerdict& b) { return a.probability > b.probability; });
  const auto right = counts.find(hidden);
  d.expected_right = right == counts.end() ? 0.0 : static_cast<double>(right->second) / options.draws;
  return d;
}

}  // namespace diagnosis
}  // namespace tread_wear
