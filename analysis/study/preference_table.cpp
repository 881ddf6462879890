#include "analysis/study/preference_table.h"

#include <stdexcept>

#include "analysis/statistics/binomial.h"

namespace fovlab::analysis {

std::vector<PreferenceRow> preference_table(const std::vector<PreferenceCount>& counts) {
  std::vector<PreferenceRow> rows;
  for (const PreferenceCount& count : counts) {
    if (count.n == 0 || count.reference_votes > count.n)
      throw std::invalid_argument("preference_table: expected 0 <= votes <= n and n >= 1, got " +
                                  std::to_string(count.reference_votes) + " of " + std::to_string(count.n));
    PreferenceRow row;
    row.study = count.study;
    row.group = count.group;
    row.condition = count.condition;
    row.reference_method = count.reference_method;
    row.test_method = count.test_method;
    row.n = count.n;
    row.reference_votes = count.reference_votes;
    row.share = double(count.reference_votes) / double(count.n);
    row.p_value = binomial_test_p_value(count.reference_votes, count.n, 0.5, Alternative::greater);
    row.log10_p = binomial_test_log10_p_value(count.reference_votes, count.n, 0.5, Alternative::greater);
    row.stars = significance_stars(row.p_value);
    if (row.stars.empty()) row.stars = "n.s.";
    row.interval = clopper_pearson_interval(count.reference_votes, count.n, 0.95);
    rows.push_back(std::move(row));
  }
  return rows;
}

std::vector<PreferenceCount> preference_counts(const AnalysisResult& result, const std::string& reference_method) {
  std::vector<PreferenceCount> counts;
  if (result.protocol != ProtocolKind::two_afc || result.question != TwoAfcQuestion::better) return counts;
  for (const ConditionRow& row : result.conditions) {
    if (row.n == 0) continue;
    counts.push_back({result.study, row.group, row.condition, reference_method, row.method, row.n - row.k, row.n});
  }
  return counts;
}

}  // namespace fovlab::analysis
