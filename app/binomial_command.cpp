// fovlab binomial K N: the exact binomial test of K successes in N trials, for checking published
// counts in one line (Ye et al. 2022's Table 2: 47 of 72 votes for RMFR over linear fall-off is p = 0.0064,
// **, one-sided; 0.0128, *, two-sided). The same test and interval as `fovlab analyze`
// (analysis/statistics/binomial.h); docs/analysis.md, "Statistics".
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "analysis/statistics/binomial.h"
#include "app/commands.h"
#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab::app {

namespace {

struct BinomialOptions {
  std::string successes;
  std::string trials;
  std::string alternative = "greater";
  double p0 = 0.5;
  double confidence = 0.95;
};

constexpr uint64_t kMaxTrials = (uint64_t{1} << 53) - 1;  // what the test's doubles count exactly

uint64_t parse_count(const std::string& text, const char* what) {
  uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value > kMaxTrials)
    throw InputError(std::string(what) + " \"" + text + "\": expected a whole number from 0 to " +
                     std::to_string(kMaxTrials));
  return value;
}

void run_binomial(const BinomialOptions& options) {
  const uint64_t k = parse_count(options.successes, "K");
  const uint64_t n = parse_count(options.trials, "N");
  if (n == 0) throw InputError("N 0: expected at least one trial");
  if (k > n) throw InputError("K " + std::to_string(k) + ": expected at most N = " + std::to_string(n));
  if (!(options.p0 > 0.0 && options.p0 < 1.0))
    throw InputError("--p0 " + format_number(options.p0, 6) + ": expected a probability strictly between 0 and 1");
  if (!(options.confidence > 0.0 && options.confidence < 1.0))
    throw InputError("--confidence " + format_number(options.confidence, 6) +
                     ": expected a level strictly between 0 and 1");
  const analysis::Alternative alternative = analysis::parse_alternative(options.alternative);
  const double p = analysis::binomial_test_p_value(k, n, options.p0, alternative);
  const analysis::ProportionInterval interval = analysis::clopper_pearson_interval(k, n, options.confidence);
  const std::string stars = analysis::significance_stars(p);
  std::printf("%llu of %llu (%.1f %%), H0: p = %g, alternative %s\n", static_cast<unsigned long long>(k),
              static_cast<unsigned long long>(n), 100.0 * double(k) / double(n), options.p0,
              analysis::alternative_name(alternative));
  const double log10_p = analysis::binomial_test_log10_p_value(k, n, options.p0, alternative);
  std::printf("exact binomial p = %s%s%s\n", analysis::p_value_text(p, log10_p, 4).c_str(), stars.empty() ? "" : " ",
              stars.c_str());
  std::printf("%g %% Clopper-Pearson interval of the share: [%.4f, %.4f]\n", 100.0 * options.confidence, interval.lower,
              interval.upper);
}

}  // namespace

void add_binomial_command(CLI::App& app) {
  auto options = std::make_shared<BinomialOptions>();
  CLI::App* command = app.add_subcommand(
      "binomial", "Exact binomial test of K successes in N trials (e.g. a published 2AFC vote count)");
  command->add_option("K", options->successes, "Successes (e.g. votes for the method)")->required();
  command->add_option("N", options->trials, "Trials")->required();
  command->add_option("--alternative", options->alternative,
                      "greater (default: more than p0, as a preference vote is tested), less or two-sided");
  command->add_option("--p0", options->p0, "Success probability under H0 (default 0.5, a 2AFC guess)");
  command->add_option("--confidence", options->confidence, "Level of the Clopper-Pearson interval (default 0.95)");
  command->callback([options] { run_binomial(*options); });
}

}  // namespace fovlab::app
