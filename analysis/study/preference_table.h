#pragma once
// Ye et al. 2022's comparison study (sections 4.3.3 and 5.2, Table 2): 2AFC "which looked better?" votes
// of the proposed method (RMFR, the config's reference) against each competitor (the test), pooled
// over participants and trials, as the share of votes for the reference with the exact binomial
// test of H0 p = 1/2 against the ONE-sided alternative "greater" (the reference preferred), its
// stars and the 95 % Clopper-Pearson interval. The paper's stars (49, 47, 50 and 35 of 72: **, **,
// ***, n.s.) are those of this one-sided test only. Definitions in docs/analysis.md.
#include <cstdint>
#include <string>
#include <vector>

#include "analysis/study/analysis_result.h"

namespace fovlab::analysis {

// One comparison's votes, and what names it in the table.
struct PreferenceCount {
  std::string study;
  GroupKey group;
  std::string condition;
  std::string reference_method;
  std::string test_method;
  uint64_t reference_votes = 0;  // the reference chosen as better
  uint64_t n = 0;                // answered trials (at least 1; std::invalid_argument otherwise)
};

// One row per count, in order: share, one-sided p (greater, H0 1/2), stars ("n.s." when p >= 0.05)
// and the 95 % Clopper-Pearson interval of the share. The p is one-sided whatever --alternative
// the rest of the analysis uses.
std::vector<PreferenceRow> preference_table(const std::vector<PreferenceCount>& counts);

// The counts of a 2afc "better" study's condition rows (k counts the test chosen, so the reference
// has n - k), with the reference's method named by the config; empty for any other protocol.
std::vector<PreferenceCount> preference_counts(const AnalysisResult& result, const std::string& reference_method);

}  // namespace fovlab::analysis
